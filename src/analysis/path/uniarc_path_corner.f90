!> A step past a corner of the equilibrium path (docs/theory.md §2.12).
!>
!> With unilateral contact the path is piecewise smooth: on each piece the working set is fixed and
!> the path is the smooth solution curve of that set; where a contact opens or closes the tangent jumps
!> (a corner). A step from a state exactly at the corner (a candidate's reaction or gap at zero) along
!> the tangent of the old set leaves the admissible region at once, and the contact LCP of the
!> predictor, posed about that tangent, may keep returning the old set: no step length converges and
!> the cut-backs run out (tests/regression/decks/pipeline_hump_corner_200.inp stopped at λ ≈ 0.062).
!>
!> The corner is passed as a piecewise-linear complementarity path is followed from one piece to the
!> next (Eaves 1976, A short course in solving equations with PL homotopies, SIAM-AMS Proc. 9; the
!> complementary pivoting of Cottle, Pang & Stone 1992, The Linear Complementarity Problem, ch. 4):
!> the next piece has a working set that differs from the current one by the candidates at their change. For each assumption — one such
!> candidate toggled, or a group of them whose values and rates agree to within the problem's round-off
!> (a symmetric pair, which must change together or the path runs into the asymmetric dead end) — the
!> tangent of that set's path, t = ±(K_S⁻¹R, 1), is computed at the committed state; the assumption is
!> consistent if every toggled candidate moves into its admissible side along t (an opened contact's
!> gap grows: a·du/ds > 0; a closed one's reaction grows: dr/ds > 0). Of the consistent directions the
!> one closest to the last increment (largest cosine) is taken, and a step is made along it with the
!> toggled set (Newton with its usual complementarity checks), halving its length on failure.
module uniarc_path_corner
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_copy, only: copy_array, reserve
   use uniarc_model, only: model_t
   use uniarc_dof_map, only: candidate_live, bed_deflection
   use uniarc_contact, only: candidate_gap
   use uniarc_path_state, only: path_state_t, path_system_t, step_trial_t, masked_dot, masked_norm, &
                                nodal_displacements, equilibrium_at, factorize_and_solve, &
                                fail_attempt
   use uniarc_path_integrator, only: degenerate_tangent
   use uniarc_path_newton, only: attempt_step
   use uniarc_path_state_copy, only: copy_state, move_trial
   use uniarc_path_contact_branch, only: tie_pair
   implicit none
   private
   public :: step_past_corner

   !> Candidates of each kind (in contact, free) that may be at their change: the few smallest.
   integer, parameter :: per_kind = 3
   !> Two candidates tie (a symmetric pair) when their values and their rates along the current
   !> tangent agree to within this fraction of the larger of the two. Relative, not absolute: on the
   !> pipeline over a hump at 200 elements (pipeline_hump_corner_200.inp, past λ = 0.0609) the symmetric pair
   !> of end contacts had reactions 2.6344439e-7 and 2.6344545e-7 (4e-6 apart, relative) and rates
   !> −3.7406507 and −3.7406509 (1.8e-7 apart): round-off of the ill-conditioned K_T of a long beam,
   !> above any absolute 1e-8, far below 1e-4.
   real(dp), parameter :: tie_tolerance = 1.0e-4_dp
   !> Halvings of the corner step before the corner is given up.
   integer, parameter :: corner_halvings = 8

contains

   !> After all step lengths failed from the committed `state`: try the working sets that toggle the
   !> candidates at their change (module comment). On return `passed` says whether a step converged;
   !> then `trial` holds it (its active set the new piece's) and `length` its step length.
   !> `system` is overwritten (its committed factors are not kept).
   subroutine step_past_corner(model, state, system, trial, length, passed)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state   !< unchanged (inout for copy_state)
      type(path_system_t), intent(inout) :: system
      type(step_trial_t), intent(inout) :: trial
      real(dp), intent(inout) :: length
      logical, intent(out) :: passed
      type(path_state_t) :: corner
      type(step_trial_t) :: attempt
      type(error_t), allocatable :: error
      integer, allocatable :: chosen(:)
      logical, allocatable :: toggled(:, :), assumed(:)
      real(dp), allocatable :: ut(:), best_ut(:), nodal(:, :), start(:)
      real(dp) :: best_cosine, cosine, sign_of, best_sign, size_ut, dl, bytes
      integer :: a, best, h, status
      passed = .false.
      bytes = 0.0_dp
      if (size(state%active) == 0) return
      call nodal_displacements(model, state, nodal, error)
      if (allocated(error)) then
         call fail_attempt(trial, 'no memory for the corner''s displacements', error)
         return
      end if
      call pick_candidates(state, chosen, error)
      if (.not. allocated(error)) then
         if (size(chosen) == 0) return
         call tie_groups(state, chosen, model%analysis%keep_ties, toggled, error)
      end if
      if (.not. allocated(error)) then
         allocate (assumed(size(state%active)), stat=status)
         call allocation_failure(status, 'the working set of a corner''s assumption', 4.0_dp*size(state%active), &
                                 error_analysis, error)
      end if
      if (allocated(error)) then
         call fail_attempt(trial, 'no memory for the corner''s candidates', error)
         return
      end if
      system%holds_committed = .false.
      system%holds_converged = .false.
      best = 0
      best_cosine = -huge(1.0_dp)
      best_sign = 1.0_dp
      do a = 1, size(toggled, 2)
         assumed(:) = state%active .neqv. toggled(:, a)
         call set_tangent(model, state, system, nodal, assumed, ut, error)
         if (allocated(error)) then
            call fail_attempt(trial, 'no memory for the tangents at a corner', error)
            return
         end if
         if (.not. allocated(ut)) cycle
         if (degenerate_tangent(state, ut)) cycle
         call consistent_sign(model, state, nodal, toggled(:, a), ut, sign_of)
         if (sign_of == 0.0_dp) cycle
         size_ut = masked_norm(state%map, ut)
         if (masked_norm(state%map, state%last_increment) > 0.0_dp) then
            cosine = sign_of*masked_dot(state%map, ut, state%last_increment)/ &
                     (size_ut*masked_norm(state%map, state%last_increment))
         else
            ! No increment yet (the start of a path or of an analysis step): forward is the sense of λ
            ! that the first increment sets (state%direction); a piece that leaves the start with λ
            ! going the other way reverses the load (a rigid plane 1e-9 under the loaded node: the
            ! opened set's direction lifted the node off it under λ < 0, docs/theory.md §2.12).
            if (sign_of*real(state%direction, dp) < 0.0_dp) cycle
            cosine = 1.0_dp
         end if
         if (cosine > best_cosine) then
            best = a
            best_cosine = cosine
            best_sign = sign_of
            call copy_array(ut, best_ut, status, bytes)
            call allocation_failure(status, 'the tangent at a corner', bytes, error_analysis, error)
            if (allocated(error)) then
               call fail_attempt(trial, 'no memory for the tangents at a corner', error)
               return
            end if
         end if
      end do
      if (best == 0) return
      call copy_state(state, corner, 'the state at a corner of the path', error)
      if (allocated(error)) then
         call fail_attempt(trial, 'no memory for the corner''s state', error)
         return
      end if
      corner%active = state%active .neqv. toggled(:, best)
      size_ut = masked_norm(state%map, best_ut)
      call reserve(start, size(best_ut), status, bytes)
      call allocation_failure(status, 'the start of the step past a corner', bytes, error_analysis, error)
      if (allocated(error)) then
         call fail_attempt(trial, 'no memory for the step past a corner', error)
         return
      end if
      dl = max(state%step_length, state%first_length)
      do h = 0, corner_halvings
         attempt%length = dl
         start(:) = best_sign*dl*best_ut/size_ut
         call attempt_step(model, corner, system, attempt, start=start, start_dlambda=best_sign*dl/size_ut)
         if (attempt%converged) then
            ! the new piece: the converged set differs from the committed one (or it was the old corner)
            if (any(attempt%active .neqv. state%active)) then
               call move_trial(attempt, trial)
               length = dl
               passed = .true.
               return
            end if
         end if
         if (allocated(attempt%fatal)) then
            call move_trial(attempt, trial)
            return
         end if
         dl = 0.5_dp*dl
         if (dl < model%analysis%min_increment*state%first_length) exit
      end do
   end subroutine step_past_corner

   !> The candidates that may be at their change: the per_kind smallest reactions among those in the
   !> working set and the per_kind smallest |gaps| among the live ones outside it.
   !> Errors: its arrays of one entry per candidate refused by the system (error_analysis, out of memory).
   subroutine pick_candidates(state, chosen, error)
      type(path_state_t), intent(in) :: state
      integer, allocatable, intent(out) :: chosen(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: reaction(:), key(:)
      logical, allocatable :: free(:)
      integer :: c, k, m, pick, status
      logical :: closed
      m = size(state%active)
      allocate (chosen(0), reaction(m), key(m), free(m), stat=status)
      call allocation_failure(status, 'the candidates of a corner', 20.0_dp*m, error_analysis, error)
      if (allocated(error)) return
      ! the committed reactions (candidate_reactions: exactly 0 out of the working set)
      reaction(:) = 0.0_dp
      if (allocated(state%reactions)) then
         do c = 1, m
            if (state%active(c)) reaction(c) = state%reactions(c)
         end do
      end if
      ! out of the working set the point's contact value is the gap
      key(:) = abs(state%point%contact_value)
      do k = 1, 2
         closed = k == 1
         free = .false.
         do c = 1, m
            free(c) = candidate_live(state%map, c) .and. (state%active(c) .eqv. closed) .and. at_change(c)
         end do
         do pick = 1, per_kind
            if (.not. any(free)) exit
            if (closed) then
               c = minloc(reaction, dim=1, mask=free)
            else
               c = minloc(key, dim=1, mask=free)
            end if
            chosen = [chosen, c]
            free(c) = .false.
         end do
      end do
   contains
      !> Candidate c is at its change: its value (reaction in the set, gap out of it) is not positive,
      !> or it is heading to zero and gets there within the step length that failed.
      logical function at_change(c)
         integer, intent(in) :: c
         real(dp) :: value, rate
         value = state%point%contact_value(c)
         if (closed) value = reaction(c)
         rate = state%point%contact_rate(c)
         at_change = value <= 0.0_dp .or. (value*rate < 0.0_dp .and. abs(value) <= abs(rate)*state%step_length)
      end function at_change
   end subroutine pick_candidates

   !> The assumptions (columns of `toggled`): each chosen candidate with the chosen ones of the same
   !> kind that tie with it (values and rates along the committed tangent within tie_tolerance).
   !> Errors: its arrays of one entry per candidate refused by the system (error_analysis, out of memory).
   subroutine tie_groups(state, chosen, keep, toggled, error)
      type(path_state_t), intent(in) :: state
      logical, intent(in) :: keep   !< *PATH, TIES=KEEP (uniarc_model)
      integer, intent(in) :: chosen(:)
      logical, allocatable, intent(out) :: toggled(:, :)
      type(error_t), allocatable, intent(out) :: error
      logical, allocatable :: group(:), kept(:, :)
      integer :: i, j, a, n, status
      allocate (toggled(size(state%active), size(chosen)), group(size(state%active)), stat=status)
      call allocation_failure(status, 'the assumptions of a corner', 4.0_dp*size(state%active)*(size(chosen) + 1), &
                              error_analysis, error)
      if (allocated(error)) return
      toggled(:, :) = .false.
      n = 0
      do i = 1, size(chosen)
         group = .false.
         group(chosen(i)) = .true.
         do j = 1, size(chosen)
            if (j == i) cycle
            if (state%active(chosen(j)) .neqv. state%active(chosen(i))) cycle
            if (ties(chosen(i), chosen(j))) group(chosen(j)) = .true.
         end do
         ! the same group twice is one assumption
         if (any([(all(toggled(:, a) .eqv. group), a=1, n)])) cycle
         n = n + 1
         toggled(:, n) = group
      end do
      if (n < size(chosen)) then
         allocate (kept(size(state%active), n), stat=status)
         call allocation_failure(status, 'the assumptions of a corner', 4.0_dp*size(state%active)*n, &
                                 error_analysis, error)
         if (allocated(error)) return
         kept(:, :) = toggled(:, 1:n)
         call move_alloc(kept, toggled)
      end if
   contains
      !> The value pick_candidates ranks: the committed reaction of a candidate in the working set (the
      !> point's value is its gap, 0, where the reaction is not positive: a mirror pair held at
      !> r = −6.8e-8 past the pipeline's limit), the point's value (the gap) of one out of it.
      real(dp) function value(c)
         integer, intent(in) :: c
         value = state%point%contact_value(c)
         if (state%active(c) .and. allocated(state%reactions)) value = state%reactions(c)
      end function value
      logical function ties(p, q)
         integer, intent(in) :: p, q
         ! TIES=KEEP: the values of candidates at their change are round-off about zero, compared on
         ! the scale of their change over the step length that failed (tie_pair); the reactions and
         ! their rates of those in the working set
         if (keep) then
            ties = tie_pair(value(p), value(q), rate(p), rate(q), state%step_length, tie_tolerance, tie_tolerance)
         else
            ties = close_to(state%point%contact_value(p), state%point%contact_value(q)) .and. &
                   close_to(state%point%contact_rate(p), state%point%contact_rate(q))
         end if
      end function ties
      logical function close_to(x, y)
         real(dp), intent(in) :: x, y
         close_to = abs(x - y) <= tie_tolerance*max(abs(x), abs(y))
      end function close_to
      !> The rate of value(c) along the committed tangent: of a reaction that is an unknown of the
      !> augmented system, its component of K_S⁻¹R (the point's rate is the gap's, round-off, where the
      !> reaction is not positive: −6.3e-13 and −3.1e-11 for that pair); else the point's.
      real(dp) function rate(c)
         integer, intent(in) :: c
         integer :: row
         rate = state%point%contact_rate(c)
         row = state%map%candidate_equation(c)
         if (state%active(c) .and. .not. state%point%in_contact(c) .and. row > 0 .and. &
             allocated(state%tangent_displacement)) rate = state%tangent_displacement(row)
      end function rate
   end subroutine tie_groups

   !> K_S⁻¹R at the committed state with the working set `active`; unallocated if K_S is singular.
   !> memory_error: a vector refused by the system (error_analysis, out of memory).
   subroutine set_tangent(model, state, system, nodal, active, ut, memory_error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(path_system_t), intent(inout) :: system
      real(dp), intent(in) :: nodal(:, :)
      logical, intent(in) :: active(:)
      real(dp), allocatable, intent(out) :: ut(:)
      type(error_t), allocatable, intent(out) :: memory_error
      real(dp), allocatable :: internal(:), reference(:), rhs(:, :)
      type(error_t), allocatable :: error
      real(dp) :: element_scale
      integer :: n, status
      n = size(state%u)
      allocate (internal(n), reference(n), rhs(n, 2), stat=status)
      call allocation_failure(status, 'the vectors of a tangent at a corner', 32.0_dp*n, error_analysis, memory_error)
      if (allocated(memory_error)) return
      call equilibrium_at(model, state, system, state%u, state%lambda, active, nodal, internal, reference, &
                          element_scale, memory_error)
      if (allocated(memory_error)) return
      internal = state%lambda*reference - internal   ! the residual, in place: no temporary
      call factorize_and_solve(system%tangent, internal, reference, rhs, error)
      if (allocated(error)) return
      allocate (ut(n), stat=status)
      call allocation_failure(status, 'the tangent at a corner', 8.0_dp*n, error_analysis, memory_error)
      if (allocated(memory_error)) return
      ut(:) = rhs(:, 2)
   end subroutine set_tangent

   !> The sign s of the direction s·(ut, 1) along which every toggled candidate moves into its
   !> admissible side (an opened one's gap grows, a closed one's reaction grows); 0 if neither sign does.
   subroutine consistent_sign(model, state, nodal, toggled, ut, sign_of)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: nodal(:, :), ut(:)
      logical, intent(in) :: toggled(:)
      real(dp), intent(out) :: sign_of
      real(dp) :: rate
      integer :: c, plus, minus, row
      plus = 0
      minus = 0
      do c = 1, size(toggled)
         if (.not. toggled(c)) cycle
         row = state%map%candidate_equation(c)
         if (state%active(c)) then
            ! opened: the gap's rate a·du
            rate = along(model, state, nodal, c, ut)
         else if (row > 0) then
            ! closed, its reaction an unknown of the augmented system
            rate = ut(row)
         else
            ! closed, condensed (an elastic medium): r = −g/t, dr = −a·du/t
            rate = -along(model, state, nodal, c, ut)/model%contacts(c)%flexibility
         end if
         if (rate > 0.0_dp) plus = plus + 1
         if (rate < 0.0_dp) minus = minus + 1
      end do
      sign_of = 0.0_dp
      if (plus > 0 .and. minus == 0) sign_of = 1.0_dp
      if (minus > 0 .and. plus == 0) sign_of = -1.0_dp
   end subroutine consistent_sign

   !> a_cᵀ v + the bed's deflection: the gap's change of candidate c for an augmented vector v.
   real(dp) function along(model, state, nodal, c, v)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: nodal(:, :), v(:)
      integer, intent(in) :: c
      real(dp) :: g, gradient(2), hessian(2, 2)
      integer :: i, node
      node = model%contacts(c)%node
      call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, gradient, hessian, state%lambda)
      along = 0.0_dp
      do i = 1, 2
         if (state%map%equation(i, node) > 0) along = along + gradient(i)*v(state%map%equation(i, node))
      end do
      along = along + bed_deflection(state%map, c, v)
   end function along

end module uniarc_path_corner
