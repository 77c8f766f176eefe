!> The `*PARAMETER` table: named values, defined in order and looked up case-insensitively.
!>
!> The names are a `name_table_t` (uniarc_name_table: a hash index, so defining n parameters and
!> looking up m names costs O(n + m) expected time — a deck of 1e5 parameters is read in linear
!> time); `values(i)` is the value of name number i.
module uniarc_parameter_table
   use uniarc_kinds, only: dp
   use uniarc_name_table, only: name_table_t, add_name, find_name
   implicit none
   private
   public :: parameter_table_t, set_parameter, find_parameter, parameter_value

   !> The parameters an expression may use: their names, numbered in the order they were defined, and
   !> `values(1:names%count)`.
   type :: parameter_table_t
      type(name_table_t) :: names
      real(dp), allocatable :: values(:)
   end type parameter_table_t

contains

   !> Define `name` with `value`, or change the value of the parameter of that name (any case).
   !> status (optional): the stat= of the growth of the table (nonzero: refused by the system, the
   !> parameter's value not set and the table not to be used further; for uniarc_memory,
   !> allocation_failure); absent, a refusal stops the program.
   pure subroutine set_parameter(table, name, value, status)
      type(parameter_table_t), intent(inout) :: table
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: value
      integer, intent(out), optional :: status
      real(dp), allocatable :: grown(:)
      integer :: i, stat

      stat = 0
      if (present(status)) then
         status = 0
         call add_name(table%names, name, i, stat)
         if (stat == 0 .and. .not. allocated(table%values)) allocate (table%values(8), stat=stat)
         if (stat == 0 .and. i > size(table%values)) allocate (grown(2*size(table%values)), stat=stat)
         status = stat
         if (stat /= 0) return
      else
         call add_name(table%names, name, i)
         if (.not. allocated(table%values)) allocate (table%values(8))
         if (i > size(table%values)) allocate (grown(2*size(table%values)))
      end if
      if (i > size(table%values)) then
         grown(1:size(table%values)) = table%values
         call move_alloc(grown, table%values)
      end if
      table%values(i) = value
   end subroutine set_parameter

   !> Number of the parameter `name` (case-insensitive, trailing blanks ignored) in `table`, 0 if it
   !> is not defined.
   pure integer function find_parameter(table, name) result(index)
      type(parameter_table_t), intent(in) :: table
      character(len=*), intent(in) :: name
      index = find_name(table%names, name)
   end function find_parameter

   !> The value of parameter number `index` (1 ≤ index ≤ number of parameters, from find_parameter).
   pure real(dp) function parameter_value(table, index)
      type(parameter_table_t), intent(in) :: table
      integer, intent(in) :: index
      parameter_value = table%values(index)
   end function parameter_value

end module uniarc_parameter_table
