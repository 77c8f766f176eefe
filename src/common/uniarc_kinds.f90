!> The one kind module of uniarc: every real is real(dp).
module uniarc_kinds
   use, intrinsic :: iso_fortran_env, only: real64, int64
   implicit none
   private
   public :: dp, i8

   !> Working precision of every real in uniarc (IEEE double).
   integer, parameter :: dp = real64
   !> Long integer kind for counts that may exceed 2**31 (band storage sizes).
   integer, parameter :: i8 = int64
end module uniarc_kinds
