!> ParaView output of `*OUTPUT, VTK`: each snapshot as VTK PolyData of line cells, twice — in VTK's
!> XML format, `STEM_NNNN.vtp`, and in the legacy format, `STEM_NNNN.vtk` (DATASET POLYDATA) — and the
!> collection `STEM.pvd` that lists the `.vtp` files. ParaView's pvd reader (vtkXMLCollectionReader)
!> builds its readers from the XML extensions only (vtu, vtp, vti, ...), so a pvd cannot list legacy
!> files, while the legacy files are what many other tools read.
!>
!> PolyData, not an unstructured grid: the elements are lines, and VTK's line filters (vtkTubeFilter,
!> ParaView's Tube; vtkRibbonFilter, vtkStripper, ...) take PolyData only, while the filters that take
!> any data set take PolyData too (ParaView's Append Datasets makes an unstructured grid of it for the
!> few that want one).
!>
!> A snapshot holds the deformed geometry x0 + u, with z = 0, one line cell per element (node 1 →
!> node 2). Point data: `displacement` (u_x, u_y, 0), `rotation` θ_z, `contact_reaction` (the sum of
!> the reactions of the node's contact candidates) and `node_label`; cell data: `axial_force` N
!> (tension positive), `shear_force` V = dM/ds, `bending_moment_start`, `bending_moment_end` and their
!> mean `bending_moment`, and `element_label`. Field data: `lambda` and `step`, one tuple each. The
!> formats are the "simple legacy" and the "XML" formats of "VTK File Formats" (Kitware, The VTK
!> User's Guide, 11th ed., 2010), the XML one with ASCII data arrays. A field data array of the
!> XML format must state NumberOfTuples: without it VTK's XML readers size it from the piece's points
!> or cells, which field data has none of, and read it empty.
!>
!> The element forces are those of the table STEM.forces (uniarc_output_forces, element_end_forces):
!> the element layer's axial force, shear force and end moments of any element kind, with the
!> element's own loads (temperature changes, loads on its span) accounted for; bending moments use
!> the beam convention M = EI κ, κ = dθ/ds along node 1 → node 2: positive when the element bends
!> towards its left normal (uniarc_transformation, transform_end_forces), and V = dM/ds along the same
!> direction. `bending_moment` is the mean of the end moments (the moment at mid-element of an element
!> without a load on its span), `axial_force` and `shear_force` the means of their end values (zero V
!> for a truss).
!>
!> The pvd's `timestep` is the step number, the NNNN of the file name, for every path: ParaView wants
!> strictly increasing time values, which λ does not give past a limit point, on unloading or under a
!> negative increment, and one meaning for every deck lets a ParaView state or script made on one run
!> serve another. λ is in every snapshot's field data.
!>
!> Every file is written in the run's work directory and moved to its final name with the other result
!> files when the run ends (uniarc_result_directory): a crash never leaves a half file under its final
!> name. Every write and close is checked (uniarc_text_file).
module uniarc_vtk
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_text_file, only: text_file_t, create_text_file, put_line, close_text_file, discard_text_file
   use uniarc_result_directory, only: result_directory_t, work_path, final_path, add_result_file
   use uniarc_strings, only: integer_text => integer_to_string
   use uniarc_model, only: model_t
   use uniarc_output_forces, only: element_end_forces
   use uniarc_output, only: step_record_t, format_number, nodal_reactions
   implicit none
   private
   public :: vtk_series_t, open_vtk_series, vtk_snapshot_due, write_vtk_snapshot, finish_vtk_series
   public :: vtk_file_name, element_forces
   public :: write_xml_reals, write_xml_integers   ! the buckling modes' files (uniarc_modes_output)

   !> The two files of a snapshot: legacy `.vtk` and XML `.vtp`.
   integer, parameter :: legacy_format = 1, xml_format = 2

   !> The snapshots of one run: where they go and what has been written.
   type :: vtk_series_t
      logical :: active = .false.                  !< the deck asked for VTK output
      character(len=:), allocatable :: stem
      integer :: every = 1                         !< snapshot interval in steps
      integer :: count = 0                         !< snapshots written
      integer, allocatable :: steps(:)             !< (count) step of each snapshot
   end type vtk_series_t

contains

   !> Start the series of a run. Nothing is written yet: the series is inactive when the deck has no
   !> `*OUTPUT, VTK`, and its interval is the deck's EVERY= or else the shape file's.
   subroutine open_vtk_series(model, stem, series)
      type(model_t), intent(in) :: model
      character(len=*), intent(in) :: stem
      type(vtk_series_t), intent(out) :: series
      series%active = model%output%vtk
      series%stem = stem
      series%every = model%output%vtk_every
      if (series%every <= 0) series%every = max(model%analysis%shape_every, 1)
      allocate (series%steps(0))
   end subroutine open_vtk_series

   !> Whether step `step` is one of the series' regular snapshots (every n-th step, step 0 included).
   pure logical function vtk_snapshot_due(series, step)
      type(vtk_series_t), intent(in) :: series
      integer, intent(in) :: step
      vtk_snapshot_due = series%active .and. mod(step, series%every) == 0
   end function vtk_snapshot_due

   !> Write the snapshot of `record` as `STEM_NNNN.vtk` and `STEM_NNNN.vtp` (NNNN the step). Does
   !> nothing when the series is inactive or the step is already its last snapshot.
   subroutine write_vtk_snapshot(series, results, model, record, error)
      type(vtk_series_t), intent(inout) :: series
      type(result_directory_t), intent(inout) :: results
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      type(error_t), allocatable, intent(out) :: error
      if (.not. series%active) return
      if (series%count > 0) then
         if (series%steps(series%count) == record%step) return
      end if
      call write_snapshot_file(results, vtk_file_name(series%stem, record%step, 'vtk'), legacy_format, model, &
                               record, series%stem, error)
      if (allocated(error)) return
      call write_snapshot_file(results, vtk_file_name(series%stem, record%step, 'vtp'), xml_format, model, &
                               record, series%stem, error)
      if (allocated(error)) return
      series%count = series%count + 1
      series%steps = [series%steps, record%step]
   end subroutine write_vtk_snapshot

   !> End the series with the last step `record` (written unless it already is the last snapshot) and
   !> write the collection `STEM.pvd`.
   subroutine finish_vtk_series(series, results, model, record, error)
      type(vtk_series_t), intent(inout) :: series
      type(result_directory_t), intent(inout) :: results
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      type(error_t), allocatable, intent(out) :: error
      if (.not. series%active) return
      call write_vtk_snapshot(series, results, model, record, error)
      if (allocated(error)) return
      call write_collection(series, results, error)
   end subroutine finish_vtk_series

   !> One file of a snapshot, `name` in the run's work directory, written and closed; on an error it
   !> is closed and removed.
   subroutine write_snapshot_file(results, name, file_format, model, record, stem, error)
      type(result_directory_t), intent(inout) :: results
      character(len=*), intent(in) :: name
      integer, intent(in) :: file_format
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      character(len=*), intent(in) :: stem
      type(error_t), allocatable, intent(out) :: error
      type(text_file_t) :: file
      real(dp), allocatable :: reaction(:), forces(:, :), reals(:)
      integer, allocatable :: integers(:)
      integer :: status
      ! The arrays of the snapshot first, allocated with stat= (the writers then make no array of the
      ! model's length): refused, no file of this snapshot (out of memory, error_analysis).
      allocate (reaction(model%n_nodes), reals(max(3*model%n_nodes, model%n_elements)), &
                integers(2*model%n_elements), stat=status)
      if (status == 0) call element_forces(model, record%displacement, record%lambda, forces, status, &
                                           record%joint_plastic, record%reactions)
      call allocation_failure(status, 'the arrays of the VTK snapshot of step '//integer_text(record%step), &
                              8.0_dp*(4*model%n_nodes + 10*model%n_elements), error_analysis, error)
      if (allocated(error)) return
      call nodal_reactions(model, record%reactions, reaction)
      call add_result_file(results, name)
      call create_text_file(file, work_path(results, name), final_path(results, name), error)
      if (allocated(error)) return
      select case (file_format)
      case (legacy_format)
         call write_legacy_vtk(file, model, record, stem, reaction, forces, reals)
      case default
         call write_xml_vtp(file, model, record, reaction, forces, reals, integers)
      end select
      call close_text_file(file, error)
      if (allocated(error)) call discard_text_file(file)
   end subroutine write_snapshot_file

   !> Name of the snapshot of step `step` with extension `extension` (`vtk` or `vtp`):
   !> `STEM_NNNN.extension`, NNNN at least four digits.
   pure function vtk_file_name(stem, step, extension) result(name)
      character(len=*), intent(in) :: stem
      integer, intent(in) :: step
      character(len=*), intent(in) :: extension
      character(len=:), allocatable :: name
      character(len=12) :: digits
      write (digits, '(i4.4)') step
      if (step > 9999 .or. step < 0) write (digits, '(i0)') step
      name = stem//'_'//trim(digits)//'.'//extension
   end function vtk_file_name

   !> Axial force, shear force and bending moments of every element: rows (N, V, M_start, M_end), shape
   !> (4, n_elements), at nodal displacements (3, n_nodes) and load factor `lambda`. Units: those of the
   !> deck's forces and forces × lengths.
   !>
   !> They are the section forces of uniarc_output_forces (element_end_forces, the same as STEM.forces:
   !> the element layer's forces with the element's own loads — temperature changes, loads on the
   !> span — accounted for, in the analysis' transformation): M_start and M_end at the two ends, and N
   !> and V the means of their values at the two ends (equal without a load along the span; the values
   !> at mid-element for a uniform one). The moments are in the beam convention M = EI κ and V = dM/ds
   !> (see the module header).
   !> `joint_plastic` (optional, (2, n_elements); absent or an unallocated actual argument without joints
   !> with a moment limit): their committed plastic rotations.
   !> `reactions` (optional, (n_contacts); absent or unallocated: none): the contact reactions, whose
   !> share on the span of a foundation's elements the forces include (element_end_forces).
   !> status: the stat= of `forces` or of the end forces refused by the system (0: `forces` complete).
   pure subroutine element_forces(model, displacement, lambda, forces, status, joint_plastic, reactions)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: displacement(:, :)
      real(dp), intent(in) :: lambda
      real(dp), allocatable, intent(out) :: forces(:, :)
      integer, intent(out) :: status
      real(dp), intent(in), optional :: joint_plastic(:, :)
      real(dp), intent(in), optional :: reactions(:)
      real(dp), allocatable :: ends(:, :)
      call element_end_forces(model, displacement, lambda, ends, status, joint_plastic=joint_plastic, &
                              reactions=reactions)
      if (status /= 0) return
      allocate (forces(4, model%n_elements), stat=status)
      if (status /= 0) return
      forces(1, :) = 0.5_dp*(ends(1, :) + ends(4, :))
      forces(2, :) = 0.5_dp*(ends(2, :) + ends(5, :))
      forces(3, :) = ends(3, :)
      forces(4, :) = ends(6, :)
   end subroutine element_forces

   !> The legacy VTK file of one snapshot (ASCII, DATASET POLYDATA with LINES).
   !> reaction (n_nodes) and forces (4, n_elements): the snapshot's (nodal_reactions, element_forces);
   !> reals: work space of at least n_elements.
   subroutine write_legacy_vtk(file, model, record, stem, reaction, forces, reals)
      type(text_file_t), intent(inout) :: file
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      character(len=*), intent(in) :: stem
      real(dp), intent(in) :: reaction(:), forces(:, :)
      real(dp), intent(inout) :: reals(:)
      character(len=:), allocatable :: title
      integer :: i, e

      ! The second line is the title, at most 256 characters (the legacy reader's line buffer).
      title = 'uniarc '//stem//' step '//integer_text(record%step)//' lambda '// &
              trim(format_number(record%lambda))
      if (allocated(model%title)) then
         if (len_trim(model%title) > 0) title = title//': '//trim(model%title)
      end if
      call put_line(file, '# vtk DataFile Version 3.0')
      call put_line(file, title(1:min(len(title), 255)))
      call put_line(file, 'ASCII')
      call put_line(file, 'DATASET POLYDATA')
      ! Field data of the data set: name, components, tuples, type, then the values.
      call put_line(file, 'FIELD FieldData 2')
      call put_line(file, 'lambda 1 1 double')
      call put_line(file, trim(format_number(record%lambda)))
      call put_line(file, 'step 1 1 int')
      call put_line(file, integer_text(record%step))

      call put_line(file, 'POINTS '//integer_text(model%n_nodes)//' double')
      do i = 1, model%n_nodes
         call put_line(file, trim(format_number(model%coordinates(1, i) + record%displacement(1, i)))//' '// &
            trim(format_number(model%coordinates(2, i) + record%displacement(2, i)))//' 0')
      end do
      ! A line cell lists its number of points (2) and its points, numbered from 0.
      call put_line(file, 'LINES '//integer_text(model%n_elements)//' '//integer_text(3*model%n_elements))
      do e = 1, model%n_elements
         call put_line(file, '2 '//integer_text(model%connectivity(1, e) - 1)//' '// &
            integer_text(model%connectivity(2, e) - 1))
      end do

      call put_line(file, 'POINT_DATA '//integer_text(model%n_nodes))
      call put_line(file, 'VECTORS displacement double')
      do i = 1, model%n_nodes
         call put_line(file, trim(format_number(record%displacement(1, i)))//' '// &
            trim(format_number(record%displacement(2, i)))//' 0')
      end do
      call write_scalars(file, 'rotation', record%displacement(3, :))
      call write_scalars(file, 'contact_reaction', reaction)
      call put_line(file, 'SCALARS node_label int 1')
      call put_line(file, 'LOOKUP_TABLE default')
      do i = 1, model%n_nodes
         call put_line(file, integer_text(model%node_label(i)))
      end do

      call put_line(file, 'CELL_DATA '//integer_text(model%n_elements))
      call write_scalars(file, 'axial_force', forces(1, :))
      call write_scalars(file, 'shear_force', forces(2, :))
      reals(1:model%n_elements) = 0.5_dp*(forces(3, :) + forces(4, :))
      call write_scalars(file, 'bending_moment', reals(1:model%n_elements))
      call write_scalars(file, 'bending_moment_start', forces(3, :))
      call write_scalars(file, 'bending_moment_end', forces(4, :))
      call put_line(file, 'SCALARS element_label int 1')
      call put_line(file, 'LOOKUP_TABLE default')
      do e = 1, model%n_elements
         call put_line(file, integer_text(model%element_label(e)))
      end do
   end subroutine write_legacy_vtk

   !> The XML file of one snapshot (VTKFile type PolyData, ASCII data arrays): the same lines and
   !> arrays as the legacy file, in VTK's order FieldData, Piece → PointData, CellData, Points, Lines.
   !> reaction (n_nodes) and forces (4, n_elements): the snapshot's; reals (at least 3 n_nodes and
   !> n_elements) and integers (2 n_elements): work space.
   subroutine write_xml_vtp(file, model, record, reaction, forces, reals, integers)
      type(text_file_t), intent(inout) :: file
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      real(dp), intent(in) :: reaction(:), forces(:, :)
      real(dp), intent(inout) :: reals(:)
      integer, intent(inout) :: integers(:)
      integer :: e, i

      call put_line(file, '<?xml version="1.0"?>')
      call put_line(file, '<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">')
      call put_line(file, '<PolyData>')
      call put_line(file, '<FieldData>')
      call write_xml_reals(file, 'lambda', 1, [record%lambda], field=.true.)
      call write_xml_integers(file, 'step', 'Int32', [record%step], field=.true.)
      call put_line(file, '</FieldData>')
      call put_line(file, '<Piece NumberOfPoints="'//integer_text(model%n_nodes)//'" NumberOfVerts="0" '// &
         'NumberOfLines="'//integer_text(model%n_elements)//'" NumberOfStrips="0" NumberOfPolys="0">')

      call put_line(file, '<PointData Vectors="displacement" Scalars="contact_reaction">')
      ! (ux, uy, 0) of every node, one after the other
      do i = 1, model%n_nodes
         reals(3*i - 2:3*i) = [record%displacement(1, i), record%displacement(2, i), 0.0_dp]
      end do
      call write_xml_reals(file, 'displacement', 3, reals(1:3*model%n_nodes))
      call write_xml_reals(file, 'rotation', 1, record%displacement(3, :))
      call write_xml_reals(file, 'contact_reaction', 1, reaction)
      call write_xml_integers(file, 'node_label', 'Int32', model%node_label)
      call put_line(file, '</PointData>')

      call put_line(file, '<CellData Scalars="bending_moment">')
      call write_xml_reals(file, 'axial_force', 1, forces(1, :))
      call write_xml_reals(file, 'shear_force', 1, forces(2, :))
      reals(1:model%n_elements) = 0.5_dp*(forces(3, :) + forces(4, :))
      call write_xml_reals(file, 'bending_moment', 1, reals(1:model%n_elements))
      call write_xml_reals(file, 'bending_moment_start', 1, forces(3, :))
      call write_xml_reals(file, 'bending_moment_end', 1, forces(4, :))
      call write_xml_integers(file, 'element_label', 'Int32', model%element_label)
      call put_line(file, '</CellData>')

      call put_line(file, '<Points>')
      do i = 1, model%n_nodes
         reals(3*i - 2:3*i) = [model%coordinates(1, i) + record%displacement(1, i), &
                               model%coordinates(2, i) + record%displacement(2, i), 0.0_dp]
      end do
      call write_xml_reals(file, 'points', 3, reals(1:3*model%n_nodes))
      call put_line(file, '</Points>')

      ! Lines as VTK stores cells: the point indices (from 0) of all lines one after the other, and
      ! the offset just past each line's last index.
      call put_line(file, '<Lines>')
      do e = 1, model%n_elements
         integers(2*e - 1:2*e) = model%connectivity(:, e) - 1
      end do
      call write_xml_integers(file, 'connectivity', 'Int32', integers(1:2*model%n_elements))
      do e = 1, model%n_elements
         integers(e) = 2*e
      end do
      call write_xml_integers(file, 'offsets', 'Int32', integers(1:model%n_elements))
      call put_line(file, '</Lines>')
      call put_line(file, '</Piece>')
      call put_line(file, '</PolyData>')
      call put_line(file, '</VTKFile>')
   end subroutine write_xml_vtp

   !> An XML DataArray of doubles, `components` to a tuple, one tuple a line. `field`: an array of the
   !> FieldData, which states its NumberOfTuples (see the module header).
   subroutine write_xml_reals(file, name, components, values, field)
      type(text_file_t), intent(inout) :: file
      character(len=*), intent(in) :: name
      integer, intent(in) :: components
      real(dp), intent(in) :: values(:)
      logical, intent(in), optional :: field
      character(len=:), allocatable :: line
      integer :: i, k
      call put_line(file, '<DataArray type="Float64" Name="'//name//'" NumberOfComponents="'// &
         integer_text(components)//'"'//tuples_attribute(size(values)/components, field)//' format="ascii">')
      do i = 1, size(values), components
         line = trim(format_number(values(i)))
         do k = i + 1, min(i + components - 1, size(values))
            line = line//' '//trim(format_number(values(k)))
         end do
         call put_line(file, line)
      end do
      call put_line(file, '</DataArray>')
   end subroutine write_xml_reals

   !> An XML DataArray of integers of VTK type `type_name`, one value a line; `field` as for
   !> write_xml_reals.
   subroutine write_xml_integers(file, name, type_name, values, field)
      type(text_file_t), intent(inout) :: file
      character(len=*), intent(in) :: name, type_name
      integer, intent(in) :: values(:)
      logical, intent(in), optional :: field
      integer :: i
      call put_line(file, '<DataArray type="'//type_name//'" Name="'//name//'"'// &
         tuples_attribute(size(values), field)//' format="ascii">')
      do i = 1, size(values)
         call put_line(file, integer_text(values(i)))
      end do
      call put_line(file, '</DataArray>')
   end subroutine write_xml_integers

   !> ` NumberOfTuples="n"` for an array of the FieldData (`field` present and true), else nothing.
   pure function tuples_attribute(tuples, field) result(attribute)
      integer, intent(in) :: tuples
      logical, intent(in), optional :: field
      character(len=:), allocatable :: attribute
      attribute = ''
      if (present(field)) then
         if (field) attribute = ' NumberOfTuples="'//integer_text(tuples)//'"'
      end if
   end function tuples_attribute

   !> One SCALARS array of doubles.
   subroutine write_scalars(file, name, values)
      type(text_file_t), intent(inout) :: file
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: values(:)
      integer :: i
      call put_line(file, 'SCALARS '//name//' double 1')
      call put_line(file, 'LOOKUP_TABLE default')
      do i = 1, size(values)
         call put_line(file, trim(format_number(values(i))))
      end do
   end subroutine write_scalars

   !> The ParaView collection `STEM.pvd` of the `.vtp` snapshots written (VTKFile type "Collection"),
   !> the step number as each one's timestep (see the module header).
   subroutine write_collection(series, results, error)
      type(vtk_series_t), intent(in) :: series
      type(result_directory_t), intent(inout) :: results
      type(error_t), allocatable, intent(out) :: error
      type(text_file_t) :: file
      character(len=:), allocatable :: name
      integer :: k
      name = series%stem//'.pvd'
      call add_result_file(results, name)
      call create_text_file(file, work_path(results, name), final_path(results, name), error)
      if (allocated(error)) return
      call put_line(file, '<?xml version="1.0"?>')
      call put_line(file, '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">')
      call put_line(file, '  <!-- uniarc: timestep is the step number; the load factor lambda is in each '// &
         'file''s field data -->')
      call put_line(file, '  <Collection>')
      do k = 1, series%count
         call put_line(file, '    <DataSet timestep="'//integer_text(series%steps(k))//'" group="" part="0" file="'// &
            xml_escaped(vtk_file_name(series%stem, series%steps(k), 'vtp'))//'"/>')
      end do
      call put_line(file, '  </Collection>')
      call put_line(file, '</VTKFile>')
      call close_text_file(file, error)
      if (allocated(error)) call discard_text_file(file)
   end subroutine write_collection

   !> Text as the value of an XML attribute: the five special characters as entities.
   pure function xml_escaped(text) result(escaped)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: escaped
      integer :: i
      escaped = ''
      do i = 1, len(text)
         select case (text(i:i))
         case ('&')
            escaped = escaped//'&amp;'
         case ('<')
            escaped = escaped//'&lt;'
         case ('>')
            escaped = escaped//'&gt;'
         case ('"')
            escaped = escaped//'&quot;'
         case ('''')
            escaped = escaped//'&apos;'
         case default
            escaped = escaped//text(i:i)
         end select
      end do
   end function xml_escaped

end module uniarc_vtk
