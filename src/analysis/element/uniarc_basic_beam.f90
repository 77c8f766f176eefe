!> The Euler–Bernoulli basic element: the law of a straight two-node beam in its basic system.
!>
!> Basic system (shared by every basic element, docs/theory.md §1.8): the deformations
!> v = (e, θ̄1, θ̄2) — the chord elongation and the two end rotations relative to the chord — and the
!> work-conjugate basic forces q = (N, M1, M2) — the axial force (tension positive) and the end moments
!> (counter-clockwise positive). A coordinate transformation (uniarc_transformation) turns v and q into
!> global element vectors; the basic element never sees the element's position or rotation.
!>
!>   N = EA/L e,   [M1; M2] = EI/L [4 2; 2 4] [θ̄1; θ̄2]      (Crisfield 1991, vol. 1, §7.2)
module uniarc_basic_beam
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: beam_basic_stiffness, beam_basic_response

contains

   !> Basic stiffness Kb (3×3) relating (e, θ̄1, θ̄2) to (N, M1, M2) of a straight element of length
   !> `length` with axial stiffness `ea` (force) and bending stiffness `ei` (force × length²).
   pure function beam_basic_stiffness(length, ea, ei) result(kb)
      real(dp), intent(in) :: length, ea, ei
      real(dp) :: kb(3, 3)
      kb = 0.0_dp
      kb(1, 1) = ea/length
      kb(2, 2) = 4.0_dp*ei/length
      kb(3, 3) = 4.0_dp*ei/length
      kb(2, 3) = 2.0_dp*ei/length
      kb(3, 2) = 2.0_dp*ei/length
   end function beam_basic_stiffness

   !> Basic forces q = Kb v (3) and basic stiffness Kb (3×3) at the basic deformations v = `deformation`
   !> (e, θ̄1, θ̄2) of an element of initial length `length` (the law is linear: small strains).
   pure subroutine beam_basic_response(length, ea, ei, deformation, force, stiffness)
      real(dp), intent(in) :: length, ea, ei
      real(dp), intent(in) :: deformation(3)
      real(dp), intent(out) :: force(3)
      real(dp), intent(out) :: stiffness(3, 3)
      stiffness = beam_basic_stiffness(length, ea, ei)
      force = matmul(stiffness, deformation)
   end subroutine beam_basic_response

end module uniarc_basic_beam
