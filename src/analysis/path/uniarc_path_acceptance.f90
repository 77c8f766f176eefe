!> The tests of a converged step of the path before it is committed (docs/theory.md §2.3): whether it
!> moved in λ alone (a load step: no direction to test), landed farther from its predictor than the
!> predictor's length, or left the branch it followed (its chord across the landing tangent, or
!> walking back against the last increment). Each test is a pure function of the step's vectors;
!> path_advance decides what a failed test does (cut the step, or take the corner step).
module uniarc_path_acceptance
   use uniarc_kinds, only: dp
   use uniarc_dof_map, only: dof_map_t
   use uniarc_path_state, only: path_state_t, step_trial_t, masked_dot, masked_norm
   use uniarc_path_integrator, only: degenerate_tangent
   use uniarc_contact_lcp, only: degenerate_fraction
   implicit none
   private
   public :: degenerate_step, far_from_predictor, far_from_committed_tangent, off_branch, tangent_turn_cosine

   !> A step whose ends agree (count of negative pivots, sign of dλ/ds, working set) may turn the
   !> path's tangent by at most 45° (docs/theory.md §2.3, "a tangent that turns too far"): the steps
   !> that crossed the neck of a loop of ex. 3's long path turned it by 58° and 62°, the angle between
   !> the branches there; a bound on the angle between successive tangents is a classic control of
   !> the step of a continuation method (Allgower & Georg 1990, ch. 6).
   real(dp), parameter, public :: max_turn_cosine = 0.7071067811865476_dp

contains

   !> Whether a converged attempt went in λ alone, its displacement round-off (the contacts carry the
   !> whole reference load, docs/theory.md §2.7: a load step, or a step under load control): it has
   !> no direction for the angle and distance tests of a step.
   !> The increment is also round-off where it is at most degenerate_fraction of the displacements the
   !> step starts from (state, the state before the step): Newton's corrections of a state that an
   !> earlier analysis step loaded (a beam settled under its weight, then heated between held ends)
   !> carry the round-off of that state, which near a critical point grows past degenerate_fraction of
   !> ψ|Δλ| (the heavy beam on its bed, 0.5 % past its bifurcation: ‖Δu‖ = 1.2e-17 for Δλ = 0.1 and
   !> ψ = 1e-4; its settled ‖u‖ is 1e-2) and then points anywhere.
   pure logical function degenerate_step(state, trial)
      type(path_state_t), intent(in) :: state
      type(step_trial_t), intent(in) :: trial
      degenerate_step = .false.
      if (.not. (abs(trial%dlambda) > 0.0_dp)) return
      degenerate_step = degenerate_tangent(state, trial%increment/abs(trial%dlambda))
      if (allocated(state%u) .and. .not. degenerate_step) &
         degenerate_step = masked_norm(state%map, trial%increment) <= degenerate_fraction*masked_norm(state%map, state%u)
   end function degenerate_step

   !> Whether a converged attempt landed farther from its predictor than the predictor's own length
   !> (displacement norm): Newton's corrections are O(Δl²) on the branch the predictor follows, while
   !> a step that converges on another branch lands at a distance of its own. Measured on every deck
   !> of the repository: at most 0.98 of the predictor on the traced branches (arch_above_long_path);
   !> 36 for Walker's arch under load control jumping past its limit point onto the inverted branch.
   pure logical function far_from_predictor(map, trial)
      type(dof_map_t), intent(in) :: map
      type(step_trial_t), intent(in) :: trial
      far_from_predictor = masked_norm(map, trial%increment - trial%predictor) > masked_norm(map, trial%predictor)
   end function far_from_predictor

   !> far_from_predictor for a converged attempt that ends in the committed working set after its
   !> predictor's contact LCP had taken another (trial%predictor_set_changed): a contact whose
   !> linearised gap closed over the step and whose exact gap does not (a grazing contact, uniarc_contact
   !> grazing; a convex corner passed close by). Its predictor followed that other set, which the
   !> corrector left; the predictor of the set the step ends in is the committed tangent K⁻¹R times
   !> the step's Δλ, and the same test is made against it (a jump to another branch of the committed
   !> set is as far from it as from any predictor).
   pure logical function far_from_committed_tangent(state, trial) result(far)
      type(path_state_t), intent(in) :: state
      type(step_trial_t), intent(in) :: trial
      far = masked_norm(state%map, trial%increment - trial%dlambda*state%tangent_displacement) > &
            masked_norm(state%map, trial%dlambda*state%tangent_displacement)
   end function far_from_committed_tangent

   !> Whether a converged step of increment Δx (n) from a state reached by `last` (n; zero at the
   !> start) lands off the branch it followed: the path's tangent at the landing state, `tangent` (n,
   !> K⁻¹R there), makes an angle above 60° with the chord Δx, or Δx makes an obtuse angle with the
   !> last increment (the path walked back). On a traced branch the chord of a step is close to the
   !> tangents at both its ends (half the turning angle of the step); a step that converged on a
   !> crossing branch lands where that branch's tangent is across it. Measured on every deck of the
   !> repository: angles at most 22° (|cos| ≥ 0.925) to the landing tangent away from sharp folds, 58°
   !> (|cos| 0.52) at the folds of arch_above_long_path, and 40° (cos ≥ 0.77) to the
   !> last increment; Walker's arch (ex. 3, k = 1e5, max_increment 50) jumping onto another loop: 87°.
   pure logical function off_branch(map, increment, last, tangent)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: increment(:), last(:), tangent(:)
      real(dp) :: size_step, size_tangent, size_last
      size_step = masked_norm(map, increment)
      size_tangent = masked_norm(map, tangent)
      size_last = masked_norm(map, last)
      off_branch = .false.
      if (size_step > 0.0_dp .and. size_tangent > 0.0_dp) then
         off_branch = abs(masked_dot(map, increment, tangent)) < 0.5_dp*size_step*size_tangent
      end if
      if (size_step > 0.0_dp .and. size_last > 0.0_dp) then
         off_branch = off_branch .or. masked_dot(map, increment, last) < 0.0_dp
      end if
   end function off_branch

   !> The cosine of the angle by which the path's tangent turns over a step: between the tangent
   !> `before` (n, K⁻¹R at the step's start, followed in the sense `sense_before` = ±1) and `after`
   !> (n, at its end, sense `sense_after`), both oriented forward along the path (2 when either is
   !> zero: no direction to compare). K⁻¹R changes sign at a limit point, where the path goes on
   !> smoothly; the senses (state%direction) orient it.
   pure real(dp) function tangent_turn_cosine(map, before, sense_before, after, sense_after) result(cosine)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: before(:), after(:)
      integer, intent(in) :: sense_before, sense_after
      real(dp) :: size_before, size_after
      size_before = masked_norm(map, before)
      size_after = masked_norm(map, after)
      cosine = 2.0_dp
      if (.not. (size_before > 0.0_dp .and. size_after > 0.0_dp)) return
      cosine = real(sense_before*sense_after, dp)*masked_dot(map, before, after)/(size_before*size_after)
   end function tangent_turn_cosine

end module uniarc_path_acceptance
