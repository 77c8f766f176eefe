!> A result file being written, every operation checked: create, each line, flush and close.
!>
!> The bytes go to a temporary path (the run's work directory, uniarc_result_directory) while messages
!> name the file by its final name. The first failure is kept with the system's words (e.g. "cannot
!> write out/arch.path: No space left on device"); later lines are not attempted, and the failure is
!> returned as an error by the next flush_text_file, close_text_file or text_file_error, so a writer
!> of many lines checks once per file or per row instead of after every line.
module uniarc_text_file
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_foreign, only: stream_t, stream_open, stream_write, stream_flush, stream_close, remove_file
   implicit none
   private
   public :: text_file_t, create_text_file, put_line, flush_text_file, close_text_file, discard_text_file
   public :: text_file_error

   !> One text file being written.
   type :: text_file_t
      character(len=:), allocatable :: path     !< where the bytes go (a temporary name)
      character(len=:), allocatable :: name     !< the file's name in messages (its final name)
      type(stream_t) :: stream
      logical :: is_open = .false.
      character(len=:), allocatable :: failure  !< the first failure, with the system's words
   end type text_file_t

contains

   !> Create (or empty) the file at `path`, named `name` in messages.
   subroutine create_text_file(file, path, name, error)
      type(text_file_t), intent(out) :: file
      character(len=*), intent(in) :: path, name
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: failure
      file%path = path
      file%name = name
      call stream_open(path, .false., file%stream, failure)
      if (allocated(failure)) then
         file%failure = 'cannot create '//path//' (for '//name//'): '//failure
         call text_file_error(file, error)
         return
      end if
      file%is_open = .true.
   end subroutine create_text_file

   !> Append one line (its text and a newline); nothing after a failure of the file.
   subroutine put_line(file, line)
      type(text_file_t), intent(inout) :: file
      character(len=*), intent(in) :: line
      character(len=:), allocatable :: failure
      if (.not. file%is_open .or. allocated(file%failure)) return
      call stream_write(file%stream, line//new_line('a'), failure)
      if (allocated(failure)) file%failure = 'cannot write '//file%name//': '//failure
   end subroutine put_line

   !> Hand what was written to the system, so that the file holds every complete line so far (a
   !> progress view, `tail -f`); the file's first failure, if any, as an error.
   subroutine flush_text_file(file, error)
      type(text_file_t), intent(inout) :: file
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: failure
      if (file%is_open .and. .not. allocated(file%failure)) then
         call stream_flush(file%stream, failure)
         if (allocated(failure)) file%failure = 'cannot write '//file%name//': '//failure
      end if
      call text_file_error(file, error)
   end subroutine flush_text_file

   !> Close the file (flushing what is buffered); the file's first failure, if any, as an error. The
   !> file is closed either way.
   subroutine close_text_file(file, error)
      type(text_file_t), intent(inout) :: file
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: failure
      if (file%is_open) then
         call stream_close(file%stream, failure)
         file%is_open = .false.
         if (allocated(failure) .and. .not. allocated(file%failure)) &
            file%failure = 'cannot write '//file%name//' (closing it): '//failure
      end if
      call text_file_error(file, error)
   end subroutine close_text_file

   !> Close the file without a word (a failure is being reported already) and remove it.
   subroutine discard_text_file(file)
      type(text_file_t), intent(inout) :: file
      character(len=:), allocatable :: failure
      if (file%is_open) then
         call stream_close(file%stream, failure)
         file%is_open = .false.
      end if
      if (allocated(file%path)) call remove_file(file%path)
   end subroutine discard_text_file

   !> The file's first failure as an error (analysis category: exit code 1), if it had one.
   subroutine text_file_error(file, error)
      type(text_file_t), intent(in) :: file
      type(error_t), allocatable, intent(out) :: error
      if (allocated(file%failure)) call make_error(error, file%failure, error_analysis)
   end subroutine text_file_error

end module uniarc_text_file
