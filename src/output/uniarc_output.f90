!> Result files of docs/contracts.md: the path file `STEM.path`, critical points `STEM.crit`, shapes `STEM.shape`.
!>
!> The files are written in the run's work directory and moved to their final names by the run's
!> commit (uniarc_result_directory), so a crash never leaves a half file under a final name. Rows are
!> written whole and flushed, so an analysis that fails part-way keeps every converged step
!> (docs/contracts.md: exit code 1, complete rows only). Every write, flush and close is checked
!> (uniarc_text_file): a failure is returned as an error naming the file and the system's words.
module uniarc_output
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_model, only: model_t, tracked_values
   use uniarc_text_file, only: text_file_t, create_text_file, put_line, flush_text_file, close_text_file, &
                               discard_text_file
   use uniarc_result_directory, only: result_directory_t, work_path, final_path, add_result_file
   implicit none
   private
   public :: step_record_t, output_files_t
   public :: open_outputs, write_path_row, write_crit_row, write_shape, close_outputs, discard_outputs
   public :: path_header, format_number, nodal_reactions

   !> What a converged step reports (one row of the path file).
   type :: step_record_t
      integer :: step = 0
      real(dp) :: lambda = 0.0_dp
      real(dp), allocatable :: displacement(:, :)   !< (3, n_nodes) total nodal displacements
      real(dp), allocatable :: reactions(:)         !< (n_contacts) reaction of every contact candidate
      integer :: n_contact = 0            !< candidates in contact
      integer :: contact_regions = 0      !< number of contiguous contact regions
      real(dp) :: s_contact(2) = 0.0_dp   !< ends of the first contact region
      real(dp) :: reaction_max = 0.0_dp
      real(dp) :: reaction_sum = 0.0_dp
      real(dp) :: lcp_residual = 0.0_dp   !< complementarity residual, relative to the scale
      integer :: lcp_pivots = 0
      integer :: iterations = 0
      integer :: neg_pivots = 0
   end type step_record_t

   !> The result files of one run.
   type :: output_files_t
      type(text_file_t) :: path, crit, shape
   end type output_files_t

   !> Number format of every real: ES with 13 significant digits (docs/contracts.md).
   character(len=*), parameter :: number_format = '(es21.12e3)'

contains

   !> Start `STEM.path|crit|shape` in the run's work directory and write their header lines.
   subroutine open_outputs(model, results, files, error)
      type(model_t), intent(in) :: model
      type(result_directory_t), intent(inout) :: results
      type(output_files_t), intent(out) :: files
      type(error_t), allocatable, intent(out) :: error
      call open_table(results, files%path, results%stem//'.path', path_header(model), error)
      if (allocated(error)) return
      call open_table(results, files%crit, results%stem//'.crit', '# kind step lambda'//track_names(model), &
                      error)
      if (allocated(error)) return
      call open_table(results, files%shape, results%stem//'.shape', &
                      '# step lambda node x0 y0 ux uy rz x y reaction', error)
   end subroutine open_outputs

   !> Header line of the path file: `# step lambda <tracks> <contact and solver columns>`.
   pure function path_header(model) result(header)
      type(model_t), intent(in) :: model
      character(len=:), allocatable :: header
      header = '# step lambda'//track_names(model)// &
               ' n_contact contact_regions s_contact_1 s_contact_2 reaction_max reaction_sum'// &
               ' lcp_residual lcp_pivots iterations neg_pivots'
   end function path_header

   pure function track_names(model) result(names)
      type(model_t), intent(in) :: model
      character(len=:), allocatable :: names
      integer :: i
      names = ''
      if (.not. allocated(model%tracks)) return
      do i = 1, size(model%tracks)
         names = names//' '//model%tracks(i)%name
      end do
   end function track_names

   !> One row of the path file, flushed.
   subroutine write_path_row(files, model, record, error)
      type(output_files_t), intent(inout) :: files
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: values(:)
      values = [real(record%step, dp), record%lambda, tracked_values(model, record%displacement), &
                real(record%n_contact, dp), real(record%contact_regions, dp), record%s_contact, &
                record%reaction_max, record%reaction_sum, record%lcp_residual, &
                real(record%lcp_pivots, dp), real(record%iterations, dp), real(record%neg_pivots, dp)]
      call write_numbers(files%path, '', values, error)
   end subroutine write_path_row

   !> One event of the critical-point file: kind, where it lies (a step number, fractional when the
   !> event was located between two steps), λ and the tracked values at the event. Flushed.
   subroutine write_crit_row(files, kind, position, lambda, tracked, error)
      type(output_files_t), intent(inout) :: files
      character(len=*), intent(in) :: kind
      real(dp), intent(in) :: position
      real(dp), intent(in) :: lambda
      real(dp), intent(in) :: tracked(:)
      type(error_t), allocatable, intent(out) :: error
      call write_numbers(files%crit, kind, [position, lambda, tracked], error)
   end subroutine write_crit_row

   !> A snapshot of the deformed shape: one line per node (the last column the sum of the contact
   !> reactions at the node), snapshots separated by two blank lines (gnuplot's `index`). Flushed.
   subroutine write_shape(files, model, record, error)
      type(output_files_t), intent(inout) :: files
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal_reaction(:)
      character(len=:), allocatable :: line
      integer :: i, k
      ! allocate with source=, not an assignment: under -fcheck=bounds gfortran 12 compares the bounds of
      ! the unallocated array before allocating it on assignment (valgrind: uninitialised values).
      allocate (nodal_reaction, source=nodal_reactions(model, record%reactions))
      do i = 1, model%n_nodes
         line = integer_to_string(record%step)//' '//trim(format_number(record%lambda))//' '// &
                integer_to_string(model%node_label(i))
         do k = 1, 2
            line = line//' '//trim(format_number(model%coordinates(k, i)))
         end do
         do k = 1, 3
            line = line//' '//trim(format_number(record%displacement(k, i)))
         end do
         do k = 1, 2
            line = line//' '//trim(format_number(model%coordinates(k, i) + record%displacement(k, i)))
         end do
         call put_line(files%shape, line//' '//trim(format_number(nodal_reaction(i))))
      end do
      call put_line(files%shape, '')
      call put_line(files%shape, '')
      call flush_text_file(files%shape, error)
   end subroutine write_shape

   !> Sum of the contact reactions at each node (a node may carry candidates of several groups).
   pure function nodal_reactions(model, reactions) result(nodal)
      type(model_t), intent(in) :: model
      real(dp), allocatable, intent(in) :: reactions(:)
      real(dp) :: nodal(model%n_nodes)
      integer :: c
      nodal = 0.0_dp
      if (.not. (allocated(reactions) .and. allocated(model%contacts))) return
      do c = 1, min(size(reactions), size(model%contacts))
         nodal(model%contacts(c)%node) = nodal(model%contacts(c)%node) + reactions(c)
      end do
   end function nodal_reactions

   !> Close every file; the first failure (of a close, or of a write not yet reported) as an error.
   !> Every file is closed either way.
   subroutine close_outputs(files, error)
      type(output_files_t), intent(inout) :: files
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: crit_error, shape_error
      call close_text_file(files%path, error)
      call close_text_file(files%crit, crit_error)
      call close_text_file(files%shape, shape_error)
      if (.not. allocated(error) .and. allocated(crit_error)) call move_alloc(crit_error, error)
      if (.not. allocated(error) .and. allocated(shape_error)) call move_alloc(shape_error, error)
   end subroutine close_outputs

   !> Close and remove every file (after a failure that is reported already).
   subroutine discard_outputs(files)
      type(output_files_t), intent(inout) :: files
      call discard_text_file(files%path)
      call discard_text_file(files%crit)
      call discard_text_file(files%shape)
   end subroutine discard_outputs

   !> A real as text in the files' number format, without surrounding blanks.
   pure function format_number(x) result(text)
      real(dp), intent(in) :: x
      character(len=:), allocatable :: text
      ! x + 0 turns a negative zero (a product of zero and a negative number) into +0 (IEEE 754
      ! round-to-nearest), so that no column shows -0.000000000000E+000.
      text = real_to_string(x + 0.0_dp, number_format)
   end function format_number

   !> Start the table `name` in the work directory with its header line.
   subroutine open_table(results, table, name, header, error)
      type(result_directory_t), intent(inout) :: results
      type(text_file_t), intent(out) :: table
      character(len=*), intent(in) :: name, header
      type(error_t), allocatable, intent(out) :: error
      call add_result_file(results, name)
      call create_text_file(table, work_path(results, name), final_path(results, name), error)
      if (allocated(error)) return
      call put_line(table, header)
   end subroutine open_table

   !> One row: `label` (if any) and the numbers, separated by single blanks; flushed.
   subroutine write_numbers(table, label, values, error)
      type(text_file_t), intent(inout) :: table
      character(len=*), intent(in) :: label
      real(dp), intent(in) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: line
      integer :: i
      line = ''
      if (len(label) > 0) line = label//' '
      do i = 1, size(values)
         line = line//trim(format_number(values(i)))
         if (i < size(values)) line = line//' '
      end do
      call put_line(table, line)
      call flush_text_file(table, error)
   end subroutine write_numbers

end module uniarc_output
