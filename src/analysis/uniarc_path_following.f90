!> Incremental-iterative path following (paper §5, Fig. 3, without contact; Crisfield 1991 ch. 9).
!>
!> Each step: a tangent predictor sized by the control (load, displacement or arc length), then full
!> Newton–Raphson corrections in which the load correction δλ comes from the iteration strategy —
!> Chan's (1988) minimum residual displacement (the paper's choice), Crisfield's cylindrical arc length,
!> or Riks/Ramm's updated normal plane. A step that does not converge is reverted and cut; the step
!> size adapts to the iterations used. The committed state is only changed by a converged step.
!>
!> Predictor sign: the predictor goes along +K⁻¹R or −K⁻¹R, whichever makes a positive angle with the
!> previous converged increment (Feng, Perić & Owen 1996). Unlike the sign of det K, which changes at
!> bifurcation points too and cannot follow a snap-back, the angle criterion keeps the direction of
!> travel along the path through limit points, turning points and snap-back.
module uniarc_path_following
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_model, only: model_t, analysis_options_t, dofs_per_node, control_load, control_displacement, &
                           control_arclength, iteration_chan, iteration_cylindrical, iteration_riks
   use uniarc_dof_map, only: dof_map_t, build_dof_map, candidate_live
   use uniarc_band, only: band_matrix_t, band_allocate, band_factorize, band_solve, band_inertia, band_copy, &
                          band_inertia_from_factors
   use uniarc_assembly, only: assemble_reference_load, gather_nodal
   use uniarc_equilibrium, only: assemble_equilibrium
   use uniarc_contact, only: candidate_gap, assemble_contact
   use uniarc_contact_lcp, only: path_constraint_t, contact_scales_t, select_contact_set, constraint_arclength, &
                                 constraint_load, constraint_displacement
   use uniarc_lcp_implicit, only: implicit_lcp_report_t
   implicit none
   private
   public :: path_state_t, path_point_t, path_initialize, path_advance, nodal_displacements
   public :: candidate_reactions

   !> How a real is written in the messages of a failed step (λ, the step length): 6 digits suffice.
   character(len=*), parameter :: message_edit = '(es12.5)'

   !> What a converged point of the path tells the critical-point detector.
   type :: path_point_t
      integer :: step = 0
      real(dp) :: s = 0.0_dp            !< path length Σ ||Δu|| up to this point
      real(dp) :: lambda = 0.0_dp
      real(dp) :: dlambda_ds = 0.0_dp   !< slope of the path in the direction of travel
      real(dp), allocatable :: rate(:)  !< du/ds (equations) in the direction of travel
      integer :: neg_pivots = 0         !< negative pivots of K_T (Sylvester: negative eigenvalues)
      real(dp) :: min_eigenvalue = 0.0_dp   !< eigenvalue of K_T of least magnitude (inverse iteration)
      integer :: iterations = 0
      integer :: lcp_pivots = 0             !< Lemke pivots spent on the step
      real(dp) :: lcp_residual = 0.0_dp     !< complementarity residual at the converged state
      integer :: n_active = 0               !< candidates in the working set
      logical, allocatable :: in_contact(:)       !< per candidate: in the working set with r > 0
      real(dp), allocatable :: contact_value(:)   !< per candidate: reaction if in contact, else gap
      real(dp), allocatable :: contact_rate(:)    !< d(contact_value)/ds in the direction of travel
   end type path_point_t

   !> The committed state of the path and what the next step needs.
   type :: path_state_t
      type(dof_map_t) :: map
      type(band_matrix_t) :: tangent            !< K_T at the committed state, factorised
      type(band_matrix_t) :: assembled          !< K_T at the committed state, unfactorised (then workspace)
      real(dp), allocatable :: committed_residual(:)  !< λR − F_aug at the committed state
      logical :: predictor_ready = .false.      !< tangent, assembled and committed_residual are those of
                                                !< the committed state (the first attempt of a step)
      real(dp), allocatable :: eigenvector(:)   !< last mode of least eigenvalue (warm start)
      real(dp), allocatable :: u(:)             !< committed unknowns: displacements and reactions
      logical, allocatable :: active(:)         !< committed working set of contact candidates
      real(dp), allocatable :: reactions(:)     !< committed reaction of every candidate (0 out of the set)
      real(dp) :: lambda = 0.0_dp
      real(dp), allocatable :: fixed_load(:)    !< u-independent part of the reference load R_r
      real(dp), allocatable :: reference(:)     !< R(u) at the committed state
      real(dp), allocatable :: tangent_displacement(:)  !< K_T⁻¹ R at the committed state
      real(dp), allocatable :: last_increment(:)
      real(dp) :: step_length = 0.0_dp          !< Δl, Δλ or Δu_c of the next step (by the control)
      real(dp) :: first_length = 0.0_dp
      real(dp) :: load_norm = 0.0_dp            !< ||R_r|| · first Δλ: the force scale of the problem
      integer :: direction = 1                  !< +1/−1: predictor along ±K⁻¹R
      integer :: control_equation = 0
      real(dp) :: length_scale = 1.0_dp         !< size of the model (gap tolerances)
      type(path_point_t) :: point
   end type path_state_t

contains

   !> Number the equations, assemble at the unloaded state and size the first step.
   subroutine path_initialize(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(out) :: state
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :)
      associate (options => model%analysis)
         call build_dof_map(model, state%map)
         call band_allocate(state%tangent, state%map%n_equations, state%map%half_bandwidth, &
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
         call tangent_at_committed_state(model, state, error)
         if (allocated(error)) then
            call add_where(error, 'unloaded state', state)
            return
         end if
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
         call describe_point(model, state, 0, 0, 0)
      end associate
   end subroutine path_initialize

   !> Advance one converged step, cutting the step length on failure; error if it cannot be done.
   subroutine path_advance(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: increment(:)
      logical, allocatable :: active(:)
      real(dp) :: dlambda, length, factor
      integer :: cuts, iterations, lcp_pivots
      logical :: converged
      character(len=:), allocatable :: reason
      associate (options => model%analysis)
         length = state%step_length
         do cuts = 0, options%max_cuts
            call try_step(model, state, length, increment, dlambda, active, iterations, lcp_pivots, converged, &
                          reason)
            if (converged) exit
            length = 0.5_dp*length
            if (length < options%min_increment*state%first_length) exit
         end do
         if (.not. converged) then
            call make_error(error, 'no convergence ('//reason//') after cutting the step down to '// &
                            real_to_string(length/state%first_length, message_edit)//' of the first', error_analysis)
            call add_where(error, 'step '//integer_to_string(state%point%step + 1), state)
            return
         end if
         state%u = state%u + increment
         state%lambda = state%lambda + dlambda
         state%active = active
         state%last_increment = increment
         state%point%s = state%point%s + masked_norm(state%map, increment)
         call tangent_at_committed_state(model, state, error)
         if (allocated(error)) then
            call add_where(error, 'step '//integer_to_string(state%point%step + 1)//' (converged state)', state)
            return
         end if
         select case (options%control)
         case (control_arclength)
            ! Keep travelling forward: positive angle between the new tangent and the last increment.
            if (masked_dot(state%map, increment, state%tangent_displacement) < 0.0_dp) then
               state%direction = -1
            else
               state%direction = 1
            end if
         end select
         call describe_point(model, state, state%point%step + 1, iterations, lcp_pivots)
         factor = sqrt(real(options%desired_iterations, dp)/real(max(iterations, 1), dp))
         factor = min(2.0_dp, max(0.25_dp, factor))
         state%step_length = min(options%max_increment*state%first_length, &
                                 max(options%min_increment*state%first_length, length*factor))
      end associate
   end subroutine path_advance

   !> One attempt at a step of the given length; the committed state is not touched.
   !>
   !> With contact candidates this is the paper's two-level iteration (Fig. 3): the contact LCP at the
   !> committed state gives the working set of the predictor; Newton converges with that set; the
   !> complementarity conditions are checked at the converged state and, if violated, the LCP at that
   !> state gives a new set and Newton goes on, until both equilibrium and contact have converged.
   subroutine try_step(model, state, length, increment, dlambda, active, iterations, lcp_pivots, converged, reason)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      real(dp), intent(in) :: length
      real(dp), allocatable, intent(out) :: increment(:)
      real(dp), intent(out) :: dlambda
      logical, allocatable, intent(out) :: active(:)
      integer, intent(out) :: iterations, lcp_pivots
      logical, intent(out) :: converged
      character(len=:), allocatable, intent(out) :: reason
      real(dp), allocatable :: nodal(:, :), internal(:), reference(:), rhs(:, :), trial(:), ut(:), predictor(:)
      logical, allocatable :: new_active(:)
      real(dp) :: lambda, dl, force_scale, element_scale, roundoff
      type(error_t), allocatable :: error
      type(path_constraint_t) :: constraint
      type(implicit_lcp_report_t) :: report
      real(dp), allocatable :: residual(:), ut_kept(:)
      logical :: kept
      logical :: small_correction, has_contacts, at_floor, ready, reuse_factors, in_equilibrium, update_set, &
                 solved, fresh_set
      real(dp) :: residual_norm, previous_residual
      integer :: n, set_changes
      integer, parameter :: max_set_changes = 40
      integer, parameter :: sign_rule_changes = 4
      n = state%map%n_equations
      allocate (nodal(dofs_per_node, model%n_nodes), internal(n), reference(n), rhs(n, 2), trial(n))
      ! Only the first attempt of a step finds the committed state's factors in place: any attempt
      ! assembles into state%tangent (or lends it to the contact LCP).
      ready = state%predictor_ready
      state%predictor_ready = .false.
      reuse_factors = .false.
      fresh_set = .false.
      converged = .false.
      reason = 'iteration limit'
      active = state%active
      has_contacts = any(state%map%candidate_equation > 0 .or. state%map%condensed)
      lcp_pivots = 0
      set_changes = 0
      iterations = 0
      dlambda = 0.0_dp
      associate (options => model%analysis)
         ut = state%tangent_displacement
         ! Predictor along the committed tangent; with contact, the LCP first chooses its working set.
         dlambda = predictor_dlambda(options, state, ut, length)
         if (has_contacts) then
            call gather_nodal(state%map, state%u, nodal)
            if (ready) then
               ! The committed state's tangent, factorised, and its residual (tangent_at_committed_state).
               residual = state%committed_residual
               reference = state%reference
               rhs(:, 1) = residual
               call band_solve(state%tangent, rhs(:, 1:1), error)
               rhs(:, 2) = state%tangent_displacement
            else
               call equilibrium_at(model, state, state%u, state%lambda, active, nodal, internal, reference, &
                                   element_scale)
               residual = state%lambda*reference - internal
               call band_copy(state%tangent, state%assembled)
               call factorize_and_solve(state%tangent, residual, reference, rhs, error)
            end if
            if (allocated(error)) then
               reason = 'singular tangent at the start of the step'
               return
            end if
            call step_constraint(options, state, ut, dlambda, constraint)
            allocate (new_active(size(active)))
            call select_contact_set(model, state%map, state%assembled, state%tangent, state%u, nodal, residual, reference, &
                                    rhs(:, 1), rhs(:, 2), constraint, units_at(model, state, state%u, nodal, active), &
                                    active, new_active, report, error, kept, ut_kept)
            lcp_pivots = lcp_pivots + report%pivots
            if (allocated(error)) then
               reason = error%message
               return
            end if
            if (any(new_active .neqv. active)) then
               active = new_active
               if (kept) then
                  ! The LCP's last frame is the new set: its factors gave K_S⁻¹R already.
                  ut = ut_kept
               else
                  call equilibrium_at(model, state, state%u, state%lambda, active, nodal, internal, reference, &
                                      element_scale)
                  call factorize_and_solve(state%tangent, state%lambda*reference - internal, reference, rhs, error)
                  if (allocated(error)) then
                     reason = 'singular tangent with the predicted contact set'
                     return
                  end if
                  ut = rhs(:, 2)
               end if
               dlambda = predictor_dlambda(options, state, ut, length)
            end if
         end if
         increment = dlambda*ut
         predictor = increment
         small_correction = .false.
         previous_residual = huge(1.0_dp)
         do while (iterations <= options%max_iterations)
            lambda = state%lambda + dlambda
            trial = state%u + increment
            call gather_nodal(state%map, trial, nodal)
            call equilibrium_at(model, state, trial, lambda, active, nodal, internal, reference, element_scale, &
                                roundoff)
            rhs(:, 1) = lambda*reference - internal
            force_scale = max(state%load_norm, norm2(lambda*reference), element_scale)
            if (.not. (norm2(rhs(:, 1)) < huge(1.0_dp))) then   ! NaN or overflow
               reason = 'the residual is not finite'
               exit
            end if
            ! At the round-off floor of the residual (below the assembly's own round-off, `roundoff`)
            ! a correction is noise of the solve, cond(K)·ε·|Δu|, which on a fine ill-conditioned mesh
            ! stays above the displacement tolerance however long Newton goes on: two iterations in a
            ! row at that floor, the second without halving the residual, are converged to working
            ! precision (docs/theory.md, convergence).
            residual_norm = masked_norm(state%map, rhs(:, 1))
            at_floor = iterations > 1 .and. residual_norm <= roundoff .and. previous_residual <= roundoff .and. &
                       residual_norm >= 0.5_dp*previous_residual
            previous_residual = residual_norm
            in_equilibrium = iterations > 0 .and. (small_correction .or. at_floor) .and. &
                             residual_norm <= max(options%force_tolerance*force_scale, roundoff) .and. &
                             constraint_residual(state%map, rhs(:, 1)) <= options%displacement_tolerance* &
                             max(maxval(abs(state%map%metric*trial)), 1.0e-12_dp*state%length_scale)
            update_set = .false.
            if (in_equilibrium) then
               ! A step must go forward: a correction that lands behind the predictor (possible with
               ! Chan's constraint-free correction when the contact set changes within the step) would
               ! make the path turn back on itself. Such an attempt is cut instead.
               if (masked_dot(state%map, increment, predictor) <= 0.0_dp) then
                  reason = 'the corrected step turned back'
                  exit
               end if
               if (.not. has_contacts) then
                  converged = .true.
                  exit
               end if
               if (complementary(model, state, trial, nodal, active)) then
                  converged = .true.
                  exit
               end if
               ! Equilibrium with a wrong contact set: the LCP at this state gives the next set.
               update_set = .true.
            else
               if (iterations == options%max_iterations) exit
               ! The working set is updated within Newton too (docs/theory.md §3.4): a trial state that
               ! a correction has reached with a violated contact gets the LCP linearised at it, whose
               ! solution is the Newton correction of the complementarity problem (Josephy–Newton). It
               ! uses the factors this iteration needs anyway, so a change of the set costs no extra
               ! factorisation and the set converges along with equilibrium instead of after it.
               update_set = has_contacts .and. .not. fresh_set
               if (update_set) update_set = .not. complementary(model, state, trial, nodal, active)
               if (update_set .and. set_changes < sign_rule_changes) then
                  if (.not. allocated(new_active)) allocate (new_active(size(active)))
                  call sign_rule(model, state, trial, nodal, active, new_active)
                  if (any(new_active .neqv. active)) then
                     set_changes = set_changes + 1
                     active = new_active
                     small_correction = .false.
                     previous_residual = huge(1.0_dp)
                     fresh_set = .true.
                     reuse_factors = .false.
                     cycle
                  end if
               end if
            end if
            solved = .false.
            if (update_set) then
               set_changes = set_changes + 1
               if (set_changes > max_set_changes) then
                  reason = 'the contact set does not settle'
                  exit
               end if
               ! state%tangent holds K_S assembled at this state (any factors kept from an earlier
               ! LCP belong to the same set and are simply not used).
               reuse_factors = .false.
               residual = rhs(:, 1)
               call band_copy(state%tangent, state%assembled)
               call factorize_and_solve(state%tangent, residual, reference, rhs, error)
               if (allocated(error)) then
                  reason = 'singular tangent'
                  exit
               end if
               call correction_constraint(options, state, increment, constraint)
               if (.not. allocated(new_active)) allocate (new_active(size(active)))
               call select_contact_set(model, state%map, state%assembled, state%tangent, trial, nodal, residual, &
                                       reference, rhs(:, 1), rhs(:, 2), constraint, units_at(model, state, trial, nodal, active), &
                                       active, new_active, report, error, kept, ut_kept)
               lcp_pivots = lcp_pivots + report%pivots
               if (allocated(error)) then
                  reason = error%message
                  exit
               end if
               if (any(new_active .neqv. active)) then
                  active = new_active
                  small_correction = .false.
                  previous_residual = huge(1.0_dp)
                  fresh_set = .true.
                  ! The LCP's last frame is K_S of the new set at this very state: its factors serve
                  ! the next correction (the loop assembles into state%tangent, so they wait in
                  ! `assembled`).
                  reuse_factors = kept
                  if (reuse_factors) call band_copy(state%tangent, state%assembled)
                  cycle
               end if
               if (in_equilibrium) then
                  reason = 'the LCP keeps a contact set that violates complementarity'
                  exit
               end if
               ! The linearised problem keeps the set: the correction of this set, already solved
               ! (rhs holds K_S⁻¹g and K_S⁻¹R), is the Newton correction.
               solved = .true.
            end if
            iterations = iterations + 1
            if (.not. solved) then
               if (reuse_factors) then
                  rhs(:, 2) = reference
                  call band_solve(state%assembled, rhs, error)
                  reuse_factors = .false.
               else
                  call factorize_and_solve(state%tangent, rhs(:, 1), reference, rhs, error)
               end if
               if (allocated(error)) then
                  reason = 'singular tangent'
                  exit
               end if
            end if
            fresh_set = .false.
            ! rhs(:, 1) = δx_g (residual correction), rhs(:, 2) = δx_t (tangent correction)
            select case (options%control)
            case (control_load)
               dl = 0.0_dp
            case (control_displacement)
               dl = -rhs(state%control_equation, 1)/rhs(state%control_equation, 2)
            case default
               call load_correction(options, state%map, increment, rhs(:, 1), rhs(:, 2), length, dl, reason)
               if (len(reason) == 0) then
                  reason = 'iteration limit'
               else
                  exit
               end if
            end select
            increment = increment + rhs(:, 1) + dl*rhs(:, 2)
            dlambda = dlambda + dl
            ! Correction small relative to the increment; a step cut very short meets the round-off of
            ! the solve first, which is some 1e3 ε of the total displacement: below that is converged.
            small_correction = masked_norm(state%map, rhs(:, 1) + dl*rhs(:, 2)) <= &
                               max(options%displacement_tolerance*masked_norm(state%map, increment), &
                                   1.0e3_dp*epsilon(1.0_dp)*masked_norm(state%map, state%u + increment), &
                                   tiny(1.0_dp))
         end do
      end associate
   end subroutine try_step

   !> Load increment of the predictor along the tangent ut for a step of the given length.
   !> For arc length the sign follows the direction of travel: positive angle with the last increment
   !> (the committed `direction` was chosen so for the committed tangent; a predictor tangent computed
   !> with another contact set may point the other way, so the angle is taken again).
   pure real(dp) function predictor_dlambda(options, state, ut, length) result(dlambda)
      type(analysis_options_t), intent(in) :: options
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: ut(:), length
      real(dp) :: cosine
      select case (options%control)
      case (control_arclength)
         dlambda = state%direction*length/masked_norm(state%map, ut)
         cosine = masked_dot(state%map, state%last_increment, ut)
         if (cosine*dlambda < 0.0_dp) dlambda = -dlambda
      case (control_displacement)
         dlambda = state%direction*length/ut(state%control_equation)
      case default
         dlambda = state%direction*length
      end select
   end function predictor_dlambda

   !> The constraint of the predictor LCP: the linearised step (normal plane to the tangent at distance
   !> Δl for arc length, the load or displacement increment otherwise).
   pure subroutine step_constraint(options, state, ut, dlambda, constraint)
      type(analysis_options_t), intent(in) :: options
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: ut(:), dlambda
      type(path_constraint_t), intent(out) :: constraint
      select case (options%control)
      case (control_arclength)
         constraint%kind = constraint_arclength
         constraint%t = state%map%metric*ut*dlambda
         constraint%target = masked_dot(state%map, constraint%t, ut*dlambda)
      case (control_displacement)
         constraint%kind = constraint_displacement
         constraint%equation = state%control_equation
         constraint%target = dlambda*ut(state%control_equation)
      case default
         constraint%kind = constraint_load
         constraint%target = dlambda
      end select
   end subroutine step_constraint

   !> The constraint of a corrector LCP inside a step: stay on the step (normal plane to the current
   !> increment, or the same load or controlled displacement).
   pure subroutine correction_constraint(options, state, increment, constraint)
      type(analysis_options_t), intent(in) :: options
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: increment(:)
      type(path_constraint_t), intent(out) :: constraint
      select case (options%control)
      case (control_arclength)
         constraint%kind = constraint_arclength
         constraint%t = state%map%metric*increment
      case (control_displacement)
         constraint%kind = constraint_displacement
         constraint%equation = state%control_equation
      case default
         constraint%kind = constraint_load
      end select
      constraint%target = 0.0_dp
   end subroutine correction_constraint

   !> Complementarity at a state that is in equilibrium for the working set `active`: no candidate in
   !> the set pulls (r ≥ 0) and none outside it penetrates (g ≥ 0), within tolerances relative to the
   !> largest reaction and the largest displacement.
   function complementary(model, state, x, nodal, active) result(ok)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: x(:), nodal(:, :)
      logical, intent(in) :: active(:)
      logical :: ok
      real(dp), allocatable :: reaction(:), gap(:)
      call candidate_state(model, state%map, x, nodal, active, reaction, gap)
      ok = violation(model, state, x, reaction, gap, active) <= model%analysis%displacement_tolerance
   end function complementary

   !> The primal–dual active-set rule (Hintermüller, Ito & Kunisch 2002) at unknowns x: a candidate
   !> outside `active` that penetrates (w < 0) enters, one inside that pulls (r < 0) leaves, each
   !> beyond the tolerance of `violation`; the others stay.
   subroutine sign_rule(model, state, x, nodal, active, new_active)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: x(:), nodal(:, :)
      logical, intent(in) :: active(:)
      logical, intent(out) :: new_active(:)
      real(dp), allocatable :: reaction(:), gap(:)
      type(contact_scales_t) :: units
      real(dp) :: tolerance
      integer :: c
      call candidate_state(model, state%map, x, nodal, active, reaction, gap)
      units = contact_units(state, x, reaction, active)
      tolerance = model%analysis%displacement_tolerance
      new_active = active
      do c = 1, size(active)
         if (.not. candidate_live(state%map, c) .or. model%contacts(c)%bilateral) cycle
         if (active(c)) then
            if (-reaction(c)/units%force > tolerance) new_active(c) = .false.
         else
            if (-gap(c)/units%gap > tolerance) new_active(c) = .true.
         end if
      end do
   end subroutine sign_rule

   !> Largest violation of complementarity, relative: −r/r_scale for pulling contacts, −g/g_scale for
   !> penetrating free candidates, |r w|/(r_scale g_scale) for both at once.
   pure real(dp) function violation(model, state, x, reaction, gap, active) result(worst)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: x(:), reaction(:), gap(:)
      logical, intent(in) :: active(:)
      real(dp) :: r_scale, g_scale, w, r
      type(contact_scales_t) :: units
      integer :: c
      worst = 0.0_dp
      if (size(reaction) == 0) return
      ! Scales: the largest reaction in contact, at least the load scale (reactions of free candidates
      ! are round-off of zero and must not set it); the largest displacement.
      units = contact_units(state, x, reaction, active)
      r_scale = units%force
      g_scale = units%gap
      do c = 1, size(reaction)
         if (.not. candidate_live(state%map, c) .or. model%contacts(c)%bilateral) cycle
         r = 0.0_dp
         if (active(c)) r = reaction(c)
         w = gap(c) + model%contacts(c)%flexibility*r
         worst = max(worst, -r/r_scale, -w/g_scale, abs(r*w)/(r_scale*g_scale))
      end do
   end function violation

   !> Units of contact forces and gaps at unknowns x with working set `active`: the largest reaction in
   !> contact, at least the load scale (reactions of free candidates are round-off of zero and must not
   !> set it); the largest displacement, at least 1e-6 of the model size (gaps computed from
   !> coordinates carry round-off of ε × size).
   pure function contact_units(state, x, reaction, active) result(units)
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: x(:), reaction(:)
      logical, intent(in) :: active(:)
      type(contact_scales_t) :: units
      real(dp) :: largest
      integer :: c
      largest = 0.0_dp
      do c = 1, size(active)
         if (candidate_live(state%map, c) .and. active(c)) largest = max(largest, abs(reaction(c)))
      end do
      units%force = max(largest, state%load_norm, tiny(1.0_dp))
      units%gap = max(maxval(abs(state%map%metric*x)), 1.0e-6_dp*state%length_scale)
   end function contact_units

   !> Contact units at unknowns x (nodal: their nodal displacements) with working set `active`.
   function units_at(model, state, x, nodal, active) result(units)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: x(:), nodal(:, :)
      logical, intent(in) :: active(:)
      type(contact_scales_t) :: units
      real(dp), allocatable :: reaction(:), gap(:)
      call candidate_state(model, state%map, x, nodal, active, reaction, gap)
      units = contact_units(state, x, reaction, active)
   end function units_at

   !> Reactions and current gaps of every candidate: a reaction unknown of x, or for a condensed spring
   !> −g/t in the working set `active` and 0 out of it.
   pure subroutine candidate_state(model, map, x, nodal, active, reaction, gap)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: x(:), nodal(:, :)
      logical, intent(in) :: active(:)
      real(dp), allocatable, intent(out) :: reaction(:), gap(:)
      real(dp) :: gradient(2), hessian(2, 2)
      integer :: c, node
      allocate (reaction(size(map%candidate_equation)), gap(size(map%candidate_equation)))
      do c = 1, size(map%candidate_equation)
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap(c), gradient, &
                            hessian)
         reaction(c) = 0.0_dp
         if (map%candidate_equation(c) > 0) then
            reaction(c) = x(map%candidate_equation(c))
         else if (map%condensed(c) .and. active(c)) then
            reaction(c) = -gap(c)/model%contacts(c)%flexibility
         end if
      end do
   end subroutine candidate_state

   !> Reactions of every candidate at the committed state (exactly 0 for those out of contact).
   pure function candidate_reactions(state) result(reaction)
      type(path_state_t), intent(in) :: state
      real(dp), allocatable :: reaction(:)
      integer :: c
      allocate (reaction(size(state%map%candidate_equation)), source=0.0_dp)
      if (.not. allocated(state%reactions)) return
      ! Out of the working set a reaction is zero by definition; its unknown holds round-off only.
      do c = 1, size(reaction)
         if (state%active(c)) reaction(c) = state%reactions(c)
      end do
   end function candidate_reactions

   !> Candidates that touch (|g| within round-off of the model size) or are bonded.
   pure subroutine touching_candidates(model, state, nodal, active)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: nodal(:, :)
      logical, intent(out) :: active(:)
      real(dp) :: gap, gradient(2), hessian(2, 2)
      integer :: c, node
      do c = 1, size(state%map%candidate_equation)
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, gradient, hessian)
         active(c) = candidate_live(state%map, c) .and. &
                     (model%contacts(c)%bilateral .or. gap <= 1.0e-9_dp*state%length_scale)
      end do
   end subroutine touching_candidates

   !> Augmented internal forces, reference load and tangent at unknowns x, load λ, working set `active`.
   subroutine equilibrium_at(model, state, x, lambda, active, nodal, internal, reference, element_scale, roundoff)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      real(dp), intent(in) :: x(:), lambda
      logical, intent(in) :: active(:)
      real(dp), intent(in) :: nodal(:, :)
      real(dp), intent(out) :: internal(:), reference(:), element_scale
      real(dp), intent(out), optional :: roundoff
      call assemble_equilibrium(model, state%map, nodal, lambda, state%fixed_load, state%tangent, &
                                internal, reference, element_scale, roundoff)
      if (size(state%map%candidate_equation) > 0) then
         call assemble_contact(model, state%map, nodal, candidate_values(state%map, x), active, &
                               state%tangent, internal)
      end if
   end subroutine equilibrium_at

   !> The reaction unknowns of x, one per candidate (0 for inert ones).
   pure function candidate_values(map, x) result(values)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: x(:)
      real(dp) :: values(size(map%candidate_equation))
      integer :: c
      values = 0.0_dp
      do c = 1, size(values)
         if (map%candidate_equation(c) > 0) values(c) = x(map%candidate_equation(c))
      end do
   end function candidate_values

   !> Largest residual of the contact rows (gap units for the working set, reactions for the rest).
   pure real(dp) function constraint_residual(map, residual) result(largest)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: residual(:)
      largest = 0.0_dp
      if (size(map%candidate_equation) > 0) largest = maxval(abs((1.0_dp - map%metric)*residual))
   end function constraint_residual

   !> Factorise the tangent and solve it for the residual and the reference load: rhs(:, 1:2).
   subroutine factorize_and_solve(tangent, residual, reference, rhs, error)
      type(band_matrix_t), intent(inout) :: tangent
      real(dp), intent(in) :: residual(:), reference(:)
      real(dp), intent(inout) :: rhs(:, :)
      type(error_t), allocatable, intent(out) :: error
      call band_factorize(tangent, error)
      if (allocated(error)) return
      rhs(:, 1) = residual
      rhs(:, 2) = reference
      call band_solve(tangent, rhs, error)
   end subroutine factorize_and_solve

   !> Load correction δλ of an arc-length iteration; `reason` is empty on success. Dot products and
   !> norms are over the displacements only (the metric masks the reactions out).
   pure subroutine load_correction(options, map, increment, du_residual, du_tangent, length, dl, reason)
      type(analysis_options_t), intent(in) :: options
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: increment(:), du_residual(:), du_tangent(:), length
      real(dp), intent(out) :: dl
      character(len=:), allocatable, intent(out) :: reason
      real(dp) :: a, b, c, discriminant, root(2), cosine(2)
      integer :: k
      reason = ''
      dl = 0.0_dp
      ! With the contacts of the working set carrying the whole reference load, K⁻¹R has no
      ! displacement part and no arc-length strategy can fix δλ (a rigid obstacle under the load).
      if (.not. (masked_dot(map, du_tangent, du_tangent) > 0.0_dp)) then
         reason = 'the reference load moves no displacement with this contact set (the contacts carry it)'
         return
      end if
      select case (options%iteration)
      case (iteration_chan)
         ! Minimum residual displacement (Chan 1988): δλ minimises ||δu_g + δλ δu_t||.
         dl = -masked_dot(map, du_tangent, du_residual)/masked_dot(map, du_tangent, du_tangent)
      case (iteration_riks)
         ! Updated normal plane (Ramm 1981): the correction is orthogonal to the current increment.
         if (.not. (abs(masked_dot(map, increment, du_tangent)) > 0.0_dp)) then
            reason = 'the tangent is orthogonal to the increment (updated normal plane)'
            return
         end if
         dl = -masked_dot(map, increment, du_residual)/masked_dot(map, increment, du_tangent)
      case (iteration_cylindrical)
         ! ||Δu + δu_g + δλ δu_t|| = Δl (Crisfield 1981): the root closer in angle to the increment.
         a = masked_dot(map, du_tangent, du_tangent)
         b = 2.0_dp*masked_dot(map, du_tangent, increment + du_residual)
         c = masked_dot(map, increment + du_residual, increment + du_residual) - length**2
         discriminant = b**2 - 4.0_dp*a*c
         if (discriminant < 0.0_dp) then
            reason = 'the arc-length constraint has no real root'
            dl = 0.0_dp
            return
         end if
         root(1) = (-b + sqrt(discriminant))/(2.0_dp*a)
         root(2) = (-b - sqrt(discriminant))/(2.0_dp*a)
         do k = 1, 2
            cosine(k) = masked_dot(map, increment, increment + du_residual + root(k)*du_tangent)
         end do
         dl = root(maxloc(cosine, 1))
      case default
         dl = 0.0_dp
         reason = 'unknown iteration strategy'
      end select
   end subroutine load_correction

   !> Assemble and factorise K_T at the committed state; its inertia, K⁻¹R and least eigenvalue.
   subroutine tangent_at_committed_state(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), internal(:), rhs(:, :)
      real(dp) :: element_scale
      logical :: singular, found
      integer :: n
      state%predictor_ready = .false.
      n = state%map%n_equations
      allocate (internal(n), rhs(n, 1))
      call nodal_displacements(model, state, nodal)
      if (.not. allocated(state%reference)) allocate (state%reference(n))
      call equilibrium_at(model, state, state%u, state%lambda, state%active, nodal, internal, state%reference, &
                          element_scale)
      ! The unfactorised tangent and the residual stay for the predictor of the next step (its contact
      ! LCP needs both): the step's first attempt does not assemble and factorise them again.
      call band_copy(state%tangent, state%assembled)
      state%committed_residual = state%lambda*state%reference - internal
      call band_factorize(state%tangent, error)
      if (allocated(error)) return
      ! Inertia: from the LU factors when they needed no row interchange, else by elimination.
      call band_inertia_from_factors(state%tangent, state%assembled, state%point%neg_pivots, singular, found)
      if (.not. found) call band_inertia(state%assembled, state%point%neg_pivots, singular)
      ! Each contact row of the working set adds one negative pivot to the saddle-point system
      ! (Haynsworth inertia additivity): what remains counts the unstable modes of the structure.
      state%point%n_active = count(state%active .and. state%map%candidate_equation > 0)
      state%point%neg_pivots = max(0, state%point%neg_pivots - state%point%n_active)
      rhs(:, 1) = state%reference
      call band_solve(state%tangent, rhs, error)
      if (allocated(error)) return
      state%predictor_ready = .true.
      state%tangent_displacement = rhs(:, 1)
      state%point%min_eigenvalue = least_eigenvalue(state%tangent, state%eigenvector)
   end subroutine tangent_at_committed_state

   !> Fill the point record of the committed state.
   subroutine describe_point(model, state, step, iterations, lcp_pivots)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      integer, intent(in) :: step, iterations, lcp_pivots
      real(dp), allocatable :: nodal(:, :), reaction(:), gap(:)
      real(dp) :: norm, g, gradient(2), hessian(2, 2)
      integer :: m, c, row, node
      state%point%step = step
      state%point%lambda = state%lambda
      state%point%iterations = iterations
      state%point%lcp_pivots = lcp_pivots
      ! Unit tangent of the path in (u, λ) with the arc-length metric ds² = ||du||² (cylindrical):
      ! du/ds = ±K⁻¹R/||K⁻¹R||, dλ/ds = ±1/||K⁻¹R||, signed by the direction of travel.
      norm = masked_norm(state%map, state%tangent_displacement)
      state%point%dlambda_ds = real(state%direction, dp)/norm
      state%point%rate = (real(state%direction, dp)/norm)*state%map%metric*state%tangent_displacement
      state%point%lcp_residual = 0.0_dp
      m = size(state%map%candidate_equation)
      state%point%in_contact = [(.false., c=1, m)]
      state%point%contact_value = [(0.0_dp, c=1, m)]
      state%point%contact_rate = [(0.0_dp, c=1, m)]
      if (m > 0) then
         call nodal_displacements(model, state, nodal)
         call candidate_state(model, state%map, state%u, nodal, state%active, reaction, gap)
         state%reactions = reaction
         state%point%lcp_residual = violation(model, state, state%u, reaction, gap, state%active)
         ! Reaction (in contact) or gap (free) of each candidate and its rate along the path, from the
         ! tangent: where a contact starts or ends between two steps is found from them.
         do c = 1, m
            row = state%map%candidate_equation(c)
            if (.not. candidate_live(state%map, c)) cycle
            node = model%contacts(c)%node
            call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, gradient, &
                               hessian)
            state%point%in_contact(c) = state%active(c) .and. reaction(c) > 0.0_dp
            if (state%point%in_contact(c)) then
               state%point%contact_value(c) = reaction(c)
               if (row > 0) then
                  state%point%contact_rate(c) = state%direction*state%tangent_displacement(row)/norm
               else
                  ! condensed: r = −g/t, dr/ds = −(a·du/ds)/t
                  state%point%contact_rate(c) = -state%direction*along(state%tangent_displacement)/norm/ &
                                                model%contacts(c)%flexibility
               end if
            else
               state%point%contact_value(c) = g
               state%point%contact_rate(c) = state%direction*along(state%tangent_displacement)/norm
            end if
         end do
      end if

   contains

      !> a_cᵀ v at the candidate's node for an augmented vector v.
      pure real(dp) function along(v)
         real(dp), intent(in) :: v(:)
         integer :: i
         along = 0.0_dp
         do i = 1, 2
            if (state%map%equation(i, node) > 0) along = along + gradient(i)*v(state%map%equation(i, node))
         end do
      end function along
   end subroutine describe_point

   !> Dot product over the displacement unknowns only.
   pure real(dp) function masked_dot(map, a, b)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: a(:), b(:)
      masked_dot = sum(map%metric*a*b)
   end function masked_dot

   !> Norm over the displacement unknowns only.
   pure real(dp) function masked_norm(map, a)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: a(:)
      masked_norm = sqrt(sum(map%metric*a**2))
   end function masked_norm

   !> Eigenvalue of least magnitude of a factorised matrix by inverse iteration (Rayleigh quotient of
   !> K⁻¹); used only to place bifurcation points between steps, so a few digits suffice.
   !> `mode` (n) is the start vector and returns the last iterate: started from the mode of the last
   !> converged step, which changes little from step to step, the iteration settles in a few solves.
   function least_eigenvalue(matrix, mode) result(mu)
      type(band_matrix_t), intent(in) :: matrix
      real(dp), allocatable, intent(inout) :: mode(:)
      real(dp) :: mu
      real(dp), allocatable :: x(:, :), y(:)
      real(dp) :: nu, previous
      type(error_t), allocatable :: error
      integer :: k, i, first_check
      mu = 0.0_dp
      if (matrix%n == 0) return
      allocate (x(matrix%n, 1))
      ! No usable last mode (first step, another size, or a zero vector): a fixed generic start.
      if (allocated(mode)) then
         if (size(mode) /= matrix%n .or. .not. (norm2(mode) > 0.0_dp)) deallocate (mode)
      end if
      first_check = 1
      if (.not. allocated(mode)) then
         mode = [(1.0_dp + 0.1_dp*sin(real(i, dp)), i=1, matrix%n)]
         first_check = 2
      end if
      x(:, 1) = mode/norm2(mode)
      nu = 0.0_dp
      ! Stop when the Rayleigh quotient has settled to 1e-4 (it only places a bifurcation inside a
      ! step, by linear interpolation whose own error is of the order of the step). Near a critical
      ! point, where it matters, the least eigenvalue is well separated and a few solves do; where the
      ! low spectrum is clustered (a ring of 1e5 elements: ratios of neighbouring eigenvalues near 1)
      ! inverse iteration cannot separate them in any affordable number of solves, and the quotient
      ! after 8 — between the clustered eigenvalues, of their common sign — is what the detector
      ! needs. A warm start from the last mode needs two solves to compare quotients, a cold one three.
      do k = 1, 8
         y = x(:, 1)
         call band_solve(matrix, x, error)
         if (allocated(error)) return
         previous = nu
         nu = dot_product(y, x(:, 1))
         x = x/norm2(x)
         if (k > first_check .and. abs(nu - previous) <= 1.0e-4_dp*abs(nu)) exit
      end do
      if (all(abs(x(:, 1)) <= huge(1.0_dp))) mode = x(:, 1)
      if (abs(nu) > tiny(1.0_dp)) mu = 1.0_dp/nu
   end function least_eigenvalue

   !> Nodal displacements (3, n_nodes) of the committed state.
   subroutine nodal_displacements(model, state, nodal)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), allocatable, intent(out) :: nodal(:, :)
      allocate (nodal(dofs_per_node, model%n_nodes))
      call gather_nodal(state%map, state%u, nodal)
   end subroutine nodal_displacements

   subroutine add_where(error, where, state)
      type(error_t), intent(inout) :: error
      character(len=*), intent(in) :: where
      type(path_state_t), intent(in) :: state
      error%message = where//', from lambda = '//real_to_string(state%lambda, message_edit)//': '//error%message
   end subroutine add_where

end module uniarc_path_following
