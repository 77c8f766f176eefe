!> Where a run's result files go, and how they get there: all together, complete, and one run at a time.
!>
!> A run first claims `OUTDIR/STEM.lock`, created exclusively (C's fopen "wx": of two runs that race
!> for it one wins) and holding the run's process id; a run that finds the lock refuses to start
!> (docs/contracts.md). A lock path taken by anything but a regular file (a FIFO, a directory, a link)
!> is refused too, after a look with statx(2) that never opens it: opening a FIFO would block forever. Its files are then written into its own work directory `OUTDIR/.STEM.part.PID`
!> under their final names, and only when every one of them is closed without error are they renamed
!> into OUTDIR, one after the other, after which the work directory and the lock are removed. A run that
!> stops on an I/O error removes its work directory and its lock instead, so OUTDIR keeps no file of it.
!> The lock is removed last: while it exists the files of STEM in OUTDIR are not known to be one run's
!> complete set (a run in progress, or one killed, possibly between two renames).
module uniarc_result_directory
   use, intrinsic :: iso_fortran_env, only: int64
   use uniarc_error, only: error_t, make_error, add_context, error_input, error_analysis
   use uniarc_foreign, only: stream_t, stream_open, stream_write, stream_close, make_directory, &
                             rename_file, remove_file, remove_directory, process_id, file_status, &
                             read_regular_file
   use uniarc_strings, only: integer_to_string
   implicit none
   private
   public :: result_directory_t, claim_result_directory, work_path, final_path, add_result_file
   public :: commit_results, abandon_results

   !> The name of one result file, relative to OUTDIR.
   type :: file_name_t
      character(len=:), allocatable :: name
   end type file_name_t

   !> A run's claim on OUTDIR for STEM, and the result files it has started.
   type :: result_directory_t
      character(len=:), allocatable :: directory   !< OUTDIR
      character(len=:), allocatable :: stem
      character(len=:), allocatable :: lock_path   !< OUTDIR/STEM.lock
      character(len=:), allocatable :: work        !< OUTDIR/.STEM.part.PID, the files until the commit
      type(file_name_t), allocatable :: files(:)   !< every file started in `work`, in order
      logical :: claimed = .false.                 !< the lock and the work directory are this run's
   end type result_directory_t

contains

   !> Create OUTDIR (with its parents) if needed, take the lock `OUTDIR/STEM.lock` and make the work
   !> directory. Errors are bad input (exit code 2: an OUTDIR that cannot be used), and leave nothing
   !> of this run behind.
   subroutine claim_result_directory(directory, stem, results, error)
      character(len=*), intent(in) :: directory, stem
      type(result_directory_t), intent(out) :: results
      type(error_t), allocatable, intent(out) :: error
      type(stream_t) :: lock
      character(len=:), allocatable :: failure, close_failure, kind, status_failure
      integer(int64) :: bytes
      logical :: exists
      results%directory = directory
      results%stem = stem
      results%lock_path = directory//'/'//stem//'.lock'
      results%work = directory//'/.'//stem//'.part.'//integer_to_string(process_id())
      allocate (results%files(0))
      call make_directory(directory, error)
      if (allocated(error)) then
         error%category = error_input
         return
      end if

      call stream_open(results%lock_path, .true., lock, failure)
      if (allocated(failure)) then
         ! Looked at without opening it, nor following a link: a FIFO's open would block (issue 14).
         call file_status(results%lock_path, kind, bytes, status_failure, follow_links=.false.)
         exists = .not. allocated(status_failure)
         if (exists .and. kind /= 'regular file') then
            call make_error(error, results%lock_path//' exists and is a '//kind//', not the lock file of '// &
                            'a uniarc run: the results of '//stem//' cannot be written into '//directory// &
                            '; remove '//results%lock_path, error_input)
         else if (exists) then
            call make_error(error, results%lock_path//' exists: another uniarc run'// &
                            lock_holder(results%lock_path)//' is writing the results of '//stem// &
                            ' into '//directory//', or one was killed before it ended; remove '// &
                            results%lock_path//' once no run is using it', error_input)
         else
            call make_error(error, 'cannot write into output directory '//directory//': cannot create '// &
                            results%lock_path//': '//failure, error_input)
         end if
         return
      end if
      call stream_write(lock, 'pid '//integer_to_string(process_id())//new_line('a'), failure)
      call stream_close(lock, close_failure)
      if (.not. allocated(failure) .and. allocated(close_failure)) call move_alloc(close_failure, failure)
      if (allocated(failure)) then
         call remove_file(results%lock_path)
         call make_error(error, 'cannot write into output directory '//directory//': cannot write '// &
                         results%lock_path//': '//failure, error_input)
         return
      end if

      call make_directory(results%work, error)
      if (allocated(error)) then
         call remove_file(results%lock_path)
         call add_context(error, 'cannot write into output directory '//directory)
         error%category = error_input
         return
      end if
      results%claimed = .true.
   end subroutine claim_result_directory

   !> Where the result file `name` is written during the run (in the work directory).
   pure function work_path(results, name) result(path)
      type(result_directory_t), intent(in) :: results
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: path
      path = results%work//'/'//name
   end function work_path

   !> The final name of the result file `name`: OUTDIR/name.
   pure function final_path(results, name) result(path)
      type(result_directory_t), intent(in) :: results
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: path
      path = results%directory//'/'//name
   end function final_path

   !> Record that the result file `name` is being written in the work directory (once per name).
   subroutine add_result_file(results, name)
      type(result_directory_t), intent(inout) :: results
      character(len=*), intent(in) :: name
      integer :: i
      do i = 1, size(results%files)
         if (results%files(i)%name == name) return
      end do
      results%files = [results%files, file_name_t(name)]
   end subroutine add_result_file

   !> Move every result file, all closed and complete, to its final name; then remove the work
   !> directory and the lock. Should a rename fail, the files not yet moved are removed, and the error
   !> (analysis category) says how many were.
   subroutine commit_results(results, error)
      type(result_directory_t), intent(inout) :: results
      type(error_t), allocatable, intent(out) :: error
      integer :: i, moved
      if (.not. results%claimed) return
      moved = 0
      do i = 1, size(results%files)
         call rename_file(work_path(results, results%files(i)%name), final_path(results, results%files(i)%name), &
                          error)
         if (allocated(error)) exit
         moved = moved + 1
      end do
      if (allocated(error)) then
         error%category = error_analysis
         call add_context(error, integer_to_string(moved)//' of '//integer_to_string(size(results%files))// &
                          ' result files were moved to '//results%directory//', the others removed')
      end if
      call abandon_results(results)
   end subroutine commit_results

   !> Remove the run's files that are still in the work directory, the work directory and the lock.
   subroutine abandon_results(results)
      type(result_directory_t), intent(inout) :: results
      integer :: i
      if (.not. results%claimed) return
      do i = 1, size(results%files)
         call remove_file(work_path(results, results%files(i)%name))
      end do
      call remove_directory(results%work)
      call remove_file(results%lock_path)
      results%claimed = .false.
   end subroutine abandon_results

   !> " (pid N)" from the lock file of another run, or nothing when it cannot be read. Read without
   !> blocking and only if it is a regular file (read_regular_file), should the lock have been
   !> replaced by a FIFO since it was looked at (issue 14).
   function lock_holder(lock_path) result(text)
      character(len=*), intent(in) :: lock_path
      character(len=:), allocatable :: text
      character(len=64) :: content
      integer :: count, line_end
      text = ''
      call read_regular_file(lock_path, content, count)
      if (count <= 0) return
      line_end = index(content(1:count), new_line('a'))
      if (line_end == 0) line_end = count + 1
      if (len_trim(content(1:line_end - 1)) > 0) text = ' ('//trim(content(1:line_end - 1))//')'
   end function lock_holder

end module uniarc_result_directory
