!> A table of names, numbered in the order they were added and looked up case-insensitively.
!>
!> Every name table of the deck that grows with it (parameters, sections, node and element sets,
!> tracks) is one of these, so that reading a deck of n names costs O(n) expected time, not the
!> O(n²) of comparing each new name with all earlier ones (issue 14).
!>
!> The names are kept in the order of their addition; a hash table indexes them by the upper-case
!> name: open addressing with linear probing (Knuth, The Art of Computer Programming vol. 3, §6.4,
!> algorithm L), FNV-1a as the hash (Fowler, Noll and Vo; 32 bits), at most half full (the slots are
!> doubled and the names hashed anew before it would be fuller), so a lookup probes O(1) slots in
!> expectation (Knuth's (1 + 1/(1 - α)²)/2 ≤ 2.5 for a miss at load α ≤ 1/2).
module uniarc_name_table
   use, intrinsic :: iso_fortran_env, only: int64
   use uniarc_strings, only: to_upper
   implicit none
   private
   public :: add_name, find_name, look_up

   !> One name as first written (trailing blanks removed), and `key`, the name in upper case, which
   !> lookups compare.
   type, public :: name_entry_t
      character(len=:), allocatable :: name
      character(len=:), allocatable :: key
   end type name_entry_t

   !> Names numbered 1..count in the order they were added (`entries(1:count)`), and the hash index:
   !> `slots(k)` is 0 (free) or the number of a name; size(slots) is a power of 2, at least twice count.
   type, public :: name_table_t
      integer :: count = 0
      type(name_entry_t), allocatable :: entries(:)
      integer, allocatable :: slots(:)
   end type name_table_t

   !> Slots of a new table (a power of 2).
   integer, parameter :: initial_slots = 16

contains

   !> Add `name` to `table` as name number table%count + 1 and return that number in `index`; a name
   !> the table already holds (any case, trailing blanks ignored) is not added again, and `index` is
   !> its number.
   !> status (optional): the stat= of the growth of the table (its entries or its slots; nonzero:
   !> refused by the system, the name not added, `index` 0; for uniarc_memory, allocation_failure);
   !> absent, a refusal stops the program.
   pure subroutine add_name(table, name, index, status)
      type(name_table_t), intent(inout) :: table
      character(len=*), intent(in) :: name
      integer, intent(out) :: index
      integer, intent(out), optional :: status
      type(name_entry_t), allocatable :: grown(:)
      integer, allocatable :: slots(:)
      integer :: i, stat

      if (present(status)) status = 0
      index = find_name(table, name)
      if (index > 0) return
      stat = 0
      if (.not. allocated(table%entries)) then
         if (present(status)) then
            allocate (table%entries(8), stat=stat)
         else
            allocate (table%entries(8))
         end if
      end if
      if (.not. allocated(table%slots) .and. stat == 0) then
         if (present(status)) then
            allocate (table%slots(initial_slots), stat=stat)
         else
            allocate (table%slots(initial_slots))
         end if
         if (stat == 0) table%slots(:) = 0
      end if
      ! the larger slots first (kept aside until the name is in): a refusal leaves the table as it was
      if (2*(table%count + 1) > size(table%slots) .and. stat == 0) then
         if (present(status)) then
            allocate (slots(2*size(table%slots)), stat=stat)
         else
            allocate (slots(2*size(table%slots)))
         end if
      end if
      if (table%count == size(table%entries) .and. stat == 0) then
         if (present(status)) then
            allocate (grown(2*size(table%entries)), stat=stat)
         else
            allocate (grown(2*size(table%entries)))
         end if
      end if
      if (stat /= 0) then
         if (present(status)) status = stat
         return
      end if
      if (table%count == size(table%entries)) then
         do i = 1, table%count
            call move_alloc(table%entries(i)%name, grown(i)%name)
            call move_alloc(table%entries(i)%key, grown(i)%key)
         end do
         call move_alloc(grown, table%entries)
      end if
      table%count = table%count + 1
      table%entries(table%count)%name = trim(name)
      table%entries(table%count)%key = to_upper(trim(name))
      if (allocated(slots)) then
         call rehash(table, slots)
      else
         call insert_slot(table, table%count)
      end if
      index = table%count
   end subroutine add_name

   !> Number of `name` (case-insensitive, trailing blanks ignored) in `table`, 0 if it is not there.
   pure integer function find_name(table, name) result(index)
      type(name_table_t), intent(in) :: table
      character(len=*), intent(in) :: name
      integer :: probes
      call look_up(table, name, index, probes)
   end function find_name

   !> `index` as find_name gives it, and `probes`, the number of slots looked at: the cost of the
   !> lookup, which tests check stays O(1) as the table grows.
   pure subroutine look_up(table, name, index, probes)
      type(name_table_t), intent(in) :: table
      character(len=*), intent(in) :: name
      integer, intent(out) :: index, probes
      character(len=:), allocatable :: key
      integer :: slot, mask

      index = 0
      probes = 0
      if (table%count == 0) return
      key = to_upper(trim(name))
      mask = size(table%slots) - 1
      slot = iand(hash(key), mask)
      do
         probes = probes + 1
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
   end subroutine look_up

   !> Give the table the slots `slots` (allocated, a power of 2 in size; moved in) and index every name
   !> in them.
   pure subroutine rehash(table, slots)
      type(name_table_t), intent(inout) :: table
      integer, allocatable, intent(inout) :: slots(:)
      integer :: i
      slots(:) = 0
      call move_alloc(slots, table%slots)
      do i = 1, table%count
         call insert_slot(table, i)
      end do
   end subroutine rehash

   !> Put name `i` into the first free slot from its hash on (linear probing); a free slot exists
   !> since the table is at most half full.
   pure subroutine insert_slot(table, i)
      type(name_table_t), intent(inout) :: table
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

end module uniarc_name_table
