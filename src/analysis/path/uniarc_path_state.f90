!> The objects of the path following and the operations all its parts share.
!>
!> The committed state of the path (`path_state_t`) and the trial of one attempt at a step
!> (`step_trial_t`) are separate objects, as OpenSees separates a domain's committed and trial state
!> (McKenna 1997, ch. 4): an attempt (uniarc_path_newton) reads the committed state only (intent(in))
!> and writes its trial and the system of equations it works in (`path_system_t`); path_advance
!> (uniarc_path_following) commits a converged trial, and a failed one is dropped.
!>
!> The system holds the band matrices every attempt assembles and factorises. Between steps they are
!> the committed state's K_T (a cache, flagged by `holds_committed`): the first attempt of a step
!> solves its predictor with those factors, and once an attempt overwrites them the flag is cleared and
!> a later attempt assembles K_T at the committed state again.
module uniarc_path_state
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_model, only: model_t, dofs_per_node, dof_rz, end_joint_t, end_joints_of, gap_fixed_direction
   use uniarc_strings, only: integer_to_string
   use uniarc_element, only: element_response_t, element_response, element_displacements, transformation_corotational
   use uniarc_dof_map, only: dof_map_t, candidate_live, bed_deflection
   use uniarc_band, only: band_matrix_t, band_factorize, band_solve, band_add, band_get
   use uniarc_assembly, only: gather_nodal
   use uniarc_equilibrium, only: assemble_equilibrium
   use uniarc_contact, only: assemble_contact, candidate_gap, carried_by_support
   use uniarc_contact_plastic, only: has_plastic, commit_slip
   use uniarc_floating_subspace, only: orthonormal_motions, unheld_motions, spring_equations
   implicit none
   private
   public :: path_point_t, path_system_t, path_state_t, step_trial_t, linearization_t, bifurcation_state_t
   public :: commit_joint_state, yielded_joints
   public :: masked_dot, masked_norm, nodal_displacements, candidate_reactions, equilibrium_at, &
             factorize_and_solve, constraint_residual, has_contacts, new_linearization
   public :: hold_floating, floating_touched
   public :: commit_plastic, accept_trial
   public :: fail_attempt

   !> What a converged point of the path tells the critical-point detector.
   type :: path_point_t
      integer :: step = 0
      real(dp) :: s = 0.0_dp            !< path length Σ ||Δu|| up to this point
      real(dp) :: lambda = 0.0_dp
      real(dp) :: dlambda_ds = 0.0_dp   !< slope of the path in the direction of travel
      real(dp), allocatable :: rate(:)  !< du/ds (equations) in the direction of travel
      integer :: neg_pivots = 0         !< negative pivots of K_T (Sylvester: negative eigenvalues)
      real(dp) :: min_eigenvalue = 0.0_dp   !< eigenvalue of K_T of least magnitude (inverse iteration)
      !> neg_pivots and min_eigenvalue are those of the tangent with the contacts that touch without
      !> force released (uniarc_path_stability, lift-off): its least mode may lift them off.
      logical :: liftoff = .false.
      integer :: iterations = 0
      integer :: lcp_pivots = 0             !< Lemke pivots spent on the step
      real(dp) :: lcp_residual = 0.0_dp     !< complementarity residual at the converged state
      integer :: n_active = 0               !< candidates in the working set
      logical, allocatable :: in_contact(:)       !< per candidate: in the working set with r > 0
      real(dp), allocatable :: contact_value(:)   !< per candidate: reaction if in contact, else gap
      real(dp), allocatable :: contact_rate(:)    !< d(contact_value)/ds in the direction of travel
      !> Critical points between the previous converged point and this one, located by re-solving
      !> (uniarc_path_locate): the fraction of that interval (−1: none located) and λ there.
      real(dp) :: limit_fraction = -1.0_dp, limit_lambda = 0.0_dp
      real(dp) :: bifurcation_fraction = -1.0_dp, bifurcation_lambda = 0.0_dp
      !> The change of neg_pivots across the located bifurcation's final bracket (uniarc_path_locate),
      !> when that bracket was narrowed to its tolerance: 2 where two eigenvalues of K_T vanish together
      !> (a double eigenvalue of a symmetric structure, the whole ring's oval modes cos 2θ and sin 2θ);
      !> 0 when no bifurcation was located or its bracket could not be narrowed.
      integer :: bifurcation_multiplicity = 0
      !> The change of the count could not be bracketed by re-solving the step (a re-solution did not
      !> converge, or converged off the piece of path between the bracket's ends, before the bracket
      !> was narrowed to its tolerance): the bifurcation is placed at a converged end of the bracket so
      !> far (uniarc_path_locate), not interpolated across it.
      logical :: bifurcation_unbracketed = .false.
      !> The change of neg_pivots since the previous point happens where the working set changes (the
      !> locator's final bracket has a different set at its ends): a contact that closes or opens
      !> makes the least eigenvalue jump across zero, the tangent is singular nowhere, and the change is
      !> a change of stability at a contact event, not a bifurcation (docs/theory.md §2.2): a
      !> `contact_stability` row.
      logical :: stability_by_contact = .false.
      !> When stability_by_contact: the fraction of the interval and λ of that contact event (the
      !> converged end of the locator's final bracket where the count has changed, within 1e-3 of the
      !> step of the change), a `contact_stability` row of STEM.crit.
      real(dp) :: stability_fraction = -1.0_dp, stability_lambda = 0.0_dp
      !> The sign change of dλ/ds since the previous point happens where the working set changes (a
      !> corner of the path, uniarc_path_locate): a contact event with λ at an extreme (`contact_corner`
      !> in STEM.crit), not a limit point (docs/theory.md §2.12).
      logical :: limit_by_contact = .false.
      !> A contact start since the previous point (none in contact there, some here) located by
      !> re-solving the step with the previous point's working set (uniarc_path_contact_start): the
      !> fraction of the interval in path length (−1: not located) and λ of the state where the first
      !> gap closes; path_state_t%contact_start_u holds its unknowns.
      real(dp) :: contact_start_fraction = -1.0_dp, contact_start_lambda = 0.0_dp
      !> This point is the first of a secondary branch, reached from a bifurcation (uniarc_path_branch):
      !> the interval before it joins two branches and holds no critical point.
      logical :: switched = .false.
      real(dp) :: switch_lambda = 0.0_dp   !< when switched: λ of the state the branch left from
      !> The step to this point was cut because a longer one changed one of two tied contacts and not
      !> the other, and it moved them together (uniarc_path_following): a branch point of the contact
      !> set passed on the branch followed (`contact_branching` in STEM.crit, docs/theory.md §2.3).
      logical :: tie_kept = .false.
   end type path_point_t

   !> A bifurcation located by re-solving a step (uniarc_path_locate): the converged state nearest to
   !> it and its buckling mode, for the modes file and branch switching (uniarc_path_branch).
   type :: bifurcation_state_t
      real(dp), allocatable :: u(:)        !< (n) unknowns of the nearest converged state
      logical, allocatable :: active(:)    !< its working set
      real(dp) :: lambda = 0.0_dp          !< its load factor
      real(dp) :: located_lambda = 0.0_dp  !< λ of the located bifurcation (point%bifurcation_lambda)
      real(dp) :: position = 0.0_dp        !< where it lies: the fractional step of STEM.crit
      real(dp) :: s = 0.0_dp               !< its path length
      !> (n) least eigenvector there: of K_T, or with the touching contacts released when `liftoff`
      !> (the mode on the admissible cone, docs/theory.md §2.2)
      real(dp), allocatable :: mode(:)
      logical :: liftoff = .false.
      real(dp), allocatable :: joint_plastic(:, :)  !< (2, n_elements) its joints' plastic rotations
   end type bifurcation_state_t

   !> The system of equations the steps work in: the augmented tangent K_T in band storage (n × n,
   !> n = map%n_equations), twice.
   type :: path_system_t
      type(band_matrix_t) :: tangent    !< K_T assembled, then factorised in place
      type(band_matrix_t) :: assembled  !< K_T unfactorised (the contact LCP's operator), or factors kept
      !> tangent and assembled are the committed state's K_T, factorised and unfactorised, with
      !> path_state_t%committed_residual: set by the commit, cleared by the first attempt that uses them.
      logical :: holds_committed = .false.
      !> tangent holds K_T assembled, unfactorised, at the converged state of the last attempt, and
      !> converged_internal, converged_reference its F_aug and R: the commit needs no assembly.
      logical :: holds_converged = .false.
      real(dp), allocatable :: converged_internal(:), converged_reference(:)
   end type path_system_t

   !> The committed state of the path and what the next step needs. Only path_initialize and
   !> path_advance change it.
   type :: path_state_t
      type(dof_map_t) :: map
      !> The band matrices of the steps (moved out for the duration of an attempt, so that an attempt
      !> cannot write the committed state it reads).
      type(path_system_t), allocatable :: system
      real(dp), allocatable :: committed_residual(:)  !< λR − F_aug at the committed state
      real(dp), allocatable :: eigenvector(:)   !< last mode of least eigenvalue (warm start)
      real(dp), allocatable :: liftoff_mode(:)  !< the same with the touching contacts released
      real(dp), allocatable :: u(:)             !< committed unknowns: displacements and reactions
      logical, allocatable :: active(:)         !< committed working set of contact candidates
      real(dp), allocatable :: reactions(:)     !< committed reaction of every candidate (0 out of the set)
      !> (2, n_elements) committed plastic rotations (radian) of the joints with a moment limit at node 1
      !> and node 2 of every element (uniarc_joint_plasticity), the history an attempt starts from;
      !> unallocated when no joint has a limit.
      real(dp), allocatable :: joint_plastic(:, :)
      !> plastic media (uniarc_contact_plastic): the committed plastic slip of every candidate (0 unless
      !> plastic; history, moved on by path_advance's commit only) and the candidates at their limit
      real(dp), allocatable :: slip(:)
      logical, allocatable :: yielding(:)
      real(dp) :: lambda = 0.0_dp
      real(dp), allocatable :: fixed_load(:)    !< u-independent part of the reference load R_r
      real(dp), allocatable :: reference(:)     !< R(u) at the committed state
      real(dp), allocatable :: tangent_displacement(:)  !< K_T⁻¹ R at the committed state
      real(dp), allocatable :: last_increment(:)
      real(dp) :: step_length = 0.0_dp          !< Δl, Δλ or Δu_c of the next step (by the control)
      real(dp) :: first_length = 0.0_dp
      !> Δl, Δλ or Δu_c the last converged step was taken with (the units of step_length; 0 before the
      !> first step): the path driver's record of the pace (uniarc_path_pace)
      real(dp) :: taken_length = 0.0_dp
      !> The least eigenvalue μ and path length s of the committed state before this one, when the step
      !> between them was smooth (the same working set, no lift-off state, no corner, release, switch or
      !> load step): μ's slope along the path, from which the next step's length is judged against the
      !> distance to μ's next zero (uniarc_path_hidden, docs/theory.md §2.3). .false.: not known.
      logical :: eigenvalue_slope_known = .false.
      real(dp) :: previous_eigenvalue = 0.0_dp, previous_s = 0.0_dp
      !> ψ: the displacement norm one unit of λ moves (length per unit λ), ||K⁻¹R|| at the unloaded state
      !> (or with its touching contacts released when they carry the whole reference load). It
      !> measures a step in λ where the reference load moves no displacement (docs/theory.md §2.7).
      real(dp) :: lambda_scale = 0.0_dp
      real(dp) :: load_norm = 0.0_dp            !< ||R_r|| · first Δλ: the force scale of the problem
      integer :: direction = 1                  !< +1/−1: predictor along ±K⁻¹R
      integer :: control_equation = 0
      real(dp) :: length_scale = 1.0_dp         !< size of the model (gap tolerances)
      !> A structure held only by its contacts (docs/theory.md §2.8): the rigid motions (n, k ≤ 3) its
      !> supports leave free, and the equation each is held at in the tangent while no contact of the
      !> working set holds it (uniarc_path_mechanism, floating_motions). Unallocated: none.
      real(dp), allocatable :: floating_motion(:, :)
      integer, allocatable :: floating_equation(:)
      type(path_point_t) :: point
      !> The bifurcation located by the last step, if it located one (else unallocated).
      type(bifurcation_state_t), allocatable :: bifurcation
      !> (n) The unknowns at the contact start located in the last step (point%contact_start_fraction
      !> ≥ 0; else unallocated): the state whose tracked values the contact_start row reports.
      real(dp), allocatable :: contact_start_u(:)
      integer :: bifurcations = 0               !< bifurcations located so far
      !> The next step leaves the primary path along the mode of `bifurcation` (*PATH, SWITCH=n).
      logical :: switch_due = .false.
      !> The last commit switched off a tangential spring that follows its radial partner (its force
      !> is dropped, commit_tangential): the next step is a release step, Δλ = 0 (docs/theory.md §3.8).
      logical :: release_due = .false.
      !> The last step failed on a plastic plateau (uniarc_path_collapse, plastic_plateau; docs/theory.md
      !> §3.9): the committed state was moved along the rigid mechanism of its yielded supports to the
      !> open contact it closes, and the next step is a plateau step, a load step of Δλ = plateau_dlambda
      !> (the slack of the candidates short of their limits) that restores equilibrium there.
      logical :: plateau_due = .false.
      real(dp) :: plateau_dlambda = 0.0_dp
      !> The working set of the committed state was changed in place since its step converged
      !> (path_change_working_set, uniarc_path_following): its equilibrium was met with another set, so
      !> the next step is judged as a step whose working set changed (no distance test, §2.3)
      logical :: set_edited = .false.
      !> The last step failed under load control from a stable state (no negative pivot), cut down to
      !> the least increment: no equilibrium was found past the committed λ, where the load reaches a
      !> limit point (or the path turns). The run reports the committed state as the `limit_max` row
      !> of STEM.crit, the highest λ load control reaches (docs/contracts.md).
      logical :: limit_under_load = .false.
   end type path_state_t

   !> One attempt at a step from the committed state: what it tried and where it got.
   type :: step_trial_t
      real(dp) :: length = 0.0_dp               !< step length of the attempt (units of state%step_length)
      real(dp), allocatable :: increment(:)     !< (n) Δx: unknowns minus the committed ones
      real(dp) :: dlambda = 0.0_dp              !< Δλ: load factor minus the committed one
      real(dp), allocatable :: predictor(:)     !< (n) Δx of the predictor (before any correction)
      real(dp) :: predictor_dlambda = 0.0_dp    !< Δλ of the predictor
      !> the attempt is a load step (Δλ fixed, no arc-length constraint): the reference load moves
      !> no displacement with its working set (docs/theory.md §2.7)
      logical :: load_step = .false.
      !> the load step is that of a floating structure meeting its first contact (docs/theory.md §2.8),
      !> not of a degenerate tangent: it need not land where the contacts carry the load
      logical :: floating_slide = .false.
      !> the attempt is a release step (path_state_t%release_due): a load step of Δλ = 0 that finds the
      !> equilibrium without the tangential springs switched off by the last commit — the jump of a law
      !> that drops a force (docs/theory.md §3.8); no direction of the path, no critical point located
      logical :: release = .false.
      logical, allocatable :: active(:)         !< (candidates) working set of the attempt
      logical, allocatable :: yielding(:)       !< (candidates) those of the set at their bearing limit
      integer :: yield_changes = 0              !< exchanges of the yield pairs within Newton
      integer :: iterations = 0                 !< Newton corrections
      integer :: lcp_pivots = 0                 !< Lemke pivots of the contact LCPs
      integer :: set_changes = 0                !< changes of the working set within Newton
      !> the predictor's contact LCP changed the working set (the predictor is of that set, not the
      !> committed one)
      logical :: predictor_set_changed = .false.
      logical :: converged = .false.            !< equilibrium and complementarity hold
      character(len=:), allocatable :: reason   !< why it did not converge (message text)
      !> An error that no shorter step cures (memory the system refused, uniarc_error: out_of_memory):
      !> path_advance ends the run with it instead of cutting the step back (fail_attempt).
      type(error_t), allocatable :: fatal
   end type step_trial_t

   !> The equations linearised at a state x: the work arrays of the predictor and of each Newton
   !> correction, and what the contact LCP is posed with.
   type :: linearization_t
      real(dp), allocatable :: x(:)            !< (n) unknowns at the state
      real(dp), allocatable :: nodal(:, :)     !< (dofs_per_node, n_nodes) nodal displacements of x
      real(dp), allocatable :: internal(:)     !< (n) F_aug(x)
      real(dp), allocatable :: reference(:)    !< (n) R(x)
      real(dp), allocatable :: residual(:)     !< (n) λR − F_aug whose solution rhs(:, 1) is (for the LCP)
      real(dp), allocatable :: rhs(:, :)       !< (n, 2) the residual and R, then K⁻¹ of both
      real(dp), allocatable :: reaction(:)     !< (m) work: the candidates' reactions (candidate_state)
      real(dp), allocatable :: gap(:)          !< (m) work: the candidates' gaps (candidate_state)
      real(dp), allocatable :: correction(:)   !< (n) work: a Newton correction, a predictor's λR − F_aug
      real(dp), allocatable :: total(:)        !< (n) work: the total displacements of a correction's test
      real(dp) :: element_scale = 0.0_dp       !< largest element force (assemble_equilibrium)
      real(dp) :: roundoff = 0.0_dp            !< round-off of the assembled residual (force units)
      real(dp) :: lambda = 0.0_dp              !< λ of the state (the gaps of moving obstacles)
   end type linearization_t

   !> A contact holds a free rigid motion v when |a_cᵀv| exceeds this fraction of |a_c| max|v|: the
   !> motion then moves the contact's gap at first order (a contact whose normal is across the motion
   !> to 1e-6 rad holds it 1e-6 as firmly as one along it).
   real(dp), parameter :: floating_tolerance = 1.0e-6_dp

contains

   !> Work arrays for a model and its equation numbering, all allocated (x and residual too: an
   !> assignment to an unallocated array makes gfortran 12 read its unset bounds first, GCC bug 77504,
   !> an integer overflow under -fsanitize=undefined; docs/testing.md, "Sanitizers").
   !> Errors: an array refused by the system (error_analysis, out of memory, uniarc_memory).
   subroutine new_linearization(model, map, lin, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(linearization_t), intent(out) :: lin
      type(error_t), allocatable, intent(out) :: error
      integer :: n, m, status
      n = map%n_equations
      m = size(map%candidate_equation)
      allocate (lin%nodal(dofs_per_node, model%n_nodes), lin%internal(n), lin%reference(n), lin%rhs(n, 2), &
                lin%x(n), lin%residual(n), lin%reaction(m), lin%gap(m), lin%correction(n), lin%total(n), stat=status)
      call allocation_failure(status, 'the work vectors of a Newton attempt', &
                              8.0_dp*(dofs_per_node*model%n_nodes + 8.0_dp*n + 2.0_dp*m), error_analysis, error)
   end subroutine new_linearization

   !> The model has contact candidates with a reaction unknown or condensed into the stiffness.
   pure logical function has_contacts(state)
      type(path_state_t), intent(in) :: state
      has_contacts = any(state%map%candidate_equation > 0 .or. state%map%condensed)
   end function has_contacts

   !> Augmented internal forces, reference load and tangent (into `system%tangent`) at unknowns x
   !> (n), load λ, working set `active`; nodal (dofs_per_node, n_nodes) are the displacements of x.
   !> Plastic media: the committed slip state%slip, and the candidates at their limit `yielding`
   !> (default: the committed state%yielding).
   !> Errors: a work array refused by the system (error_analysis, out of memory, uniarc_memory).
   subroutine equilibrium_at(model, state, system, x, lambda, active, nodal, internal, reference, &
                             element_scale, error, roundoff, yielding)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(path_system_t), intent(inout) :: system
      real(dp), intent(in) :: x(:), lambda
      logical, intent(in) :: active(:)
      real(dp), intent(in) :: nodal(:, :)
      real(dp), intent(out) :: internal(:), reference(:), element_scale
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(out), optional :: roundoff
      logical, intent(in), optional :: yielding(:)
      real(dp), allocatable :: values(:), deflections(:)
      logical, allocatable :: holding(:)
      integer :: m, c, status
      if (allocated(state%joint_plastic)) then
         call assemble_equilibrium(model, state%map, nodal, lambda, state%fixed_load, system%tangent, &
                                   internal, reference, element_scale, error, roundoff, state%joint_plastic)
      else
         call assemble_equilibrium(model, state%map, nodal, lambda, state%fixed_load, system%tangent, &
                                   internal, reference, element_scale, error, roundoff)
      end if
      if (allocated(error)) return
      m = size(state%map%candidate_equation)
      if (m > 0) then
         ! the candidates' unknowns and bed deflections in work vectors of their own, checked (function
         ! results of this length are not, in the Release build)
         allocate (values(m), deflections(m), holding(m), stat=status)
         call allocation_failure(status, 'the contact vectors of the equilibrium', 20.0_dp*m, error_analysis, error)
         if (allocated(error)) return
         values = 0.0_dp
         do c = 1, m
            if (state%map%candidate_equation(c) > 0) values(c) = x(state%map%candidate_equation(c))
            deflections(c) = bed_deflection(state%map, c, x)
         end do
         if (present(yielding)) then
            call assemble_contact(model, state%map, nodal, values, active, &
                                  system%tangent, internal, state%slip, yielding, &
                                  deflections=deflections, reference=reference, lambda=lambda)
         else if (allocated(state%yielding)) then
            call assemble_contact(model, state%map, nodal, values, active, &
                                  system%tangent, internal, state%slip, state%yielding, &
                                  deflections=deflections, reference=reference, lambda=lambda)
         else
            call assemble_contact(model, state%map, nodal, values, active, &
                                  system%tangent, internal, deflections=deflections, &
                                  reference=reference, lambda=lambda)
         end if
      end if
      if (allocated(state%floating_equation)) then
         ! a candidate at its bearing limit has no stiffness: it holds no motion (docs/theory.md §3.9)
         if (present(yielding)) then
            holding = active .and. .not. yielding
            call hold_floating(model, state, holding, nodal, system%tangent, error)
         else if (allocated(state%yielding)) then
            holding = active .and. .not. state%yielding
            call hold_floating(model, state, holding, nodal, system%tangent, error)
         else
            call hold_floating(model, state, active, nodal, system%tangent, error)
         end if
         if (allocated(error)) return
      end if
      if (allocated(state%joint_plastic)) call hold_yielded_nodes(model, state%map, system%tangent, error)
   end subroutine equilibrium_at

   !> A node whose every element end is a joint at its moment limit (`*RELEASE, MY=` on all the ends that
   !> meet there) has, at that state, no rotational stiffness: the joints pass their moments ±MY whatever
   !> it turns, its row of K_T is zero and its rotation is indeterminate — not a mechanism of the
   !> structure. As hold_floating does for a free rigid motion, its rotation is held in the tangent only,
   !> by a spring of the stiffness k of its stiffest joint: the residual is untouched, so the correction
   !> of the rotation is the node's moment residual over k — zero when the joints' moments balance there
   !> (exactly, as they are ±MY), and an equilibrium that cannot be met (a moment on the node beyond what
   !> the joints pass) stays a failed step.
   !> Errors: the nodes' joint stiffnesses (one real per node) refused by the system (out of memory).
   subroutine hold_yielded_nodes(model, map, tangent, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(band_matrix_t), intent(inout) :: tangent
      type(error_t), allocatable, intent(inout) :: error
      real(dp), allocatable :: stiffness(:)
      type(end_joint_t) :: joints(2)
      integer :: e, i, node, j, status
      allocate (stiffness(model%n_nodes), stat=status)
      call allocation_failure(status, 'the joint stiffnesses of the nodes', 8.0_dp*model%n_nodes, error_analysis, &
                              error)
      if (allocated(error)) return
      stiffness = 0.0_dp
      do e = 1, model%n_elements
         joints = end_joints_of(model, e)
         do i = 1, 2
            if (.not. joints(i)%moment_limit > 0.0_dp) cycle
            node = model%connectivity(i, e)
            stiffness(node) = max(stiffness(node), 1.0_dp/joints(i)%compliance)
         end do
      end do
      do node = 1, model%n_nodes
         if (.not. stiffness(node) > 0.0_dp) cycle
         j = map%equation(dof_rz, node)
         if (j == 0) cycle
         if (band_get(tangent, j, j) /= 0.0_dp) cycle
         call band_add(tangent, j, j, stiffness(node))
      end do
   end subroutine hold_yielded_nodes

   !> The tangent of a structure held only by its contacts, where the working set `active` does not
   !> hold one of its free rigid motions v (no candidate of the set has a_cᵀv ≠ 0 at its node): the
   !> tangent is singular along v, and a solve would add round-off over round-off times v to every
   !> correction. The motion is held at its equation j by a spring of the size of K_jj, in the tangent
   !> only: the residual is untouched, so a converged state is in exact equilibrium, and a right-hand
   !> side with no component along v (every self-equilibrated one: no contact force) is solved exactly,
   !> with δx_j = 0 — the structure does not drift while nothing pushes it (docs/theory.md §2.8).
   !> One motion at a time is not enough (uniarc_floating_subspace): one contact may see two motions
   !> and leave a mixture of them free — a ring held only by one contact at the end of its bed,
   !> whose normal sees the vertical translation and the rotation, leaves the rotation about that
   !> contact free; unloaded to zero at increment 0.2, a step on that tangent moved the ring 2.6e6
   !> (issue 16, second review). When the set's normals leave more of the span free
   !> (unheld_motions) than the motions it does not see one by one, the springs hold that subspace
   !> instead, at its pivoted equations (spring_equations), as the static analysis does.
   !> `released` (optional, one per candidate): candidates of `active` left out of the set (the
   !> lift-off test's pieces), read in place of an array expression `active .and. .not. released`
   !> (a temporary of the candidates' length, not checked).
   !> Errors (error_analysis, out of memory): the work arrays of the subspace test.
   subroutine hold_floating(model, state, active, nodal, tangent, error, released)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      logical, intent(in) :: active(:)
      real(dp), intent(in) :: nodal(:, :)
      type(band_matrix_t), intent(inout) :: tangent
      type(error_t), allocatable, intent(out) :: error
      logical, intent(in), optional :: released(:)
      real(dp), allocatable :: basis(:, :), unheld(:, :)
      logical, allocatable :: set(:)
      integer, allocatable :: equations(:)
      real(dp) :: diagonal
      integer :: i, j, held(3), unseen, status
      unseen = 0
      do i = 1, size(state%floating_equation)
         if (.not. sees_floating(model, state, active, nodal, i, released)) unseen = unseen + 1
      end do
      if (unseen < size(state%floating_equation)) then
         allocate (set(size(active)), stat=status)
         call allocation_failure(status, 'the set of the floating subspace test', 4.0_dp*size(active), &
                                 error_analysis, error)
         if (allocated(error)) return
         set(:) = active
         if (present(released)) set(:) = set .and. .not. released
         call orthonormal_motions(state%map, state%floating_motion, basis, error)
         if (allocated(error)) return
         ! (the set's tangential springs hold too, as they do one motion at a time in sees_floating)
         call unheld_motions(model, state%map, set, basis, unheld, error, tangential=.true.)
         if (allocated(error)) return
         if (size(unheld, 2) > unseen) then
            call spring_equations(state%map, unheld, equations, error)
            if (allocated(error)) return
            do i = 1, size(equations)
               j = equations(i)
               if (j <= 0) cycle
               diagonal = abs(band_get(tangent, j, j))
               if (.not. (diagonal > 0.0_dp)) diagonal = 1.0_dp
               call band_add(tangent, j, j, diagonal)
            end do
            return
         end if
      end if
      held = 0
      do i = 1, size(state%floating_equation)
         if (sees_floating(model, state, active, nodal, i, released)) cycle
         j = held_equation(model, state, active, i, held, released)
         if (i <= size(held)) held(i) = j
         diagonal = abs(band_get(tangent, j, j))
         if (.not. (diagonal > 0.0_dp)) diagonal = 1.0_dp
         call band_add(tangent, j, j, diagonal)
      end do
   end subroutine hold_floating

   !> The equation at which hold_floating holds the free rigid motion i that no contact of the set
   !> `active` sees. With no contact in the set, state%floating_equation(i) (where the motion moves
   !> most). With contacts that touch but do not see the motion (their normals across it: an oval
   !> liner pressed against its host at the side, where the host's normal is square to its vertical
   !> floating motion), at a node of one of them, the equation where the motion moves that node most
   !> (at least half its largest component, so that the spring holds the motion as firmly as at
   !> floating_equation; an equation `held` by another motion is skipped). The spring fixes that
   !> equation in every self-equilibrated solve (δx_j = 0): held at the contact, the structure deforms
   !> about the point where it touches, and that point does not move along the motion. Held elsewhere,
   !> a liner's own deformation carried the contact node along the motion (a symmetric ovalisation
   !> moved the side of a liner held at its crown by half the crown's deflection), the tilt of the
   !> host's normal that this drift made grew past floating_tolerance, the contact "saw" the motion
   !> with no load pushing along it, and the tangent became the slide of a contact tilted by a drift
   !> (docs/theory.md §2.8): the perfect liner (eps = 0) failed its first steps.
   !> `released` (optional): candidates of `active` left out of the set.
   integer function held_equation(model, state, active, i, held, released) result(j)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      logical, intent(in) :: active(:)
      integer, intent(in) :: i
      integer, intent(in) :: held(:)
      logical, intent(in), optional :: released(:)
      real(dp) :: size_v, best
      integer :: c, k, node, e
      j = state%floating_equation(i)
      size_v = maxval(abs(state%floating_motion(:, i)))
      best = 0.5_dp*size_v
      do c = 1, size(active)
         if (.not. (active(c) .and. candidate_live(state%map, c))) cycle
         if (present(released)) then
            if (released(c)) cycle
         end if
         node = model%contacts(c)%node
         do k = 1, 2
            e = state%map%equation(k, node)
            if (e <= 0) cycle
            if (any(held == e)) cycle
            if (abs(state%floating_motion(e, i)) > best) then
               best = abs(state%floating_motion(e, i))
               j = e
            end if
         end do
      end do
   end function held_equation

   !> A structure held only by its contacts that floats free at the committed state (no contact in
   !> state%active) is touched by the working set `active` (nodal: the committed displacements): a
   !> contact of the set sees one of its free rigid motions v. The closing contact pushes it along v
   !> with no force (docs/theory.md §2.8), which the arc length cannot measure: the step is a load step.
   logical function floating_touched(model, state, active, nodal) result(touched)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      logical, intent(in) :: active(:)
      real(dp), intent(in) :: nodal(:, :)
      integer :: i, c
      touched = .false.
      if (.not. allocated(state%floating_equation)) return
      do c = 1, size(state%active)
         if (state%active(c) .and. candidate_live(state%map, c)) return
      end do
      do i = 1, size(state%floating_equation)
         if (sees_floating(model, state, active, nodal, i)) touched = .true.
      end do
   end function floating_touched

   !> Whether a contact of the working set `active` sees the free rigid motion i (at nodal displacements
   !> `nodal`): its normal moves the gap at first order along the motion, |a_cᵀv| above
   !> floating_tolerance × |a_c| max|v|. `released` (optional): candidates of `active` not in the set.
   logical function sees_floating(model, state, active, nodal, i, released) result(sees)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      logical, intent(in) :: active(:)
      real(dp), intent(in) :: nodal(:, :)
      integer, intent(in) :: i
      logical, intent(in), optional :: released(:)
      real(dp) :: g, gradient(2), hessian(2, 2), along, size_v
      integer :: c, node, k
      sees = .false.
      size_v = maxval(abs(state%floating_motion(:, i)))
      do c = 1, size(active)
         if (.not. (active(c) .and. candidate_live(state%map, c))) cycle
         if (present(released)) then
            if (released(c)) cycle
         end if
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, gradient, hessian, state%lambda)
         along = 0.0_dp
         do k = 1, 2
            if (state%map%equation(k, node) > 0) along = along + &
               gradient(k)*state%floating_motion(state%map%equation(k, node), i)
         end do
         ! Held by a contact whose normal sees the motion (above round-off of a direction).
         if (abs(along) > floating_tolerance*norm2(gradient)*size_v) then
            sees = .true.
            return
         end if
      end do
   end function sees_floating

   !> Commit the joints' history at the state's unknowns `state%u` (the converged state of a step,
   !> just committed): the plastic rotations of the return mapping from the committed ones
   !> (uniarc_joint_plasticity), as OpenSees' commitState stores a material's trial state. Nothing
   !> without joints with a moment limit (state%joint_plastic unallocated).
   !> Errors: its nodal displacements refused by the system (error_analysis, out of memory).
   subroutine commit_joint_state(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :)
      type(element_response_t) :: response
      type(end_joint_t) :: joints(2)
      integer :: e
      if (.not. allocated(state%joint_plastic)) return
      call nodal_displacements(model, state, nodal, error)
      if (allocated(error)) return
      do e = 1, model%n_elements
         joints = end_joints_of(model, e)
         if (.not. any(joints%moment_limit > 0.0_dp)) cycle
         call element_response(model, e, element_displacements(model, e, nodal), transformation_corotational, &
                               response, state%joint_plastic(:, e))
         state%joint_plastic(:, e) = response%plastic_rotation
      end do
   end subroutine commit_joint_state

   !> The joints at their moment limit at the committed state (count), and the labels of the elements
   !> they belong to, for the message of a path that ends in a mechanism of yielded joints.
   subroutine yielded_joints(model, state, count, labels)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      integer, intent(out) :: count
      character(len=:), allocatable, intent(out) :: labels
      real(dp), allocatable :: nodal(:, :)
      type(element_response_t) :: response
      type(end_joint_t) :: joints(2)
      type(error_t), allocatable :: memory_error
      integer :: e, i
      count = 0
      labels = ''
      if (.not. allocated(state%joint_plastic)) return
      ! A hint of the message: none if its nodal displacements are refused (as the other hints).
      call nodal_displacements(model, state, nodal, memory_error)
      if (allocated(memory_error)) return
      do e = 1, model%n_elements
         joints = end_joints_of(model, e)
         if (.not. any(joints%moment_limit > 0.0_dp)) cycle
         call element_response(model, e, element_displacements(model, e, nodal), transformation_corotational, &
                               response, state%joint_plastic(:, e))
         do i = 1, 2
            if (.not. joints(i)%moment_limit > 0.0_dp) cycle
            if (abs(response%basic_force(1 + i)) < (1.0_dp - 1.0e-6_dp)*joints(i)%moment_limit) cycle
            count = count + 1
            if (count > 8) cycle
            if (count > 1) labels = labels//', '
            labels = labels//'element '//integer_to_string(model%element_label(e))//' end '//integer_to_string(i)
         end do
      end do
      if (count > 8) labels = labels//', ...'
   end subroutine yielded_joints

   !> Largest residual of the contact rows (gap units for the working set, reactions for the rest).
   pure real(dp) function constraint_residual(map, residual) result(largest)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: residual(:)
      largest = 0.0_dp
      if (size(map%candidate_equation) > 0) largest = maxval(abs((1.0_dp - map%metric)*residual))
   end function constraint_residual

   !> Factorise the tangent and solve it for the residual and the reference load: rhs(:, 1:2).
   !> Errors: band_factorize's and band_solve's (a singular tangent).
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

   !> An attempt at a step failed: `reason` says why (a singular tangent, an LCP without solution ...)
   !> and the step is cut back and tried again (path_advance) — unless `error` is out of memory
   !> (uniarc_error: out_of_memory), which a shorter step does not cure: it moves to trial%fatal and
   !> ends the run (docs/contracts.md, "Memory"). `error` may be unallocated (a failure without one).
   subroutine fail_attempt(trial, reason, error)
      type(step_trial_t), intent(inout) :: trial
      character(len=*), intent(in) :: reason
      type(error_t), allocatable, intent(inout) :: error
      trial%converged = .false.
      trial%reason = reason
      if (.not. allocated(error)) return
      if (error%out_of_memory) call move_alloc(error, trial%fatal)
   end subroutine fail_attempt

   !> Dot product over the displacement unknowns only (the metric masks the reactions out).
   pure real(dp) function masked_dot(map, a, b)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: a(:), b(:)
      masked_dot = sum(map%metric*a*b)
   end function masked_dot

   !> Norm over the displacement unknowns only. Masked before squaring (a reaction takes no part, the
   !> same bits as metric·a² for a metric of 0 and 1); entries beyond 1e150 (a deck of absurd numbers,
   !> forces of 1e300) are scaled before squaring: a number or +Inf, never an overflow trap.
   pure real(dp) function masked_norm(map, a)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: a(:)
      real(dp) :: largest
      largest = maxval(abs(map%metric*a))
      if (largest > 1.0e150_dp .and. largest <= huge(1.0_dp)) then
         masked_norm = largest*sqrt(sum((map%metric*a/largest)**2))
      else
         masked_norm = sqrt(sum((map%metric*a)**2))
      end if
   end function masked_norm

   !> A converged attempt `trial` made the committed state (path_advance's commit; the critical-point
   !> probes and branch switching do the same on their copies): u += Δx, λ += Δλ (or `lambda`, where
   !> the step lands on a target exactly), the trial's working set, the plastic slip and yielding set
   !> (commit_plastic), the last increment, the arc length s and the joints' plastic rotations
   !> (commit_joint_state). The tangent is committed apart (uniarc_path_stability, commit_tangent).
   !> Errors: the nodal displacements of the commits refused by the system (error_analysis, out of
   !> memory): the state is then partly committed and must end the run.
   subroutine accept_trial(model, state, trial, error, lambda)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(step_trial_t), intent(in) :: trial
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(in), optional :: lambda
      state%u = state%u + trial%increment
      state%lambda = state%lambda + trial%dlambda
      if (present(lambda)) state%lambda = lambda
      state%active = trial%active
      state%set_edited = .false.
      call commit_carried(model, state, error)
      if (allocated(error)) return
      call commit_tangential(model, state, error)
      if (allocated(error)) return
      call commit_plastic(model, state, trial%yielding, error)
      if (allocated(error)) return
      state%last_increment = trial%increment
      state%point%s = state%point%s + masked_norm(state%map, trial%increment)
      call commit_joint_state(model, state, error)
   end subroutine accept_trial

   !> A candidate that the converged state leaves carried by its node's support (a curved obstacle's
   !> normal along a held DOF: uniarc_contact, held_by_support) is no contact of the committed set: its
   !> row was r = 0 whatever the set said, and the inertia of the tangent counts one negative pivot per
   !> contact row of the set (uniarc_path_stability, structural_inertia). The trial's set may still
   !> hold it where the node moved onto such a normal within the step. Nothing without curved
   !> obstacles. Errors: its nodal displacements refused by the system (error_analysis, out of memory).
   subroutine commit_carried(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :)
      integer :: c
      if (.not. allocated(model%contacts)) return
      if (all(model%contacts%gap_kind == gap_fixed_direction)) return
      if (.not. any(state%active)) return
      call nodal_displacements(model, state, nodal, error)
      if (allocated(error)) return
      do c = 1, size(state%active)
         if (.not. state%active(c) .or. model%contacts(c)%bilateral) cycle
         if (carried_by_support(model, state%map, c, nodal, state%lambda)) state%active(c) = .false.
      end do
   end subroutine commit_carried

   !> The commit of the tangential springs that follow a radial partner (*FOUNDATION, KT=,
   !> TANGENTIAL=CONTACT; docs/theory.md §3.8), after state%u and state%active have become the
   !> converged state and working set of a trial: each spring's status for the next step is its
   !> partner's membership of the committed set (the trial held it as committed before, never
   !> switching it within the step), and a spring that comes on is anchored where its node is,
   !> a_c = t·u (slip −a_c, uniarc_contact_plastic: slip_shift), so that it starts stress-free; one
   !> that stays on keeps its anchor. A spring switched off drops its force: the next step is a
   !> release step (state%release_due). Nothing without such springs.
   !> Errors: its nodal displacements refused by the system (error_analysis, out of memory).
   subroutine commit_tangential(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :)
      real(dp) :: gap, gradient(2), hessian(2, 2)
      logical :: on
      integer :: c, node
      state%release_due = .false.
      if (.not. allocated(model%contacts)) return
      if (.not. any(model%contacts%partner > 0)) return
      call nodal_displacements(model, state, nodal, error)
      if (allocated(error)) return
      do c = 1, size(state%active)
         if (model%contacts(c)%partner == 0) cycle
         on = state%active(model%contacts(c)%partner)
         if (on .and. .not. state%active(c)) then
            node = model%contacts(c)%node
            call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, &
                               gradient, hessian)
            state%slip(c) = -gap
         end if
         if (state%active(c) .and. .not. on) state%release_due = .true.
         state%active(c) = on
      end do
   end subroutine commit_tangential

   !> The commit of plastic media (docs/theory.md §3.9), after state%u has become the converged state of
   !> a trial with the candidates `yielding` at their limit: the slip of each of them moves on by its
   !> increment (uniarc_contact_plastic, commit_slip), and `yielding` becomes the committed one. Nothing
   !> without plastic candidates. Errors: its nodal displacements refused by the system
   !> (error_analysis, out of memory).
   subroutine commit_plastic(model, state, yielding, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      logical, intent(in) :: yielding(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :)
      if (.not. has_plastic(model)) return
      call nodal_displacements(model, state, nodal, error)
      if (allocated(error)) return
      call commit_slip(model, state%map, state%u, nodal, yielding, state%slip)
      state%yielding = yielding
   end subroutine commit_plastic

   !> Nodal displacements (dofs_per_node, n_nodes) of the committed state; `nodal` keeps its storage
   !> when it has that shape already. Errors: the allocation refused by the system (error_analysis,
   !> out of memory).
   subroutine nodal_displacements(model, state, nodal, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), allocatable, intent(inout) :: nodal(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer :: status
      if (allocated(nodal)) then
         if (size(nodal, 1) /= dofs_per_node .or. size(nodal, 2) /= model%n_nodes) deallocate (nodal)
      end if
      if (.not. allocated(nodal)) then
         allocate (nodal(dofs_per_node, model%n_nodes), stat=status)
         call allocation_failure(status, 'the nodal displacements', 8.0_dp*dofs_per_node*model%n_nodes, &
                                 error_analysis, error)
         if (allocated(error)) return
      end if
      call gather_nodal(state%map, state%u, nodal)
   end subroutine nodal_displacements

   !> Reactions of every candidate at the committed state (exactly 0 for those out of contact).
   !> Out: reaction (m), m the map's candidates, force units of the load; status, 0 or the stat= of
   !> the allocation the system refused (reaction then unallocated).
   pure subroutine candidate_reactions(state, reaction, status)
      type(path_state_t), intent(in) :: state
      real(dp), allocatable, intent(out) :: reaction(:)
      integer, intent(out) :: status
      integer :: c
      allocate (reaction(size(state%map%candidate_equation)), stat=status)
      if (status /= 0) return
      reaction = 0.0_dp
      if (.not. allocated(state%reactions)) return
      ! Out of the working set a reaction is zero by definition; its unknown holds round-off only.
      do c = 1, size(reaction)
         if (state%active(c)) reaction(c) = state%reactions(c)
      end do
   end subroutine candidate_reactions

end module uniarc_path_state
