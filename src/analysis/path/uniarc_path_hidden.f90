!> Critical points hidden in a step (docs/theory.md §2.3): a step long against the path's turning can
!> pass two limit points (a loop of the path) or two changes of the inertia at once, or converge on
!> a neighbouring branch across such a loop. Its ends then agree — same sign of dλ/ds, same count of
!> negative pivots — and neither the locator (uniarc_path_locate) nor the angle tests see anything.
!> The state half-way along the step tells: re-solved from the step's start with half its length, it
!> lies on the loop and disagrees with both ends, or (Chan's corrections are drawn to the fold) it
!> stops near the start while the full step ended far beyond. Only steps that turn are checked: the
!> re-solution costs as much as the step.
module uniarc_path_hidden
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t
   use uniarc_path_state, only: path_state_t, path_system_t, masked_dot, masked_norm
   use uniarc_path_probe, only: re_solve_step, restore_tangent
   use uniarc_error, only: error_t
   use uniarc_path_integrator, only: degenerate_tangent
   use uniarc_critical_points, only: opposite_signs, same_signs
   implicit none
   private
   public :: find_hidden_pair, eigenvalue_overshoot

   !> A step is checked when the path's tangent at its end makes more than 25° with its chord (|cos|
   !> below this): the chord of a step on a branch is close to the tangents at its ends (at most 22°
   !> from the landing tangent on the decks of the repository away from sharp folds, docs/theory.md
   !> §2.3; up to 58° at the folds of ex. 3's long path, which the check passes), while the step that
   !> skipped a loop of ex. 3 (k = 1e5) made 42°. 16 of the 2393 accepted arc-length steps of the
   !> repository's decks are checked.
   real(dp), parameter :: turning_cosine = 0.9_dp
   !> The second half of a checked step may be at most this many times as long as its first.
   real(dp), parameter :: halves_ratio = 3.0_dp

contains

   !> `hides`: whether the converged step from `before` (the committed state at its start, system not
   !> allocated) to `after` (the state it reached with `trial`, of length `length` in the units of
   !> state%step_length) hides a pair of critical points: its ends agree in the sign of dλ/ds and
   !> the count of negative pivots, but the state re-solved half-way (a step of length/2 from
   !> `before`) has the other sign or another count, or the step's second half is more than three
   !> times as long as its first (||u_b − u_h|| > 3||u_h − u_a||: on a branch the halves are alike; a
   !> step through a sharp fold has its half-way state beyond the full step's end, a ratio below 1;
   !> the loop skipped by ex. 3 at k = 1e5 with steps of 20 times the first, 15). Checked only where
   !> the path's tangent at `after` makes more than 25° with the chord. `system` holds after's
   !> committed tangent on entry and on return. A half step that does not converge proves nothing
   !> (false).
   subroutine find_hidden_pair(model, before, after, system, length, hides, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: before, after   !< unchanged (inout for copy_state)
      type(path_system_t), intent(inout) :: system
      real(dp), intent(in) :: length
      logical, intent(out) :: hides
      type(error_t), allocatable, intent(out) :: error
      type(path_state_t) :: half
      real(dp), allocatable :: chord(:)
      real(dp) :: size_chord, size_tangent, first, second
      logical :: ok
      hides = .false.
      if (opposite_signs(before%point%dlambda_ds, after%point%dlambda_ds)) then
         ! A regular limit point changes the sign of det K_T (the augmented tangent is regular there,
         ! one eigenvalue of K_T crosses zero: docs/theory.md §2.2), so the count of negative pivots
         ! changes with the slope's sign. A step that turned the slope with the count unchanged, the
         ! working set, the yielding set and the joints the same, passed a second critical point too,
         ! or crossed onto another branch at a near-bifurcation (Walker's whole arch with a crown
         ! imperfection of 1e-4: past its limit_min onto the complementary path).
         if (before%point%neg_pivots /= after%point%neg_pivots) return
         if (before%point%liftoff .or. after%point%liftoff) return
         if (allocated(before%joint_plastic)) return
         if (any(before%active .neqv. after%active)) return
         if (allocated(before%yielding) .and. allocated(after%yielding)) then
            if (any(before%yielding .neqv. after%yielding)) return
         end if
         ! The state half-way tells the two apart. The second point changes the count between the
         ! ends, or the step left its branch: the half-way state has another count or the halves are
         ! unequal (Walker's arch at 1e-4: count 0 half-way, 1 at both ends, λ −23.19 between −35.699
         ! and −35.714). But a symmetric structure's bifurcation point passed along its bifurcated
         ! branch, λ(−a) = λ(a) with a the mode's amplitude, is a turning point of λ with the same
         ! count on both sides (mirror images share their spectrum): the limit and the bifurcation
         ! coincide by symmetry and no cut separates them. Its halves are alike and the half-way
         ! state has the ends' count (ex. 2 whole arch on its bed, SWITCH=1, at 146.969 and where
         ! the branch returns to 118.2746: halves 0.86 to 1.16 of each other, counts 0, 0, 0; rejected,
         ! every cut down to 2.5e-3 of the first step turned the slope again and the shorter ones
         ! landed on the primary path, until the run stopped). A half step that does not converge
         ! proves nothing: the step is cut.
         call re_solve_step(model, before, system, 0.5_dp*length, half, ok, error)
         if (allocated(error)) return
         hides = .true.
         if (ok) then
            first = masked_norm(after%map, half%u - before%u)
            second = masked_norm(after%map, after%u - half%u)
            hides = half%point%neg_pivots /= after%point%neg_pivots .or. &
                    second > halves_ratio*first .or. first > halves_ratio*second
         end if
         call restore_tangent(model, after, system, error)
         return
      end if
      ! λ went against the slope of both ends: with no limit point between them λ is monotone along
      ! the step, so it passed two (a loop), or landed on another branch (Walker's whole arch with a
      ! crown imperfection of 1e-3, docs/theory.md §2.3: past the limit_min the step went on across
      ! the near-bifurcation onto the complementary path, λ falling where the path rises).
      if (same_signs(before%point%dlambda_ds, after%point%dlambda_ds) .and. &
          opposite_signs(after%lambda - before%lambda, after%point%dlambda_ds)) then
         hides = .true.
         return
      end if
      if (before%point%neg_pivots /= after%point%neg_pivots) then
         ! One change of the inertia with the slope's sign kept: a bifurcation, or a step that went
         ! past a near-bifurcation of an imperfect structure (where the path turns sharply to a limit
         ! point) onto the complementary path. The half step tells: on a branch through a
         ! bifurcation it lies between the ends, with their slope.
         if (abs(before%point%neg_pivots - after%point%neg_pivots) /= 1) return
         if (before%point%liftoff .or. after%point%liftoff) return
         call re_solve_step(model, before, system, 0.5_dp*length, half, ok, error)
         if (allocated(error)) return
         if (ok) then
            first = masked_norm(after%map, half%u - before%u)
            second = masked_norm(after%map, after%u - half%u)
            hides = opposite_signs(half%point%dlambda_ds, after%point%dlambda_ds) .or. &
                    opposite_signs(half%lambda - before%lambda, after%lambda - half%lambda) .or. &
                    second > halves_ratio*first .or. first > halves_ratio*second
         end if
         call restore_tangent(model, after, system, error)
         return
      end if
      ! A degenerate landing tangent (round-off of a load the contacts carry) has no direction.
      if (degenerate_tangent(after, after%tangent_displacement)) return
      chord = after%u - before%u
      size_chord = masked_norm(after%map, chord)
      size_tangent = masked_norm(after%map, after%tangent_displacement)
      if (.not. (size_chord > 0.0_dp .and. size_tangent > 0.0_dp)) return
      if (abs(masked_dot(after%map, chord, after%tangent_displacement)) >= turning_cosine*size_chord*size_tangent) return
      call re_solve_step(model, before, system, 0.5_dp*length, half, ok, error)
      if (allocated(error)) return
      if (ok) then
         first = masked_norm(after%map, half%u - before%u)
         second = masked_norm(after%map, after%u - half%u)
         hides = opposite_signs(half%point%dlambda_ds, after%point%dlambda_ds) .or. &
                 half%point%neg_pivots /= after%point%neg_pivots .or. second > halves_ratio*first
      end if
      call restore_tangent(model, after, system, error)
   end subroutine find_hidden_pair

   !> Whether the step from `before` to `after`, whose working set changed, went farther along the
   !> path than d/2, d the distance at which the least eigenvalue μ of the tangent, extrapolated
   !> linearly from the last step (before%previous_eigenvalue at before%previous_s,
   !> before%point%min_eigenvalue at before%point%s), reaches zero, from a stable state (count 0,
   !> μ > 0) with μ falling, and with the count at its end the same or changed by one (docs/theory.md
   !> §2.3, "a zero of the least eigenvalue inside the step"). Such a step may have passed a zero of μ
   !> and come back across a contact event whose springs made μ jump up (ex. 2 as a whole arch on its
   !> bed, 120 elements: the count went 0-1-0 between λ = 116.47 and 118.18, μ 4.4e-7 and 3.2e-7 at
   !> the ends, falling by 3.6e-6 per unit λ over the step before). Cut, the step lands short of the
   !> zero or where the count has changed, and the locator places it. d/2, not d: across a change of
   !> the set μ curves down between its jumps (under load control the step from 112.79 to 117.34 went
   !> 0.64 d through the zero at 116.16 and the closing contacts at 116.95). Not tested (false): μ's
   !> slope not known (no step before it in the analysis step, a corner, release or load step, a
   !> branch switch), a lift-off state at either end (μ of a piece of the cone test, §2.2), a
   !> structure held only by its contacts, a step whose dλ/ds changes sign (judged by
   !> find_hidden_pair), one on a single working set (μ smooth), a count changed by more than one,
   !> μ of the other sign at the end with the count unchanged, a path length that did not grow.
   logical function eigenvalue_overshoot(before, after) result(over)
      type(path_state_t), intent(in) :: before, after
      real(dp) :: slope, distance, travelled, run
      integer :: change
      logical :: set_changed
      over = .false.
      if (.not. before%eigenvalue_slope_known .or. before%point%switched) return
      if (before%point%liftoff .or. after%point%liftoff) return
      ! λ turns inside the step: the limit point's tests above (find_hidden_pair) judge it. At a
      ! symmetric structure's bifurcation passed along its bifurcated branch μ touches zero where λ
      ! turns, with the count unchanged (mirror images share their spectrum), and cutting steps there
      ! only crept up to it (ex. 2 whole arch on its bed, SWITCH=1, at 146.969: exit 1).
      if (.not. same_signs(before%point%dlambda_ds, after%point%dlambda_ds)) return
      ! A structure held only by its contacts (docs/theory.md §2.8) has rigid motions that no support
      ! holds, neutral where its contacts let them slide: μ is of round-off there and its slope says
      ! nothing (the ring in its circular cavity, gap_ring_in_cavity.inp: cut into 20 steps where 4
      ! did, the count flickered 0-1-0 at six states).
      if (allocated(before%floating_motion)) return
      ! A stable state whose least eigenvalue falls towards zero.
      if (before%point%neg_pivots /= 0 .or. .not. before%point%min_eigenvalue > 0.0_dp) return
      change = abs(after%point%neg_pivots - before%point%neg_pivots)
      if (change > 1) return
      if (size(after%active) /= size(before%active)) return
      ! Only a step whose working set changed: the contacts that close in it make μ jump up, which is
      ! what hid the zero. On one working set μ is smooth and a step approaching a limit point or a
      ! bifurcation with μ curving down was cut short of it for nothing (the whole ring under pressure,
      ! ring_full_pressure_fixed_creep.inp; ex. 3 whole arch at its first steps, where the last step's
      ! slope, from the unloaded state, was not this step's).
      set_changed = any(after%active .neqv. before%active)
      if (.not. set_changed) return
      if (change == 0 .and. .not. same_signs(before%point%min_eigenvalue, after%point%min_eigenvalue)) return
      run = before%point%s - before%previous_s
      travelled = after%point%s - before%point%s
      if (.not. (run > 0.0_dp .and. travelled > 0.0_dp)) return
      slope = (before%point%min_eigenvalue - before%previous_eigenvalue)/run
      ! μ moving towards zero
      if (.not. opposite_signs(slope, before%point%min_eigenvalue)) return
      distance = -before%point%min_eigenvalue/slope
      over = travelled > 0.5_dp*distance
   end function eigenvalue_overshoot

end module uniarc_path_hidden
