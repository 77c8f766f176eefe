!> Copies of allocatable arrays and texts whose allocation is checked (docs/contracts.md, "Memory"):
!> `copy_array(src, dst, status, bytes)` allocates `dst` with the bounds of `src` with stat= and copies
!> it — what the intrinsic assignment `dst = src` does without a check (reallocation on assignment has
!> no stat=). An unallocated `src` leaves `dst` unallocated. status: the stat= (0: copied); bytes: set
!> to the size of the array, for uniarc_memory's allocation_failure. Used by the copies of the model
!> (uniarc_model_copy) and of the path state (uniarc_path_state_copy), record by record.
module uniarc_copy
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: copy_array, copy_text, move_text, reserve

   interface copy_array
      module procedure copy_reals_1, copy_reals_2, copy_integers_1, copy_integers_2, copy_logicals_1, &
         copy_logicals_2
   end interface copy_array

   !> `reserve(array, n, status, bytes)` (also `(array, rows, columns, status, bytes)`): `array` allocated
   !> with stat= to the given extents unless it already has them (then kept as it is, its values too);
   !> its values are undefined after a new allocation. So that the assignments that follow (`array = ...`
   !> of the same shape) allocate nothing: reallocation on assignment has no stat=. status: the stat=
   !> (0: allocated); bytes: set to the size asked for, for uniarc_memory's allocation_failure.
   interface reserve
      module procedure reserve_reals_1, reserve_reals_2, reserve_logicals_1, reserve_integers_1
   end interface reserve

contains

   !> A deferred-length text moved (an unallocated `from` leaves `to` unallocated).
   subroutine move_text(from, to)
      character(len=:), allocatable, intent(inout) :: from, to
      if (allocated(to)) deallocate (to)
      if (allocated(from)) call move_alloc(from, to)
   end subroutine move_text

   subroutine copy_text(src, dst, status, bytes)
      character(len=:), allocatable, intent(in) :: src
      character(len=:), allocatable, intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      status = 0
      if (allocated(dst)) deallocate (dst)
      if (.not. allocated(src)) return
      bytes = real(len(src), dp)
      allocate (character(len=len(src)) :: dst, stat=status)
      if (status == 0) dst = src
   end subroutine copy_text

   subroutine copy_reals_2(src, dst, status, bytes)
      real(dp), allocatable, intent(in) :: src(:, :)
      real(dp), allocatable, intent(inout) :: dst(:, :)
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      status = 0
      if (allocated(dst)) deallocate (dst)
      if (.not. allocated(src)) return
      bytes = 8.0_dp*size(src)
      allocate (dst(lbound(src, 1):ubound(src, 1), lbound(src, 2):ubound(src, 2)), stat=status)
      if (status == 0) dst(:, :) = src
   end subroutine copy_reals_2

   subroutine copy_integers_1(src, dst, status, bytes)
      integer, allocatable, intent(in) :: src(:)
      integer, allocatable, intent(inout) :: dst(:)
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      status = 0
      if (allocated(dst)) deallocate (dst)
      if (.not. allocated(src)) return
      bytes = 4.0_dp*size(src)
      allocate (dst(lbound(src, 1):ubound(src, 1)), stat=status)
      if (status == 0) dst(:) = src
   end subroutine copy_integers_1

   subroutine copy_integers_2(src, dst, status, bytes)
      integer, allocatable, intent(in) :: src(:, :)
      integer, allocatable, intent(inout) :: dst(:, :)
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      status = 0
      if (allocated(dst)) deallocate (dst)
      if (.not. allocated(src)) return
      bytes = 4.0_dp*size(src)
      allocate (dst(lbound(src, 1):ubound(src, 1), lbound(src, 2):ubound(src, 2)), stat=status)
      if (status == 0) dst(:, :) = src
   end subroutine copy_integers_2

   subroutine copy_logicals_2(src, dst, status, bytes)
      logical, allocatable, intent(in) :: src(:, :)
      logical, allocatable, intent(inout) :: dst(:, :)
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      status = 0
      if (allocated(dst)) deallocate (dst)
      if (.not. allocated(src)) return
      bytes = 4.0_dp*size(src)
      allocate (dst(lbound(src, 1):ubound(src, 1), lbound(src, 2):ubound(src, 2)), stat=status)
      if (status == 0) dst(:, :) = src
   end subroutine copy_logicals_2

   subroutine copy_reals_1(src, dst, status, bytes)
      real(dp), allocatable, intent(in) :: src(:)
      real(dp), allocatable, intent(inout) :: dst(:)
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      status = 0
      if (allocated(dst)) deallocate (dst)
      if (.not. allocated(src)) return
      bytes = 8.0_dp*size(src)
      allocate (dst(lbound(src, 1):ubound(src, 1)), stat=status)
      if (status == 0) dst(:) = src
   end subroutine copy_reals_1

   subroutine copy_logicals_1(src, dst, status, bytes)
      logical, allocatable, intent(in) :: src(:)
      logical, allocatable, intent(inout) :: dst(:)
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      status = 0
      if (allocated(dst)) deallocate (dst)
      if (.not. allocated(src)) return
      bytes = 4.0_dp*size(src)
      allocate (dst(lbound(src, 1):ubound(src, 1)), stat=status)
      if (status == 0) dst(:) = src
   end subroutine copy_logicals_1

   subroutine reserve_reals_1(array, n, status, bytes)
      real(dp), allocatable, intent(inout) :: array(:)
      integer, intent(in) :: n
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      status = 0
      if (allocated(array)) then
         if (size(array) == n) return
         deallocate (array)
      end if
      bytes = 8.0_dp*max(n, 0)
      allocate (array(n), stat=status)
   end subroutine reserve_reals_1

   subroutine reserve_reals_2(array, rows, columns, status, bytes)
      real(dp), allocatable, intent(inout) :: array(:, :)
      integer, intent(in) :: rows, columns
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      status = 0
      if (allocated(array)) then
         if (size(array, 1) == rows .and. size(array, 2) == columns) return
         deallocate (array)
      end if
      bytes = 8.0_dp*max(rows, 0)*max(columns, 0)
      allocate (array(rows, columns), stat=status)
   end subroutine reserve_reals_2

   subroutine reserve_logicals_1(array, n, status, bytes)
      logical, allocatable, intent(inout) :: array(:)
      integer, intent(in) :: n
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      status = 0
      if (allocated(array)) then
         if (size(array) == n) return
         deallocate (array)
      end if
      bytes = 4.0_dp*max(n, 0)
      allocate (array(n), stat=status)
   end subroutine reserve_logicals_1

   subroutine reserve_integers_1(array, n, status, bytes)
      integer, allocatable, intent(inout) :: array(:)
      integer, intent(in) :: n
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      status = 0
      if (allocated(array)) then
         if (size(array) == n) return
         deallocate (array)
      end if
      bytes = 4.0_dp*max(n, 0)
      allocate (array(n), stat=status)
   end subroutine reserve_integers_1

end module uniarc_copy
