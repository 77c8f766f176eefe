!> A step re-solved on a copy of the committed state: the probes of the critical-point locator
!> (uniarc_path_locate) and of the check for critical points hidden in a step (uniarc_path_hidden).
!> A probe is the commit of path_advance (uniarc_path_following) on a copy: it never changes the
!> committed state, only the system of equations, which then holds the probe's tangent.
module uniarc_path_probe
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t
   use uniarc_model, only: model_t, control_arclength
   use uniarc_path_state, only: path_state_t, path_system_t, step_trial_t, masked_dot, accept_trial
   use uniarc_path_newton, only: attempt_step
   use uniarc_path_state_copy, only: copy_state
   use uniarc_path_stability, only: commit_tangent
   use uniarc_path_point, only: describe_point
   implicit none
   private
   public :: re_solve_step, restore_tangent

contains

   !> The converged state `probe` of a step of length `step_h` (the units of state%step_length) from
   !> `before` (the committed state at the start of a step, system not allocated): its point record
   !> (numbered before%point%step + 1), tangent, inertia and least eigenvalue, as path_advance would
   !> commit it. `ok` is false if the attempt does not converge or its tangent is singular. `system`
   !> returns holding the probe's tangent (restore_tangent puts the committed one back).
   subroutine re_solve_step(model, before, system, step_h, probe, ok, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: before   !< unchanged (inout for copy_state)
      type(path_system_t), intent(inout) :: system
      real(dp), intent(in) :: step_h
      type(path_state_t), intent(out) :: probe
      logical, intent(out) :: ok
      type(error_t), allocatable, intent(out) :: error
      type(step_trial_t) :: trial
      type(error_t), allocatable :: commit_error
      trial%length = step_h
      call attempt_step(model, before, system, trial)
      ok = trial%converged
      if (allocated(trial%fatal)) call move_alloc(trial%fatal, error)   ! out of memory: ends the run
      if (.not. ok) return
      call copy_state(before, probe, 'the state of a probe of the step', error)
      ok = .not. allocated(error)
      if (.not. ok) return
      call accept_trial(model, probe, trial, error)
      ok = .not. allocated(error)
      if (.not. ok) return
      call commit_tangent(model, probe, system, .false., commit_error)
      if (allocated(commit_error)) then
         ok = .false.
         if (commit_error%out_of_memory) call move_alloc(commit_error, error)
         return
      end if
      if (model%analysis%control == control_arclength) then
         if (masked_dot(probe%map, trial%increment, probe%tangent_displacement) < 0.0_dp) then
            probe%direction = -1
         else
            probe%direction = 1
         end if
      end if
      call describe_point(model, probe, before%point%step + 1, trial%iterations, trial%lcp_pivots, error)
      if (allocated(error)) ok = .false.
   end subroutine re_solve_step

   !> Put the committed tangent of `state` back into `system` after probes (its factors, K⁻¹R and
   !> inertia are recomputed on a copy; the state itself is not changed).
   !> Errors: out of memory (the run ends); a failure of the commit itself is ignored, as it was
   !> not when the state was committed.
   subroutine restore_tangent(model, state, system, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state   !< unchanged (inout for copy_state)
      type(path_system_t), intent(inout) :: system
      type(error_t), allocatable, intent(out) :: error
      type(path_state_t) :: restore
      type(error_t), allocatable :: commit_error
      call copy_state(state, restore, 'the committed state restored after the probes', error)
      if (allocated(error)) return
      call commit_tangent(model, restore, system, .false., commit_error)
      if (allocated(commit_error)) then
         if (commit_error%out_of_memory) call move_alloc(commit_error, error)
      end if
   end subroutine restore_tangent

end module uniarc_path_probe
