!> One attempt at a step of the path (OpenSees' SolutionAlgorithm with its ConvergenceTest): the
!> predictor along the committed tangent, then full Newton–Raphson corrections with the load
!> correction of the integrator (uniarc_path_integrator), until the convergence test holds
!> (`newton_test_t`).
!>
!> With contact candidates this is the paper's two-level iteration (Silveira et al. 2013, Fig. 3): the
!> contact LCP at the committed state gives the working set of the predictor; Newton converges with
!> that set; the complementarity conditions are checked at the converged state and, if violated, the
!> LCP at that state gives a new set and Newton goes on, until both equilibrium and contact have
!> converged. Within Newton the set is updated too (docs/theory.md §3.4; uniarc_path_contact_set).
!>
!> An attempt reads the committed state only; it writes its `step_trial_t` and the system of equations.
module uniarc_path_newton
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_foreign, only: interrupt_signal
   use uniarc_memory, only: allocation_failure
   use uniarc_copy, only: reserve
   use uniarc_model, only: model_t, analysis_options_t
   use uniarc_dof_map, only: dof_map_t, bed_deflection
   use uniarc_band, only: band_matrix_t, band_solve, band_copy, band_factorize
   use uniarc_assembly, only: gather_nodal
   use uniarc_contact_lcp, only: path_constraint_t
   use uniarc_path_state, only: path_state_t, path_system_t, step_trial_t, fail_attempt, linearization_t, masked_dot, &
                                masked_norm, equilibrium_at, factorize_and_solve, constraint_residual, &
                                has_contacts, new_linearization, floating_touched
   use uniarc_contact, only: toggle_contacts
   use uniarc_path_integrator, only: predictor_dlambda, step_constraint, correction_constraint, iteration_dlambda, &
                                     degenerate_tangent
   use uniarc_model, only: control_arclength, control_displacement
   use uniarc_path_contact_set, only: set_update_t, complementary, sign_rule, solve_contact_lcp, candidate_state, &
                                      contact_units
   use uniarc_contact_lcp, only: contact_scales_t
   use uniarc_contact_plastic, only: has_plastic, yield_rule
   implicit none
   private
   public :: attempt_step, newton_test_t, new_newton_test, restart_test, check_equilibrium, check_correction

   !> Changes of the working set within one attempt before it is given up.
   integer, parameter :: max_set_changes = 40
   !> The first set changes within Newton follow the sign rule (no LCP, no factorisation); later ones
   !> are the contact LCP's.
   integer, parameter :: sign_rule_changes = 4

   !> The convergence test of Newton (docs/theory.md, convergence): a correction small against the
   !> increment, or the residual at its round-off floor twice in a row; with the residual within the
   !> force tolerance and the contact rows within the displacement tolerance.
   type :: newton_test_t
      real(dp) :: force_tolerance = 0.0_dp         !< relative to the force scale
      real(dp) :: displacement_tolerance = 0.0_dp  !< relative to the increment, the displacements
      real(dp) :: length_scale = 1.0_dp            !< size of the model (length)
      logical :: small_correction = .false.        !< the last correction was small
      real(dp) :: previous_residual = huge(1.0_dp) !< ||residual|| of the last iteration (force)
   end type newton_test_t

contains

   !> A convergence test with the tolerances of `options` for a model of size length_scale.
   pure function new_newton_test(options, length_scale) result(test)
      type(analysis_options_t), intent(in) :: options
      real(dp), intent(in) :: length_scale
      type(newton_test_t) :: test
      test%force_tolerance = options%force_tolerance
      test%displacement_tolerance = options%displacement_tolerance
      test%length_scale = length_scale
   end function new_newton_test

   !> Forget the history of the test (a new working set starts a new Newton sequence).
   pure subroutine restart_test(test)
      type(newton_test_t), intent(inout) :: test
      test%small_correction = .false.
      test%previous_residual = huge(1.0_dp)
   end subroutine restart_test

   !> Equilibrium at the state of `lin` after `iterations` corrections: lin%rhs(:, 1) is its residual,
   !> lin%x its unknowns, lin%roundoff the round-off of the assembly; force_scale the force units.
   !>
   !> At the round-off floor of the residual (below the assembly's own round-off) a correction is noise
   !> of the solve, cond(K)·ε·|Δu|, which on a fine ill-conditioned mesh stays above the displacement
   !> tolerance however long Newton goes on: two iterations in a row at that floor, the second without
   !> halving the residual, are converged to working precision.
   !>
   !> `load_scale`: the loads' own scale (the path's load norm, |λR|). A state whose element forces
   !> exceed it by more than 1/ε has loads below the round-off of its element forces: its residual and
   !> resultant cannot tell whether the loads are balanced (the loads vanish from both sums: 1e25 +
   !> 1e-4 − 1e25 = 0), so beyond 1e3/ε (a margin for a load norm that is a length, that of a moving
   !> obstacle's gap rate) it is not taken as in equilibrium — a runaway iterate, not a state of the
   !> path (a beam on a yielding bed flung to 1e33 by a step past its fold, element forces 3.7e30 times
   !> the load, passed the test with its bed carrying 1.7 times the load, and was then certified a
   !> collapse, in the Release build; review of issue 16).
   subroutine check_equilibrium(test, map, iterations, lin, force_scale, load_scale, in_equilibrium)
      type(newton_test_t), intent(inout) :: test
      type(dof_map_t), intent(in) :: map
      integer, intent(in) :: iterations
      type(linearization_t), intent(in) :: lin
      real(dp), intent(in) :: force_scale, load_scale
      logical, intent(out) :: in_equilibrium
      real(dp) :: residual_norm
      logical :: at_floor
      residual_norm = masked_norm(map, lin%rhs(:, 1))
      at_floor = iterations > 1 .and. residual_norm <= lin%roundoff .and. test%previous_residual <= lin%roundoff &
                 .and. residual_norm >= 0.5_dp*test%previous_residual
      test%previous_residual = residual_norm
      in_equilibrium = iterations > 0 .and. (test%small_correction .or. at_floor) .and. &
                       residual_norm <= max(test%force_tolerance*force_scale, lin%roundoff) .and. &
                       floating_resultant(map, lin%rhs(:, 1)) <= test%force_tolerance*force_scale .and. &
                       constraint_residual(map, lin%rhs(:, 1)) <= test%displacement_tolerance* &
                       max(maxval(abs(map%metric*lin%x)), 1.0e-12_dp*test%length_scale)
      if (load_scale > 0.0_dp .and. lin%element_scale*epsilon(1.0_dp) > 1.0e3_dp*load_scale) in_equilibrium = .false.
   end subroutine check_equilibrium

   !> The resultant of the residual in the global directions (x, y) in which no DOF of any node is
   !> held: there the structure floats on its media (a footing on its bed, a pipe on soil springs), and
   !> the loads, the contact forces and nothing else must balance — the largest |Σ_i g_i| over those
   !> directions (0 if every direction has a support). The elements' forces cancel in it to the last
   !> bit (each element's end forces Bᵀq are opposite), so it is free of the round-off floor of the
   !> residual's components (lin%roundoff, which for a member far stiffer than its bed is above the
   !> loads themselves): a state that passes the floor with its bed carrying more or less than the load
   !> (an eccentric footing on a yielding bed past its bearing capacity) is not in equilibrium.
   pure real(dp) function floating_resultant(map, residual) result(resultant)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: residual(:)
      integer :: i
      resultant = 0.0_dp
      if (.not. allocated(map%equation)) return
      if (size(map%equation, 2) == 0) return
      do i = 1, 2
         if (any(map%equation(i, :) <= 0)) cycle
         resultant = max(resultant, abs(sum(residual(map%equation(i, :)))))
      end do
   end function floating_resultant

   !> Record whether the correction (n) just added to the increment (n) was small: relative to the
   !> increment; a step cut very short meets the round-off of the solve first, which is some 1e3 ε of
   !> the total displacement (`total`, n): below that is converged.
   pure subroutine check_correction(test, map, correction, increment, total)
      type(newton_test_t), intent(inout) :: test
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: correction(:), increment(:), total(:)
      test%small_correction = masked_norm(map, correction) <= &
                              max(test%displacement_tolerance*masked_norm(map, increment), &
                                  1.0e3_dp*epsilon(1.0_dp)*masked_norm(map, total), tiny(1.0_dp))
   end subroutine check_correction

   !> The converged state's assembly stays for the commit (system%tangent still holds it, unfactorised).
   subroutine keep_converged(system, lin)
      type(path_system_t), intent(inout) :: system
      type(linearization_t), intent(in) :: lin
      system%holds_converged = .true.
      system%converged_internal = lin%internal
      system%converged_reference = lin%reference
   end subroutine keep_converged

   !> One attempt at a step of length trial%length from the committed state: on return trial%converged
   !> says whether equilibrium and complementarity hold at state%u + trial%increment, state%lambda +
   !> trial%dlambda with the working set trial%active; if not, trial%reason says why. `system` is
   !> overwritten (its committed factors used first if it still holds them).
   !> `start` (n, optional) replaces the tangent predictor: the increment the corrections start from, at
   !> the committed λ (the predictor along a buckling mode onto a secondary branch, uniarc_path_branch),
   !> or at λ + `start_dlambda` (optional; along the tangent of the next piece at a corner of the path,
   !> uniarc_path_corner).
   !> `keep_set` (optional, default false): the attempt keeps the committed working set throughout —
   !> no contact LCP in the predictor, no complementarity test, no set or yield exchange: the
   !> equilibrium of the structure with the contacts of state%active alone, whatever the gaps of the
   !> others (the continuation of the old set's piece of path, on which uniarc_path_contact_start
   !> finds where a gap closes).
   subroutine attempt_step(model, state, system, trial, start, start_dlambda, analysis, keep_set)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(path_system_t), intent(inout) :: system
      type(step_trial_t), intent(inout) :: trial
      real(dp), intent(in), optional :: start(:)
      real(dp), intent(in), optional :: start_dlambda
      !> the analysis options of the attempt, for model%analysis (Riks' normal plane of a branch switch,
      !> uniarc_path_branch; load control to land on lambda_max, uniarc_path_following): no copy of the
      !> model is made for them
      type(analysis_options_t), intent(in), optional :: analysis
      logical, intent(in), optional :: keep_set
      type(analysis_options_t) :: options_used
      type(linearization_t) :: lin
      type(newton_test_t) :: test
      type(path_constraint_t) :: constraint
      type(set_update_t) :: update
      type(error_t), allocatable :: error
      real(dp), allocatable :: predictor(:)
      ! the candidates' unknowns and bed deflections, and the flipped set, of the sign rule's edit
      real(dp), allocatable :: values(:), deflections(:)
      logical, allocatable :: new_active(:), flip(:)
      character(len=:), allocatable :: reason
      real(dp) :: lambda, dl, force_scale, bytes
      integer :: n, m, status, c
      logical :: contacts, predicted, reuse_factors, in_equilibrium, update_set, solved, fresh_set, lands
      trial%converged = .false.
      system%holds_converged = .false.
      trial%reason = 'iteration limit'
      ! The attempt's vectors allocated with stat= first: the assignments below then allocate nothing
      ! (reallocation on assignment is not checked; docs/contracts.md, "Memory").
      n = state%map%n_equations
      m = size(state%active)
      bytes = 0.0_dp
      call reserve(trial%active, m, status, bytes)
      if (status == 0) call reserve(trial%yielding, m, status, bytes)
      if (status == 0) call reserve(trial%increment, n, status, bytes)
      if (status == 0) call reserve(trial%predictor, n, status, bytes)
      if (status == 0) call reserve(predictor, n, status, bytes)
      if (status == 0) call reserve(new_active, m, status, bytes)
      if (status == 0) call reserve(flip, m, status, bytes)
      if (status == 0) call reserve(values, m, status, bytes)
      if (status == 0) call reserve(deflections, m, status, bytes)
      if (status == 0) call reserve(system%converged_internal, n, status, bytes)
      if (status == 0) call reserve(system%converged_reference, n, status, bytes)
      call allocation_failure(status, 'a work vector of a Newton attempt', bytes, error_analysis, error)
      if (.not. allocated(error)) call new_linearization(model, state%map, lin, error)
      if (allocated(error)) then
         call fail_attempt(trial, 'no memory for the work vectors of the attempt', error)
         return
      end if
      trial%active(:) = state%active
      if (allocated(state%yielding)) then
         trial%yielding(:) = state%yielding
      else
         trial%yielding(:) = .false.
      end if
      trial%yield_changes = 0
      trial%lcp_pivots = 0
      trial%set_changes = 0
      trial%predictor_set_changed = .false.
      trial%iterations = 0
      trial%dlambda = 0.0_dp
      trial%load_step = .false.
      trial%floating_slide = .false.
      trial%release = .false.
      contacts = has_contacts(state)
      if (present(keep_set)) contacts = contacts .and. .not. keep_set
      reuse_factors = .false.
      fresh_set = .false.
      if (present(analysis)) then
         options_used = analysis
      else
         options_used = model%analysis
      end if
      if (present(start)) then
         system%holds_committed = .false.
         trial%increment(:) = start
         if (present(start_dlambda)) trial%dlambda = start_dlambda
      else
         call predict(model, options_used, state, system, lin, trial, contacts, predicted)
         if (allocated(trial%fatal)) return
         if (.not. predicted) return
      end if
      associate (options => options_used)
         predictor(:) = trial%increment
         trial%predictor = predictor
         trial%predictor_dlambda = trial%dlambda
         test = new_newton_test(options, state%length_scale)
         do while (trial%iterations <= options%max_iterations)
            ! A SIGINT or SIGTERM abandons the attempt, not converged (docs/contracts.md, "Interrupts").
            if (interrupt_signal() /= 0) then
               trial%reason = 'interrupted by a signal'
               exit
            end if
            lambda = state%lambda + trial%dlambda
            lin%x = state%u + trial%increment
            call gather_nodal(state%map, lin%x, lin%nodal)
            call equilibrium_at(model, state, system, lin%x, lambda, trial%active, lin%nodal, lin%internal, &
                                lin%reference, lin%element_scale, error, lin%roundoff, trial%yielding)
            if (allocated(error)) then
               call fail_attempt(trial, 'no memory for the equilibrium', error)
               exit
            end if
            lin%lambda = lambda
            lin%rhs(:, 1) = lambda*lin%reference - lin%internal
            force_scale = max(state%load_norm, norm2(lambda*lin%reference), lin%element_scale)
            ! NaN or overflow; a scale that overflowed would make any residual pass the test.
            if (.not. (norm2(lin%rhs(:, 1)) < huge(1.0_dp) .and. force_scale < huge(1.0_dp) .and. &
                       lin%roundoff < huge(1.0_dp))) then
               trial%reason = 'the residual is not finite'
               exit
            end if
            call check_equilibrium(test, state%map, trial%iterations, lin, force_scale, &
                                   max(state%load_norm, norm2(lambda*lin%reference)), in_equilibrium)
            update_set = .false.
            if (in_equilibrium) then
               ! A step must go forward: a correction that lands behind the predictor (possible with
               ! Chan's constraint-free correction when the contact set changes within the step) would
               ! make the path turn back on itself. Such an attempt is cut instead.
               ! (A predictor without displacement — a load step, or any step of a degenerate tangent,
               ! docs/theory.md §2.7 — has no direction to turn back from.)
               if (masked_dot(state%map, trial%increment, predictor) <= 0.0_dp .and. .not. trial%load_step .and. &
                   .not. degenerate_tangent(state, predictor/max(abs(trial%predictor_dlambda), tiny(1.0_dp)))) then
                  trial%reason = 'the corrected step turned back'
                  exit
               end if
               if (.not. contacts) then
                  trial%converged = .true.
                  call keep_converged(system, lin)
                  exit
               end if
               if (complementary(model, state, lin%x, lin%nodal, trial%active, lin%reaction, lin%gap, &
                                 trial%yielding, lambda)) then
                  call lands_degenerate(options, state, system, lin, trial, lands, error)
                  if (allocated(error)) then
                     call fail_attempt(trial, 'no memory for the load step''s test', error)
                     exit
                  end if
                  if (.not. lands) then
                     trial%reason = 'the arc-length step cannot be solved with this contact set (contact LCP: '// &
                                    'no solution), and as a load step it does not end where the contacts carry the load'
                     exit
                  end if
                  trial%converged = .true.
                  call keep_converged(system, lin)
                  exit
               end if
               ! Plastic media: the yield pairs first (an elastic candidate beyond its limit yields, a
               ! yielding one that would unload becomes elastic), the contact pairs of that frame then
               ! the LCP's (docs/theory.md §3.9).
               if (yield_exchange(model, state, lin, trial, new_active)) then
                  if (trial%yield_changes > max_set_changes) then
                     trial%reason = 'the yielding set does not settle'
                     exit
                  end if
                  call restart_test(test)
                  reuse_factors = .false.
                  fresh_set = .false.
                  cycle
               end if
               ! Equilibrium with a wrong contact set: the LCP at this state gives the next set.
               update_set = .true.
            else
               if (trial%iterations == options%max_iterations) exit
               ! The working set is updated within Newton too (docs/theory.md §3.4), at a trial state
               ! that a correction has reached with a violated contact. The first `sign_rule_changes`
               ! changes follow the primal–dual active-set rule, edited into this iteration's tangent
               ! (no assembly, no LCP); later ones take the LCP linearised at the state, whose solution
               ! is the Newton correction of the complementarity problem (Josephy–Newton), with the
               ! factors this iteration needs anyway. The set converges along with equilibrium.
               update_set = contacts .and. .not. fresh_set
               if (update_set) update_set = .not. complementary(model, state, lin%x, lin%nodal, trial%active, &
                                                                lin%reaction, lin%gap, trial%yielding, lambda)
               ! The yield pairs are exchanged like the sign rule's contacts (the tangent of the new
               ! yielding set assembled again at this state).
               if (update_set) then
                  if (yield_exchange(model, state, lin, trial, new_active)) then
                     if (trial%yield_changes > max_set_changes) then
                        trial%reason = 'the yielding set does not settle'
                        exit
                     end if
                     call restart_test(test)
                     reuse_factors = .false.
                     cycle
                  end if
               end if
               if (update_set .and. trial%set_changes < sign_rule_changes) then
                  call sign_rule(model, state, lin%x, lin%nodal, trial%active, new_active, lin%reaction, lin%gap, &
                                 trial%yielding, lambda)
                  if (any(new_active .neqv. trial%active)) then
                     trial%set_changes = trial%set_changes + 1
                     ! The tangent and residual of the new set at this same state: the flipped
                     ! candidates' rows and springs edited in place, no assembly.
                     ! (in the attempt's work vectors: no function results or temporaries of length m)
                     do c = 1, m
                        values(c) = 0.0_dp
                        if (state%map%candidate_equation(c) > 0) values(c) = lin%x(state%map%candidate_equation(c))
                        deflections(c) = bed_deflection(state%map, c, lin%x)
                        flip(c) = new_active(c) .neqv. trial%active(c)
                     end do
                     call toggle_contacts(model, state%map, lin%nodal, values, &
                                          flip, new_active, system%tangent, &
                                          lin%rhs(:, 1), state%slip, deflections, &
                                          lambda=lambda, reference=lin%reference)
                     trial%active = new_active
                     call restart_test(test)
                     reuse_factors = .false.
                     update_set = .false.
                  end if
               end if
            end if
            solved = .false.
            if (update_set) then
               trial%set_changes = trial%set_changes + 1
               if (trial%set_changes > max_set_changes) then
                  trial%reason = 'the contact set does not settle'
                  exit
               end if
               ! system%tangent holds K_S assembled at this state (any factors kept from an earlier
               ! LCP belong to the same set and are simply not used).
               reuse_factors = .false.
               lin%residual = lin%rhs(:, 1)
               call band_copy(system%tangent, system%assembled, error, error_analysis)
               if (.not. allocated(error)) &
                  call factorize_and_solve(system%tangent, lin%residual, lin%reference, lin%rhs, error)
               if (allocated(error)) then
                  call fail_attempt(trial, 'singular tangent', error)
                  exit
               end if
               call correction_constraint(options, state, trial%increment, constraint, trial%load_step)
               call solve_contact_lcp(model, state, system, lin, constraint, trial%active, update, error, &
                                   trial%yielding)
               trial%lcp_pivots = trial%lcp_pivots + update%pivots
               if (allocated(error) .and. update%degenerate .and. .not. trial%load_step) then
                  ! The arc length cannot fix δλ in a set whose contacts carry the whole reference
                  ! load: the rest of the attempt is a load step (docs/theory.md §2.7). The LCP has
                  ! overwritten the tangent: the iteration assembles it again at this state.
                  trial%load_step = .true.
                  reuse_factors = .false.
                  fresh_set = .false.
                  cycle
               end if
               if (allocated(error)) then
                  call fail_attempt(trial, (error%message), error)
                  exit
               end if
               if (update%changed) then
                  trial%active = update%active
                  call restart_test(test)
                  fresh_set = .true.
                  ! The LCP's last frame is K_S of the new set at this very state: its factors serve
                  ! the next correction (the loop assembles into system%tangent, so they wait in
                  ! `assembled`).
                  reuse_factors = update%kept
                  if (reuse_factors) call band_copy(system%tangent, system%assembled, error, error_analysis)
                  if (allocated(error)) then
                     call fail_attempt(trial, 'no memory for the factors of the new contact set', error)
                     exit
                  end if
                  cycle
               end if
               if (in_equilibrium) then
                  trial%reason = 'the LCP keeps a contact set that violates complementarity'
                  exit
               end if
               ! The linearised problem keeps the set: the correction of this set, already solved
               ! (rhs holds K_S⁻¹g and K_S⁻¹R), is the Newton correction.
               solved = .true.
            end if
            trial%iterations = trial%iterations + 1
            if (.not. solved) then
               if (reuse_factors) then
                  lin%rhs(:, 2) = lin%reference
                  call band_solve(system%assembled, lin%rhs, error)
                  reuse_factors = .false.
               else
                  call factorize_and_solve(system%tangent, lin%rhs(:, 1), lin%reference, lin%rhs, error)
               end if
               if (allocated(error)) then
                  call fail_attempt(trial, 'singular tangent', error)
                  exit
               end if
            end if
            fresh_set = .false.
            ! rhs(:, 1) = δx_g (residual correction), rhs(:, 2) = δx_t (tangent correction)
            call iteration_dlambda(options, state, trial%increment, lin%rhs(:, 1), lin%rhs(:, 2), trial%length, &
                                   dl, reason, trial%load_step)
            if (len(reason) > 0) then
               trial%reason = reason
               exit
            end if
            trial%increment = trial%increment + lin%rhs(:, 1) + dl*lin%rhs(:, 2)
            trial%dlambda = trial%dlambda + dl
            ! the correction and the total displacements formed in checked work arrays (an expression
            ! passed as an argument is a temporary that gfortran 12 allocates unchecked)
            lin%correction(:) = lin%rhs(:, 1) + dl*lin%rhs(:, 2)
            lin%total(:) = state%u + trial%increment
            call check_correction(test, state%map, lin%correction, trial%increment, lin%total)
         end do
      end associate
   end subroutine attempt_step

   !> The block exchange of the yield pairs at a state in equilibrium (uniarc_contact_plastic,
   !> yield_rule): true if trial%yielding changed (then trial%yield_changes counts it).
   !> new_yielding: a work array of one entry per candidate (the attempt's, allocated with stat=);
   !> lin%reaction and lin%gap are overwritten.
   logical function yield_exchange(model, state, lin, trial, new_yielding) result(changed)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(linearization_t), intent(inout) :: lin
      type(step_trial_t), intent(inout) :: trial
      logical, intent(out) :: new_yielding(:)
      type(contact_scales_t) :: units
      changed = .false.
      if (.not. has_plastic(model)) return
      call candidate_state(model, state%map, lin%x, lin%nodal, trial%active, lin%reaction, lin%gap, state%slip, &
                           trial%yielding)
      units = contact_units(state, lin%x, lin%reaction, trial%active)
      call yield_rule(model, state%map, lin%reaction, lin%gap, trial%active, trial%yielding, units%force, units%gap, &
                      model%analysis%displacement_tolerance, new_yielding)
      changed = any(new_yielding .neqv. trial%yielding)
      if (.not. changed) return
      trial%yielding = new_yielding
      trial%yield_changes = trial%yield_changes + 1
   end function yield_exchange

   !> Whether an attempt may end here as far as its load step goes: a load step begun from a regular
   !> state (the arc-length LCP found a degenerate frame or no solution, docs/theory.md §2.7) must end
   !> where the contacts carry the whole reference load, K_S⁻¹R without displacement; one that ends
   !> elsewhere took another parametrisation of the path than the arc length asked for, and the attempt
   !> is cut instead. Every other attempt may (true), and so may the load step of a floating structure
   !> meeting its first contact (trial%floating_slide, docs/theory.md §2.8): it is taken in λ because the
   !> slide along its free motion has no length for the arc length to measure, wherever it lands. `system%tangent` holds K_S at the state of `lin`,
   !> unfactorised, and is left so (a copy is factorised).
   !> Errors: the copy of the tangent or the solve's vector refused by the system (error_analysis, out
   !> of memory; `ok` false).
   subroutine lands_degenerate(options, state, system, lin, trial, ok, error)
      type(analysis_options_t), intent(in) :: options   !< the attempt's (its control)
      type(path_state_t), intent(in) :: state
      type(path_system_t), intent(in) :: system
      type(linearization_t), intent(in) :: lin
      type(step_trial_t), intent(in) :: trial
      logical, intent(out) :: ok
      type(error_t), allocatable, intent(out) :: error
      type(band_matrix_t) :: factors
      real(dp), allocatable :: response(:, :)
      integer :: status
      ok = .true.
      if (.not. trial%load_step .or. options%control /= control_arclength) return
      if (trial%floating_slide .or. trial%release) return
      if (degenerate_tangent(state, state%tangent_displacement)) return
      ok = .false.
      call band_copy(system%tangent, factors, error, error_analysis)
      if (allocated(error)) return
      call band_factorize(factors, error)
      if (allocated(error)) then
         deallocate (error)   ! singular: not a degenerate landing
         return
      end if
      allocate (response(size(lin%reference), 1), stat=status)
      call allocation_failure(status, 'the load step''s solve', 8.0_dp*size(lin%reference), error_analysis, error)
      if (allocated(error)) return
      response(:, 1) = lin%reference
      call band_solve(factors, response, error)
      if (allocated(error)) then
         deallocate (error)
         return
      end if
      ok = degenerate_tangent(state, response(:, 1))
   end subroutine lands_degenerate

   !> The committed state linearised with the working set `active`: K_T assembled (its copy kept in
   !> system%assembled) and factorised, the residual λR − F and the solves K⁻¹[residual, R] in lin%rhs.
   !> Errors: a singular tangent, or a copy the system refuses (error_analysis).
   subroutine linearize_at_start(model, state, system, lin, active, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(path_system_t), intent(inout) :: system
      type(linearization_t), intent(inout) :: lin
      logical, intent(in) :: active(:)
      type(error_t), allocatable, intent(out) :: error
      call equilibrium_at(model, state, system, state%u, state%lambda, active, lin%nodal, &
                          lin%internal, lin%reference, lin%element_scale, error)
      if (allocated(error)) return
      lin%lambda = state%lambda
      lin%residual = state%lambda*lin%reference - lin%internal
      call band_copy(system%tangent, system%assembled, error, error_analysis)
      if (.not. allocated(error)) &
         call factorize_and_solve(system%tangent, lin%residual, lin%reference, lin%rhs, error)
   end subroutine linearize_at_start


   !> The predictor of an attempt: trial%dlambda and trial%increment along the committed tangent K⁻¹R;
   !> with contact, the contact LCP at the committed state first chooses the working set trial%active
   !> and the tangent is that of the set (not when `contacts` is false: the committed set is kept).
   !> `predicted` is false (and trial%reason says why) if a tangent is singular or the LCP fails.
   subroutine predict(model, options, state, system, lin, trial, contacts, predicted)
      type(model_t), intent(in) :: model
      type(analysis_options_t), intent(in) :: options   !< the attempt's (model%analysis or its own)
      type(path_state_t), intent(in) :: state
      type(path_system_t), intent(inout) :: system
      type(linearization_t), intent(inout) :: lin
      type(step_trial_t), intent(inout) :: trial
      logical, intent(in) :: contacts   !< the contact LCP chooses the predictor's working set
      logical, intent(out) :: predicted
      real(dp), allocatable :: ut(:)
      type(path_constraint_t) :: constraint
      type(set_update_t) :: update
      type(error_t), allocatable :: error
      logical :: ready
      integer :: status
      real(dp) :: bytes
      predicted = .false.
      bytes = 0.0_dp
      call reserve(ut, size(state%tangent_displacement), status, bytes)
      call allocation_failure(status, 'the tangent of the predictor', bytes, error_analysis, error)
      if (allocated(error)) then
         call fail_attempt(trial, 'no memory for the predictor', error)
         return
      end if
      ! Only while the system holds the committed state's factors can the predictor use them; from
      ! here on this attempt assembles into system%tangent (or lends it to the contact LCP).
      ready = system%holds_committed
      system%holds_committed = .false.
         ut(:) = state%tangent_displacement
         trial%dlambda = predictor_dlambda(options, state, ut, trial%length)
         ! A degenerate tangent (the contacts carry the whole reference load) makes the step a load
         ! step of Δλ = Δl/ψ (predictor_dlambda; docs/theory.md §2.7).
         trial%load_step = options%control == control_arclength .and. degenerate_tangent(state, ut)
         if (state%release_due) then
            ! The last commit switched tangential springs off (docs/theory.md §3.8): their dropped forces
            ! are balanced at the same λ before the path goes on, a load step of Δλ = 0.
            trial%release = .true.
            trial%load_step = .true.
            trial%dlambda = 0.0_dp
         end if
         if (state%plateau_due) then
            ! The committed state was moved along a plastic plateau to the contact that ends it
            ! (docs/theory.md §3.9): equilibrium is restored at the plateau's load, a load step of the
            ! slack's Δλ, taken as a release step (no direction of the path, no critical point).
            trial%release = .true.
            trial%load_step = .true.
            trial%dlambda = state%plateau_dlambda
         end if
         if (options%control == control_displacement .and. .not. trial%release) then
            if (.not. (abs(ut(state%control_equation)) > 0.0_dp)) then
               ! The contacts carry the reference load at the controlled DOF: no Δλ moves it.
               trial%reason = 'the reference load does not move the controlled displacement with this contact '// &
                              'set (the contacts carry it): trace it with CONTROL=ARCLENGTH or CONTROL=LOAD'
               return
            end if
         end if
         if (contacts) then
            lin%x = state%u
            call gather_nodal(state%map, state%u, lin%nodal)
            if (ready) then
               ! The committed state's tangent, factorised, and its residual (the commit's).
               lin%residual = state%committed_residual
               lin%reference = state%reference
               lin%rhs(:, 1) = lin%residual
               call band_solve(system%tangent, lin%rhs(:, 1:1), error)
               lin%rhs(:, 2) = state%tangent_displacement
            else
               call linearize_at_start(model, state, system, lin, trial%active, error)
            end if
            if (allocated(error)) then
               call fail_attempt(trial, 'singular tangent at the start of the step', error)
               return
            end if
            call step_constraint(options, state, ut, trial%dlambda, constraint, trial%load_step)
            call solve_contact_lcp(model, state, system, lin, constraint, trial%active, update, error, &
                                   trial%yielding)
            trial%lcp_pivots = trial%lcp_pivots + update%pivots
            if (allocated(error) .and. update%degenerate .and. .not. trial%load_step) then
               ! The step reaches a set whose contacts carry the whole reference load (an obstacle
               ! closing under the load): the arc length has no displacement left to measure there,
               ! and the predictor's Δλ is taken as a load step (docs/theory.md §2.7). The LCP lent
               ! the system's matrices: the committed tangent is assembled again.
               trial%load_step = .true.
               call linearize_at_start(model, state, system, lin, trial%active, error)
               if (allocated(error)) then
                  call fail_attempt(trial, 'singular tangent at the start of the step', error)
                  return
               end if
               call step_constraint(options, state, ut, trial%dlambda, constraint, trial%load_step)
               call solve_contact_lcp(model, state, system, lin, constraint, trial%active, update, error, &
                                   trial%yielding)
               trial%lcp_pivots = trial%lcp_pivots + update%pivots
            end if
            if (allocated(error)) then
               call fail_attempt(trial, (error%message), error)
               return
            end if
            if (update%changed) then
               trial%active = update%active
               trial%predictor_set_changed = .true.
               if (update%kept) then
                  ! The LCP's last frame is the new set: its factors gave K_S⁻¹R already.
                  ut = update%du_tangent
               else
                  call equilibrium_at(model, state, system, state%u, state%lambda, trial%active, lin%nodal, &
                                      lin%internal, lin%reference, lin%element_scale, error)
                  if (allocated(error)) then
                     call fail_attempt(trial, 'no memory for the equilibrium', error)
                     return
                  end if
                  lin%lambda = state%lambda
                  lin%correction(:) = state%lambda*lin%reference - lin%internal   ! checked, no temporary
                  call factorize_and_solve(system%tangent, lin%correction, lin%reference, lin%rhs, error)
                  if (allocated(error)) then
                     call fail_attempt(trial, 'singular tangent with the predicted contact set', error)
                     return
                  end if
                  ut = lin%rhs(:, 2)
               end if
               if (.not. trial%load_step) then
                  trial%dlambda = predictor_dlambda(options, state, ut, trial%length)
                  trial%load_step = options%control == control_arclength .and. degenerate_tangent(state, ut)
               end if
               ! A floating structure meets its first contact: the contact pushes it along its free
               ! rigid motion with no force, a slide the arc length cannot measure (the tangent of
               ! the set is that slide over the tilt of the contact's normal, and its sign decides
               ! the direction): the step is taken in λ, a load step (docs/theory.md §2.8).
               if (.not. trial%load_step .and. options%control == control_arclength) then
                  trial%floating_slide = floating_touched(model, state, trial%active, lin%nodal)
                  trial%load_step = trial%floating_slide
               end if
            end if
         end if
         trial%increment = trial%dlambda*ut
      predicted = .true.
   end subroutine predict

end module uniarc_path_newton
