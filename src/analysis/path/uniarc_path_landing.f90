!> The landing of a converged step on the deck's stop values (docs/theory.md §2.11): a step that takes
!> |λ| through lambda_max (arc-length or displacement control) is solved again under load control to end
!> on it; a step that takes a stop track through stop_value is solved again under displacement control
!> of the tracked DOF. Used by the path following (uniarc_path_following, path_advance) only.
module uniarc_path_landing
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t
   use uniarc_model, only: model_t, control_displacement, control_load, analysis_options_t
   use uniarc_path_state, only: path_state_t, path_system_t, step_trial_t, fail_attempt
   use uniarc_path_newton, only: attempt_step
   use uniarc_path_state_copy, only: copy_state, move_trial
   implicit none
   private
   public :: land_on_load_limit, land_on_track_limit

contains

   !> The landing on lambda_max of a step under arc-length or displacement control (docs/theory.md
   !> §2.11): a converged `trial` from the committed `state` whose λ takes |λ| from below lambda_max to
   !> lambda_max or beyond (the path reaching the deck's load while |λ| rises; a step cannot end past
   !> it otherwise, since the path stops at the first point with |λ| >= lambda_max) is solved again from
   !> the same committed state under load control with Δλ = ±lambda_max − λ_n, the sign of the
   !> trial's λ. If that attempt converges it replaces `trial`, `target` is ±lambda_max (the λ the
   !> commit sets, free of the round-off of λ_n + Δλ), `landed` is true, and `length` becomes the
   !> deck's step length scaled by the fraction of the trial's Δλ the landing takes (the length the
   !> critical-point locator and a cut of the landed step start from). If it does not converge (a
   !> limit point between λ_n and lambda_max passed inside the step), the trial is kept: the path then
   !> ends past lambda_max as it reached it (docs/contracts.md). `system` is work space.
   subroutine land_on_load_limit(model, state, system, trial, length, target, landed)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state   !< unchanged (inout for copy_state)
      type(path_system_t), intent(inout) :: system
      type(step_trial_t), intent(inout) :: trial
      real(dp), intent(inout) :: length
      real(dp), intent(out) :: target
      logical, intent(out) :: landed
      type(analysis_options_t) :: load_controlled
      type(path_state_t) :: start
      type(step_trial_t) :: landing
      type(error_t), allocatable :: error
      real(dp) :: lambda_max, reached
      landed = .false.
      target = 0.0_dp
      lambda_max = model%analysis%lambda_max
      if (.not. (lambda_max < huge(1.0_dp))) return
      reached = state%lambda + trial%dlambda
      if (.not. (abs(state%lambda) < lambda_max .and. abs(reached) >= lambda_max)) return
      target = sign(lambda_max, reached)
      ! The same model under load control (its options only: no copy of the model), from a copy of
      ! the committed state going towards the target. A copy or a landing refused memory ends the
      ! run (trial%fatal, as fail_attempt).
      load_controlled = model%analysis
      load_controlled%control = control_load
      call copy_state(state, start, 'the state a step lands on lambda_max from', error)
      if (allocated(error)) then
         call fail_attempt(trial, 'no memory for the landing on lambda_max', error)
         return
      end if
      start%direction = 1
      if (target < state%lambda) start%direction = -1
      landing%length = abs(target - state%lambda)
      ! (attempt_step leaves the system holding the landing's converged assembly, or none.)
      call attempt_step(model, start, system, landing, analysis=load_controlled)
      if (allocated(landing%fatal)) then
         call fail_attempt(trial, 'no memory for the landing on lambda_max', landing%fatal)
         return
      end if
      if (.not. landing%converged) return
      length = length*abs(target - state%lambda)/abs(trial%dlambda)
      call move_trial(landing, trial)
      landed = .true.
   end subroutine land_on_load_limit

   !> The landing on stop_value of a step that takes the stop track's |value| from below stop_value to
   !> stop_value or beyond (docs/theory.md §2.11): the step is solved again from the same committed
   !> state under displacement control of the tracked DOF (value = scale × u there), its increment the
   !> one that puts the value on sign(value) × stop_value; if that converges it replaces the trial
   !> (`landed`) and `length` is scaled by the share of the tracked increment it covers. A tracked DOF
   !> that is held, or a landing that does not converge (the contacts carry the load at the DOF, a
   !> limit of the tracked value inside the step), keeps the trial.
   subroutine land_on_track_limit(model, state, system, trial, length, landed)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state   !< unchanged (inout for copy_state)
      type(path_system_t), intent(inout) :: system
      type(step_trial_t), intent(inout) :: trial
      real(dp), intent(inout) :: length
      logical, intent(out) :: landed
      type(analysis_options_t) :: controlled
      type(path_state_t) :: start
      type(step_trial_t) :: landing
      type(error_t), allocatable :: error
      real(dp) :: before, after, goal, stop_value
      integer :: k, equation
      landed = .false.
      k = model%analysis%stop_track
      if (k <= 0) return
      stop_value = model%analysis%stop_value
      equation = state%map%equation(model%tracks(k)%dof, model%tracks(k)%node)
      if (equation <= 0 .or. model%tracks(k)%scale == 0.0_dp) return
      before = model%tracks(k)%scale*state%u(equation)
      after = model%tracks(k)%scale*(state%u(equation) + trial%increment(equation))
      if (.not. (abs(before) < stop_value .and. abs(after) >= stop_value)) return
      ! the tracked DOF's increment to the goal, u_goal − u_n
      goal = (sign(stop_value, after) - before)/model%tracks(k)%scale
      if (.not. (abs(goal) > 0.0_dp)) return
      ! The same model under displacement control of the tracked DOF (its options only: no copy of
      ! the model), from a copy of the committed state; a copy or a landing refused memory ends the
      ! run (trial%fatal, as fail_attempt), as for the landing on lambda_max.
      controlled = model%analysis
      controlled%control = control_displacement
      controlled%control_node = model%tracks(k)%node
      controlled%control_dof = model%tracks(k)%dof
      call copy_state(state, start, 'the state a step lands on stop_value from', error)
      if (allocated(error)) then
         call fail_attempt(trial, 'no memory for the landing on stop_value', error)
         return
      end if
      start%control_equation = equation
      start%direction = 1
      if (goal < 0.0_dp) start%direction = -1
      landing%length = abs(goal)
      call attempt_step(model, start, system, landing, analysis=controlled)
      if (allocated(landing%fatal)) then
         call fail_attempt(trial, 'no memory for the landing on stop_value', landing%fatal)
         return
      end if
      if (.not. landing%converged) return
      length = length*abs(goal)/max(abs(trial%increment(equation)), tiny(1.0_dp))
      call move_trial(landing, trial)
      landed = .true.
   end subroutine land_on_track_limit

end module uniarc_path_landing
