!> Where a run's result files go, and how they get there: all together, complete, and one run at a time.
!>
!> A run first claims `OUTDIR/STEM.lock`, created exclusively (C's fopen "wx": of two runs that race
!> for it one wins) and holding the run's process id; a run that finds the lock refuses to start
!> (docs/contracts.md). A lock that names a process of this host (its lines `pid N` and `host H`)
!> which no longer exists (kill(pid, 0) fails with ESRCH: the run was killed by SIGKILL or the OOM
!> killer) is stale: it is removed and the claim made again, once, with a note for the caller to say.
!> A lock path taken by anything but a regular file (a FIFO, a directory, a link)
!> is refused too, after a look with statx(2) that never opens it: opening a FIFO would block forever. Its files are then written into its own work directory `OUTDIR/.STEM.part.PID`
!> under their final names, and only when every one of them is closed without error are they renamed
!> into OUTDIR, one after the other, after which the work directory and the lock are removed. Every
!> final name is looked at before the first rename: one taken by a directory (which a rename cannot
!> replace) stops the commit with nothing moved. After the renames, the files of STEM that an earlier
!> run wrote with other names (the suffixes of `stem_file`: a .csv table of a --csv run, a VTK
!> snapshot beyond this run's last step) are removed, so OUTDIR holds one run's set. A run that
!> stops on an I/O error removes its work directory and its lock instead, so OUTDIR keeps no file of it.
!> The lock is removed last: while it exists the files of STEM in OUTDIR are not known to be one run's
!> complete set (a run in progress, or one killed, possibly between two renames).
module uniarc_result_directory
   use, intrinsic :: iso_fortran_env, only: int64
   use uniarc_error, only: error_t, make_error, add_context, error_input, error_analysis
   use uniarc_foreign, only: stream_t, stream_open, stream_write, stream_close, make_directory, &
                             rename_file, remove_file, remove_directory, process_id, file_status, &
                             read_regular_file, process_state, process_gone, host_name, &
                             directory_entries, entry_name_t
   use uniarc_strings, only: integer_to_string
   implicit none
   private
   public :: result_directory_t, claim_result_directory, work_path, final_path, add_result_file
   public :: commit_results, abandon_results, stem_file

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
      !> Set when a stale lock was taken over (claim_result_directory): for the caller to say on stderr.
      character(len=:), allocatable :: note
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
      integer :: stale_pid
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
         ! A stale lock of this host (its process gone): removed, and the lock claimed once more.
         stale_pid = stale_lock_pid(results%lock_path)
         if (stale_pid > 0) then
            call remove_file(results%lock_path)
            deallocate (failure)
            call stream_open(results%lock_path, .true., lock, failure)
            if (.not. allocated(failure)) results%note = 'removed the stale lock '//results%lock_path// &
               ' of process '//integer_to_string(stale_pid)//', which no longer exists on this host (killed '// &
               'before it ended); the files of '//stem//' in '//directory//' may be an incomplete set of that run'
         end if
      end if
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
      call stream_write(lock, 'pid '//integer_to_string(process_id())//new_line('a')//'host '//host_name()// &
                        new_line('a'), failure)
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
      character(len=:), allocatable :: kind, failure
      integer(int64) :: bytes
      integer :: i, moved
      if (.not. results%claimed) return
      ! Every target first: a directory in the way (a rename cannot replace it) stops the commit with
      ! nothing moved, so OUTDIR keeps the earlier run's set whole (docs/contracts.md, exit code 1).
      do i = 1, size(results%files)
         call file_status(final_path(results, results%files(i)%name), kind, bytes, failure, follow_links=.false.)
         if (kind == 'directory') then
            call make_error(error, 'cannot move the result files into '//results%directory//': '// &
                            final_path(results, results%files(i)%name)//' is a directory; no result file '// &
                            'of this run was moved, the earlier files are unchanged', error_analysis)
            call abandon_results(results)
            return
         end if
      end do
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
      else
         call remove_stale_files(results)
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

   !> Remove from OUTDIR the files of STEM that uniarc writes (stem_file) and this run did not: those
   !> of an earlier run of the deck (a --csv table, VTK snapshots past this run's last step, a modes
   !> file), so that OUTDIR holds one run's consistent set. Called after every rename succeeded; a file
   !> that cannot be removed stays (nothing else to do about it; the run's own set is complete).
   subroutine remove_stale_files(results)
      type(result_directory_t), intent(in) :: results
      type(entry_name_t), allocatable :: names(:)
      logical :: ok, own
      integer :: i, j
      call directory_entries(results%directory, names, ok)
      if (.not. ok) return
      do i = 1, size(names)
         if (.not. stem_file(results%stem, names(i)%name)) cycle
         own = .false.
         do j = 1, size(results%files)
            if (results%files(j)%name == names(i)%name) then
               own = .true.
               exit
            end if
         end do
         if (.not. own) call remove_file(final_path(results, names(i)%name))
      end do
   end subroutine remove_stale_files

   !> Whether `name` is one of the result files uniarc writes for `stem` (docs/contracts.md, "Result
   !> files"): STEM.path, .crit, .shape, .forces, .contact, .surface (each also with .csv), .modes,
   !> .pvd, the VTK snapshots
   !> STEM_NNNN.vtp or .vtk (at least four digits) and the modes' STEM_mode_NN.vtp (at least two).
   pure logical function stem_file(stem, name)
      character(len=*), intent(in) :: stem, name
      character(len=*), parameter :: tables(6) = ['.path    ', '.crit    ', '.shape   ', '.forces  ', &
                                                  '.contact ', '.surface ']
      integer :: k
      stem_file = .false.
      if (len(name) <= len(stem)) return
      if (name(1:len(stem)) /= stem) return
      associate (tail => name(len(stem) + 1:))
         do k = 1, size(tables)
            if (tail == trim(tables(k)) .or. tail == trim(tables(k))//'.csv') stem_file = .true.
         end do
         if (tail == '.modes' .or. tail == '.pvd') stem_file = .true.
         ! only the numbers as uniarc writes them: a snapshot's at least four digits (zero-padded to
         ! four), a mode's two (01-99) or three (100-999) — so that another deck's snapshots,
         ! STEM_mode_0000.vtp of the deck STEM_mode, are not taken for modes of STEM. A mode numbered
         ! 1000 or more would read as such a snapshot and is not removed.
         if (numbered(tail, '_', '.vtp', 4, 4) .or. numbered(tail, '_', '.vtk', 4, 4) .or. &
             (numbered(tail, '_mode_', '.vtp', 2, 2) .and. len(tail) <= len('_mode_999.vtp') .and. &
              tail /= '_mode_00.vtp')) stem_file = .true.
      end associate
   end function stem_file

   !> Whether `text` is `before`, a number written as uniarc writes it, then `after`: at least
   !> `fewest` decimal digits, and at most `most` of them unless the first is not 0 (a number
   !> zero-padded to `most` digits, or a larger one written in full without leading zeros).
   pure logical function numbered(text, before, after, fewest, most)
      character(len=*), intent(in) :: text, before, after
      integer, intent(in) :: fewest, most
      integer :: n
      numbered = .false.
      n = len(text) - len(before) - len(after)
      if (n < fewest) return
      if (text(1:len(before)) /= before .or. text(len(text) - len(after) + 1:) /= after) return
      if (verify(text(len(before) + 1:len(before) + n), '0123456789') /= 0) return
      if (n > most .and. text(len(before) + 1:len(before) + 1) == '0') return
      numbered = .true.
   end function numbered

   !> The process id of a stale lock at `lock_path`: one whose lines `pid N` and `host H` name this
   !> host and a process that no longer exists on it (process_state: ESRCH), or this process itself
   !> (its id reused); 0 for any other lock (a
   !> live process, another host, a lock without a host line, one that cannot be read).
   integer function stale_lock_pid(lock_path) result(pid)
      character(len=*), intent(in) :: lock_path
      character(len=256) :: content
      character(len=:), allocatable :: host
      integer :: count, first_end, status
      pid = 0
      call read_regular_file(lock_path, content, count)
      if (count <= 0) return
      first_end = index(content(1:count), new_line('a'))
      if (first_end < 6 .or. content(1:4) /= 'pid ') return
      read (content(5:first_end - 1), *, iostat=status) pid
      if (status /= 0 .or. pid <= 0) then
         pid = 0
         return
      end if
      host = host_name()
      if (len(host) == 0 .or. content(first_end + 1:count) /= 'host '//host//new_line('a')) then
         pid = 0
         return
      end if
      ! A lock naming this very process is stale too: this run has not written its lock yet, so
      ! the process that did is gone and its id came back (a container's PID namespace restarts
      ! at the same ids: a run killed in one, the next one given the same pid).
      if (pid == process_id()) return
      if (process_state(pid) /= process_gone) pid = 0
   end function stale_lock_pid

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
