!> The buckling modes of `*OUTPUT, MODES`: `STEM.modes`, one block per bifurcation located on the path
!> (docs/contracts.md). The table's format is that of every table (uniarc_output): column names on
!> line 1, `#` provenance lines, then rows; integers as integers, other numbers in the files' ES format.
!> Columns `bifurcation kind step lambda node x0 y0 ux uy rz`: the bifurcation's number (1, 2, ... in
!> the order located), its kind as in STEM.crit (`bifurcation`, `unilateral_bifurcation`), where it
!> lies (the fractional step of STEM.crit), its λ, and per node its label, initial coordinates and the
!> mode (uniarc_path_branch, nodal_mode: largest nodal translation 1, first
!> significant translation positive).
!> Blocks are separated by two blank lines (gnuplot's `index`, as STEM.shape).
!>
!> With `*OUTPUT, VTK` each mode is also `STEM_mode_N.vtp` (N the bifurcation's number, two digits at
!> least): VTK PolyData in the XML format of uniarc_vtk's snapshots, on the undeformed geometry x0,
!> with the point data `mode` (ux, uy, 0) and `mode_rotation`, `node_label`, and the field data `lambda`
!> and `bifurcation`; ParaView's Warp By Vector on `mode` draws the buckled shape. Not in STEM.pvd
!> (the series of the path's snapshots): a mode is a shape, not a state of the path.
!>
!> The modes are kept in memory and the files are written whole when the path ends (a bifurcation is
!> rare; a run that fails part-way writes the modes found before), in the run's work directory, moved
!> to their final names with the other files (uniarc_result_directory).
module uniarc_modes_output
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: integer_to_string
   use uniarc_model, only: model_t
   use uniarc_text_file, only: text_file_t, create_text_file, put_line, close_text_file, discard_text_file
   use uniarc_result_directory, only: result_directory_t, work_path, final_path, add_result_file
   use uniarc_provenance, only: provenance_t, provenance_lines
   use uniarc_output, only: format_number
   use uniarc_vtk, only: write_xml_reals, write_xml_integers
   implicit none
   private
   public :: modes_table_t, modes_header, add_mode, write_modes_file

   !> Column names of STEM.modes (line 1).
   character(len=*), parameter :: modes_header = 'bifurcation kind step lambda node x0 y0 ux uy rz'

   !> One bifurcation's mode.
   type :: mode_block_t
      character(len=:), allocatable :: kind   !< as in STEM.crit
      real(dp) :: position = 0.0_dp           !< fractional step
      real(dp) :: lambda = 0.0_dp
      real(dp), allocatable :: mode(:, :)     !< (dofs_per_node, n_nodes), dimensionless
   end type mode_block_t
   !> The modes collected so far.
   type :: modes_table_t
      type(mode_block_t), allocatable :: blocks(:)
   end type modes_table_t

contains

   !> Append the block of one bifurcation: its kind (as in STEM.crit), fractional step `position`, λ and
   !> nodal mode `mode` (dofs_per_node, n_nodes), dimensionless; `mode` is moved into the table (left
   !> unallocated). The blocks kept are moved, not copied. Errors: the grown list refused by the system
   !> (error_analysis, out of memory, uniarc_memory); the table is then as it was.
   subroutine add_mode(table, kind, position, lambda, mode, error)
      type(modes_table_t), intent(inout) :: table
      character(len=*), intent(in) :: kind
      real(dp), intent(in) :: position, lambda
      real(dp), allocatable, intent(inout) :: mode(:, :)
      type(error_t), allocatable, intent(out) :: error
      type(mode_block_t), allocatable :: grown(:)
      integer :: b, n, status
      n = 0
      if (allocated(table%blocks)) n = size(table%blocks)
      allocate (grown(n + 1), stat=status)
      call allocation_failure(status, 'the list of buckling modes', real(storage_size(grown)/8, dp)*(n + 1), &
                              error_analysis, error)
      if (allocated(error)) return
      do b = 1, n
         call move_alloc(table%blocks(b)%kind, grown(b)%kind)
         grown(b)%position = table%blocks(b)%position
         grown(b)%lambda = table%blocks(b)%lambda
         call move_alloc(table%blocks(b)%mode, grown(b)%mode)
      end do
      grown(n + 1)%kind = kind
      grown(n + 1)%position = position
      grown(n + 1)%lambda = lambda
      call move_alloc(mode, grown(n + 1)%mode)
      call move_alloc(grown, table%blocks)
   end subroutine add_mode

   !> Write `STEM.modes` (stem `stem`) in the run's work directory — header, provenance, the blocks —
   !> and with `vtk` each mode as `STEM_mode_N.vtp`.
   !> Errors: those of the files (uniarc_text_file), the file then removed.
   subroutine write_modes_file(table, results, stem, provenance, model, vtk, error)
      type(modes_table_t), intent(in) :: table
      type(result_directory_t), intent(inout) :: results
      character(len=*), intent(in) :: stem
      type(provenance_t), intent(in) :: provenance
      type(model_t), intent(in) :: model
      logical, intent(in) :: vtk
      type(error_t), allocatable, intent(out) :: error
      type(text_file_t) :: file
      character(len=:), allocatable :: comments(:), name, head, line
      integer :: b, i, k
      name = stem//'.modes'
      call add_result_file(results, name)
      call create_text_file(file, work_path(results, name), final_path(results, name), error)
      if (allocated(error)) return
      call put_line(file, modes_header)
      comments = provenance_lines(provenance)
      do i = 1, size(comments)
         call put_line(file, trim(comments(i)))
      end do
      if (allocated(table%blocks)) then
         do b = 1, size(table%blocks)
            associate (block => table%blocks(b))
               head = integer_to_string(b)//' '//block%kind//' '//trim(format_number(block%position))//' '// &
                      trim(format_number(block%lambda))
               do i = 1, model%n_nodes
                  line = head//' '//integer_to_string(model%node_label(i))
                  do k = 1, 2
                     line = line//' '//trim(format_number(model%coordinates(k, i)))
                  end do
                  do k = 1, 3
                     line = line//' '//trim(format_number(block%mode(k, i)))
                  end do
                  call put_line(file, line)
               end do
               call put_line(file, '')
               call put_line(file, '')
            end associate
         end do
      end if
      call close_text_file(file, error)
      if (allocated(error)) then
         call discard_text_file(file)
         return
      end if
      if (.not. vtk .or. .not. allocated(table%blocks)) return
      do b = 1, size(table%blocks)
         call write_mode_vtp(results, stem, b, model, table%blocks(b), error)
         if (allocated(error)) return
      end do
   end subroutine write_modes_file

   !> `STEM_mode_N.vtp`: the mode of bifurcation `number` on the undeformed geometry (module header).
   subroutine write_mode_vtp(results, stem, number, model, block, error)
      type(result_directory_t), intent(inout) :: results
      character(len=*), intent(in) :: stem
      integer, intent(in) :: number
      type(model_t), intent(in) :: model
      type(mode_block_t), intent(in) :: block
      type(error_t), allocatable, intent(out) :: error
      type(text_file_t) :: file
      character(len=:), allocatable :: name
      character(len=12) :: digits
      real(dp), allocatable :: reals(:)
      integer, allocatable :: integers(:)
      integer :: e, i, status
      write (digits, '(i2.2)') number
      if (number > 99) write (digits, '(i0)') number
      name = stem//'_mode_'//trim(digits)//'.vtp'
      ! the file's arrays in work space allocated with stat= first (no temporary of the model's length)
      allocate (reals(3*model%n_nodes), integers(2*model%n_elements), stat=status)
      call allocation_failure(status, 'the arrays of the mode file '//name, &
                              24.0_dp*model%n_nodes + 8.0_dp*model%n_elements, error_analysis, error)
      if (allocated(error)) return
      call add_result_file(results, name)
      call create_text_file(file, work_path(results, name), final_path(results, name), error)
      if (allocated(error)) return
      call put_line(file, '<?xml version="1.0"?>')
      call put_line(file, '<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">')
      call put_line(file, '<PolyData>')
      call put_line(file, '<FieldData>')
      call write_xml_reals(file, 'lambda', 1, [block%lambda], field=.true.)
      call write_xml_integers(file, 'bifurcation', 'Int32', [number], field=.true.)
      call put_line(file, '</FieldData>')
      call put_line(file, '<Piece NumberOfPoints="'//integer_to_string(model%n_nodes)//'" NumberOfVerts="0" '// &
                    'NumberOfLines="'//integer_to_string(model%n_elements)//'" NumberOfStrips="0" NumberOfPolys="0">')
      call put_line(file, '<PointData Vectors="mode">')
      do i = 1, model%n_nodes
         reals(3*i - 2:3*i) = [block%mode(1, i), block%mode(2, i), 0.0_dp]
      end do
      call write_xml_reals(file, 'mode', 3, reals)
      call write_xml_reals(file, 'mode_rotation', 1, block%mode(3, :))
      call write_xml_integers(file, 'node_label', 'Int32', model%node_label)
      call put_line(file, '</PointData>')
      call put_line(file, '<Points>')
      do i = 1, model%n_nodes
         reals(3*i - 2:3*i) = [model%coordinates(1, i), model%coordinates(2, i), 0.0_dp]
      end do
      call write_xml_reals(file, 'points', 3, reals)
      call put_line(file, '</Points>')
      call put_line(file, '<Lines>')
      do e = 1, model%n_elements
         integers(2*e - 1:2*e) = model%connectivity(:, e) - 1
      end do
      call write_xml_integers(file, 'connectivity', 'Int32', integers)
      do e = 1, model%n_elements
         integers(e) = 2*e
      end do
      call write_xml_integers(file, 'offsets', 'Int32', integers(1:model%n_elements))
      call put_line(file, '</Lines>')
      call put_line(file, '</Piece>')
      call put_line(file, '</PolyData>')
      call put_line(file, '</VTKFile>')
      call close_text_file(file, error)
      if (allocated(error)) call discard_text_file(file)
   end subroutine write_mode_vtp

end module uniarc_modes_output
