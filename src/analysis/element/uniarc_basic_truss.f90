!> The truss (bar) basic element: axial force only.
!>
!> In the basic system of docs/theory.md §1.8 — deformations v = (e, θ̄1, θ̄2), forces q = (N, M1, M2) —
!> a bar pinned at both ends carries N = EA/L e and no end moments, whatever its end rotations:
!>
!>   q = (EA/L e, 0, 0),   Kb = diag(EA/L, 0, 0)       (Crisfield 1991, vol. 1, ch. 3, the truss element)
!>
!> With the corotational transformation this is the exact bar of Crisfield's "rotated engineering
!> strain" e/L0, e = Ln − L0 (large rotations, small strain); with the linear one the classic
!> small-displacement truss. Its end rotations get no stiffness: a node held only by trusses needs its
!> rotation held (the deck does it, docs/input.md `*ELEMENT`).
module uniarc_basic_truss
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: truss_basic_response

contains

   !> Basic forces q = (N, 0, 0) (3) and basic stiffness Kb = diag(EA/L, 0, 0) (3×3) at the basic
   !> deformations `deformation` = (e, θ̄1, θ̄2) of a bar of initial length `length` and axial stiffness
   !> `ea` (force); the end rotations θ̄1, θ̄2 do no work.
   pure subroutine truss_basic_response(length, ea, deformation, force, stiffness)
      real(dp), intent(in) :: length, ea
      real(dp), intent(in) :: deformation(3)
      real(dp), intent(out) :: force(3)
      real(dp), intent(out) :: stiffness(3, 3)
      stiffness = 0.0_dp
      stiffness(1, 1) = ea/length
      force = [stiffness(1, 1)*deformation(1), 0.0_dp, 0.0_dp]
   end subroutine truss_basic_response

end module uniarc_basic_truss
