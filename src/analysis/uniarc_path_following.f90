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
!> uniarc_path_stability (inertia, least eigenvalue), uniarc_path_point (the point record),
!> uniarc_path_locate (critical points passed by a step, located by re-solving it), uniarc_path_landing
!> (a step landed on lambda_max or stop_value), uniarc_path_trace (the memory of the path traced that
!> the caller keeps: the tests of a step going back and of a loop of corners). Here: path_initialize,
!> and path_advance with the cut-back, the commit and the next step length.
!>
!> Predictor sign: the predictor goes along +K⁻¹R or −K⁻¹R, whichever makes a positive angle with the
!> previous converged increment (Feng, Perić & Owen 1996). Unlike the sign of det K, which changes at
!> bifurcation points too and cannot follow a snap-back, the angle criterion keeps the direction of
!> travel along the path through limit points, turning points and snap-back.
module uniarc_path_following
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis, error_internal, error_input
   use uniarc_foreign, only: interrupt_signal
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_model, only: model_t, control_displacement, control_arclength, control_load, has_moment_limits
   use uniarc_dof_map, only: build_dof_map, candidate_live
   use uniarc_contact_plastic, only: branch_changed
   use uniarc_band, only: band_allocate
   use uniarc_assembly, only: assemble_reference_load
   use uniarc_path_state, only: path_state_t, path_point_t, path_system_t, step_trial_t, masked_dot, &
                                masked_norm, nodal_displacements, candidate_reactions, accept_trial
   use uniarc_path_newton, only: attempt_step
   use uniarc_path_contact_set, only: touching_candidates
   use uniarc_path_stability, only: commit_tangent
   use uniarc_path_point, only: describe_point
   use uniarc_path_locate, only: locate_critical_points
   use uniarc_path_contact_start, only: locate_contact_start
   use uniarc_path_hidden, only: find_hidden_pair, eigenvalue_overshoot
   use uniarc_critical_points, only: same_signs
   use uniarc_path_mechanism, only: check_mechanism
   use uniarc_path_integrator, only: degenerate_tangent
   use uniarc_path_acceptance, only: degenerate_step, far_from_predictor, far_from_committed_tangent, off_branch, &
                                     tangent_turn_cosine, max_turn_cosine
   use uniarc_path_branch, only: switch_branch
   use uniarc_path_corner, only: step_past_corner
   use uniarc_path_contact_branch, only: split_tie, split_tolerance
   use uniarc_path_state_copy, only: copy_state, move_state
   use uniarc_path_landing, only: land_on_load_limit, land_on_track_limit
   use uniarc_path_trace, only: path_trace_t, trace_allocate, trace_forget, trace_remember, &
                                trace_retraced_step, trace_set_origin, trace_remember_corner, &
                                trace_corner_revisited
   use uniarc_path_failure, only: add_crest_hint, add_mechanism_hint, lift_off_error, at_bearing_limit, &
                                  add_concave_corner_hint, add_convex_corner_hint, add_unstable_branch_hint
   use uniarc_path_start, only: size_first_step, find_floating, approach_first_contact
   implicit none
   private
   public :: path_state_t, path_point_t, path_trace_t, path_initialize, path_advance, nodal_displacements
   public :: path_restart, path_change_working_set
   public :: candidate_reactions

   !> How a real is written in the messages of a failed step (λ, the step length): 6 digits suffice.
   character(len=*), parameter :: message_edit = '(es12.5)'
   !> A converged arc-length step whose chord ||Δu|| exceeds this many step lengths Δl has left the
   !> branch it followed (docs/theory.md §2.3): Chan's corrections land near the step length on the
   !> branch (measured on every deck of the repository: at most 1.25), while a step that
   !> crossed onto another branch lands at the distance between the branches.
   real(dp), parameter :: overlong_ratio = 2.0_dp

contains

   !> Number the equations, assemble at the unloaded state and size the first step; `trace`, the
   !> memory of the path traced that the caller keeps for path_advance (uniarc_path_trace), allocated
   !> for the path's unknowns and empty.
   !> Errors (error_analysis): displacement control of a held DOF; a singular tangent at the unloaded
   !> state; a zero first increment or reference load.
   subroutine path_initialize(model, state, trace, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(out) :: state
      type(path_trace_t), intent(inout) :: trace
      type(error_t), allocatable, intent(out) :: error
      type(path_system_t), allocatable :: system
      real(dp), allocatable :: nodal(:, :)
      integer :: status
      associate (options => model%analysis)
         call build_dof_map(model, state%map, error, error_analysis)
         if (allocated(error)) return
         allocate (system)
         call band_allocate(system%tangent, state%map%n_equations, state%map%half_bandwidth, &
                            state%map%half_bandwidth, error)
         if (allocated(error)) return
         allocate (state%u(state%map%n_equations), state%last_increment(state%map%n_equations), &
                   state%fixed_load(state%map%n_equations), state%active(size(state%map%candidate_equation)), &
                   stat=status)
         call allocation_failure(status, 'the displacement, increment and load vectors of the path', &
                                 24.0_dp*state%map%n_equations + 4.0_dp*size(state%active), error_analysis, error)
         if (allocated(error)) return
         state%u = 0.0_dp
         state%last_increment = 0.0_dp
         call trace_allocate(trace, state%map%n_equations)
         ! the unloaded state: where the path's first branch begins (a closed loop comes back to it)
         call trace_set_origin(trace, state%u, 0.0_dp, 0)
         if (has_moment_limits(model)) then
            allocate (state%joint_plastic(2, model%n_elements), stat=status)
            call allocation_failure(status, 'the committed plastic rotations of the joints', &
                                    16.0_dp*model%n_elements, error_analysis, error)
            if (allocated(error)) return
            state%joint_plastic = 0.0_dp
         end if
         call assemble_reference_load(model, state%map, .false., state%fixed_load)
         state%length_scale = max(maxval(model%coordinates) - minval(model%coordinates), tiny(1.0_dp))
         ! The first working set: every candidate that touches (zero gap) and every bonded one. It
         ! holds what the contacts hold (a ring resting in a cavity), so the augmented tangent is
         ! regular; the first LCP then keeps only the contacts that push.
         ! plastic media: no slip and nothing yielding at the unloaded state (docs/theory.md §3.9)
         allocate (state%slip(size(state%active)), state%yielding(size(state%active)), stat=status)
         call allocation_failure(status, 'the plastic slip and yielding set of the candidates', &
                                 12.0_dp*size(state%active), error_analysis, error)
         if (allocated(error)) return
         state%slip = 0.0_dp
         state%yielding = .false.
         call nodal_displacements(model, state, nodal, error)
         if (allocated(error)) return
         call touching_candidates(model, state, nodal, state%active)
         call set_control_equation(model, state, error)
         if (allocated(error)) return
         ! A model that no contact can hold is refused before the path starts (exit code 2).
         call check_mechanism(model, state, system, nodal, error)
         if (allocated(error)) return
         call find_floating(model, state, system, nodal, error)
         if (.not. allocated(error)) then
            call approach_first_contact(model, state, system, nodal, error)
            if (allocated(error)) return
            call commit_tangent(model, state, system, .true., error)
         end if
         call move_alloc(system, state%system)
         if (allocated(error)) then
            call add_where(error, 'unloaded state', state)
            return
         end if
         call size_first_step(model, state, error)
         if (allocated(error)) return
         call describe_point(model, state, 0, 0, 0, error)
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
   subroutine path_restart(model, state, trace, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(path_trace_t), intent(inout) :: trace   !< path_advance's memory: its kept states forgotten
      type(error_t), allocatable, intent(out) :: error
      type(path_system_t), allocatable :: system
      real(dp), allocatable :: nodal(:, :)
      associate (options => model%analysis)
         state%lambda = 0.0_dp
         state%last_increment = 0.0_dp
         ! The states traced so far belong to another load pattern: not this step's path.
         call trace_forget(trace)
         state%eigenvalue_slope_known = .false.
         call assemble_reference_load(model, state%map, .false., state%fixed_load)
         call set_control_equation(model, state, error)
         if (allocated(error)) return
         call move_alloc(state%system, system)
         system%holds_converged = .false.
         ! A structure held only by its contacts that ended the last step with none in its working set
         ! (no load pushed it onto them) and that this step's load pushes along a free translation
         ! meets its first contact before λ grows, as at the start of the path (docs/theory.md §2.8).
         if (rests_on_nothing(model, state)) then
            call nodal_displacements(model, state, nodal, error)
            if (.not. allocated(error)) call approach_first_contact(model, state, system, nodal, error)
            if (allocated(error)) then
               ! the load pushes the structure off every contact: no equilibrium past λ = 0 (§3.12), a
               ! failed analysis step, not bad input (the steps before have their results)
               if (error%category == error_input) error%category = error_analysis
               call move_alloc(system, state%system)
               call add_where(error, 'start of the step', state)
               return
            end if
         end if
         call commit_tangent(model, state, system, .false., error)
         call move_alloc(system, state%system)
         if (allocated(error)) then
            call add_where(error, 'start of the step', state)
            return
         end if
         call size_first_step(model, state, error)
         if (allocated(error)) return
         call describe_point(model, state, state%point%step, 0, 0, error)
         if (allocated(error)) return
         call trace_set_origin(trace, state%u, 0.0_dp, state%point%step)
      end associate
   end subroutine path_restart

   !> A structure held only by its contacts (it has floating motions) with no contact in its working
   !> set: no live candidate of state%active but the tangential springs (which follow a radial partner).
   pure logical function rests_on_nothing(model, state)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      integer :: c
      rests_on_nothing = .false.
      if (.not. allocated(state%floating_equation)) return
      do c = 1, size(state%active)
         if (state%active(c) .and. candidate_live(state%map, c) .and. .not. model%contacts(c)%tangential) return
      end do
      rests_on_nothing = .true.
   end function rests_on_nothing

   !> The committed state's working set replaced by `active` (n_candidates) at the same displacements
   !> and λ: the driver's retry of a failed step with the contacts that touch out of the set
   !> (docs/theory.md §3.9, "Plateau of no length"). The committed tangent, K_S⁻¹R, residual, inertia
   !> and point record are those of the new set (commit_tangent, describe_point), as after a commit:
   !> the next step's predictor follows K_S⁻¹R of the set it starts with, and its distance test
   !> (far_from_predictor) compares the corrector with that predictor, not with the tangent of the
   !> old set (whose rigid motion, held in the tangent only while no contact saw it, made every
   !> converged step of the new set land "far from the predictor"). The slope of the least
   !> eigenvalue is forgotten (a new tangent, not a step along the old one).
   !> Errors: commit_tangent's (a singular tangent with the new set; out of memory), describe_point's;
   !> the state then holds `active` and the caller restores it (by this procedure with the old set).
   subroutine path_change_working_set(model, state, active, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      logical, intent(in) :: active(:)
      type(error_t), allocatable, intent(out) :: error
      type(path_system_t), allocatable :: system
      if (.not. allocated(state%system)) then
         call make_error(error, 'path_change_working_set: the committed state has no system of equations', &
                         error_internal)
         return
      end if
      state%active(:) = active
      state%set_edited = .true.
      state%eigenvalue_slope_known = .false.
      ! The last increment belongs to the old set's piece of the path: the next step has no direction
      ! of its own to keep (as after a floating slide), and under arc length it goes on with |λ|
      ! growing, so that a step of the load presses the contacts the new set holds.
      state%last_increment = 0.0_dp
      if (model%analysis%control == control_arclength) then
         state%direction = 1
         if (state%lambda < 0.0_dp) state%direction = -1
      end if
      ! The pace of the old set (cut down where its tangent met the mechanism it could not follow) is
      ! not the new set's: the next step starts from the path's first length (cut back as usual), so
      ! that it goes forward by more than the old set's residual, which its corrector takes up (a
      ! step of round-off length went back by that residual: the arc-length beam of 200 elements).
      state%step_length = max(state%step_length, state%first_length)
      call move_alloc(state%system, system)
      system%holds_converged = .false.
      call commit_tangent(model, state, system, .false., error)
      call move_alloc(system, state%system)
      if (allocated(error)) return
      call describe_point(model, state, state%point%step, state%point%iterations, state%point%lcp_pivots, error)
   end subroutine path_change_working_set

   !> The equation of the displacement that `*PATH, CONTROL=DISPLACEMENT` controls (0 under the other
   !> controls). Errors (error_analysis): a controlled DOF held by a support has no equation.
   subroutine set_control_equation(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      state%control_equation = 0
      if (model%analysis%control /= control_displacement) return
      state%control_equation = state%map%equation(model%analysis%control_dof, model%analysis%control_node)
      if (state%control_equation == 0) &
         call make_error(error, 'displacement control of a DOF held by a support', error_analysis)
   end subroutine set_control_equation

   !> Advance one converged step, cutting the step length on failure; error if it cannot be done.
   !>
   !> Each attempt (uniarc_path_newton, attempt_step) works on a trial of its own; the committed state
   !> is changed only by the attempt that converges. `cuts` (optional) returns the halvings of the step
   !> length before that attempt (0: the first converged), or, on failure, the halvings made.
   !> A converged attempt off the branch it followed is cut like one that did not converge
   !> (docs/theory.md §2.3): far from its predictor (far_from_predictor), its landing tangent across
   !> the step or a reversal (off_branch), a chord longer than overlong_ratio step lengths (arc length),
   !> a change of the inertia by more than one while the step can be halved (on a lift-off tangent: with
   !> the working set unchanged), a tangent that turns by more than 45° over a step whose ends agree
   !> (tangent_turn_cosine: a loop of the path may lie inside it), or a pair of critical
   !> points hidden in the step (uniarc_path_hidden, find_hidden_pair).
   !> Errors (error_analysis): no convergence down to the smallest step (which step, from which λ, why;
   !> under load control from a stable state, that this is where the load reaches a limit point); a
   !> singular tangent at the converged state.
   subroutine path_advance(model, state, trace, error, cuts)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      !> the memory of the path traced (path_initialize's): the tests of a loop of corners and of a step
      !> going back read it, a corner passed and the committed step are appended
      type(path_trace_t), intent(inout) :: trace
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out), optional :: cuts
      type(path_system_t), allocatable :: system
      type(step_trial_t) :: trial
      type(path_state_t) :: before
      real(dp) :: length, factor, remaining, target, committed_lambda
      real(dp), allocatable :: landing(:)
      character(len=:), allocatable :: jump, went_back
      integer :: attempt, halvings
      logical :: to_limit, hidden, landed, track_landed, cornered, corner_passed, left_branch, unresolved, multiple
      logical :: tie_split_cut, split_allowed, unexplained_limit
      integer :: revisited
      state%point%tie_kept = .false.
      state%limit_under_load = .false.
      tie_split_cut = .false.
      split_allowed = .false.
      ! *PATH, SWITCH=n: the step after the n-th located bifurcation leaves along its mode.
      if (state%switch_due) then
         call switch_branch(model, state, error, halvings)
         if (present(cuts)) cuts = halvings
         if (allocated(error)) then
            call add_where(error, 'step '//integer_to_string(state%point%step + 1), state)
            return
         end if
         ! the secondary branch begins at the bifurcation it left from
         call trace_set_origin(trace, state%bifurcation%u, state%point%switch_lambda, state%point%step)
         return
      end if
      if (allocated(state%bifurcation)) deallocate (state%bifurcation)
      ! (nor is a contact start located by the last step this one's)
      if (allocated(state%contact_start_u)) deallocate (state%contact_start_u)
      state%point%contact_start_fraction = -1.0_dp
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
         cornered = .false.
         corner_passed = .false.
         ! A converged attempt that landed on another branch (far from its predictor, where the
         ! path's tangent lies across the step, or reversing the last step) is rejected and cut like
         ! one that did not converge: no silent jump (docs/theory.md §2.3).
         steps: do
            do attempt = halvings, options%max_cuts
               trial%length = length
               call attempt_step(model, state, system, trial)
               if (interrupt_signal() /= 0) then
                  ! A SIGINT or SIGTERM: no cut-back, the step is abandoned (the committed state is
                  ! unchanged) and the run ends with the steps traced (docs/contracts.md, "Interrupts").
                  call move_alloc(system, state%system)
                  call make_error(error, 'step '//integer_to_string(state%point%step + 1)// &
                                  ' abandoned: interrupted by a signal', error_analysis)
                  if (present(cuts)) cuts = halvings
                  return
               end if
               if (allocated(trial%fatal)) then
                  ! Out of memory: a shorter step would not fit either (fail_attempt); the run ends.
                  call move_alloc(system, state%system)
                  call move_alloc(trial%fatal, error)
                  if (present(cuts)) cuts = halvings
                  call add_where(error, 'step '//integer_to_string(state%point%step + 1), state)
                  return
               end if
               ! Under arc-length or displacement control a step that takes |λ| through lambda_max is
               ! re-solved under load control to land on it (docs/theory.md §2.11).
               landed = .false.
               if (trial%converged .and. options%control /= control_load) &
                  call land_on_load_limit(model, state, system, trial, length, target, landed)
               ! A step that takes the stop track through stop_value is re-solved under displacement
               ! control of the tracked DOF to land on it (docs/theory.md §2.11).
               ! (Not a release step: its jump is at constant λ, docs/theory.md §3.8.)
               track_landed = .false.
               if (trial%converged .and. .not. trial%release) &
                  call land_on_track_limit(model, state, system, trial, length, track_landed)
               if (track_landed) landed = .false.
               if (allocated(trial%fatal)) then
                  ! Out of memory while it lands (land_on_load_limit): the run ends.
                  call move_alloc(system, state%system)
                  call move_alloc(trial%fatal, error)
                  if (present(cuts)) cuts = halvings
                  call add_where(error, 'step '//integer_to_string(state%point%step + 1), state)
                  return
               end if
               ! *PATH, TIES=KEEP: a step that changes one of two tied candidates and not the other
               ! (mirror images on a symmetric path) leaves the branch it followed at a branch point of the contact
               ! set, by the round-off that chose between them (docs/theory.md §2.3, "Contacts that
               ! tie"): cut like a step off its branch. Where every length splits the pair, the tied
               ! candidates are at their change and the corner step moves them together (§2.12).
               if (trial%converged .and. options%control == control_arclength .and. .not. trial%release .and. &
                   options%keep_ties .and. .not. split_allowed) then
                  if (split_tie(state%point, state%active, trial%active, length, split_tolerance, split_tolerance) > 0) then
                     tie_split_cut = .true.
                     trial%converged = .false.
                     trial%reason = 'it changes one of two tied contacts and not the other (a branch point of '// &
                                    'the contact set)'
                     system%holds_converged = .false.
                  end if
               end if
               if (trial%converged) then
                  ! The distance test holds only where the predictor's linearisation does: a step
                  ! whose working set changed (a contact closed or opened) corrects by O(Δl), not
                  ! O(Δl²) (a tip stopped by an obstacle moves far less than the free predictor said);
                  ! such a step is judged by the angle tests of its commit (off_branch) alone.
                  if (any(trial%active .neqv. state%active)) exit
                  ! (or the committed state's own set was changed in place: its equilibrium was met with
                  ! another set, and the corrector takes up that residual with the new set's stiffness)
                  if (state%set_edited) exit
                  ! so does one whose yielding set changed (a spring at its bearing limit loses its stiffness)
                  if (allocated(state%yielding)) then
                     if (any(trial%yielding .neqv. state%yielding)) exit
                  end if
                  ! and one where a spring with its own uplift stiffness (KU=) changed the branch of its
                  ! elastic law (its tangent jumps from k to k_u within the step: docs/theory.md §3.9)
                  if (allocated(state%slip)) then
                     if (branch_changed(model, state%map, state%u, state%u + trial%increment, state%slip)) exit
                  end if
                  ! A load step of a degenerate tangent has no displacement predictor to be near; nor has
                  ! a release step (Δλ = 0, docs/theory.md §3.8).
                  if (degenerate_step(state, trial) .or. trial%release) exit
                  ! Nor has a step whose committed K⁻¹R moves nothing (the contacts that touch at the
                  ! start carry the load) but whose corrector closes the gap, within the touching
                  ! tolerance, of a contact of the set: a rigid plane 1e-9 under the loaded node
                  ! (docs/theory.md §2.3). Its landing is judged by the angle tests of its commit.
                  if (degenerate_tangent(state, state%tangent_displacement)) exit
                  ! A step that ends in the committed set after its predictor took another (the
                  ! linearised gap of a contact closed, the exact one did not: a grazing contact, a
                  ! convex corner passed close by) is judged against the committed set's predictor.
                  if (trial%predictor_set_changed) then
                     if (.not. far_from_committed_tangent(state, trial)) exit
                  else
                     if (.not. far_from_predictor(state%map, trial)) exit
                  end if
                  trial%converged = .false.
                  trial%reason = 'the corrector landed farther from the predictor than the predictor''s own length'// &
                                 ' (another branch)'
                  system%holds_converged = .false.
               end if
               length = 0.5_dp*length
               halvings = halvings + 1
               if (length < options%min_increment*state%first_length) exit
            end do
            if (present(cuts)) cuts = halvings
            ! No step length converges along this piece of the path: a corner, where a contact opens or
            ! closes exactly at the committed state (docs/theory.md §2.12). Under arc length the
            ! next piece's working set and tangent are sought (uniarc_path_corner); once per step.
            if (.not. trial%converged .and. options%control == control_arclength .and. .not. cornered) then
               cornered = .true.
               revisited = trace_corner_revisited(trace, state%u)
               if (revisited > 0) then
                  ! The path came back to a corner it passed already: around a closed loop of pieces
                  ! (contacts opening and closing in turn), it would trace the same states for ever.
                  ! Not an equilibrium path going on: the run stops (the rows so far are kept).
                  trial%reason = 'the path returned to the corner it passed at step '// &
                                 integer_to_string(revisited)//': a loop of corners, not traced further'
               else
                  call step_past_corner(model, state, system, trial, length, corner_passed)
                  if (allocated(trial%fatal)) then
                     call move_alloc(system, state%system)
                     call move_alloc(trial%fatal, error)
                     call add_where(error, 'step '//integer_to_string(state%point%step + 1), state)
                     return
                  end if
                  if (corner_passed) call trace_remember_corner(trace, state%u, state%point%step)
               end if
            end if
            if (.not. trial%converged .and. tie_split_cut .and. .not. split_allowed) then
               ! The branch followed does not go on with the tied contacts together (it folds back at
               ! the branch point, or no step moves them together): the step is made again from its full
               ! length with the split allowed, leaving the branch there as the contact LCP chooses
               ! (a contact_branching row, docs/theory.md §2.3).
               call restart_with_split()
               cycle steps
            end if
            if (.not. trial%converged) then
               ! A load that lifts the structure off every contact that could hold it: no equilibrium
               ! exists, whatever the step (docs/theory.md §3.12); said so instead of the solver's words.
               ! Under load control the step's length is its Δλ; the smallest attempt was 2 × length.
               if (options%control == control_load) &
                  call lift_off_error(model, state, system, real(state%direction, dp)*2.0_dp*length, error)
               call move_alloc(system, state%system)
               if (allocated(error)) then
                  call add_where(error, 'step '//integer_to_string(state%point%step + 1), state)
                  return
               end if
               ! `length` was halved after the last attempt failed: the smallest attempt was twice it
               call make_error(error, 'no convergence ('//trial%reason//') after cutting the step down to '// &
                               real_to_string(2.0_dp*length/state%first_length, message_edit)//' of the first', &
                               error_analysis)
               ! A step that converged but went back along the path (the piece past a corner folding
               ! back) is said: the path does not go on forward from here (docs/theory.md §2.3).
               if (allocated(went_back)) then
                  if (index(trial%reason, went_back) == 0) error%message = error%message// &
                     '; a converged step was rejected: '//went_back//' (the path folds back here)'
                  call add_unstable_branch_hint(state%point%neg_pivots, state%bifurcations, &
                                                options%switch_bifurcation, error)
               end if
               call add_concave_corner_hint(model, state, error)
               if (index(error%message, 'concave corner') == 0) &
                  call add_convex_corner_hint(model, state, options%control == control_load, &
                                              2.0_dp*length/state%first_length, error)
               if (options%control == control_load .and. state%point%neg_pivots == 0 .and. &
                   index(error%message, 'concave corner') == 0 .and. index(error%message, 'convex corner') == 0 &
                   .and. .not. at_bearing_limit(state)) then
                  ! Under load control the path cannot pass a limit point: past it there is no
                  ! equilibrium near the last one (docs/contracts.md, exit code 1). Not said where
                  ! contacts are at their bearing limit: arc length meets the same plateau there
                  ! (add_mechanism_hint and the collapse test say what is known, docs/theory.md §3.9).
                  error%message = error%message//'; under load control this is where the load reaches a '// &
                                  'limit point (or the path turns): trace it with CONTROL=ARCLENGTH'
                  state%limit_under_load = .true.
               end if
               call add_crest_hint(model, state, error)
               call add_mechanism_hint(model, state, error)
               call add_where(error, 'step '//integer_to_string(state%point%step + 1), state)
               return
            end if
            ! The state at the start of the step, for the critical-point locator and a rejection (no
            ! system: moved out).
            call copy_state(state, before, 'the state at the start of the step', error)
            if (allocated(error)) then
               call move_alloc(system, state%system)
               call add_where(error, 'step '//integer_to_string(state%point%step + 1)//' (converged state)', state)
               return
            end if
            ! Commit the converged trial.
            committed_lambda = state%lambda + trial%dlambda
            ! The uncut step to the limit lands on it exactly (λ + (λ_max − λ) may differ in the last bit).
            if (to_limit .and. halvings == 0 .and. .not. (track_landed .or. trial%release)) &
               committed_lambda = real(state%direction, dp)*options%lambda_max
            if (landed) committed_lambda = target
            call accept_trial(model, state, trial, error, committed_lambda)
            if (allocated(error)) then
               call move_alloc(system, state%system)
               call add_where(error, 'step '//integer_to_string(state%point%step + 1)//' (converged state)', state)
               return
            end if
            ! A load step's displacement is round-off where the contacts carry the load: no direction
            ! for the next step's angle tests.
            if (degenerate_step(before, trial)) state%last_increment = 0.0_dp
            ! Nor is the slide of a floating structure onto its first contact (docs/theory.md §2.8) a
            ! direction of the path: a rigid motion at no force, as long as its contact's tilt allows.
            if (trial%floating_slide) state%last_increment = 0.0_dp
            ! Nor is a release step's jump (docs/theory.md §3.8): the next step's angle tests compare
            ! with the step before it.
            if (trial%release) state%last_increment = before%last_increment
            ! Nor is the first step from a working set changed in place (path_change_working_set): its
            ! increment takes up the residual the old set left, which the new set's stiffness makes a
            ! motion of its own (the ends of a beam on a yielded bed pressed by the load's excess).
            if (before%set_edited) state%last_increment = 0.0_dp
            call commit_tangent(model, state, system, .false., error)
            if (allocated(error)) then
               call move_alloc(system, state%system)
               call add_mechanism_hint(model, state, error)
               call add_where(error, 'step '//integer_to_string(state%point%step + 1)//' (converged state)', state)
               return
            end if
            select case (options%control)
            case (control_arclength)
               ! Keep travelling forward: positive angle between the new tangent and the last increment.
               if (trial%release) then
                  ! A release step went nowhere in λ: forward is the way the step before it went, by
                  ! the angle of its increment with the new tangent (kept where it had none).
                  if (masked_dot(state%map, before%last_increment, state%tangent_displacement) < 0.0_dp) then
                     state%direction = -1
                  else if (masked_dot(state%map, before%last_increment, state%tangent_displacement) > 0.0_dp) then
                     state%direction = 1
                  end if
               else if (before%set_edited) then
                  ! The first step from a working set changed in place (path_change_working_set) went
                  ! the sense it set (|λ| growing); its increment also takes up the start's residual
                  ! of the old set, no direction of the path: the sense is kept.
                  continue
               else if (degenerate_tangent(state, state%tangent_displacement)) then
                  ! No displacement to take the angle with: forward is the way λ went (a load step).
                  state%direction = 1
                  if (trial%dlambda < 0.0_dp) state%direction = -1
               else if (masked_dot(state%map, trial%increment, state%tangent_displacement) < 0.0_dp) then
                  state%direction = -1
               else
                  state%direction = 1
               end if
            end select
            call describe_point(model, state, state%point%step + 1, trial%iterations, trial%lcp_pivots, error)
            if (allocated(error)) then
               call move_alloc(system, state%system)
               call add_where(error, 'step '//integer_to_string(state%point%step + 1)//' (converged state)', state)
               return
            end if
            state%point%switched = .false.
            ! A converged state whose tangent is far from the step's chord, or a step that reverses
            ! the last one, is not on the branch the step followed.
            ! (A degenerate landing tangent, round-off of a load carried by the contacts, has no
            ! direction to compare with.)
            landing = state%tangent_displacement
            if (degenerate_tangent(state, landing)) landing = 0.0_dp
            ! A load step (docs/theory.md §2.7) went in λ alone: its chord has no direction either; nor
            ! has the slide of a floating structure onto its first contact (§2.8), a rigid motion.
            jump = ''
            multiple = .false.
            ! With no increment yet (the start of a path or of an analysis step) forward is the sense of
            ! λ the first increment sets: a first step whose λ goes the other way reversed the load (a
            ! rigid plane 1e-9 under the loaded node, docs/theory.md §2.3).
            if (options%control == control_arclength .and. &
                .not. (trial%floating_slide .or. trial%release .or. before%set_edited) .and. &
                trial%dlambda*real(before%direction, dp) < 0.0_dp) then
               if (.not. masked_norm(state%map, before%last_increment) > 0.0_dp) &
                  jump = 'the first step goes against the sense of lambda its first increment sets'
            end if
            if (len(jump) > 0) then
               continue
            else if (.not. (degenerate_step(before, trial) .or. trial%floating_slide .or. trial%release .or. &
                            before%set_edited)) then
               ! At a corner the path may turn by more than a right angle (a contact closing where the
               ! smooth piece would have folded back): only the landing tangent is checked there.
               if (corner_passed) then
                  if (off_branch(state%map, trial%increment, 0.0_dp*before%last_increment, landing)) &
                     jump = 'the path''s tangent there is across the step past the corner'
               else if (off_branch(state%map, trial%increment, before%last_increment, landing)) then
                  jump = 'the path''s tangent there is across the step, or the step reverses the last one'
               else if (options%control == control_arclength .and. &
                        masked_norm(state%map, trial%increment) > overlong_ratio*length) then
                  jump = 'it lies more than '//integer_to_string(nint(overlong_ratio))//' step lengths from the start'
               ! (A lift-off tangent's count may change by more where the working set changes — contacts
               ! touching or leaving at once; with the same set it counts the lift-off modes passed, one
               ! per event: the strut on a tensionless bed with increment 0.3 passed Euler's 9th and
               ! 16th modes in one step and reported one of them.)
               else if (abs(state%point%neg_pivots - before%point%neg_pivots) > 1 .and. &
                        (.not. (state%point%liftoff .or. before%point%liftoff) .or. &
                         all(state%active .eqv. before%active)) .and. &
                        0.5_dp*length >= options%min_increment*state%first_length) then
                  ! Several critical points passed at once, or one multiple eigenvalue (the whole
                  ! ring's two oval modes): the locator below tells, by whether the whole change
                  ! happens across its final bracket. Not at a lift-off state, whose count is that of
                  ! a piece of the cone test (docs/theory.md §2.2, step 4), no multiplicity of one
                  ! tangent's eigenvalue.
                  if (state%point%liftoff .or. before%point%liftoff) then
                     jump = 'the count of negative pivots changed by more than one critical point can change it'
                  else
                     multiple = .true.
                  end if
               else if (0.5_dp*length >= options%min_increment*state%first_length .and. &
                        eigenvalue_overshoot(before, state)) then
                  ! The count may have changed and changed back inside the step: μ, extrapolated
                  ! from the last step, vanishes within it (docs/theory.md §2.3).
                  jump = 'the least eigenvalue, extrapolated from the last step, vanishes inside it '// &
                         'while the count of negative pivots at its end is that of its start'
               else if (options%control == control_arclength .and. &
                        0.5_dp*length >= options%min_increment*state%first_length .and. &
                        state%point%neg_pivots == before%point%neg_pivots .and. &
                        same_signs(before%point%dlambda_ds, state%point%dlambda_ds) .and. &
                        .not. (state%point%liftoff .or. before%point%liftoff) .and. &
                        same_set(before, state) .and. &
                        .not. degenerate_tangent(before, before%tangent_displacement) .and. &
                        tangent_turn_cosine(state%map, before%tangent_displacement, before%direction, landing, &
                                            state%direction) < max_turn_cosine) then
                  ! Ends that agree say nothing of what lies between them: a step that turns the
                  ! tangent this far may have crossed the narrow neck of a loop of the path, from the
                  ! branch going into it to the one coming out (ex. 3 at k = 1e5, docs/theory.md §2.3,
                  ! "a tangent that turns too far"); cut, the shorter steps follow the loop.
                  jump = 'the path''s tangent turns by more than 45 degrees in the step, whose ends agree '// &
                         '(a loop of the path may lie inside it)'
               else
                  call find_hidden_pair(model, before, state, system, length, hidden, error)
                  if (allocated(error)) then
                     call move_alloc(system, state%system)
                     call add_where(error, 'step '//integer_to_string(state%point%step)//' (converged state)', state)
                     return
                  end if
                  if (hidden) jump = 'the state half-way along the step is not between its ends: a loop of '// &
                                     'the path, two critical points, passed in one step'
               end if
            end if
            ! A step that lands on a piece of the path traced before, going back along it, retraces the
            ! path (a corner step whose piece runs back along the old one, pipeline over the hump:
            ! docs/theory.md §2.3, "back along the path"). Only where the tangent may jump: a corner step
            ! or one whose working set changed. Along one smooth piece the path turns back only through a
            ! limit point, whose far side may run within the sagitta of the near one at a sharp fold (ex. 3's
            ! long path with max_increment 20: step 138 past the limit 422.63 lies along steps 134–135).
            ! (So may the first step from a working set changed in place, whose angle tests are skipped:
            ! the retry of a failed step at a fold of the pipeline over its hump went back so.)
            if (len(jump) == 0 .and. (corner_passed .or. before%set_edited .or. &
                                      any(trial%active .neqv. before%active)) .and. &
                .not. (degenerate_step(before, trial) .or. trial%floating_slide .or. trial%release)) then
               revisited = trace_retraced_step(trace, state%map, state%u, state%lambda, before%point%step, &
                                               trial%increment, trial%dlambda, -1)
               if (revisited > 0) then
                  jump = 'it goes back along the path traced between steps '// &
                         integer_to_string(revisited)//' and '//integer_to_string(revisited + 1)
                  went_back = jump
               end if
            else if (len(jump) == 0 .and. options%control == control_arclength .and. &
                     state%point%neg_pivots == before%point%neg_pivots .and. &
                     same_signs(before%point%dlambda_ds, state%point%dlambda_ds) .and. &
                     .not. (degenerate_step(before, trial) .or. trial%floating_slide .or. trial%release)) then
               ! A step on one smooth piece with no critical point in it (the count and the sign of
               ! dλ/ds of its ends agree) goes back along the path only where the path came back to a
               ! piece it traced through a loop of its branches and turned onto it, backwards, at the
               ! branch point where the loop ends: such a state lies on the traced piece with that
               ! piece's inertia, which the far side of a fold does not have (docs/theory.md §2.3,
               ! "back along the path"). The circular liner in its host went round a loop of corners
               ! into the bifurcation at 35.75 it had passed and back down its path to 31.46, where
               ! no step converged (exit 1); ex. 2 as a whole arch on its bed (200 elements, steps of
               ! 0.04) round its asymmetric loop into the contact branch point at 118.85 and back down
               ! the symmetric path to lambda < 0 (exit 0).
               revisited = trace_retraced_step(trace, state%map, state%u, state%lambda, before%point%step, &
                                               trial%increment, trial%dlambda, state%point%neg_pivots)
               if (revisited > 0) then
                  jump = 'it goes back along the path traced between steps '// &
                         integer_to_string(revisited)//' and '//integer_to_string(revisited + 1)
                  went_back = jump
               end if
            end if
            ! A release step (Δλ = 0) is a jump of the law, not a piece of the path to re-solve.
            ! (Nor is the first step from a working set changed in place, whose start is a corner of
            ! the path: its inertia is that of the new set at the old set's equilibrium.)
            if (len(jump) == 0 .and. .not. (trial%release .or. before%set_edited)) then
               ! A limit point or bifurcation the step has passed is located by re-solving from its start.
               call locate_critical_points(model, before, state, system, length, left_branch, unresolved, &
                                           unexplained_limit, error, &
                                           switching=state%bifurcations + 1 == options%switch_bifurcation)
               if (allocated(error)) then
                  call move_alloc(system, state%system)
                  call add_where(error, 'step '//integer_to_string(state%point%step)//' (converged state)', state)
                  return
               end if
               if (left_branch) jump = 'the states re-solved along it change branch where the inertia changes'
               ! λ turned at a limit point that the load sees (φᵀR ≠ 0), and the count of negative
               ! pivots at the step's end is that of its start: a limit point changes it by one, so the
               ! step passed another critical point too, or landed on another branch (docs/theory.md
               ! §2.3, "a limit that the inertia does not see"). Cut while it can be.
               if (unexplained_limit .and. 0.5_dp*length >= options%min_increment*state%first_length) &
                  jump = 'lambda turns in it at a limit point, and the count of negative pivots at its end is '// &
                         'that of its start'
               ! A change of the count by more than one is a multiple bifurcation only if the locator
               ! found all of it at one bifurcation, across a bracket narrowed to its tolerance (a
               ! double eigenvalue of a symmetric structure: two eigenvalues of K_T vanish at once);
               ! else the step passed several critical points, and it is cut (docs/theory.md §2.3).
               if (multiple .and. len(jump) == 0) then
                  if (.not. (state%point%bifurcation_fraction >= 0.0_dp .and. &
                             state%point%bifurcation_multiplicity == &
                             abs(state%point%neg_pivots - before%point%neg_pivots))) &
                     jump = 'the count of negative pivots changed by more than one critical point can change it'
               end if
               ! A critical point that the re-solutions could not bracket is located again in a
               ! shorter step (while the step may be cut: else the interpolation is kept). Not a step
               ! past a corner: the locator re-solves from the step's start along the old piece, whose
               ! every length failed (what made it a corner), so no shorter step is bracketed either;
               ! the sign change of dλ/ds is at the corner, the step's start, a contact_corner row
               ! (ex. 2 whole arch on its bed, SWITCH=1: the corner at 117.768 was cut for this and
               ! the run stopped there, docs/theory.md §2.12).
               if (unresolved .and. .not. corner_passed .and. &
                   0.5_dp*length >= options%min_increment*state%first_length) &
                  jump = 'the critical point it passed could not be bracketed by re-solving it'
            end if
            if (len(jump) == 0 .and. .not. (trial%release .or. before%set_edited .or. corner_passed .or. &
                                            trial%floating_slide)) then
               ! A contact that closes in a step begun with none: where its gap reaches zero, located by
               ! re-solving the step with the old set (uniarc_path_contact_start). Not across a release
               ! step, a set changed in place or a corner (whose start is on another piece), nor the
               ! slide of a floating structure onto its first contact (a rigid motion the old set does
               ! not hold).
               call locate_contact_start(model, before, state, system, length, error)
               if (allocated(error)) then
                  call move_alloc(system, state%system)
                  call add_where(error, 'step '//integer_to_string(state%point%step)//' (converged state)', state)
                  return
               end if
            end if
            if (len(jump) == 0) then
               if (allocated(state%bifurcation)) then
                  state%bifurcations = state%bifurcations + 1
                  state%switch_due = state%bifurcations == options%switch_bifurcation
               end if
               call trace_remember(trace, state%u, state%lambda, state%point%step, state%point%neg_pivots, &
                                   before%u, before%lambda, before%point%step, before%point%neg_pivots)
               ! μ's slope along this step, for the next step's test of a hidden zero of μ
               ! (uniarc_path_hidden): only across a smooth piece with one working set, where μ is
               ! the least eigenvalue of one continuous tangent.
               state%eigenvalue_slope_known = .not. (corner_passed .or. trial%floating_slide .or. &
                  trial%release .or. degenerate_step(before, trial) .or. state%point%liftoff .or. &
                  before%point%liftoff .or. state%point%switched)
               if (state%eigenvalue_slope_known) state%eigenvalue_slope_known = size(state%active) == size(before%active)
               state%previous_eigenvalue = before%point%min_eigenvalue
               state%previous_s = before%point%s
               state%point%tie_kept = tie_split_cut
               exit steps
            end if
            call move_state(before, state)   ! the step rejected: back to its start
            system%holds_committed = .false.
            system%holds_converged = .false.
            trial%reason = 'the converged state is off the branch the step followed ('//jump//')'
            trial%converged = .false.
            length = 0.5_dp*length
            halvings = halvings + 1
            if (length < options%min_increment*state%first_length .and. &
                options%control == control_arclength .and. .not. cornered) then
               ! Every length converged but turned back or left the piece: at a corner whose next
               ! piece folds back (a contact closing where the smooth piece would have turned), the
               ! converged states of the old piece reverse the last step. The corner is sought as when
               ! no length converges (uniarc_path_corner), from the step's full length; the attempts
               ! are skipped (halvings past max_cuts). pipeline_hump_corner_100 at step 90 in the
               ! Release build (the Debug build's round-off reached the corner by a failed length).
               length = state%step_length
               halvings = options%max_cuts + 1
               cycle steps
            end if
            if (length < options%min_increment*state%first_length .and. tie_split_cut .and. &
                .not. split_allowed) then
               ! as above: the tied contacts kept together lead nowhere but back
               call restart_with_split()
               cycle steps
            end if
            if (length < options%min_increment*state%first_length) then
               call move_alloc(system, state%system)
               ! `length` was halved after the last attempt failed: the smallest attempt was twice it
               call make_error(error, 'no convergence ('//trial%reason//') after cutting the step down to '// &
                               real_to_string(2.0_dp*length/state%first_length, message_edit)//' of the first', &
                               error_analysis)
               if (allocated(went_back)) then
                  if (index(trial%reason, went_back) == 0) error%message = error%message// &
                     '; a converged step was rejected: '//went_back//' (the path folds back here)'
                  call add_unstable_branch_hint(state%point%neg_pivots, state%bifurcations, &
                                                options%switch_bifurcation, error)
               end if
               call add_where(error, 'step '//integer_to_string(state%point%step + 1), state)
               if (present(cuts)) cuts = halvings
               return
            end if
         end do steps
         call move_alloc(system, state%system)
         state%taken_length = length
         factor = sqrt(real(options%desired_iterations, dp)/real(max(trial%iterations, 1), dp))
         factor = min(2.0_dp, max(0.25_dp, factor))
         state%step_length = min(options%max_increment*state%first_length, &
                                 max(options%min_increment*state%first_length, length*factor))
      end associate

   contains

      !> TIES=KEEP: the step made again from its full length (no halving made yet) with the tied
      !> contacts free to split, the rejection of an earlier attempt forgotten.
      subroutine restart_with_split()
         split_allowed = .true.
         tie_split_cut = .false.
         if (allocated(went_back)) deallocate (went_back)
         length = state%step_length
         halvings = 0
      end subroutine restart_with_split

   end subroutine path_advance

   !> Whether the working set, the yielding set and the joints are those of `before` at `after`: the
   !> step followed one smooth piece of the path.
   pure logical function same_set(before, after)
      type(path_state_t), intent(in) :: before, after
      same_set = .false.
      if (size(before%active) /= size(after%active)) return
      if (any(before%active .neqv. after%active)) return
      if (allocated(before%joint_plastic)) return
      if (allocated(before%yielding) .and. allocated(after%yielding)) then
         if (size(before%yielding) /= size(after%yielding)) return
         if (any(before%yielding .neqv. after%yielding)) return
      end if
      same_set = .true.
   end function same_set

   !> Prefix a step's error message with where it happened and from which λ.
   subroutine add_where(error, where, state)
      type(error_t), intent(inout) :: error
      character(len=*), intent(in) :: where
      type(path_state_t), intent(in) :: state
      error%message = where//', from lambda = '//real_to_string(state%lambda, message_edit)//': '//error%message
   end subroutine add_where

end module uniarc_path_following
