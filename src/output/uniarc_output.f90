!> Result files of docs/contracts.md: the path file `STEM.path`, critical points `STEM.crit`, shapes `STEM.shape`.
!>
!> Each file is written under a temporary name (`NAME.part`) and renamed when the run ends, so a crash
!> never leaves a half file under the final name. Rows are written whole and flushed, so an analysis
!> that fails part-way keeps every converged step (docs/contracts.md: exit code 1, complete rows only).
module uniarc_output
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_foreign, only: rename_file, make_directory
   use uniarc_model, only: model_t, tracked_values
   implicit none
   private
   public :: step_record_t, output_files_t
   public :: open_outputs, write_path_row, write_crit_row, write_shape, commit_outputs
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

   !> One table file being written.
   type :: table_file_t
      character(len=:), allocatable :: final_path
      character(len=:), allocatable :: part_path
      integer :: unit = 0
      logical :: is_open = .false.
   end type table_file_t

   !> The result files of one run.
   type :: output_files_t
      type(table_file_t) :: path, crit, shape
   end type output_files_t

   !> Number format of every real: ES with 13 significant digits (docs/contracts.md).
   character(len=*), parameter :: number_format = '(es21.12e3)'

contains

   !> Open `DIRECTORY/STEM.path|crit|shape` (as .part files) and write their header lines.
   subroutine open_outputs(model, directory, stem, files, error)
      type(model_t), intent(in) :: model
      character(len=*), intent(in) :: directory, stem
      type(output_files_t), intent(out) :: files
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: base
      call make_directory(directory, error)
      if (allocated(error)) return
      base = directory//'/'//stem
      call open_table(files%path, base//'.path', path_header(model), error)
      if (allocated(error)) return
      call open_table(files%crit, base//'.crit', '# kind step lambda'//track_names(model), error)
      if (allocated(error)) return
      call open_table(files%shape, base//'.shape', &
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

   !> One row of the path file.
   subroutine write_path_row(files, model, record)
      type(output_files_t), intent(inout) :: files
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      real(dp), allocatable :: values(:)
      values = [real(record%step, dp), record%lambda, tracked_values(model, record%displacement), &
                real(record%n_contact, dp), real(record%contact_regions, dp), record%s_contact, &
                record%reaction_max, record%reaction_sum, record%lcp_residual, &
                real(record%lcp_pivots, dp), real(record%iterations, dp), real(record%neg_pivots, dp)]
      call write_numbers(files%path%unit, '', values)
   end subroutine write_path_row

   !> One event of the critical-point file: kind, where it lies (a step number, fractional when the
   !> event was located between two steps), λ and the tracked values at the event.
   subroutine write_crit_row(files, kind, position, lambda, tracked)
      type(output_files_t), intent(inout) :: files
      character(len=*), intent(in) :: kind
      real(dp), intent(in) :: position
      real(dp), intent(in) :: lambda
      real(dp), intent(in) :: tracked(:)
      call write_numbers(files%crit%unit, kind, [position, lambda, tracked])
   end subroutine write_crit_row

   !> A snapshot of the deformed shape: one line per node (the last column the sum of the contact
   !> reactions at the node), snapshots separated by two blank lines (gnuplot's `index`).
   subroutine write_shape(files, model, record)
      type(output_files_t), intent(inout) :: files
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      real(dp), allocatable :: nodal_reaction(:)
      integer :: i, k
      nodal_reaction = nodal_reactions(model, record%reactions)
      do i = 1, model%n_nodes
         write (files%shape%unit, '(i0,*(1x,a))') record%step, trim(format_number(record%lambda)), &
            integer_to_string(model%node_label(i)), &
            (trim(format_number(model%coordinates(k, i))), k=1, 2), &
            (trim(format_number(record%displacement(k, i))), k=1, 3), &
            (trim(format_number(model%coordinates(k, i) + record%displacement(k, i))), k=1, 2), &
            trim(format_number(nodal_reaction(i)))
      end do
      write (files%shape%unit, '(/)')
      flush (files%shape%unit)
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

   !> Close every file and rename it to its final name.
   subroutine commit_outputs(files, error)
      type(output_files_t), intent(inout) :: files
      type(error_t), allocatable, intent(out) :: error
      call commit_table(files%path, error)
      if (allocated(error)) return
      call commit_table(files%crit, error)
      if (allocated(error)) return
      call commit_table(files%shape, error)
   end subroutine commit_outputs

   !> A real as text in the files' number format, without surrounding blanks.
   pure function format_number(x) result(text)
      real(dp), intent(in) :: x
      character(len=:), allocatable :: text
      text = real_to_string(x, number_format)
   end function format_number

   subroutine open_table(table, path, header, error)
      type(table_file_t), intent(out) :: table
      character(len=*), intent(in) :: path, header
      type(error_t), allocatable, intent(out) :: error
      integer :: status
      character(len=256) :: message
      table%final_path = path
      table%part_path = path//'.part'
      open (newunit=table%unit, file=table%part_path, status='replace', action='write', &
            iostat=status, iomsg=message)
      if (status /= 0) then
         call make_error(error, 'cannot write '//table%part_path//': '//trim(message), error_analysis)
         return
      end if
      table%is_open = .true.
      write (table%unit, '(a)') header
   end subroutine open_table

   subroutine write_numbers(unit, label, values)
      integer, intent(in) :: unit
      character(len=*), intent(in) :: label
      real(dp), intent(in) :: values(:)
      integer :: i
      if (len(label) > 0) write (unit, '(a)', advance='no') label//' '
      do i = 1, size(values)
         write (unit, '(a)', advance='no') trim(format_number(values(i)))
         if (i < size(values)) write (unit, '(a)', advance='no') ' '
      end do
      write (unit, '(a)') ''
      flush (unit)
   end subroutine write_numbers

   subroutine commit_table(table, error)
      type(table_file_t), intent(inout) :: table
      type(error_t), allocatable, intent(out) :: error
      if (.not. table%is_open) return
      close (table%unit)
      table%is_open = .false.
      call rename_file(table%part_path, table%final_path, error)
   end subroutine commit_table

end module uniarc_output
