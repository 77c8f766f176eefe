!> End joints of a beam in the basic system: hinges (moment releases) and linear rotational springs
!> between an element end and its node, as at the joints of a segmental tunnel lining.
!>
!> A joint at end i sits in series with the member: the node's rotation relative to the chord is the
!> member end's plus the joint's turn M_i/k_i. In flexibility form (docs/theory.md §1.10)
!>
!>   [θ̄1; θ̄2] = (F + diag(1/k1, 1/k2)) [M1; M2],
!>
!> F the member's bending flexibility (uniarc_basic_timoshenko: beam_bending_flexibility). A hinge
!> (k = 0) carries no moment: its row and column are condensed out, M_i = 0, and the other end's
!> stiffness is 1/F_jj (with its own joint); with both ends hinged the element carries N only. The
!> bending stiffness is the inverse of the (condensed) flexibility, so a spring of any k, 0 < k < ∞,
!> lies between the hinge and the rigid joint (McGuire, Gallagher & Ziemian 2000, Matrix Structural
!> Analysis, 2nd ed., the semi-rigid connection in flexibility form). The axial law is the member's.
!>
!> A Timoshenko member's flexibility is G + s [1 1; 1 1], G = F_b + diag(1/k1, 1/k2) (F_b its bending
!> flexibility) and s = 1/(κGA L) its shear flexibility, given apart: where s ≫ |G| (κGA L² ≪ EI, a
!> member nearly without shear stiffness) G is lost in the round-off of the sums G_ij + s and the
!> determinant formed from them cancels to zero. It is formed from the parts instead, by the matrix
!> determinant lemma, det(G + s 1 1ᵀ) = det G + s 1ᵀ adj(G) 1 = det G + s (G11 + G22 − G12 − G21),
!> whose terms are all positive (G is positive definite, G12 = −L/(6EI) ≤ 0): no cancellation.
module uniarc_end_joints
   use uniarc_kinds, only: dp
   use uniarc_model, only: end_joint_t
   implicit none
   private
   public :: jointed_basic_response, has_joints, series_determinant

contains

   !> True when a joint of `joints` (2) is not rigid: a hinge or a spring.
   pure logical function has_joints(joints)
      type(end_joint_t), intent(in) :: joints(2)
      has_joints = any(joints%hinge) .or. any(joints%compliance > 0.0_dp)
   end function has_joints

   !> Basic forces q = Kb v (3) and basic stiffness Kb (3×3) of a member of axial stiffness `axial`
   !> (EA/L, force per length), bending flexibility `flexibility` (2×2, symmetric positive definite,
   !> radian per moment; the Euler–Bernoulli part, without shear) and shear flexibility `shear`
   !> (optional, radian per moment: 1/(κGA L) of a Timoshenko member, added to all four entries; 0 when
   !> absent) with the end joints `joints` (2) in series, at the basic deformations `deformation`
   !> (e, θ̄1, θ̄2). Kb(2:3, 2:3) is the inverse of flexibility + shear + diag(compliances), hinged rows
   !> and columns condensed out (zero); its determinant by series_determinant. No errors.
   pure subroutine jointed_basic_response(axial, flexibility, joints, deformation, force, stiffness, shear)
      real(dp), intent(in) :: axial
      real(dp), intent(in) :: flexibility(2, 2)
      type(end_joint_t), intent(in) :: joints(2)
      real(dp), intent(in) :: deformation(3)
      real(dp), intent(out) :: force(3)
      real(dp), intent(out) :: stiffness(3, 3)
      real(dp), intent(in), optional :: shear
      real(dp) :: g(2, 2), f(2, 2), s, determinant
      integer :: i
      s = 0.0_dp
      if (present(shear)) s = shear
      g = flexibility
      do i = 1, 2
         g(i, i) = g(i, i) + joints(i)%compliance
      end do
      f = g + s
      stiffness = 0.0_dp
      stiffness(1, 1) = axial
      if (joints(1)%hinge .and. joints(2)%hinge) then
         continue
      else if (joints(1)%hinge) then
         stiffness(3, 3) = 1.0_dp/f(2, 2)
      else if (joints(2)%hinge) then
         stiffness(2, 2) = 1.0_dp/f(1, 1)
      else
         determinant = series_determinant(g, s)
         stiffness(2, 2) = f(2, 2)/determinant
         stiffness(3, 3) = f(1, 1)/determinant
         stiffness(2, 3) = -f(1, 2)/determinant
         stiffness(3, 2) = -f(2, 1)/determinant
      end if
      force = matmul(stiffness, deformation)
   end subroutine jointed_basic_response

   !> The determinant of g + s [1 1; 1 1] (radian² per moment²) for `g` (2×2, symmetric positive
   !> definite with g12 ≤ 0: a member's bending flexibility plus its joints' compliances) and `s` ≥ 0 (a
   !> shear flexibility), by the matrix determinant lemma (module header): det g + s (g11 + g22 − g12 −
   !> g21), a sum of positive terms that cannot cancel, where the product form (g11 + s)(g22 + s) −
   !> (g12 + s)² loses det g in round-off once s exceeds |g|/ε (zero: a division by zero). With s = 0
   !> it is the product form exactly. No errors.
   pure real(dp) function series_determinant(g, s) result(determinant)
      real(dp), intent(in) :: g(2, 2)
      real(dp), intent(in) :: s
      determinant = g(1, 1)*g(2, 2) - g(1, 2)*g(2, 1)
      if (s > 0.0_dp) determinant = determinant + s*(g(1, 1) + g(2, 2) - g(1, 2) - g(2, 1))
   end function series_determinant

end module uniarc_end_joints
