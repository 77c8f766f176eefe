!> The Timoshenko (shear-deformable) basic element: the law of a straight two-node beam with shear
!> deformation in the basic system of docs/theory.md §1.8 — deformations v = (e, θ̄1, θ̄2), forces
!> q = (N, M1, M2).
!>
!> The law is the exact one of a prismatic Timoshenko beam without load on its span. In the basic system
!> the shear force is V = (M1 + M2)/L, constant, and the complementary energy of the bending moment (linear
!> along the beam) and of the shear force gives the bending flexibility
!>
!>   F = L/(6 EI) [2 −1; −1 2] + 1/(κGA L) [1 1; 1 1],          [θ̄1; θ̄2] = F [M1; M2],
!>
!> whose inverse is the classic shear-deformable stiffness with φ = 12 EI/(κGA L²):
!>
!>   N = EA/L e,   [M1; M2] = EI/(L (1 + φ)) [4 + φ, 2 − φ; 2 − φ, 4 + φ] [θ̄1; θ̄2]
!>
!> (Przemieniecki 1968, Theory of Matrix Structural Analysis, ch. 5, the beam with shear deformation;
!> the same matrix is Reddy's interdependent-interpolation element, Reddy 1997, Comput. Methods Appl.
!> Mech. Engrg. 149:113–132). Being exact for any L, it has no shear locking: as κGA L²/EI grows, φ → 0
!> and the law tends to the Euler–Bernoulli one of uniarc_basic_beam. Inside the corotational
!> transformation (uniarc_transformation, Crisfield 1991, vol. 1, ch. 7; the element-independent frame of
!> Felippa & Haugen 2005, Comput. Methods Appl. Mech. Engrg. 194:2285–2335) it is the corotational
!> Timoshenko beam: large rotations, small strains.
module uniarc_basic_timoshenko
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: timoshenko_basic_response, beam_bending_flexibility, beam_shear_flexibility

contains

   !> Bending flexibility F (2×2, radian per moment) of the basic system of a straight beam of length
   !> `length`, bending stiffness `ei` (force × length²) and shear stiffness `gas` = κGA (force); `gas` = 0
   !> means no shear deformation (the Euler–Bernoulli beam, F = L/(6 EI) [2 −1; −1 2]).
   pure function beam_bending_flexibility(length, ei, gas) result(flexibility)
      real(dp), intent(in) :: length, ei, gas
      real(dp) :: flexibility(2, 2)
      flexibility = (length/(6.0_dp*ei))*reshape([2.0_dp, -1.0_dp, -1.0_dp, 2.0_dp], [2, 2])
      if (gas > 0.0_dp) flexibility = flexibility + beam_shear_flexibility(length, gas)
   end function beam_bending_flexibility

   !> Shear flexibility s = 1/(κGA L) (radian per moment) of the basic system of a straight beam of length
   !> `length` and shear stiffness `gas` = κGA (force): the term of F added to all four entries (module
   !> header); 0 for `gas` = 0 (no shear deformation). End joints take it apart from the bending part
   !> (uniarc_end_joints: series_determinant).
   pure real(dp) function beam_shear_flexibility(length, gas) result(s)
      real(dp), intent(in) :: length, gas
      s = 0.0_dp
      if (gas > 0.0_dp) s = 1.0_dp/(gas*length)
   end function beam_shear_flexibility

   !> Basic forces q = Kb v (3) and basic stiffness Kb (3×3) of the Timoshenko beam at the basic
   !> deformations v = `deformation` (e, θ̄1, θ̄2) of an element of initial length `length`, axial
   !> stiffness `ea`, bending stiffness `ei` and shear stiffness `gas` = κGA > 0 (the law is linear: small
   !> strains). Kb in the closed form of the module header.
   pure subroutine timoshenko_basic_response(length, ea, ei, gas, deformation, force, stiffness)
      real(dp), intent(in) :: length, ea, ei, gas
      real(dp), intent(in) :: deformation(3)
      real(dp), intent(out) :: force(3)
      real(dp), intent(out) :: stiffness(3, 3)
      real(dp) :: phi, factor
      phi = 12.0_dp*ei/(gas*length**2)
      factor = ei/(length*(1.0_dp + phi))
      stiffness = 0.0_dp
      stiffness(1, 1) = ea/length
      stiffness(2, 2) = factor*(4.0_dp + phi)
      stiffness(3, 3) = stiffness(2, 2)
      stiffness(2, 3) = factor*(2.0_dp - phi)
      stiffness(3, 2) = stiffness(2, 3)
      force = matmul(stiffness, deformation)
   end subroutine timoshenko_basic_response

end module uniarc_basic_timoshenko
