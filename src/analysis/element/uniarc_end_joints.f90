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
module uniarc_end_joints
   use uniarc_kinds, only: dp
   use uniarc_model, only: end_joint_t
   implicit none
   private
   public :: jointed_basic_response, has_joints

contains

   !> True when a joint of `joints` (2) is not rigid: a hinge or a spring.
   pure logical function has_joints(joints)
      type(end_joint_t), intent(in) :: joints(2)
      has_joints = any(joints%hinge) .or. any(joints%compliance > 0.0_dp)
   end function has_joints

   !> Basic forces q = Kb v (3) and basic stiffness Kb (3×3) of a member of axial stiffness `axial`
   !> (EA/L, force per length) and bending flexibility `flexibility` (2×2, symmetric positive definite)
   !> with the end joints `joints` (2) in series, at the basic deformations `deformation` (e, θ̄1, θ̄2).
   !> Kb(2:3, 2:3) is the inverse of flexibility + diag(compliances), hinged rows and columns condensed
   !> out (zero).
   pure subroutine jointed_basic_response(axial, flexibility, joints, deformation, force, stiffness)
      real(dp), intent(in) :: axial
      real(dp), intent(in) :: flexibility(2, 2)
      type(end_joint_t), intent(in) :: joints(2)
      real(dp), intent(in) :: deformation(3)
      real(dp), intent(out) :: force(3)
      real(dp), intent(out) :: stiffness(3, 3)
      real(dp) :: f(2, 2), determinant
      integer :: i
      f = flexibility
      do i = 1, 2
         f(i, i) = f(i, i) + joints(i)%compliance
      end do
      stiffness = 0.0_dp
      stiffness(1, 1) = axial
      if (joints(1)%hinge .and. joints(2)%hinge) then
         continue
      else if (joints(1)%hinge) then
         stiffness(3, 3) = 1.0_dp/f(2, 2)
      else if (joints(2)%hinge) then
         stiffness(2, 2) = 1.0_dp/f(1, 1)
      else
         determinant = f(1, 1)*f(2, 2) - f(1, 2)*f(2, 1)
         stiffness(2, 2) = f(2, 2)/determinant
         stiffness(3, 3) = f(1, 1)/determinant
         stiffness(2, 3) = -f(1, 2)/determinant
         stiffness(3, 2) = -f(2, 1)/determinant
      end if
      force = matmul(stiffness, deformation)
   end subroutine jointed_basic_response

end module uniarc_end_joints
