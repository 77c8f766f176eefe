!> The one module of interface blocks: the routines uniarc calls outside Fortran (LAPACK, libc).
!>
!> Keeping them here means every call is checked against an explicit interface
!> (-Werror=implicit-interface) and LAPACK's `info` is translated into an error in one place.
!>
!> The result files are written through C's stdio (stream_t) rather than Fortran units: libgfortran
!> (12.2) drops the errors of write(2) — a full file system or a file size limit gives iostat = 0
!> and a file cut short — whereas fwrite/fflush/fclose report them, with errno's words (strerror).
!> errno is read through `__errno_location`, the accessor of glibc and musl (Linux).
module uniarc_foreign
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_ptr, c_null_ptr, c_size_t, &
                                          c_funptr, c_null_funptr, c_intptr_t, c_associated, c_f_pointer, &
                                          c_int16_t, c_int32_t, c_int64_t
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis, error_internal
   use uniarc_strings, only: integer_to_string
   implicit none
   private
   public :: dgbtrf, dgbtrs, dgetrf, dgetrs
   public :: lapack_check, rename_file, make_directory, exit_program
   public :: stream_t, stream_open, stream_write, stream_flush, stream_close
   public :: remove_file, remove_directory, process_id, ignore_file_size_signal
   public :: file_status, read_regular_file, process_state, host_name, directory_entries, entry_name_t
   public :: process_alive, process_gone, process_unknown
   public :: catch_interrupts, interrupt_signal, signal_name, same_file

   !> An open C stdio stream (FILE *), written by stream_write and ended by stream_close.
   type :: stream_t
      private
      type(c_ptr) :: handle = c_null_ptr
   end type stream_t

   !> What Linux's statx(2) returns (struct statx of <linux/stat.h>, 256 bytes, the same on every
   !> architecture): the fields up to the size, then the times, device numbers and spare room.
   type, bind(c) :: statx_t
      integer(c_int32_t) :: mask = 0, block_size = 0
      integer(c_int64_t) :: attributes = 0
      integer(c_int32_t) :: links = 0, user = 0, group = 0
      integer(c_int16_t) :: mode = 0, spare = 0
      integer(c_int64_t) :: inode = 0, size = 0, blocks = 0, attributes_mask = 0
      integer(c_int64_t) :: rest(24) = 0
   end type statx_t

   !> statx(2): AT_FDCWD (paths relative to the working directory) and the fields asked for,
   !> STATX_TYPE | STATX_SIZE.
   integer(c_int), parameter :: at_current_directory = -100_c_int, statx_type_and_size = int(z'201', c_int)
   !> statx(2)'s AT_SYMLINK_NOFOLLOW (<fcntl.h>, Linux): a symbolic link is looked at, not its target.
   integer(c_int), parameter :: at_symlink_nofollow = int(z'100', c_int)

   !> One name of a directory listing (directory_entries).
   type :: entry_name_t
      character(len=:), allocatable :: name
   end type entry_name_t

   !> process_state's answers.
   integer, parameter :: process_alive = 1, process_gone = 0, process_unknown = -1
   !> SIGXFSZ, sent to a process that writes past its file size limit (Linux; BSD and macOS too).
   integer(c_int), parameter :: signal_file_size = 25_c_int

   interface
      !> LU factorisation of a general band matrix with partial pivoting (LAPACK).
      subroutine dgbtrf(m, n, kl, ku, ab, ldab, ipiv, info)
         import :: dp
         integer, intent(in) :: m, n, kl, ku, ldab
         real(dp), intent(inout) :: ab(ldab, *)
         integer, intent(out) :: ipiv(*)
         integer, intent(out) :: info
      end subroutine dgbtrf

      !> Solve with the band LU factors of dgbtrf (LAPACK).
      subroutine dgbtrs(trans, n, kl, ku, nrhs, ab, ldab, ipiv, b, ldb, info)
         import :: dp
         character(len=1), intent(in) :: trans
         integer, intent(in) :: n, kl, ku, nrhs, ldab, ldb
         real(dp), intent(in) :: ab(ldab, *)
         integer, intent(in) :: ipiv(*)
         real(dp), intent(inout) :: b(ldb, *)
         integer, intent(out) :: info
      end subroutine dgbtrs

      !> LU factorisation of a general dense matrix with partial pivoting (LAPACK).
      subroutine dgetrf(m, n, a, lda, ipiv, info)
         import :: dp
         integer, intent(in) :: m, n, lda
         real(dp), intent(inout) :: a(lda, *)
         integer, intent(out) :: ipiv(*)
         integer, intent(out) :: info
      end subroutine dgetrf

      !> Solve with the dense LU factors of dgetrf (LAPACK).
      subroutine dgetrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
         import :: dp
         character(len=1), intent(in) :: trans
         integer, intent(in) :: n, nrhs, lda, ldb
         real(dp), intent(in) :: a(lda, *)
         integer, intent(in) :: ipiv(*)
         real(dp), intent(inout) :: b(ldb, *)
         integer, intent(out) :: info
      end subroutine dgetrs

      function c_rename(old_path, new_path) bind(c, name='rename') result(status)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: old_path(*), new_path(*)
         integer(c_int) :: status
      end function c_rename

      subroutine c_exit(status) bind(c, name='exit')
         import :: c_int
         integer(c_int), value, intent(in) :: status
      end subroutine c_exit

      function c_mkdir(path, mode) bind(c, name='mkdir') result(status)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int), value, intent(in) :: mode
         integer(c_int) :: status
      end function c_mkdir

      function c_rmdir(path) bind(c, name='rmdir') result(status)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int) :: status
      end function c_rmdir

      function c_unlink(path) bind(c, name='unlink') result(status)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int) :: status
      end function c_unlink

      function c_getpid() bind(c, name='getpid') result(pid)
         import :: c_int
         integer(c_int) :: pid
      end function c_getpid

      function c_signal(signal_number, handler) bind(c, name='signal') result(previous)
         import :: c_int, c_funptr
         integer(c_int), value, intent(in) :: signal_number
         type(c_funptr), value, intent(in) :: handler
         type(c_funptr) :: previous
      end function c_signal

      function c_fopen(path, mode) bind(c, name='fopen') result(stream)
         import :: c_char, c_ptr
         character(kind=c_char), intent(in) :: path(*), mode(*)
         type(c_ptr) :: stream
      end function c_fopen

      function c_fwrite(buffer, size, count, stream) bind(c, name='fwrite') result(written)
         import :: c_char, c_size_t, c_ptr
         character(kind=c_char), intent(in) :: buffer(*)
         integer(c_size_t), value, intent(in) :: size, count
         type(c_ptr), value, intent(in) :: stream
         integer(c_size_t) :: written
      end function c_fwrite

      function c_fflush(stream) bind(c, name='fflush') result(status)
         import :: c_int, c_ptr
         type(c_ptr), value, intent(in) :: stream
         integer(c_int) :: status
      end function c_fflush

      function c_fclose(stream) bind(c, name='fclose') result(status)
         import :: c_int, c_ptr
         type(c_ptr), value, intent(in) :: stream
         integer(c_int) :: status
      end function c_fclose

      function c_errno_location() bind(c, name='__errno_location') result(location)
         import :: c_ptr
         type(c_ptr) :: location
      end function c_errno_location

      function c_strerror(number) bind(c, name='strerror') result(text)
         import :: c_int, c_ptr
         integer(c_int), value, intent(in) :: number
         type(c_ptr) :: text
      end function c_strerror

      function c_catch_interrupts() bind(c, name='uniarc_catch_interrupts') result(status)
         import :: c_int
         integer(c_int) :: status
      end function c_catch_interrupts

      function c_interrupt_signal() bind(c, name='uniarc_interrupt_signal') result(number)
         import :: c_int
         integer(c_int) :: number
      end function c_interrupt_signal

      function c_signal_number(which) bind(c, name='uniarc_signal_number') result(number)
         import :: c_int
         integer(c_int), value, intent(in) :: which
         integer(c_int) :: number
      end function c_signal_number

      function c_read_regular_file(path, buffer, size) bind(c, name='uniarc_read_regular_file') result(count)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         character(kind=c_char), intent(out) :: buffer(*)
         integer(c_int), value, intent(in) :: size
         integer(c_int) :: count
      end function c_read_regular_file

      function c_process_exists(pid) bind(c, name='uniarc_process_exists') result(state)
         import :: c_int
         integer(c_int), value, intent(in) :: pid
         integer(c_int) :: state
      end function c_process_exists

      function c_same_file(first, second) bind(c, name='uniarc_same_file') result(same)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: first(*), second(*)
         integer(c_int) :: same
      end function c_same_file

      function c_open_directory(path) bind(c, name='uniarc_open_directory') result(directory)
         import :: c_char, c_ptr
         character(kind=c_char), intent(in) :: path(*)
         type(c_ptr) :: directory
      end function c_open_directory

      function c_next_entry(directory, buffer, size) bind(c, name='uniarc_next_entry') result(length)
         import :: c_ptr, c_char, c_int
         type(c_ptr), value, intent(in) :: directory
         character(kind=c_char), intent(out) :: buffer(*)
         integer(c_int), value, intent(in) :: size
         integer(c_int) :: length
      end function c_next_entry

      subroutine c_close_directory(directory) bind(c, name='uniarc_close_directory')
         import :: c_ptr
         type(c_ptr), value, intent(in) :: directory
      end subroutine c_close_directory

      function c_host_name(buffer, size) bind(c, name='uniarc_host_name') result(length)
         import :: c_int, c_char
         character(kind=c_char), intent(out) :: buffer(*)
         integer(c_int), value, intent(in) :: size
         integer(c_int) :: length
      end function c_host_name

      function c_strlen(text) bind(c, name='strlen') result(length)
         import :: c_ptr, c_size_t
         type(c_ptr), value, intent(in) :: text
         integer(c_size_t) :: length
      end function c_strlen

      function c_statx(directory, path, flags, mask, buffer) bind(c, name='statx') result(status)
         import :: c_int, c_char, statx_t
         integer(c_int), value, intent(in) :: directory, flags, mask
         character(kind=c_char), intent(in) :: path(*)
         type(statx_t), intent(out) :: buffer
         integer(c_int) :: status
      end function c_statx
   end interface

contains

   !> Translate a LAPACK `info` into an error: the one place where LAPACK failures get their words.
   !> info > 0 from a factorisation means an exactly zero pivot: the tangent is singular there.
   subroutine lapack_check(routine, info, error)
      character(len=*), intent(in) :: routine
      integer, intent(in) :: info
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: text
      if (info == 0) return
      text = integer_to_string(abs(info))
      if (info < 0) then
         call make_error(error, routine//': argument '//text//' has an illegal value', error_internal)
      else
         call make_error(error, routine//': the matrix is singular (zero pivot at equation '// &
                         text//')', error_analysis)
      end if
   end subroutine lapack_check

   !> Rename a file atomically (POSIX rename): output is written to a temporary name, then renamed.
   subroutine rename_file(old_path, new_path, error)
      character(len=*), intent(in) :: old_path, new_path
      type(error_t), allocatable, intent(out) :: error
      if (c_rename(old_path//c_null_char, new_path//c_null_char) /= 0) then
         call make_error(error, 'cannot rename '//old_path//' to '//new_path//': '//system_error_text(), &
                         error_analysis)
      end if
   end subroutine rename_file

   !> Create a directory and its missing parents (mode 0755), like `mkdir -p`.
   subroutine make_directory(path, error)
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(out) :: error
      logical :: exists
      integer :: i
      integer(c_int) :: status
      ! Every prefix that ends before a '/' is a parent, created first if missing.
      do i = 2, len(path)
         if (path(i:i) /= '/') cycle
         inquire (file=path(:i - 1)//'/.', exist=exists)
         if (.not. exists) status = c_mkdir(path(:i - 1)//c_null_char, int(o'755', c_int))
      end do
      inquire (file=path//'/.', exist=exists)
      if (exists) return
      inquire (file=path, exist=exists)
      if (exists) then
         call make_error(error, 'cannot create output directory '//path//': expected a directory, found a file '// &
                         'of that name', error_analysis)
         return
      end if
      status = c_mkdir(path//c_null_char, int(o'755', c_int))
      if (status /= 0) call make_error(error, 'cannot create output directory '//path//': '// &
                                       system_error_text(), error_analysis)
   end subroutine make_directory

   !> Open `path` for writing as a new empty file (C's fopen mode "w"), or, when `exclusive`, only if
   !> no file of that name exists (mode "wx", O_CREAT|O_EXCL: the one creation among racing processes
   !> that succeeds). On failure `failure` holds the system's words (strerror of errno).
   subroutine stream_open(path, exclusive, stream, failure)
      character(len=*), intent(in) :: path
      logical, intent(in) :: exclusive
      type(stream_t), intent(out) :: stream
      character(len=:), allocatable, intent(out) :: failure
      if (exclusive) then
         stream%handle = c_fopen(path//c_null_char, 'wx'//c_null_char)
      else
         stream%handle = c_fopen(path//c_null_char, 'w'//c_null_char)
      end if
      if (.not. c_associated(stream%handle)) failure = system_error_text()
   end subroutine stream_open

   !> Append `text` to the stream (buffered by stdio); `failure` is allocated when it was refused.
   subroutine stream_write(stream, text, failure)
      type(stream_t), intent(in) :: stream
      character(len=*), intent(in) :: text
      character(len=:), allocatable, intent(out) :: failure
      if (len(text) == 0) return
      if (c_fwrite(text, 1_c_size_t, int(len(text), c_size_t), stream%handle) /= int(len(text), c_size_t)) &
         failure = system_error_text()
   end subroutine stream_write

   !> Hand the stream's buffer to the system (fflush); `failure` is allocated when that failed.
   subroutine stream_flush(stream, failure)
      type(stream_t), intent(in) :: stream
      character(len=:), allocatable, intent(out) :: failure
      if (c_fflush(stream%handle) /= 0) failure = system_error_text()
   end subroutine stream_flush

   !> Flush and close the stream (fclose); the stream is closed even when `failure` is allocated.
   subroutine stream_close(stream, failure)
      type(stream_t), intent(inout) :: stream
      character(len=:), allocatable, intent(out) :: failure
      if (.not. c_associated(stream%handle)) return
      if (c_fclose(stream%handle) /= 0) failure = system_error_text()
      stream%handle = c_null_ptr
   end subroutine stream_close

   !> Remove a file (unlink); `removed` says whether it worked (a missing file is not removed).
   subroutine remove_file(path, removed)
      character(len=*), intent(in) :: path
      logical, intent(out), optional :: removed
      integer(c_int) :: status
      status = c_unlink(path//c_null_char)
      if (present(removed)) removed = status == 0
   end subroutine remove_file

   !> Remove an empty directory (rmdir); `removed` says whether it worked.
   subroutine remove_directory(path, removed)
      character(len=*), intent(in) :: path
      logical, intent(out), optional :: removed
      integer(c_int) :: status
      status = c_rmdir(path//c_null_char)
      if (present(removed)) removed = status == 0
   end subroutine remove_directory

   !> The type and size of the file `path` (symbolic links followed unless `follow_links` is false),
   !> from statx(2) (Linux 4.11, glibc 2.28), which never opens the file (a FIFO cannot block it):
   !> `kind` is 'regular file', 'directory', 'character device', 'block device', 'FIFO', 'socket',
   !> 'symbolic link' (only when not followed) or 'file of unknown type'; `bytes` its size (of a regular
   !> file). When the file cannot be looked at (it does not exist, a folder on its path is not
   !> searchable), `failure` holds the system's words and `kind` is ''.
   subroutine file_status(path, kind, bytes, failure, follow_links)
      character(len=*), intent(in) :: path
      character(len=:), allocatable, intent(out) :: kind
      integer(c_int64_t), intent(out) :: bytes
      character(len=:), allocatable, intent(out) :: failure
      logical, intent(in), optional :: follow_links
      type(statx_t) :: status
      integer :: type_bits
      integer(c_int) :: flags
      kind = ''
      bytes = 0
      flags = 0_c_int
      if (present(follow_links)) then
         if (.not. follow_links) flags = at_symlink_nofollow
      end if
      if (c_statx(at_current_directory, path//c_null_char, flags, statx_type_and_size, status) /= 0) then
         failure = system_error_text()
         return
      end if
      bytes = status%size
      ! S_IFMT of the mode (an unsigned 16-bit field, read through a signed one)
      type_bits = iand(iand(int(status%mode), int(z'FFFF')), int(o'170000'))
      select case (type_bits)
      case (int(o'100000'))
         kind = 'regular file'
      case (int(o'040000'))
         kind = 'directory'
      case (int(o'020000'))
         kind = 'character device'
      case (int(o'060000'))
         kind = 'block device'
      case (int(o'010000'))
         kind = 'FIFO'
      case (int(o'140000'))
         kind = 'socket'
      case (int(o'120000'))
         kind = 'symbolic link'
      case default
         kind = 'file of unknown type'
      end select
   end subroutine file_status

   !> The first at most len(text) characters of the regular file `path`, read without ever blocking
   !> (uniarc_foreign.c: open with O_NONBLOCK and O_NOFOLLOW, then fstat): `count` is the number of
   !> characters read into text(1:count), -1 when the file cannot be opened or read, -2 when `path` is
   !> not a regular file (a FIFO, a device, a directory, a symbolic link), which is not read.
   subroutine read_regular_file(path, text, count)
      character(len=*), intent(in) :: path
      character(len=*), intent(out) :: text
      integer, intent(out) :: count
      character(kind=c_char) :: buffer(max(1, len(text)))
      integer :: i
      text = ''
      count = int(c_read_regular_file(path//c_null_char, buffer, int(len(text), c_int)))
      do i = 1, count
         text(i:i) = buffer(i)
      end do
   end subroutine read_regular_file

   !> The process id (getpid), which makes the names of a run's temporary files its own.
   integer function process_id()
      process_id = int(c_getpid())
   end function process_id

   !> Whether process `pid` exists on this host (kill(pid, 0), POSIX): process_alive, process_gone
   !> (ESRCH: no such process) or process_unknown (pid ≤ 0 or another failure).
   integer function process_state(pid)
      integer, intent(in) :: pid
      process_state = int(c_process_exists(int(pid, c_int)))
   end function process_state

   !> Whether the paths `first` and `second` name one file (the same device and inode, links
   !> followed); false when either does not exist or cannot be looked at.
   logical function same_file(first, second)
      character(len=*), intent(in) :: first, second
      same_file = c_same_file(first//c_null_char, second//c_null_char) == 1_c_int
   end function same_file

   !> The names in directory `path` (opendir/readdir, POSIX; "." and ".." left out, names longer than
   !> 4095 bytes skipped), in the system's order. `ok` is false, with no names, when it cannot be read
   !> or its names do not fit in memory.
   subroutine directory_entries(path, names, ok)
      character(len=*), intent(in) :: path
      type(entry_name_t), allocatable, intent(out) :: names(:)
      logical, intent(out) :: ok
      type(entry_name_t), allocatable :: grown(:)
      type(c_ptr) :: directory
      character(kind=c_char) :: buffer(4096)
      integer :: length, count, i, status
      allocate (names(0))
      directory = c_open_directory(path//c_null_char)
      ok = c_associated(directory)
      if (.not. ok) return
      count = 0
      deallocate (names)
      allocate (names(16), stat=status)
      ok = status == 0
      do while (ok)
         length = int(c_next_entry(directory, buffer, int(size(buffer), c_int)))
         if (length == -1) exit
         if (length < 0) cycle
         if (count == size(names)) then
            allocate (grown(2*count), stat=status)
            ok = status == 0
            if (.not. ok) exit
            do i = 1, count
               call move_alloc(names(i)%name, grown(i)%name)
            end do
            call move_alloc(grown, names)
         end if
         count = count + 1
         allocate (character(len=length) :: names(count)%name, stat=status)
         ok = status == 0
         if (.not. ok) exit
         do i = 1, length
            names(count)%name(i:i) = buffer(i)
         end do
      end do
      call c_close_directory(directory)
      if (ok) then
         names = names(1:count)
      else
         if (allocated(names)) deallocate (names)
         allocate (names(0))
      end if
   end subroutine directory_entries

   !> This host's name (gethostname, POSIX), or '' when it cannot be had.
   function host_name() result(name)
      character(len=:), allocatable :: name
      character(kind=c_char) :: buffer(256)
      integer :: length, i
      length = int(c_host_name(buffer, int(size(buffer), c_int)))
      allocate (character(len=max(0, length)) :: name)
      do i = 1, length
         name(i:i) = buffer(i)
      end do
   end function host_name

   !> Ignore SIGXFSZ, so that a write past the file size limit (`ulimit -f`) fails with EFBIG and is
   !> reported like a full file system, instead of killing the process (libgfortran installs a handler
   !> that prints a backtrace and aborts, over an inherited SIG_IGN too).
   subroutine ignore_file_size_signal()
      type(c_funptr) :: previous
      ! SIG_IGN is the handler address 1 in every C library uniarc is built with (glibc, musl).
      previous = c_signal(signal_file_size, transfer(1_c_intptr_t, c_null_funptr))
   end subroutine ignore_file_size_signal

   !> Catch SIGINT, SIGTERM, SIGHUP and SIGXCPU (src/common/uniarc_foreign.c): from now on they only set a flag, read by
   !> interrupt_signal, and the step loop ends the run with the steps traced (docs/contracts.md,
   !> "Interrupts"). A second signal of the same kind ends the program at once. Signals ignored at
   !> start stay ignored. `caught` is false when the system refused (the signals then kill as before).
   subroutine catch_interrupts(caught)
      logical, intent(out), optional :: caught
      integer(c_int) :: status
      status = c_catch_interrupts()
      if (present(caught)) caught = status == 0
   end subroutine catch_interrupts

   !> The number of the SIGINT, SIGTERM, SIGHUP or SIGXCPU received since catch_interrupts, or 0 when none was.
   integer function interrupt_signal()
      interrupt_signal = int(c_interrupt_signal())
   end function interrupt_signal

   !> "SIGINT", "SIGTERM", "SIGHUP" or "SIGXCPU" for the number of each, else "signal N".
   function signal_name(number) result(name)
      integer, intent(in) :: number
      character(len=:), allocatable :: name
      if (number == int(c_signal_number(0_c_int))) then
         name = 'SIGINT'
      else if (number == int(c_signal_number(1_c_int))) then
         name = 'SIGTERM'
      else if (number == int(c_signal_number(2_c_int))) then
         name = 'SIGHUP'
      else if (number == int(c_signal_number(3_c_int))) then
         name = 'SIGXCPU'
      else
         name = 'signal '//integer_to_string(number)
      end if
   end function signal_name

   !> The system's words for the current errno (strerror), right after a failed C call.
   function system_error_text() result(text)
      character(len=:), allocatable :: text
      integer(c_int), pointer :: errno
      type(c_ptr) :: words
      character(kind=c_char), pointer :: characters(:)
      integer :: length
      call c_f_pointer(c_errno_location(), errno)
      words = c_strerror(errno)
      length = int(c_strlen(words))
      call c_f_pointer(words, characters, [length])
      allocate (character(len=length) :: text)
      text = transfer(characters, text)
   end function system_error_text

   !> End the program with an exit status and no further words: Fortran's `stop n` would add
   !> "STOP n" to stderr under the error message. libgfortran closes its units at exit.
   subroutine exit_program(status)
      integer, intent(in) :: status
      flush (output_unit)
      flush (error_unit)
      call c_exit(int(status, c_int))
   end subroutine exit_program

end module uniarc_foreign
