!> The buckling modes of `*OUTPUT, MODES`: `STEM.modes`, one block per bifurcation located on the path
!> (docs/contracts.md). The table's format is that of every table (uniarc_output): column names on
!> line 1, `#` provenance lines, then rows; integers as integers, other numbers in the files' ES format.
!> Columns `bifurcation kind step lambda node x0 y0 ux uy rz`: the bifurcation's number (1, 2, ... in
!> the order located), its kind as in STEM.crit (`bifurcation`, `unilateral_bifurcation`), where it
!> lies (the fractional step of STEM.crit), its λ, and per node its label, initial coordinates and the
!> mode (uniarc_path_branch, nodal_mode: largest nodal translation 1, largest component positive).
!> Blocks are separated by two blank lines (gnuplot's `index`, as STEM.shape).
!>
!> The rows are kept in memory and the file is written whole when the path ends (a bifurcation is
!> rare; a run that fails part-way writes the modes found before), in the run's work directory, moved
!> to its final name with the other files (uniarc_result_directory).
module uniarc_modes_output
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t
   use uniarc_strings, only: integer_to_string
   use uniarc_model, only: model_t
   use uniarc_text_file, only: text_file_t, create_text_file, put_line, close_text_file, discard_text_file
   use uniarc_result_directory, only: result_directory_t, work_path, final_path, add_result_file
   use uniarc_provenance, only: provenance_t, provenance_lines
   use uniarc_output, only: format_number
   implicit none
   private
   public :: modes_table_t, modes_header, add_mode, write_modes_file

   !> Column names of STEM.modes (line 1).
   character(len=*), parameter :: modes_header = 'bifurcation kind step lambda node x0 y0 ux uy rz'

   !> The blocks collected so far, as text lines.
   type :: line_t
      character(len=:), allocatable :: text
   end type line_t
   type :: modes_table_t
      integer :: count = 0                   !< blocks (bifurcations) collected
      type(line_t), allocatable :: lines(:)
   end type modes_table_t

contains

   !> Append the block of one bifurcation: its kind (as in STEM.crit), fractional step `position`, λ and
   !> nodal mode `mode` (dofs_per_node, n_nodes), dimensionless.
   subroutine add_mode(table, model, kind, position, lambda, mode)
      type(modes_table_t), intent(inout) :: table
      type(model_t), intent(in) :: model
      character(len=*), intent(in) :: kind
      real(dp), intent(in) :: position, lambda
      real(dp), intent(in) :: mode(:, :)
      character(len=:), allocatable :: head, line
      integer :: i, k
      if (.not. allocated(table%lines)) allocate (table%lines(0))
      table%count = table%count + 1
      head = integer_to_string(table%count)//' '//kind//' '//trim(format_number(position))//' '// &
             trim(format_number(lambda))
      do i = 1, model%n_nodes
         line = head//' '//integer_to_string(model%node_label(i))
         do k = 1, 2
            line = line//' '//trim(format_number(model%coordinates(k, i)))
         end do
         do k = 1, 3
            line = line//' '//trim(format_number(mode(k, i)))
         end do
         table%lines = [table%lines, line_t(line)]
      end do
      table%lines = [table%lines, line_t(''), line_t('')]
   end subroutine add_mode

   !> Write `STEM.modes` (stem `stem`) in the run's work directory: header, provenance, the blocks.
   !> Errors: those of the file (uniarc_text_file), the file then removed.
   subroutine write_modes_file(table, results, stem, provenance, error)
      type(modes_table_t), intent(in) :: table
      type(result_directory_t), intent(inout) :: results
      character(len=*), intent(in) :: stem
      type(provenance_t), intent(in) :: provenance
      type(error_t), allocatable, intent(out) :: error
      type(text_file_t) :: file
      character(len=:), allocatable :: comments(:), name
      integer :: i
      name = stem//'.modes'
      call add_result_file(results, name)
      call create_text_file(file, work_path(results, name), final_path(results, name), error)
      if (allocated(error)) return
      call put_line(file, modes_header)
      comments = provenance_lines(provenance)
      do i = 1, size(comments)
         call put_line(file, trim(comments(i)))
      end do
      if (allocated(table%lines)) then
         do i = 1, size(table%lines)
            call put_line(file, table%lines(i)%text)
         end do
      end if
      call close_text_file(file, error)
      if (allocated(error)) call discard_text_file(file)
   end subroutine write_modes_file

end module uniarc_modes_output
