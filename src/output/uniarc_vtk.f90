!> ParaView output of `*OUTPUT, VTK`: each snapshot as a legacy VTK file `STEM_NNNN.vtk` and as the
!> same grid in VTK's XML format, `STEM_NNNN.vtu`, and the collection `STEM.pvd` that lists the
!> `.vtu` files with their time values. Both are needed: ParaView's pvd reader (vtkXMLCollectionReader)
!> builds its readers from the XML extensions only (vtu, vtp, vti, ...), so a pvd cannot list legacy
!> files, while the legacy files are what most other tools read.
!>
!> A snapshot is an unstructured grid of VTK_LINE cells (one per element) on the deformed geometry
!> x0 + u, with z = 0. Point data: `displacement` (u_x, u_y, 0), `rotation` θ_z, `contact_reaction`
!> (the sum of the reactions of the node's contact candidates) and `node_label`; cell data:
!> `axial_force` N (tension positive), `bending_moment_start`, `bending_moment_end` and their mean
!> `bending_moment`, and `element_label`. Field data: `lambda` and `step`. The formats are the
!> "simple legacy" and the "XML" formats of "VTK File Formats" (Kitware, The VTK User's Guide, 11th ed.,
!> 2010), the XML one with ASCII data arrays.
!>
!> The element forces are the element layer's (uniarc_element: axial force and end moments of any
!> element kind); bending moments use the beam convention M = EI κ, κ = dθ/ds along node 1 → node 2:
!> positive when the element bends towards its left normal (uniarc_transformation,
!> transform_end_forces). Between the ends the moment of the element's cubic field is linear, so the
!> mean is the moment at mid-element (zero for a truss). Like every moment of a
!> displacement-based element it leaves out the fixed-end moments of a load distributed on the
!> element itself, a difference that vanishes as the mesh is refined.
!>
!> The pvd's `timestep` is λ when λ increases strictly over the snapshots (ParaView sorts and indexes
!> by timestep); otherwise (snap-through under arc length, unloading, a negative increment) it is the
!> step number, and the file says so in a comment. λ is in every snapshot's field data either way.
!>
!> Every file is written in the run's work directory and moved to its final name with the other result
!> files when the run ends (uniarc_result_directory): a crash never leaves a half file under its final
!> name. Every write and close is checked (uniarc_text_file).
module uniarc_vtk
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t
   use uniarc_text_file, only: text_file_t, create_text_file, put_line, close_text_file, discard_text_file
   use uniarc_result_directory, only: result_directory_t, work_path, final_path, add_result_file
   use uniarc_strings, only: integer_text => integer_to_string
   use uniarc_model, only: model_t
   use uniarc_element, only: element_response_t, element_response, element_displacements, analysis_transformation
   use uniarc_output, only: step_record_t, format_number, nodal_reactions
   implicit none
   private
   public :: vtk_series_t, open_vtk_series, vtk_snapshot_due, write_vtk_snapshot, finish_vtk_series
   public :: vtk_file_name, element_moments

   !> The two files of a snapshot.
   integer, parameter :: legacy_format = 1, xml_format = 2

   !> The snapshots of one run: where they go and what has been written.
   type :: vtk_series_t
      logical :: active = .false.                  !< the deck asked for VTK output
      character(len=:), allocatable :: stem
      integer :: every = 1                         !< snapshot interval in steps
      integer :: count = 0                         !< snapshots written
      integer, allocatable :: steps(:)             !< (count) step of each snapshot
      real(dp), allocatable :: lambdas(:)          !< (count) λ of each snapshot
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
      allocate (series%steps(0), series%lambdas(0))
   end subroutine open_vtk_series

   !> Whether step `step` is one of the series' regular snapshots (every n-th step, step 0 included).
   pure logical function vtk_snapshot_due(series, step)
      type(vtk_series_t), intent(in) :: series
      integer, intent(in) :: step
      vtk_snapshot_due = series%active .and. mod(step, series%every) == 0
   end function vtk_snapshot_due

   !> Write the snapshot of `record` as `STEM_NNNN.vtk` and `STEM_NNNN.vtu` (NNNN the step). Does
   !> nothing when the series is inactive or the step is already its last snapshot.
   subroutine write_vtk_snapshot(series, results, model, record, error)
      type(vtk_series_t), intent(inout) :: series
      type(result_directory_t), intent(inout) :: results
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      if (.not. series%active) return
      if (series%count > 0) then
         if (series%steps(series%count) == record%step) return
      end if
      name = vtk_file_name(series%stem, record%step)
      call write_snapshot_file(results, name, legacy_format, model, record, series%stem, error)
      if (allocated(error)) return
      call write_snapshot_file(results, xml_twin(name), xml_format, model, record, series%stem, error)
      if (allocated(error)) return
      series%count = series%count + 1
      series%steps = [series%steps, record%step]
      series%lambdas = [series%lambdas, record%lambda]
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
      call add_result_file(results, name)
      call create_text_file(file, work_path(results, name), final_path(results, name), error)
      if (allocated(error)) return
      select case (file_format)
      case (legacy_format)
         call write_legacy_vtk(file, model, record, stem)
      case default
         call write_xml_vtu(file, model, record)
      end select
      call close_text_file(file, error)
      if (allocated(error)) call discard_text_file(file)
   end subroutine write_snapshot_file

   !> The `.vtu` name of a `.vtk` snapshot.
   pure function xml_twin(name) result(twin)
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: twin
      twin = name(1:len(name) - 1)//'u'
   end function xml_twin

   !> Name of the snapshot of step `step`: `STEM_NNNN.vtk`, at least four digits.
   pure function vtk_file_name(stem, step) result(name)
      character(len=*), intent(in) :: stem
      integer, intent(in) :: step
      character(len=:), allocatable :: name
      character(len=12) :: digits
      write (digits, '(i4.4)') step
      if (step > 9999 .or. step < 0) write (digits, '(i0)') step
      name = stem//'_'//trim(digits)//'.vtk'
   end function vtk_file_name


   !> Axial force and bending moments at both ends of every element: rows (N, M_start, M_end), shape
   !> (3, n_elements), from the element layer (uniarc_element) at nodal displacements (3, n_nodes).
   !>
   !> The transformation is the analysis' (analysis_transformation): a nonlinear analysis reports the
   !> corotational forces of the deformed element, a linear one the small-displacement forces Kb B0 u_e
   !> on the initial chord, which are the forces its solution is in equilibrium with. The moments are
   !> in the beam convention M = EI κ (see the module header).
   pure function element_moments(model, displacement) result(forces)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: displacement(:, :)
      real(dp) :: forces(3, model%n_elements)
      type(element_response_t) :: response
      integer :: e, transformation
      transformation = analysis_transformation(model%analysis%kind)
      do e = 1, model%n_elements
         call element_response(model, e, element_displacements(model, e, displacement), transformation, response)
         forces(1, e) = response%axial_force
         forces(2:3, e) = response%end_moments
      end do
   end function element_moments

   !> The legacy VTK file of one snapshot (ASCII, UNSTRUCTURED_GRID, VTK_LINE cells).
   subroutine write_legacy_vtk(file, model, record, stem)
      type(text_file_t), intent(inout) :: file
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      character(len=*), intent(in) :: stem
      real(dp), allocatable :: reaction(:), forces(:, :)
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
      call put_line(file, 'DATASET UNSTRUCTURED_GRID')
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
      ! A VTK_LINE cell lists its two points, numbered from 0.
      call put_line(file, 'CELLS '//integer_text(model%n_elements)//' '//integer_text(3*model%n_elements))
      do e = 1, model%n_elements
         call put_line(file, '2 '//integer_text(model%connectivity(1, e) - 1)//' '// &
            integer_text(model%connectivity(2, e) - 1))
      end do
      call put_line(file, 'CELL_TYPES '//integer_text(model%n_elements))
      do e = 1, model%n_elements
         call put_line(file, '3')
      end do

      reaction = nodal_reactions(model, record%reactions)
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

      forces = element_moments(model, record%displacement)
      call put_line(file, 'CELL_DATA '//integer_text(model%n_elements))
      call write_scalars(file, 'axial_force', forces(1, :))
      call write_scalars(file, 'bending_moment', 0.5_dp*(forces(2, :) + forces(3, :)))
      call write_scalars(file, 'bending_moment_start', forces(2, :))
      call write_scalars(file, 'bending_moment_end', forces(3, :))
      call put_line(file, 'SCALARS element_label int 1')
      call put_line(file, 'LOOKUP_TABLE default')
      do e = 1, model%n_elements
         call put_line(file, integer_text(model%element_label(e)))
      end do
   end subroutine write_legacy_vtk

   !> The XML file of one snapshot (VTKFile type UnstructuredGrid, ASCII data arrays): the same
   !> grid and arrays as the legacy file, in VTK's order Piece → PointData, CellData, Points, Cells.
   subroutine write_xml_vtu(file, model, record)
      type(text_file_t), intent(inout) :: file
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      real(dp), allocatable :: forces(:, :), deformed(:, :), vectors(:, :)
      integer :: e

      call put_line(file, '<?xml version="1.0"?>')
      call put_line(file, '<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">')
      call put_line(file, '<UnstructuredGrid>')
      call put_line(file, '<FieldData>')
      call write_xml_reals(file, 'lambda', 1, [record%lambda])
      call write_xml_integers(file, 'step', 'Int32', [record%step])
      call put_line(file, '</FieldData>')
      call put_line(file, '<Piece NumberOfPoints="'//integer_text(model%n_nodes)//'" NumberOfCells="'// &
         integer_text(model%n_elements)//'">')

      call put_line(file, '<PointData Vectors="displacement" Scalars="contact_reaction">')
      allocate (vectors(3, model%n_nodes), source=0.0_dp)
      vectors(1:2, :) = record%displacement(1:2, :)
      call write_xml_reals(file, 'displacement', 3, reshape(vectors, [3*model%n_nodes]))
      call write_xml_reals(file, 'rotation', 1, record%displacement(3, :))
      call write_xml_reals(file, 'contact_reaction', 1, nodal_reactions(model, record%reactions))
      call write_xml_integers(file, 'node_label', 'Int32', model%node_label)
      call put_line(file, '</PointData>')

      forces = element_moments(model, record%displacement)
      call put_line(file, '<CellData Scalars="bending_moment">')
      call write_xml_reals(file, 'axial_force', 1, forces(1, :))
      call write_xml_reals(file, 'bending_moment', 1, 0.5_dp*(forces(2, :) + forces(3, :)))
      call write_xml_reals(file, 'bending_moment_start', 1, forces(2, :))
      call write_xml_reals(file, 'bending_moment_end', 1, forces(3, :))
      call write_xml_integers(file, 'element_label', 'Int32', model%element_label)
      call put_line(file, '</CellData>')

      call put_line(file, '<Points>')
      allocate (deformed(3, model%n_nodes), source=0.0_dp)
      deformed(1:2, :) = model%coordinates + record%displacement(1:2, :)
      call write_xml_reals(file, 'points', 3, reshape(deformed, [3*model%n_nodes]))
      call put_line(file, '</Points>')

      ! Cells as VTK stores them: the point indices (from 0) of all cells one after the other, the
      ! offset just past each cell's last index, and the cell types (3, VTK_LINE).
      call put_line(file, '<Cells>')
      call write_xml_integers(file, 'connectivity', 'Int32', reshape(model%connectivity - 1, [2*model%n_elements]))
      call write_xml_integers(file, 'offsets', 'Int32', [(2*e, e=1, model%n_elements)])
      call write_xml_integers(file, 'types', 'UInt8', [(3, e=1, model%n_elements)])
      call put_line(file, '</Cells>')
      call put_line(file, '</Piece>')
      call put_line(file, '</UnstructuredGrid>')
      call put_line(file, '</VTKFile>')
   end subroutine write_xml_vtu

   !> An XML DataArray of doubles, `components` to a tuple, one tuple a line.
   subroutine write_xml_reals(file, name, components, values)
      type(text_file_t), intent(inout) :: file
      character(len=*), intent(in) :: name
      integer, intent(in) :: components
      real(dp), intent(in) :: values(:)
      character(len=:), allocatable :: line
      integer :: i, k
      call put_line(file, '<DataArray type="Float64" Name="'//name//'" NumberOfComponents="'// &
         integer_text(components)//'" format="ascii">')
      do i = 1, size(values), components
         line = trim(format_number(values(i)))
         do k = i + 1, min(i + components - 1, size(values))
            line = line//' '//trim(format_number(values(k)))
         end do
         call put_line(file, line)
      end do
      call put_line(file, '</DataArray>')
   end subroutine write_xml_reals

   !> An XML DataArray of integers of VTK type `type_name`, one value a line.
   subroutine write_xml_integers(file, name, type_name, values)
      type(text_file_t), intent(inout) :: file
      character(len=*), intent(in) :: name, type_name
      integer, intent(in) :: values(:)
      integer :: i
      call put_line(file, '<DataArray type="'//type_name//'" Name="'//name//'" format="ascii">')
      do i = 1, size(values)
         call put_line(file, integer_text(values(i)))
      end do
      call put_line(file, '</DataArray>')
   end subroutine write_xml_integers

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

   !> The ParaView collection `STEM.pvd` of the snapshots written (VTKFile type "Collection").
   subroutine write_collection(series, results, error)
      type(vtk_series_t), intent(in) :: series
      type(result_directory_t), intent(inout) :: results
      type(error_t), allocatable, intent(out) :: error
      type(text_file_t) :: file
      character(len=:), allocatable :: name
      integer :: k
      logical :: by_lambda
      real(dp) :: time
      name = series%stem//'.pvd'
      by_lambda = strictly_increasing(series%lambdas)
      call add_result_file(results, name)
      call create_text_file(file, work_path(results, name), final_path(results, name), error)
      if (allocated(error)) return
      call put_line(file, '<?xml version="1.0"?>')
      call put_line(file, '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">')
      if (by_lambda) then
         call put_line(file, '  <!-- uniarc: timestep is the load factor lambda -->')
      else
         call put_line(file, '  <!-- uniarc: timestep is the step number, as lambda does not increase '// &
            'along this path; lambda is in each file''s field data -->')
      end if
      call put_line(file, '  <Collection>')
      do k = 1, series%count
         if (by_lambda) then
            time = series%lambdas(k)
         else
            time = real(series%steps(k), dp)
         end if
         call put_line(file, '    <DataSet timestep="'//trim(format_number(time))//'" group="" part="0" file="'// &
            xml_escaped(xml_twin(vtk_file_name(series%stem, series%steps(k))))//'"/>')
      end do
      call put_line(file, '  </Collection>')
      call put_line(file, '</VTKFile>')
      call close_text_file(file, error)
      if (allocated(error)) call discard_text_file(file)
   end subroutine write_collection

   pure logical function strictly_increasing(values)
      real(dp), intent(in) :: values(:)
      integer :: k
      strictly_increasing = .true.
      do k = 2, size(values)
         if (.not. values(k) > values(k - 1)) then
            strictly_increasing = .false.
            return
         end if
      end do
   end function strictly_increasing

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
