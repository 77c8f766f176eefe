!> The contact working set of the path following: which candidates are held (docs/theory.md §3).
!>
!> At a state x (unknowns, with their nodal displacements) and a working set: the reactions and gaps
!> of every candidate, the complementarity check (no held candidate pulls, no free one penetrates,
!> within tolerances relative to the contact units), the primal–dual active-set rule (Hintermüller, Ito
!> & Kunisch 2002) and the contact LCP (uniarc_contact_lcp, Lemke then block pivoting) that give the
!> next set. The committed state is read for the equation numbering and the scales, never written.
module uniarc_path_contact_set
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_copy, only: copy_array, reserve
   use uniarc_model, only: model_t
   use uniarc_dof_map, only: dof_map_t, candidate_live, bed_deflection
   use uniarc_contact, only: candidate_gap, in_set, carried_by_support, grazing
   use uniarc_contact_plastic, only: slip_shift, shifts_gap, plastic_violation, limit_force, branch_flexibility
   use uniarc_contact_lcp, only: path_constraint_t, contact_scales_t, select_contact_set, contact_linearization_t, &
                                 contact_selection_t
   use uniarc_lcp_implicit, only: implicit_lcp_report_t
   use uniarc_path_state, only: path_state_t, path_system_t, linearization_t
   implicit none
   private
   public :: set_update_t, complementary, violation, sign_rule, candidate_state, touching_candidates, &
             solve_contact_lcp, contact_units

   !> The working set the contact LCP chose.
   type :: set_update_t
      logical, allocatable :: active(:)        !< (candidates) the new working set
      logical :: changed = .false.             !< it differs from the set the LCP was posed in
      !> `system%tangent` holds the band LU of K_S for `active` (the LCP's last frame) and du_tangent
      !> = K_S⁻¹R (n) for it: no need to assemble and factorise again.
      logical :: kept = .false.
      real(dp), allocatable :: du_tangent(:)
      integer :: pivots = 0                    !< Lemke pivots spent
      !> the LCP failed because the path constraint does not fix δλ in a set whose contacts carry the
      !> whole reference load (the caller may take the step as a load step)
      logical :: degenerate = .false.
   end type set_update_t

contains

   !> The contact LCP linearised at `lin` (x, nodal, the residual and R with their solutions rhs by
   !> the factors in `system%tangent`, `system%assembled` unfactorised) with the step's `constraint`,
   !> posed in the working set `active` (uniarc_contact_lcp, select_contact_set). `system` is
   !> overwritten (the LCP's frames). Errors: those of select_contact_set (a singular frame, an LCP
   !> that Lemke cannot solve).
   !> Plastic media: `yielding` (optional) are the candidates at their bearing limit, held at r = q in
   !> K_S and no variable of the LCP; the committed slip state%slip shifts the gaps.
   subroutine solve_contact_lcp(model, state, system, lin, constraint, active, update, error, yielding)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(path_system_t), intent(inout) :: system
      type(linearization_t), intent(in) :: lin
      type(path_constraint_t), intent(in) :: constraint
      logical, intent(in) :: active(:)
      type(set_update_t), intent(out) :: update
      type(error_t), allocatable, intent(out) :: error
      logical, intent(in), optional :: yielding(:)
      type(contact_linearization_t) :: linearization
      type(contact_selection_t) :: selection
      real(dp), allocatable :: reaction(:), gap(:)
      integer :: n, status
      real(dp) :: bytes
      ! The LCP's copies of the linearisation allocated with stat= (docs/contracts.md, "Memory").
      n = size(lin%x)
      bytes = 0.0_dp
      call copy_array(lin%x, linearization%x, status, bytes)
      if (status == 0) call copy_array(lin%nodal, linearization%nodal, status, bytes)
      if (status == 0) call copy_array(lin%residual, linearization%residual, status, bytes)
      if (status == 0) call copy_array(lin%reference, linearization%reference, status, bytes)
      if (status == 0) call reserve(linearization%du_residual, n, status, bytes)
      if (status == 0) call reserve(linearization%du_tangent, n, status, bytes)
      if (status == 0 .and. present(yielding) .and. allocated(state%slip)) then
         call copy_array(state%slip, linearization%slip, status, bytes)
         if (status == 0) call reserve(linearization%yielding, size(yielding), status, bytes)
         if (status == 0) linearization%yielding(:) = yielding
      end if
      if (status == 0) call reserve(reaction, size(active), status, bytes)
      if (status == 0) call reserve(gap, size(active), status, bytes)
      call allocation_failure(status, 'a vector of the contact LCP''s linearisation', bytes, error_analysis, error)
      if (allocated(error)) return
      linearization%lambda = lin%lambda
      linearization%du_residual(:) = lin%rhs(:, 1)
      linearization%du_tangent(:) = lin%rhs(:, 2)
      linearization%constraint = constraint
      linearization%units = units_at(model, state, lin%x, lin%nodal, active, reaction, gap)
      call select_contact_set(model, state%map, linearization, active, system%assembled, system%tangent, &
                              selection, error)
      call move_alloc(selection%active, update%active)
      update%kept = selection%kept
      if (selection%kept) call move_alloc(selection%du_tangent, update%du_tangent)
      update%pivots = selection%report%pivots
      update%degenerate = selection%degenerate
      if (allocated(error)) return
      update%changed = any(update%active .neqv. active)
   end subroutine solve_contact_lcp

   !> Complementarity at a state that is in equilibrium for the working set `active`: no candidate in
   !> the set pulls (r ≥ 0) and none outside it penetrates (g ≥ 0), within tolerances relative to the
   !> largest reaction and the largest displacement.
   !> Plastic media: `yielding` (default state%yielding) are the candidates at their limit, and the
   !> yield pairs are checked too (uniarc_contact_plastic).
   !> reaction, gap: work arrays of one entry per candidate (allocated by the caller with stat=,
   !> docs/contracts.md, "Memory"), overwritten by candidate_state.
   function complementary(model, state, x, nodal, active, reaction, gap, yielding, lambda) result(ok)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: x(:), nodal(:, :)
      logical, intent(in) :: active(:)
      real(dp), intent(out) :: reaction(:), gap(:)
      logical, intent(in), optional :: yielding(:)
      real(dp), intent(in), optional :: lambda   !< of the state: moving obstacles (candidate_state)
      logical :: ok
      if (present(yielding)) then
         call candidate_state(model, state%map, x, nodal, active, reaction, gap, state%slip, yielding, lambda)
         ok = violation(model, state, x, reaction, gap, active, yielding) <= model%analysis%displacement_tolerance
      else
         call candidate_state(model, state%map, x, nodal, active, reaction, gap, state%slip, state%yielding, lambda)
         ok = violation(model, state, x, reaction, gap, active, state%yielding) <= &
              model%analysis%displacement_tolerance
      end if
      ! a closed candidate that grazes its obstacle carries a reaction its contact cannot (uniarc_contact,
      ! grazing): the set is wrong even where r ≥ 0 and g = 0
      if (ok) ok = .not. grazes_in_set(model, state, x, nodal, reaction, active, lambda)
   end function complementary

   !> Whether a candidate of the set `active` grazes its obstacle at unknowns x (nodal: their nodal
   !> displacements; reaction: the candidates', candidate_state) and load factor `lambda` (default 0),
   !> within the gap tolerance of `violation` (uniarc_contact, grazing).
   pure logical function grazes_in_set(model, state, x, nodal, reaction, active, lambda) result(grazes)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: x(:), nodal(:, :), reaction(:)
      logical, intent(in) :: active(:)
      real(dp), intent(in), optional :: lambda
      type(contact_scales_t) :: units
      real(dp) :: at
      integer :: c
      grazes = .false.
      if (.not. any(active)) return
      at = 0.0_dp
      if (present(lambda)) at = lambda
      units = contact_units(state, x, reaction, active)
      do c = 1, size(active)
         if (.not. active(c) .or. .not. candidate_live(state%map, c)) cycle
         if (grazing(model, state%map, c, nodal, at, model%analysis%displacement_tolerance*units%gap)) then
            grazes = .true.
            return
         end if
      end do
   end function grazes_in_set

   !> The primal–dual active-set rule (Hintermüller, Ito & Kunisch 2002) at unknowns x: a candidate
   !> outside `active` that penetrates (w < 0) enters, one inside that pulls (r < 0) leaves, each
   !> beyond the tolerance of `violation`; the others stay.
   !> A candidate at its bearing limit (`yielding`, optional) stays: its pair is the yield rule's.
   !> A rigid candidate whose gap moves only along held DOFs at x leaves the set (its node's support
   !> carries it: uniarc_contact, held_by_support) and does not enter it; one that grazes its obstacle
   !> (uniarc_contact, grazing) leaves it.
   !> reaction, gap: work arrays of one entry per candidate (as for `complementary`).
   subroutine sign_rule(model, state, x, nodal, active, new_active, reaction, gap, yielding, lambda)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: x(:), nodal(:, :)
      logical, intent(in) :: active(:)
      logical, intent(out) :: new_active(:)
      real(dp), intent(out) :: reaction(:), gap(:)
      logical, intent(in), optional :: yielding(:)
      real(dp), intent(in), optional :: lambda   !< of the state: moving obstacles (candidate_state)
      type(contact_scales_t) :: units
      real(dp) :: tolerance, at
      integer :: c
      at = 0.0_dp
      if (present(lambda)) at = lambda
      call candidate_state(model, state%map, x, nodal, active, reaction, gap, state%slip, yielding, lambda)
      units = contact_units(state, x, reaction, active)
      tolerance = model%analysis%displacement_tolerance
      new_active = active
      do c = 1, size(active)
         if (.not. candidate_live(state%map, c) .or. model%contacts(c)%bilateral) cycle
         if (present(yielding)) then
            if (yielding(c)) cycle
         end if
         if (carried_by_support(model, state%map, c, nodal, lambda)) then
            new_active(c) = .false.
         else if (active(c)) then
            if (-reaction(c)/units%force > tolerance) new_active(c) = .false.
            ! a grazing contact (uniarc_contact, grazing) leaves the set whatever its reaction
            if (grazing(model, state%map, c, nodal, at, tolerance*units%gap)) new_active(c) = .false.
         else
            if (-gap(c)/units%gap > tolerance) new_active(c) = .true.
         end if
      end do
   end subroutine sign_rule

   !> Largest violation of complementarity, relative: −r/r_scale for pulling contacts, −g/g_scale for
   !> penetrating free candidates, |r w|/(r_scale g_scale) for both at once.
   !> Plastic media (`yielding` given): a yielding candidate is checked by its yield pair instead
   !> (Δs ≥ 0), and an elastic one also for r ≤ q (uniarc_contact_plastic, plastic_violation).
   pure real(dp) function violation(model, state, x, reaction, gap, active, yielding) result(worst)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: x(:), reaction(:), gap(:)
      logical, intent(in) :: active(:)
      logical, intent(in), optional :: yielding(:)
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
         if (present(yielding)) then
            if (yielding(c)) cycle
         end if
         r = 0.0_dp
         if (active(c)) r = reaction(c)
         ! the spring's deflection only where it carries a force: a free candidate (r = 0) adds none,
         ! whatever its flexibility (0 × a flexibility that overflowed would be NaN)
         w = gap(c)
         if (r /= 0.0_dp) w = w + model%contacts(c)%flexibility*r
         worst = max(worst, -r/r_scale, -w/g_scale, complementarity(r, w, r_scale, g_scale))
      end do
      if (present(yielding)) worst = max(worst, plastic_violation(model, state%map, reaction, gap, active, &
                                                                  yielding, r_scale, g_scale))
   end function violation

   !> |r w| / (r_scale g_scale), the products formed only where they cannot overflow (a fuzz mutant
   !> with EI = 1e-150 had reactions and gaps near 1e200: SIGFPE in the Debug build); elsewhere the
   !> ratios are multiplied, the same value but for the last bits.
   pure real(dp) function complementarity(r, w, r_scale, g_scale) result(term)
      real(dp), intent(in) :: r, w, r_scale, g_scale
      real(dp), parameter :: safe = 1.0e150_dp
      if (abs(r) < safe .and. abs(w) < safe .and. r_scale < safe .and. g_scale < safe) then
         term = abs(r*w)/(r_scale*g_scale)
      else
         term = (abs(r)/r_scale)*(abs(w)/g_scale)
      end if
   end function complementarity

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

   !> Contact units at unknowns x (nodal: their nodal displacements) with working set `active`;
   !> reaction, gap: work arrays of one entry per candidate (as for `complementary`).
   function units_at(model, state, x, nodal, active, reaction, gap) result(units)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: x(:), nodal(:, :)
      logical, intent(in) :: active(:)
      real(dp), intent(out) :: reaction(:), gap(:)
      type(contact_scales_t) :: units
      call candidate_state(model, state%map, x, nodal, active, reaction, gap)
      units = contact_units(state, x, reaction, active)
   end function units_at

   !> Reactions and current gaps of every candidate: a reaction unknown of x, or for a condensed spring
   !> −g/t in the working set `active` and 0 out of it; the gap of a Pasternak bed point is the one with
   !> the bed's surface, g + d.
   !> Plastic media: the gaps include the committed `slip` (optional, one per candidate), and a condensed
   !> candidate at its limit (`yielding`, optional) has r = q (r = −t at an uplift limit).
   !> reaction, gap: one entry per candidate, allocated by the caller (with stat=: docs/contracts.md,
   !> "Memory"; no allocation here).
   pure subroutine candidate_state(model, map, x, nodal, active, reaction, gap, slip, yielding, lambda)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: x(:), nodal(:, :)
      logical, intent(in) :: active(:)
      real(dp), intent(out) :: reaction(:), gap(:)
      real(dp), intent(in), optional :: slip(:)
      logical, intent(in), optional :: yielding(:)
      !> λ of the state: a moving obstacle's gap is g(u) + λ ∂g/∂λ (docs/theory.md §3.11); absent: λ = 0
      real(dp), intent(in), optional :: lambda
      real(dp) :: gradient(2), hessian(2, 2)
      integer :: c, node
      do c = 1, size(map%candidate_equation)
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap(c), gradient, &
                            hessian, lambda)
         if (shifts_gap(model, c, present(slip))) gap(c) = gap(c) + slip_shift(model, c, slip)
         gap(c) = gap(c) + bed_deflection(map, c, x)   ! a Pasternak bed point: the gap with the surface
         if (model%contacts(c)%gap_rate /= 0.0_dp .and. present(lambda)) &
            gap(c) = gap(c) + lambda*model%contacts(c)%gap_rate
         reaction(c) = 0.0_dp
         if (map%candidate_equation(c) > 0) then
            reaction(c) = x(map%candidate_equation(c))
         else if (map%condensed(c) .and. in_set(model, active, c)) then
            ! t of the branch of δ = −g (1/k_u in tension with KU=; docs/theory.md §3.9)
            reaction(c) = -gap(c)/branch_flexibility(model%contacts(c), -gap(c))
            if (present(yielding)) then
               if (yielding(c)) reaction(c) = limit_force(model%contacts(c), reaction(c))
            end if
         end if
      end do
   end subroutine candidate_state

   !> Candidates that touch (|g| within round-off of the model size) or are bonded; a tangential spring
   !> that follows a radial partner acts where its partner touches (its status along the path,
   !> docs/theory.md §3.8). A touching candidate carried by its node's support (uniarc_contact,
   !> held_by_support: a node on a polyline's face along its held DOF) is not in the set.
   pure subroutine touching_candidates(model, state, nodal, active)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: nodal(:, :)
      logical, intent(out) :: active(:)
      real(dp) :: gap, gradient(2), hessian(2, 2)
      integer :: c, node
      do c = 1, size(state%map%candidate_equation)
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, gradient, hessian, &
                            state%lambda)
         ! a plastic medium's surface has sunk by its committed slip (zero on a path's unloaded state)
         if (model%contacts(c)%plastic .and. allocated(state%slip)) gap = gap + slip_shift(model, c, state%slip)
         active(c) = candidate_live(state%map, c) .and. &
                     (model%contacts(c)%bilateral .or. gap <= 1.0e-9_dp*state%length_scale)
         if (active(c) .and. .not. model%contacts(c)%bilateral) &
            active(c) = .not. carried_by_support(model, state%map, c, nodal, state%lambda)
      end do
      ! the partners come first (uniarc_contact_law: the radial candidates, then the tangential ones)
      do c = 1, size(state%map%candidate_equation)
         if (model%contacts(c)%partner > 0) active(c) = active(c) .and. active(model%contacts(c)%partner)
      end do
   end subroutine touching_candidates

end module uniarc_path_contact_set
