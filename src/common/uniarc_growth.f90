!> Arrays that grow as a reader or builder appends to them: capacities double, so that n appends cost
!> O(n) copies in all (the deck of 1e5 nodes is read in linear time).
module uniarc_growth
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: append_integers, grow_integers, grow_integers_2, grow_reals_2, grow_logicals_2

contains

   !> Append `values` to `list(1:count)`, doubling the capacity of `list` when needed; `count` is updated.
   !> With `status` present, a growth the system refuses is returned as grow_integers does, and nothing
   !> is appended.
   pure subroutine append_integers(list, count, values, status)
      integer, allocatable, intent(inout) :: list(:)   !< allocated on entry; entries past count are spare
      integer, intent(inout) :: count
      integer, intent(in) :: values(:)
      integer, intent(out), optional :: status
      if (present(status)) status = 0
      if (count + size(values) > size(list)) then
         call grow_integers(list, max(2*size(list), count + size(values)), status)
         if (present(status)) then
            if (status /= 0) return
         end if
      end if
      list(count + 1:count + size(values)) = values
      count = count + size(values)
   end subroutine append_integers

   !> Make sure `list` holds at least `needed` entries (at least doubling it), keeping its contents; new
   !> entries are 0. An unallocated `list` is allocated. With `status` present, an allocation the
   !> system refuses leaves `list` as it was, with the nonzero stat= in `status` (for uniarc_memory:
   !> allocation_failure); without it, the runtime stops the program.
   pure subroutine grow_integers(list, needed, status)
      integer, allocatable, intent(inout) :: list(:)
      integer, intent(in) :: needed
      integer, intent(out), optional :: status
      integer, allocatable :: grown(:)
      if (present(status)) status = 0
      if (.not. allocated(list)) allocate (list(0))
      if (size(list) >= needed) return
      if (present(status)) then
         allocate (grown(max(needed, 2*size(list))), stat=status)
         if (status /= 0) return
         grown = 0
      else
         allocate (grown(max(needed, 2*size(list))), source=0)
      end if
      grown(1:size(list)) = list
      call move_alloc(grown, list)
   end subroutine grow_integers

   !> Give `array` (rows, columns) `columns` columns, keeping its contents; new entries are 0.
   !> With `status` present, an allocation the system refuses leaves `array` as it was, with the nonzero
   !> stat= in `status` (as grow_integers); without it, the runtime stops the program.
   pure subroutine grow_integers_2(array, columns, status)
      integer, allocatable, intent(inout) :: array(:, :)
      integer, intent(in) :: columns
      integer, intent(out), optional :: status
      integer, allocatable :: grown(:, :)
      if (present(status)) then
         allocate (grown(size(array, 1), columns), stat=status)
         if (status /= 0) return
         grown = 0
      else
         allocate (grown(size(array, 1), columns), source=0)
      end if
      grown(:, 1:size(array, 2)) = array
      call move_alloc(grown, array)
   end subroutine grow_integers_2

   !> Give `array` (rows, columns) `columns` columns, keeping its contents; new entries are 0.
   !> With `status` present, an allocation the system refuses leaves `array` as it was, with the nonzero
   !> stat= in `status` (as grow_integers); without it, the runtime stops the program.
   pure subroutine grow_reals_2(array, columns, status)
      real(dp), allocatable, intent(inout) :: array(:, :)
      integer, intent(in) :: columns
      integer, intent(out), optional :: status
      real(dp), allocatable :: grown(:, :)
      if (present(status)) then
         allocate (grown(size(array, 1), columns), stat=status)
         if (status /= 0) return
         grown = 0.0_dp
      else
         allocate (grown(size(array, 1), columns), source=0.0_dp)
      end if
      grown(:, 1:size(array, 2)) = array
      call move_alloc(grown, array)
   end subroutine grow_reals_2

   !> Give `array` (rows, columns) `columns` columns, keeping its contents; new entries are false.
   !> With `status` present, an allocation the system refuses leaves `array` as it was, with the nonzero
   !> stat= in `status` (as grow_integers); without it, the runtime stops the program.
   pure subroutine grow_logicals_2(array, columns, status)
      logical, allocatable, intent(inout) :: array(:, :)
      integer, intent(in) :: columns
      integer, intent(out), optional :: status
      logical, allocatable :: grown(:, :)
      if (present(status)) then
         allocate (grown(size(array, 1), columns), stat=status)
         if (status /= 0) return
         grown = .false.
      else
         allocate (grown(size(array, 1), columns), source=.false.)
      end if
      grown(:, 1:size(array, 2)) = array
      call move_alloc(grown, array)
   end subroutine grow_logicals_2

end module uniarc_growth
