!> Incremental-iterative path following (paper §5, Fig. 3; Crisfield 1991 ch. 9): the public API of
!> the path following and its step control.
!>
!> Each step: a tangent predictor sized by the control (load, displacement or arc length), then full
!> Newton–Raphson corrections in which the load correction δλ comes from the iteration strategy —
!> Chan's (1988) minimum residual displacement (the paper's choice), Crisfield's cylindrical arc length,
!> or Riks/Ramm's updated normal plane. A step that does not converge is dropped and cut; the step
!> size adapts to the iterations used. The committed state is only changed by a converged step.
!>
!> The parts, one job each (src/analysis/path/, after OpenSees' integrator / algorithm / convergence
!> test / system of equations): uniarc_path_state (committed state, trial, system of equations),
!> uniarc_path_integrator (step constraint and δλ strategies), uniarc_path_newton (one attempt:
!> predictor, Newton and its convergence test), uniarc_path_contact_set (contact working set),
!> uniarc_path_stability (inertia, least eigenvalue), uniarc_path_point (the point record). Here:
!> path_initialize, and path_advance with the cut-back, the commit and the next step length.
!>
!> Predictor sign: the predictor goes along +K⁻¹R or −K⁻¹R, whichever makes a positive angle with the
!> previous converged increment (Feng, Perić & Owen 1996). Unlike the sign of det K, which changes at
!> bifurcation points too and cannot follow a snap-back, the angle criterion keeps the direction of
!> travel along the path through limit points, turning points and snap-back.
module uniarc_path_following
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_model, only: model_t, control_displacement, control_arclength, control_load
   use uniarc_dof_map, only: build_dof_map
   use uniarc_band, only: band_allocate, band_factorize, band_solve, band_copy
   use uniarc_assembly, only: assemble_reference_load
   use uniarc_path_state, only: path_state_t, path_point_t, path_system_t, step_trial_t, masked_dot, masked_norm, &
                                nodal_displacements, candidate_reactions, equilibrium_at
   use uniarc_path_newton, only: attempt_step
   use uniarc_path_contact_set, only: touching_candidates
   use uniarc_path_stability, only: structural_inertia, least_eigenvalue, liftoff_stability
   use uniarc_path_point, only: describe_point
   implicit none
   private
   public :: path_state_t, path_point_t, path_initialize, path_advance, nodal_displacements
   public :: path_restart
   public :: candidate_reactions

   !> How a real is written in the messages of a failed step (λ, the step length): 6 digits suffice.
   character(len=*), parameter :: message_edit = '(es12.5)'

contains

   !> Number the equations, assemble at the unloaded state and size the first step.
   !> Errors (error_analysis): displacement control of a held DOF; a singular tangent at the unloaded
   !> state; a zero first increment or reference load.
   subroutine path_initialize(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(out) :: state
      type(error_t), allocatable, intent(out) :: error
      type(path_system_t), allocatable :: system
      real(dp), allocatable :: nodal(:, :)
      associate (options => model%analysis)
         call build_dof_map(model, state%map)
         allocate (system)
         call band_allocate(system%tangent, state%map%n_equations, state%map%half_bandwidth, &
                            state%map%half_bandwidth)
         allocate (state%u(state%map%n_equations), source=0.0_dp)
         allocate (state%last_increment(state%map%n_equations), source=0.0_dp)
         allocate (state%fixed_load(state%map%n_equations))
         call assemble_reference_load(model, state%map, .false., state%fixed_load)
         state%length_scale = max(maxval(model%coordinates) - minval(model%coordinates), tiny(1.0_dp))
         ! The first working set: every candidate that touches (zero gap) and every bonded one. It
         ! holds what the contacts hold (a ring resting in a cavity), so the augmented tangent is
         ! regular; the first LCP then keeps only the contacts that push.
         allocate (state%active(size(state%map%candidate_equation)))
         call nodal_displacements(model, state, nodal)
         call touching_candidates(model, state, nodal, state%active)
         if (options%control == control_displacement) then
            state%control_equation = state%map%equation(options%control_dof, options%control_node)
            if (state%control_equation == 0) then
               call make_error(error, 'displacement control of a DOF held by a support', error_analysis)
               return
            end if
         end if
         call commit_tangent(model, state, system, .true., error)
         call move_alloc(system, state%system)
         if (allocated(error)) then
            call add_where(error, 'unloaded state', state)
            return
         end if
         call size_first_step(model, state, error)
         if (allocated(error)) return
         call describe_point(model, state, 0, 0, 0)
      end associate
   end subroutine path_initialize

   !> Start the next analysis step (docs/theory.md §2.5) from the committed state of the previous one:
   !> `model` is the new step's (uniarc_model_steps: its loads scaled by λ, the earlier ones held), and
   !> the state keeps its displacements, working set, reactions, path length and step number; λ starts
   !> at 0, the reference load, K_T and its point record are those of the new step at that state, and
   !> the first step is sized by the new step's controls. The previous step's last increment is
   !> forgotten: the first predictor goes along +K⁻¹R (or −K⁻¹R for a negative first increment), as at
   !> the start of a path.
   !> Errors (error_analysis): displacement control of a held DOF; a singular tangent; a zero first
   !> increment or reference load.
   subroutine path_restart(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      type(path_system_t), allocatable :: system
      associate (options => model%analysis)
         state%lambda = 0.0_dp
         state%last_increment = 0.0_dp
         call assemble_reference_load(model, state%map, .false., state%fixed_load)
         state%control_equation = 0
         if (options%control == control_displacement) then
            state%control_equation = state%map%equation(options%control_dof, options%control_node)
            if (state%control_equation == 0) then
               call make_error(error, 'displacement control of a DOF held by a support', error_analysis)
               return
            end if
         end if
         call move_alloc(state%system, system)
         system%holds_converged = .false.
         call commit_tangent(model, state, system, .false., error)
         call move_alloc(system, state%system)
         if (allocated(error)) then
            call add_where(error, 'start of the step', state)
            return
         end if
         call size_first_step(model, state, error)
         if (allocated(error)) return
         call describe_point(model, state, state%point%step, 0, 0)
      end associate
   end subroutine path_restart

   !> The first step length, direction and force scale of a path (or an analysis step) from the
   !> committed K⁻¹R and R and the controls of `model%analysis`.
   !> Errors (error_analysis): a zero first increment or reference load.
   subroutine size_first_step(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      associate (options => model%analysis)
         select case (options%control)
         case (control_arclength)
            state%first_length = abs(options%first_increment)*masked_norm(state%map, state%tangent_displacement)
         case default
            state%first_length = abs(options%first_increment)
         end select
         state%step_length = state%first_length
         state%direction = 1
         if (options%first_increment < 0.0_dp) state%direction = -1
         state%load_norm = abs(options%first_increment)*norm2(state%reference)
         if (options%control == control_displacement) state%load_norm = norm2(state%reference)
         if (state%first_length <= 0.0_dp .or. state%load_norm <= 0.0_dp) then
            call make_error(error, 'the first increment or the reference load is zero: nothing to follow', &
                            error_analysis)
            return
         end if
      end associate
   end subroutine size_first_step

   !> Advance one converged step, cutting the step length on failure; error if it cannot be done.
   !>
   !> Each attempt (uniarc_path_newton, attempt_step) works on a trial of its own; the committed state
   !> is changed only by the attempt that converges. `cuts` (optional) returns the halvings of the step
   !> length before that attempt (0: the first converged), or, on failure, the halvings made.
   !> Errors (error_analysis): no convergence down to the smallest step (which step, from which λ, why);
   !> a singular tangent at the converged state.
   subroutine path_advance(model, state, error, cuts)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out), optional :: cuts
      type(path_system_t), allocatable :: system
      type(step_trial_t) :: trial
      real(dp) :: length, factor, remaining
      integer :: attempt, halvings
      logical :: to_limit
      associate (options => model%analysis)
         ! The system of equations is the attempts' while they run: the committed state they read
         ! (intent(in)) cannot be written through it.
         call move_alloc(state%system, system)
         length = state%step_length
         ! Under load control a step that would pass lambda_max, or stop within 1e-6 of a step short
         ! of it, goes to lambda_max exactly: the path ends on the load the deck asks for (not
         ! 1.084 for 1), and no sliver of a step is left from the round-off of the sum of increments.
         to_limit = .false.
         if (options%control == control_load .and. options%lambda_max < huge(1.0_dp)) then
            remaining = options%lambda_max - real(state%direction, dp)*state%lambda
            if (remaining > 0.0_dp .and. remaining <= (1.0_dp + 1.0e-6_dp)*length) then
               length = remaining
               to_limit = .true.
            end if
         end if
         halvings = 0
         do attempt = 0, options%max_cuts
            trial%length = length
            call attempt_step(model, state, system, trial)
            if (trial%converged) exit
            length = 0.5_dp*length
            halvings = halvings + 1
            if (length < options%min_increment*state%first_length) exit
         end do
         if (present(cuts)) cuts = halvings
         if (.not. trial%converged) then
            call move_alloc(system, state%system)
            call make_error(error, 'no convergence ('//trial%reason//') after cutting the step down to '// &
                            real_to_string(length/state%first_length, message_edit)//' of the first', error_analysis)
            call add_where(error, 'step '//integer_to_string(state%point%step + 1), state)
            return
         end if
         ! Commit the converged trial.
         state%u = state%u + trial%increment
         state%lambda = state%lambda + trial%dlambda
         ! The uncut step to the limit lands on it exactly (λ + (λ_max − λ) may differ in the last bit).
         if (to_limit .and. halvings == 0) state%lambda = real(state%direction, dp)*options%lambda_max
         state%active = trial%active
         state%last_increment = trial%increment
         state%point%s = state%point%s + masked_norm(state%map, trial%increment)
         call commit_tangent(model, state, system, .false., error)
         call move_alloc(system, state%system)
         if (allocated(error)) then
            call add_where(error, 'step '//integer_to_string(state%point%step + 1)//' (converged state)', state)
            return
         end if
         select case (options%control)
         case (control_arclength)
            ! Keep travelling forward: positive angle between the new tangent and the last increment.
            if (masked_dot(state%map, trial%increment, state%tangent_displacement) < 0.0_dp) then
               state%direction = -1
            else
               state%direction = 1
            end if
         end select
         call describe_point(model, state, state%point%step + 1, trial%iterations, trial%lcp_pivots)
         factor = sqrt(real(options%desired_iterations, dp)/real(max(trial%iterations, 1), dp))
         factor = min(2.0_dp, max(0.25_dp, factor))
         state%step_length = min(options%max_increment*state%first_length, &
                                 max(options%min_increment*state%first_length, length*factor))
      end associate
   end subroutine path_advance

   !> Assemble and factorise K_T at the committed state (into `system`, which then holds it); its
   !> residual, K⁻¹R, inertia and least eigenvalue into the state.
   !> Errors: a singular tangent (band_factorize, band_solve).
   subroutine commit_tangent(model, state, system, unloaded, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(path_system_t), intent(inout) :: system
      logical, intent(in) :: unloaded   !< the unloaded state of path_initialize
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), internal(:), reference(:), rhs(:, :)
      real(dp) :: element_scale
      integer :: n
      system%holds_committed = .false.
      n = state%map%n_equations
      allocate (internal(n), reference(n), rhs(n, 1))
      if (system%holds_converged) then
         ! The attempt's last assembly is this very state (the same u, λ and working set).
         internal = system%converged_internal
         reference = system%converged_reference
         system%holds_converged = .false.
      else
         call nodal_displacements(model, state, nodal)
         call equilibrium_at(model, state, system, state%u, state%lambda, state%active, nodal, internal, &
                             reference, element_scale)
      end if
      state%reference = reference
      ! The unfactorised tangent and the residual stay for the predictor of the next step (its contact
      ! LCP needs both): the step's first attempt does not assemble and factorise them again.
      call band_copy(system%tangent, system%assembled)
      state%committed_residual = state%lambda*state%reference - internal
      call band_factorize(system%tangent, error)
      if (allocated(error)) return
      call structural_inertia(system%tangent, system%assembled, state%active, state%map%candidate_equation, &
                              state%point%neg_pivots, state%point%n_active)
      rhs(:, 1) = state%reference
      call band_solve(system%tangent, rhs, error)
      if (allocated(error)) return
      system%holds_committed = .true.
      state%tangent_displacement = rhs(:, 1)
      state%point%min_eigenvalue = least_eigenvalue(system%tangent, state%eigenvector)
      call liftoff_stability(model, state, system%assembled, model%analysis%displacement_tolerance, unloaded)
   end subroutine commit_tangent

   !> Prefix a step's error message with where it happened and from which λ.
   subroutine add_where(error, where, state)
      type(error_t), intent(inout) :: error
      character(len=*), intent(in) :: where
      type(path_state_t), intent(in) :: state
      error%message = where//', from lambda = '//real_to_string(state%lambda, message_edit)//': '//error%message
   end subroutine add_where

end module uniarc_path_following
