!> Rotational-spring joints with a moment limit (`*RELEASE, MY=`): the elastic–perfectly plastic spring
!> between an element end and its node, in series with the member (docs/theory.md §1.11).
!>
!> A joint i of stiffness k_i = 1/c_i and moment limit M_y,i carries a plastic rotation θ_p,i, the
!> history of the element: M_i = k_i (Δθ_i − θ_p,i), |M_i| ≤ M_y,i, Δθ_i the joint's turn. In series with
!> the member's bending flexibility F (as uniarc_end_joints), the basic end rotations are
!>
!>   θ̄ = (F + diag(c)) M + θ_p,
!>
!> so the plastic rotations enter as natural deformations. The state update is the backward-Euler
!> return mapping of perfect plasticity from the committed θ_p (Simo & Hughes 1998, Computational
!> Inelasticity, §1.2 (1-D) and §3.3 (closest-point projection)): with f = F + diag(c) symmetric positive
!> definite and d = θ̄ − θ_p(committed), the moments minimise the complementary energy ½ Mᵀ f M − Mᵀ d
!> on the box |M_i| ≤ M_y,i — a strictly convex problem whose solution is unique. Its Kuhn–Tucker
!> conditions say: Δθ_p = d − f M, with Δθ_p,i = 0 where |M_i| < M_y,i and sign(Δθ_p,i) = sign(M_i)
!> where |M_i| = M_y,i (a joint at its limit flows in the direction of its moment; an unloading one is
!> elastic again). With two joints the solution is found in closed form among the 3² states of the
!> ends (elastic, at +M_y, at −M_y): on each, the elastic ends solve f_EE M_E = d_E − f_EY M_Y.
!>
!> The consistent tangent of a joint at its limit is 0 (dM = 0): the element's bending stiffness is then
!> that of a hinged end (the other end's 1/f_jj), as for a hinge of uniarc_end_joints. A joint at its
!> limit to within `limit_tolerance` is taken as yielding, so that the tangent at a committed state
!> whose joint flowed in the step is the plastic one (OpenSees keeps the tangent of the last trial
!> likewise; McKenna 1997, ch. 4).
module uniarc_joint_plasticity
   use uniarc_kinds, only: dp
   use uniarc_model, only: end_joint_t
   use uniarc_end_joints, only: series_determinant
   implicit none
   private
   public :: plastic_joint_response, has_moment_limit

   !> Relative slack of the return mapping's conditions: a moment within 1e-9 M_y of the limit is at
   !> it, and a plastic increment down to −1e-9 M_y f_ii (the rotation that slack stands for) is none.
   !> Far above round-off of the moments (1e-16 relative) and far below any engineering tolerance.
   real(dp), parameter :: limit_tolerance = 1.0e-9_dp

   !> The states tried, most ends at the limit first: (state of end 1, state of end 2), 0 elastic,
   !> ±1 at ±M_y. The first admissible one is taken (near the limits several are, with the same M to
   !> within the tolerance; the first gives the plastic tangent).
   integer, parameter :: states(2, 9) = reshape([1, 1, 1, -1, -1, 1, -1, -1, 1, 0, -1, 0, 0, 1, 0, -1, 0, 0], [2, 9])

contains

   !> True when a joint of `joints` (2) has a moment limit.
   pure logical function has_moment_limit(joints)
      type(end_joint_t), intent(in) :: joints(2)
      has_moment_limit = any(joints%moment_limit > 0.0_dp)
   end function has_moment_limit

   !> Basic forces q (3) and consistent basic stiffness Kb (3×3) of a member of axial stiffness `axial`
   !> (EA/L, force per length), bending flexibility `flexibility` (2×2, symmetric positive definite,
   !> radian per moment; the Euler–Bernoulli part) and shear flexibility `shear` (optional, radian per
   !> moment: 1/(κGA L) of a Timoshenko member, added to all four entries; 0 when absent) with the end
   !> joints `joints` (2: hinges, springs, springs with a moment limit) in series, at the basic
   !> deformations `deformation` (e, θ̄1, θ̄2) from the committed plastic rotations `committed` (2,
   !> radian; 0 at a joint without limit); `plastic` (2) returns the trial plastic rotations (the
   !> committed ones plus this state's plastic increments). The determinant of the series flexibility
   !> is formed from its parts (uniarc_end_joints: series_determinant). No errors: the box problem
   !> always has its solution (module header).
   pure subroutine plastic_joint_response(axial, flexibility, joints, deformation, committed, force, stiffness, plastic, &
                                          shear)
      real(dp), intent(in) :: axial
      real(dp), intent(in) :: flexibility(2, 2)
      type(end_joint_t), intent(in) :: joints(2)
      real(dp), intent(in) :: deformation(3), committed(2)
      real(dp), intent(out) :: force(3), stiffness(3, 3), plastic(2)
      real(dp), intent(in), optional :: shear
      real(dp) :: g(2, 2), f(2, 2), s, d(2), moment(2), residual(2), best_moment(2), best_residual(2), violation, best
      logical :: fixed(2), best_fixed(2)
      integer :: i, k, best_state
      s = 0.0_dp
      if (present(shear)) s = shear
      g = flexibility
      do i = 1, 2
         g(i, i) = g(i, i) + joints(i)%compliance
      end do
      f = g + s
      d = deformation(2:3) - committed
      best = huge(1.0_dp)
      best_state = 0
      do k = 1, size(states, 2)
         if (any(states(:, k) /= 0 .and. .not. joints%moment_limit > 0.0_dp)) cycle
         fixed = joints%hinge .or. states(:, k) /= 0
         moment = real(states(:, k), dp)*joints%moment_limit
         call solve_free_ends(f, series_determinant(g, s), d, fixed, moment)
         residual = d - matmul(f, moment)
         violation = 0.0_dp
         do i = 1, 2
            if (.not. joints(i)%moment_limit > 0.0_dp) cycle
            if (states(i, k) == 0) then
               violation = max(violation, abs(moment(i))/joints(i)%moment_limit - 1.0_dp)
            else
               violation = max(violation, -real(states(i, k), dp)*residual(i)/(joints(i)%moment_limit*f(i, i)))
            end if
         end do
         if (violation < best) then
            best = violation
            best_state = k
            best_moment = moment
            best_residual = residual
            best_fixed = fixed
         end if
         if (violation <= limit_tolerance) exit
      end do
      plastic = committed
      do i = 1, 2
         if (states(i, best_state) /= 0) plastic(i) = committed(i) + best_residual(i)
      end do
      stiffness = 0.0_dp
      stiffness(1, 1) = axial
      stiffness(2:3, 2:3) = free_end_stiffness(f, series_determinant(g, s), best_fixed)
      force(1) = axial*deformation(1)
      force(2:3) = best_moment
   end subroutine plastic_joint_response

   !> The moments of the free ends (not `fixed`) from f M = d, the fixed ends' moments given in
   !> `moment` (2) and kept; `determinant` is det f (series_determinant).
   pure subroutine solve_free_ends(f, determinant, d, fixed, moment)
      real(dp), intent(in) :: f(2, 2), determinant, d(2)
      logical, intent(in) :: fixed(2)
      real(dp), intent(inout) :: moment(2)
      if (fixed(1) .and. fixed(2)) then
         return
      else if (fixed(1)) then
         moment(2) = (d(2) - f(2, 1)*moment(1))/f(2, 2)
      else if (fixed(2)) then
         moment(1) = (d(1) - f(1, 2)*moment(2))/f(1, 1)
      else
         moment(1) = (f(2, 2)*d(1) - f(1, 2)*d(2))/determinant
         moment(2) = (f(1, 1)*d(2) - f(2, 1)*d(1))/determinant
      end if
   end subroutine solve_free_ends

   !> The bending stiffness (2×2) of the flexibility f (2×2, determinant `determinant`) with the `fixed`
   !> ends' moments held (a hinge, a joint at its limit: dM = 0, their rows and columns zero).
   pure function free_end_stiffness(f, determinant, fixed) result(k)
      real(dp), intent(in) :: f(2, 2), determinant
      logical, intent(in) :: fixed(2)
      real(dp) :: k(2, 2)
      k = 0.0_dp
      if (fixed(1) .and. fixed(2)) then
         return
      else if (fixed(1)) then
         k(2, 2) = 1.0_dp/f(2, 2)
      else if (fixed(2)) then
         k(1, 1) = 1.0_dp/f(1, 1)
      else
         k(1, 1) = f(2, 2)/determinant
         k(2, 2) = f(1, 1)/determinant
         k(1, 2) = -f(1, 2)/determinant
         k(2, 1) = -f(2, 1)/determinant
      end if
   end function free_end_stiffness

end module uniarc_joint_plasticity
