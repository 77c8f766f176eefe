!> The `*PARAMETER` table: named values, defined in order and looked up case-insensitively.
!>
!> The entries are kept in the order of their definition; a hash table indexes them by the upper-case
!> name: open addressing with linear probing (Knuth, The Art of Computer Programming vol. 3, §6.4,
!> algorithm L), FNV-1a as the hash (Fowler, Noll and Vo; 32 bits), at most half full (the slots are
!> doubled and the entries hashed anew before it would be fuller). Defining n parameters and looking
!> up m names costs O(n + m) expected time — a deck of 1e5 parameters is read in linear time.
module uniarc_parameter_table
   use, intrinsic :: iso_fortran_env, only: int64
   use uniarc_kinds, only: dp
   use uniarc_strings, only: to_upper
   implicit none
   private
   public :: parameter_table_t, set_parameter, find_parameter, parameter_value

   !> A named value; `key` is the name in upper case, what lookups compare.
   type :: parameter_entry_t
      character(len=:), allocatable :: name
      character(len=:), allocatable :: key
      real(dp) :: value = 0.0_dp
   end type parameter_entry_t

   !> The parameters an expression may use, in the order they were defined (`entries(1:count)`),
   !> and the hash index: `slots(k)` is 0 (free) or the number of an entry; size(slots) is a power of 2.
   type :: parameter_table_t
      integer :: count = 0
      type(parameter_entry_t), allocatable :: entries(:)
      integer, allocatable :: slots(:)
   end type parameter_table_t

   !> Slots of a new table (a power of 2).
   integer, parameter :: initial_slots = 16

contains

   !> Define `name` with `value`, or change the value of the parameter of that name (any case).
   pure subroutine set_parameter(table, name, value)
      type(parameter_table_t), intent(inout) :: table
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: value
      type(parameter_entry_t), allocatable :: grown(:)
      integer :: i

      i = find_parameter(table, name)
      if (i > 0) then
         table%entries(i)%value = value
         return
      end if
      if (.not. allocated(table%entries)) allocate (table%entries(8))
      if (table%count == size(table%entries)) then
         allocate (grown(2*size(table%entries)))
         grown(1:table%count) = table%entries(1:table%count)
         call move_alloc(grown, table%entries)
      end if
      table%count = table%count + 1
      table%entries(table%count)%name = trim(name)
      table%entries(table%count)%key = to_upper(trim(name))
      table%entries(table%count)%value = value
      if (.not. allocated(table%slots)) allocate (table%slots(initial_slots), source=0)
      if (2*table%count > size(table%slots)) then
         call rehash(table, 2*size(table%slots))
      else
         call insert_slot(table, table%count)
      end if
   end subroutine set_parameter

   !> Number of the parameter `name` (case-insensitive, trailing blanks ignored) in `table`, 0 if it
   !> is not defined.
   pure integer function find_parameter(table, name) result(index)
      type(parameter_table_t), intent(in) :: table
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: key
      integer :: slot, mask

      index = 0
      if (table%count == 0) return
      key = to_upper(trim(name))
      mask = size(table%slots) - 1
      slot = iand(hash(key), mask)
      do
         if (table%slots(slot + 1) == 0) return
         associate (entry => table%entries(table%slots(slot + 1)))
            if (len(entry%key) == len(key)) then
               if (entry%key == key) then
                  index = table%slots(slot + 1)
                  return
               end if
            end if
         end associate
         slot = iand(slot + 1, mask)
      end do
   end function find_parameter

   !> The value of parameter number `index` (1 ≤ index ≤ table%count, from find_parameter).
   pure real(dp) function parameter_value(table, index)
      type(parameter_table_t), intent(in) :: table
      integer, intent(in) :: index
      parameter_value = table%entries(index)%value
   end function parameter_value

   !> Give the table `slots` slots (a power of 2) and index every entry in them.
   pure subroutine rehash(table, slots)
      type(parameter_table_t), intent(inout) :: table
      integer, intent(in) :: slots
      integer :: i
      deallocate (table%slots)
      allocate (table%slots(slots), source=0)
      do i = 1, table%count
         call insert_slot(table, i)
      end do
   end subroutine rehash

   !> Put entry `i` into the first free slot from its hash on (linear probing); a free slot exists
   !> since the table is at most half full.
   pure subroutine insert_slot(table, i)
      type(parameter_table_t), intent(inout) :: table
      integer, intent(in) :: i
      integer :: slot, mask
      mask = size(table%slots) - 1
      slot = iand(hash(table%entries(i)%key), mask)
      do while (table%slots(slot + 1) /= 0)
         slot = iand(slot + 1, mask)
      end do
      table%slots(slot + 1) = i
   end subroutine insert_slot

   !> FNV-1a hash of `key` (32 bits, offset basis 2166136261, prime 16777619), as a non-negative
   !> integer below 2**31: the product stays below 2**57, so 64-bit arithmetic is exact.
   pure integer function hash(key)
      character(len=*), intent(in) :: key
      integer(int64), parameter :: basis = 2166136261_int64, prime = 16777619_int64
      integer(int64), parameter :: low_32 = 4294967295_int64
      integer(int64) :: h
      integer :: i
      h = basis
      do i = 1, len(key)
         h = ieor(h, int(iachar(key(i:i)), int64))
         h = iand(h*prime, low_32)
      end do
      hash = int(iand(h, 2147483647_int64))
   end function hash

end module uniarc_parameter_table
