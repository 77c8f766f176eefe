!> Errors are values: library routines return an allocated error_t on failure and never stop.
!>
!> Convention (after fpm): `type(error_t), allocatable, intent(out) :: error`; the caller checks
!> `if (allocated(error)) return` and adds context on the way up. Only the main program prints and exits.
module uniarc_error
   implicit none
   private
   public :: error_t, make_error, add_context
   public :: error_input, error_analysis, error_internal

   !> Error categories; the main program maps them to exit codes (input → 2, analysis → 1).
   integer, parameter :: error_input = 2
   integer, parameter :: error_analysis = 1
   integer, parameter :: error_internal = 3

   !> An error: a category and a message that carries its context.
   type :: error_t
      integer :: category = error_internal
      character(len=:), allocatable :: message
      !> The system refused memory (uniarc_memory: allocation_failure). Within an analysis step such an
      !> error ends the run: it is not a failed step to cut back and retry (docs/contracts.md, "Memory").
      logical :: out_of_memory = .false.
   end type error_t

contains

   !> Allocate `error` with a message and a category (default: internal).
   subroutine make_error(error, message, category)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: message
      integer, intent(in), optional :: category
      allocate (error)
      error%message = message
      if (present(category)) error%category = category
   end subroutine make_error

   !> Prefix an existing error's message with context (routine, step, load factor ...).
   subroutine add_context(error, context, location)
      type(error_t), intent(inout) :: error
      character(len=*), intent(in) :: context
      !> The deck's path: a message that starts with it (`file:` or `file:line:col:`, docs/contracts.md)
      !> keeps it first, and the context follows it.
      character(len=*), intent(in), optional :: location
      integer :: n, colon
      if (present(location)) then
         n = len(location)
         if (n > 0 .and. len(error%message) > n) then
            if (error%message(1:n + 1) == location//':') then
               ! past `file:` and the `line:col:` that may follow
               colon = n + 1
               do while (colon < len(error%message))
                  if (scan(error%message(colon + 1:colon + 1), '0123456789') == 0) exit
                  colon = colon + index(error%message(colon + 1:), ':')
               end do
               error%message = error%message(1:colon)//' '//context//':'//error%message(colon + 1:)
               return
            end if
         end if
      end if
      error%message = context//': '//error%message
   end subroutine add_context

end module uniarc_error
