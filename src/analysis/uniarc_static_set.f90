!> The linear static analysis (uniarc_linear_static) on one contact set: the augmented equations of
!> the set assembled and solved with iterative refinement, the contact state it leaves, and the
!> exchanges that settle the set — the LCP posed again at the refined solution, block exchanges before
!> it, single exchanges (Murty's least-index rule) after it, and the search for a consistent set where
!> tangential springs switch with their radial contacts (docs/theory.md §3.6, §3.8).
module uniarc_static_set
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, add_context, make_error, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_copy, only: reserve
   use uniarc_model, only: model_t, dofs_per_node
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_dof_map, only: dof_map_t, candidate_live, element_equations, bed_deflection
   use uniarc_band, only: band_matrix_t, band_allocate, band_factorize, band_solve, band_copy, band_product, &
                          band_zero, band_add, band_get
   use uniarc_assembly, only: assemble_linear_stiffness, gather_nodal, scatter_add
   use uniarc_element, only: element_response_t, element_response, element_displacements, transformation_linear
   use uniarc_contact, only: candidate_gap, assemble_contact, in_set
   use uniarc_floating_subspace, only: unheld_motions, spring_equations, remove_unheld
   use uniarc_contact_lcp, only: contact_linearization_t, constraint_load
   use uniarc_static_set_search, only: largest_violation, set_signature, switching_group
   use uniarc_kinds, only: i8
   implicit none
   private
   public :: solve_set, single_exchanges, search_consistent_set, linearize_at_solution, assemble_set, &
             touching, refine_solution, block_exchange, complementarity_tolerance, add_settlement_load

   !> Single exchanges of the refined solution after the LCP (single_exchanges): each one a
   !> factorisation; the edges of contact regions the LCP left move a few candidates each.
   integer, parameter :: max_single_exchanges = 200
   !> Complementarity accepted within this fraction of the force and gap units (the LCP solver's own
   !> acceptance tolerance, uniarc_lcp_implicit, with a decade of room for the final solve's round-off).
   real(dp), parameter :: complementarity_tolerance = 1.0e-8_dp
   !> Iterative refinement of a solve (refine_solution): at most this many corrections, applied while the
   !> resultant of the residual exceeds `balance_target` of the forces (or complementarity is violated).
   !> A solve of K_S with a condition number κ leaves an error of about κε in x; each correction from the
   !> residual of the element forces multiplies it by about κε again (Higham 2002, §12.1), so two
   !> suffice for κ up to 1e13; the others are for safety.
   integer, parameter :: max_refinements = 4
   !> The resultant of the residual a well-conditioned solve leaves: a few ε times the forces summed.
   real(dp), parameter :: balance_target = 1.0e-12_dp

contains

   !> One solve of the linear problem with the contact set `set`: K_S assembled (`assembled`, with the
   !> floating motions of `floating` the set leaves free held, assemble_set) and factorised (`factors`),
   !> rhs(:, 1) = K_S⁻¹ (−F_aug(0)) (from `residual`, which assemble_set overwrites) and
   !> rhs(:, 2) = K_S⁻¹ R (`reference`), x their sum without the unheld floating motions, refined
   !> (refine_solution), with its reactions r, linearised gaps g and complementarity violation `worst`.
   !> `assembled` holds the contact part of K_S on return (refine_solution's workspace), not K_S.
   !> Errors: a singular K_S (the supports and contacts of the set do not hold the structure; then
   !> `singular`, if present, is true), memory.
   subroutine solve_set(model, map, zero_nodal, set, floating, residual, reference, applied, length_scale, &
                        assembled, factors, rhs, x, r, g, worst, error, singular)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: zero_nodal(:, :)
      logical, intent(in) :: set(:)
      real(dp), allocatable, intent(in) :: floating(:, :)
      real(dp), intent(inout) :: residual(:)
      real(dp), intent(in) :: reference(:), applied(:), length_scale
      type(band_matrix_t), intent(inout) :: assembled, factors
      real(dp), intent(inout) :: rhs(:, :)
      real(dp), intent(out) :: x(:), r(:), g(:), worst
      type(error_t), allocatable, intent(out) :: error
      logical, intent(out), optional :: singular
      real(dp), allocatable :: unheld(:, :)
      integer :: status
      if (present(singular)) singular = .false.
      worst = huge(1.0_dp)
      x = 0.0_dp
      r = 0.0_dp
      g = 0.0_dp
      call assemble_set(model, map, zero_nodal, set, assembled, residual, error, floating)
      if (allocated(error)) return
      call band_copy(assembled, factors, error)
      if (allocated(error)) return
      call band_factorize(factors, error)
      if (allocated(error)) then
         if (present(singular)) singular = .true.
         call add_context(error, 'linear static analysis (are the supports and contacts enough to hold '// &
                          'the structure?)')
         return
      end if
      rhs(:, 1) = residual
      rhs(:, 2) = reference
      call band_solve(factors, rhs, error)
      if (allocated(error)) return
      x(:) = rhs(:, 1) + rhs(:, 2)
      ! The floating motions the set leaves free: defined up to them, the solution is taken with none
      ! of them (its minimum-norm one), not with the amount the springs' equations and round-off set.
      if (allocated(floating)) then
         call unheld_motions(model, map, set, floating, unheld, error)
         if (allocated(error)) return
      else
         allocate (unheld(map%n_equations, 0), stat=status)
         call allocation_failure(status, 'the floating motions no contact holds', 0.0_dp, error_analysis, error)
         if (allocated(error)) return
      end if
      call remove_unheld(map, unheld, x)
      call linear_contact_state(model, map, x, set, r, g)
      worst = complementarity_violation(model, map, length_scale, x, reference, r, g, set)
      call refine_solution(model, map, set, applied, factors, assembled, length_scale, zero_nodal, x, r, g, &
                           worst, error)
      if (allocated(error)) return
      if (size(unheld, 2) > 0) then
         call remove_unheld(map, unheld, x)
         call linear_contact_state(model, map, x, set, r, g)
         worst = complementarity_violation(model, map, length_scale, x, reference, r, g, set)
      end if
   end subroutine solve_set

   !> The set of the linear problem by single exchanges of its refined solution, when the contact LCP
   !> did not settle it (its rounds spent, or its frames short of its accuracy: a free span lifted
   !> 10³ above a bed of 10⁵ candidates, whose contact edges the frames' one-product refinement cannot
   !> resolve): from `set` (on entry the last set solved, with x, r, g and `worst` of it), the
   !> violating candidate of least index (block_exchange's test) changes sides and the set is solved
   !> and refined again (solve_set), until complementarity holds. Murty's least-index rule (Murty 1974;
   !> Cottle, Pang & Stone 1992, §4.2) is finite for a P-matrix LCP, as a structure's contacts on a
   !> medium with every motion held give; each exchange costs one factorisation, so at most
   !> max_single_exchanges. Out: `set`, x, r, g, `worst`, `assembled` K_S of the set; `pivots` counts
   !> the exchanges. Errors (error_analysis): the set not settled in that many; a set that does not
   !> hold the structure (singular K_S); memory.
   subroutine single_exchanges(model, map, zero_nodal, floating, residual, reference, applied, length_scale, &
                               assembled, factors, rhs, x, r, g, set, worst, pivots, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: zero_nodal(:, :)
      real(dp), allocatable, intent(in) :: floating(:, :)
      real(dp), intent(inout) :: residual(:)
      real(dp), intent(in) :: reference(:), applied(:), length_scale
      type(band_matrix_t), intent(inout) :: assembled, factors
      real(dp), intent(inout) :: rhs(:, :)
      real(dp), intent(inout) :: x(:), r(:), g(:)
      logical, intent(inout) :: set(:)
      real(dp), intent(inout) :: worst
      integer, intent(inout) :: pivots
      type(error_t), allocatable, intent(out) :: error
      logical, allocatable :: flip(:)
      integer :: k, c, status
      allocate (flip(size(set)), stat=status)
      call allocation_failure(status, 'the exchanges of the contact set', 4.0_dp*size(set), error_analysis, error)
      if (allocated(error)) return
      do k = 1, max_single_exchanges
         call block_exchange(model, map, length_scale, x, reference, r, g, set, flip)
         c = findloc(flip, .true., dim=1)
         ! no candidate on the wrong side: what is left of the violation is the round-off of r w
         if (c == 0) exit
         set(c) = .not. set(c)
         pivots = pivots + 1
         call solve_set(model, map, zero_nodal, set, floating, residual, reference, applied, length_scale, &
                        assembled, factors, rhs, x, r, g, worst, error)
         if (allocated(error)) return
         if (worst <= complementarity_tolerance) return
      end do
      if (worst <= complementarity_tolerance .or. c == 0) return
      call make_error(error, 'linear static analysis: the contact set did not settle after the contact LCP and '// &
                      integer_to_string(max_single_exchanges)//' single exchanges of its candidates (largest '// &
                      'relative violation of complementarity '//trim(adjustl(real_to_string(worst, '(es10.3)')))// &
                      ')', error_analysis)
   end subroutine single_exchanges

   !> The contact set of a model whose tangential springs switch with their radial contacts, when the
   !> rounds of the contact LCP did not settle (docs/theory.md §3.8): from `set` (on entry the set of the
   !> unloaded state, where every touching contact and its spring act), solve with the set
   !> (solve_set), and while a candidate's sign condition fails change one of them,
   !> (uniarc_static_set_search: the largest violation first), until the solution is consistent (on return: `set`, x, r,
   !> g and `worst` of it, `assembled` K_S) or a set comes back, or max_changes sets were solved: then
   !> no consistent set at λ = 1 was reached, an analysis error that names the cause and the remedies.
   subroutine search_consistent_set(model, map, zero_nodal, floating, residual, reference, applied, length_scale, &
                                    assembled, factors, rhs, x, r, g, set, worst, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: zero_nodal(:, :)
      real(dp), allocatable, intent(in) :: floating(:, :)
      real(dp), intent(inout) :: residual(:)
      real(dp), intent(in) :: reference(:), applied(:), length_scale
      type(band_matrix_t), intent(inout) :: assembled, factors
      real(dp), intent(inout) :: rhs(:, :)
      real(dp), intent(out) :: x(:), r(:), g(:)
      logical, intent(inout) :: set(:)
      real(dp), intent(out) :: worst
      type(error_t), allocatable, intent(out) :: error
      integer(i8), allocatable :: seen(:)
      integer(i8) :: signature
      real(dp) :: r_unit, g_unit
      integer :: max_changes, k, c, status, n_unilateral
      logical :: singular
      character(len=:), allocatable :: why, group
      n_unilateral = 0
      do c = 1, size(set)
         if (candidate_live(map, c) .and. .not. model%contacts(c)%bilateral) n_unilateral = n_unilateral + 1
      end do
      ! the searches measured changed each candidate at most a few times (the lining: 14 to 40 sets for
      ! 48 radial springs); ten changes per candidate and a hundred more bound the solves (each one band
      ! solve) where no set comes back first.
      max_changes = 10*n_unilateral + 100
      allocate (seen(max_changes), stat=status)
      call allocation_failure(status, 'the signatures of the contact sets searched', 8.0_dp*max_changes, &
                              error_analysis, error)
      if (allocated(error)) return
      why = ''
      do k = 1, max_changes
         call solve_set(model, map, zero_nodal, set, floating, residual, reference, applied, length_scale, &
                        assembled, factors, rhs, x, r, g, worst, error, singular)
         if (allocated(error)) then
            ! a set too small to hold the structure is no answer: the search ends there
            if (.not. singular) return
            deallocate (error)
            why = 'a search by single changes from the unloaded contact set reached a set that does not '// &
                  'hold the structure after '//integer_to_string(k - 1)//' sets'
            exit
         end if
         if (worst <= complementarity_tolerance) then
            call assemble_set(model, map, zero_nodal, set, assembled, residual, error, floating)
            return
         end if
         signature = set_signature(set)
         if (any(seen(1:k - 1) == signature)) then
            why = 'a search by single changes from the unloaded contact set came back to a set after '// &
                  integer_to_string(k - 1)//' sets'
            exit
         end if
         seen(k) = signature
         r_unit = max(maxval(abs(r)), norm2(reference), tiny(1.0_dp))
         g_unit = max(maxval(abs(map%metric*x)), 1.0e-12_dp*length_scale, tiny(1.0_dp))
         c = largest_violation(model, map, set, r, g, r_unit, g_unit, complementarity_tolerance)
         if (c == 0) then
            why = 'a search by single changes stopped at a set whose only violation is the round-off of the '// &
                  'reactions times the gaps'
            exit
         end if
         set(c) = .not. set(c)
      end do
      if (len(why) == 0) why = 'a search by single changes tried '//integer_to_string(max_changes)//' sets'
      group = switching_group(model)
      if (len(group) > 0) group = ' of '''//group//''''
      call make_error(error, 'linear static analysis: no consistent contact set at lambda = 1: the tangential '// &
                      'springs'//group//' (KT=, TANGENTIAL=CONTACT) act only where their radial contact is '// &
                      'closed, so they switch with the contact set, and every set tried leaves a radial spring '// &
                      'of the set pulling or a node outside it in the ground once its tangential springs are '// &
                      'switched (the rounds of the contact LCP did not settle; '//why//'). Trace the load with '// &
                      '*PATH, where the springs'' status is history (docs/theory.md 3.8), or make the springs '// &
                      'act everywhere with TANGENTIAL=BONDED', error_analysis)
   end subroutine search_consistent_set

   !> The contact LCP of the linear problem posed at the solution x of the working set `set` (refined,
   !> refine_solution) rather than at u = 0: the state x, its residual ρ = R − F_aug(x) from the
   !> elements' forces (linear_residual) and K_S⁻¹ρ (`factors`, the band LU of the set's K_S), the
   !> load held (δλ = 0). For the linear gaps the LCP is the same, but its q, the reactions and gaps at
   !> x, are as accurate as the refined x: posed at u = 0 they were K_S⁻¹(R − F_aug(0)) of one solve,
   !> whose error κε|u| (a long span lifted off a bed, |u| ~ 10³ where the gaps at a lift-off point are
   !> ~10⁻⁴) decided the edge of a contact region against the refined solution, and the rounds never
   !> settled. Each frame the LCP refactorises is refined by products K_S v of its increments, which
   !> are small near the solution: their round-off is that of the increment, not of u.
   !> `du_tangent`: K_S⁻¹R; `matrix`: work space (the contact part of K_S is assembled in it).
   !> Errors (error_analysis): a vector refused by the system (out of memory).
   subroutine linearize_at_solution(model, map, set, applied, factors, zero_nodal, length_scale, x, du_tangent, &
                                    matrix, lin, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      logical, intent(in) :: set(:)
      real(dp), intent(in) :: applied(:)          !< R without the settlements' load (they move the elements)
      type(band_matrix_t), intent(in) :: factors
      real(dp), intent(in) :: zero_nodal(:, :), length_scale, x(:), du_tangent(:)
      type(band_matrix_t), intent(inout) :: matrix
      type(contact_linearization_t), intent(inout) :: lin
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: contact_force(:), zero_r(:), correction(:, :)
      real(dp) :: bytes
      integer :: n, status
      n = size(x)
      ! its vectors allocated with stat= first: the assignments below then allocate nothing
      bytes = 0.0_dp
      call reserve(lin%x, n, status, bytes)
      if (status == 0) call reserve(lin%nodal, dofs_per_node, model%n_nodes, status, bytes)
      if (status == 0) call reserve(lin%residual, n, status, bytes)
      if (status == 0) call reserve(lin%reference, n, status, bytes)
      if (status == 0) call reserve(lin%du_residual, n, status, bytes)
      if (status == 0) call reserve(lin%du_tangent, n, status, bytes)
      if (status == 0) allocate (contact_force(n), zero_r(size(set)), correction(n, 1), stat=status)
      call allocation_failure(status, 'a vector of the contact LCP of the linear analysis', &
                              bytes + 16.0_dp*n + 8.0_dp*size(set), error_analysis, error)
      if (allocated(error)) return
      zero_r(:) = 0.0_dp
      contact_force(:) = 0.0_dp
      call band_zero(matrix)
      if (size(map%candidate_equation) > 0) call assemble_contact(model, map, zero_nodal, zero_r, set, matrix, &
                                                                 contact_force)
      call linear_residual(model, map, applied, contact_force, matrix, x, lin%nodal, lin%residual)
      correction(:, 1) = lin%residual
      call band_solve(factors, correction, error)
      if (allocated(error)) return
      lin%x = x
      ! the nodal displacements of x without the settlements, as the gaps of linear_contact_state
      call gather_nodal(map, x, lin%nodal)
      lin%reference = applied
      if (allocated(model%prescribed)) call add_settlement_load(model, map, lin%reference)
      lin%du_residual = correction(:, 1)
      lin%du_tangent = du_tangent
      lin%constraint%kind = constraint_load
      lin%constraint%target = 0.0_dp
      lin%units%force = max(norm2(lin%reference), tiny(1.0_dp))
      lin%units%gap = max(maxval(abs(map%metric*x)), 1.0e-6_dp*length_scale)
   end subroutine linearize_at_solution

   !> K_S (linear K with the contact rows of `set`, unfactorised) and its residual −F_aug at u = 0,
   !> r = 0: g_c(0) on the rows of the candidates in the set, the force of condensed springs in it.
   !> With `floating` (n, k, orthonormal in the metric), the floating motions of a structure held only by
   !> its contacts across a gap (approach_first_contact): those of their span that no contact of the set
   !> holds (unheld_motions, the null space of the set's normals on that span) are held, in K_S only,
   !> by springs of the size of the diagonal at the equations spring_equations picks (the path's device,
   !> docs/theory.md §2.8): a right-hand side with no component along them is then solved exactly with
   !> the springs' forces zero; one with a component fails the equilibrium check of the result
   !> (uniarc_static_balance).
   subroutine assemble_set(model, map, zero_nodal, set, assembled, residual, error, floating)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: zero_nodal(:, :)
      logical, intent(in) :: set(:)
      type(band_matrix_t), intent(inout) :: assembled
      real(dp), intent(out) :: residual(:)
      type(error_t), allocatable, intent(out) :: error   !< a band matrix that cannot be allocated (band_allocate)
      real(dp), allocatable, intent(in), optional :: floating(:, :)
      real(dp), allocatable :: internal(:), no_reactions(:), unheld(:, :), diagonal(:)
      integer, allocatable :: equations(:)
      integer :: status, i
      if (assembled%n /= map%n_equations) then
         call band_allocate(assembled, map%n_equations, map%half_bandwidth, map%half_bandwidth, error)
         if (allocated(error)) return
      end if
      call assemble_linear_stiffness(model, map, assembled)
      allocate (internal(map%n_equations), no_reactions(size(map%candidate_equation)), stat=status)
      call allocation_failure(status, 'the internal forces of the linear analysis', &
                              8.0_dp*(map%n_equations + size(map%candidate_equation)), error_analysis, error)
      if (allocated(error)) return
      internal = 0.0_dp
      no_reactions = 0.0_dp
      if (size(map%candidate_equation) > 0) call assemble_contact(model, map, zero_nodal, no_reactions, set, &
                                                                  assembled, internal)
      residual = -internal
      if (.not. present(floating)) return
      if (.not. allocated(floating)) return
      call unheld_motions(model, map, set, floating, unheld, error)
      if (allocated(error)) return
      call spring_equations(map, unheld, equations, error)
      if (allocated(error)) return
      ! the diagonals before any spring: the springs do not depend on the order they are added in
      diagonal = [(abs(band_get(assembled, equations(i), equations(i))), i=1, size(equations))]
      do i = 1, size(equations)
         if (.not. (diagonal(i) > 0.0_dp)) diagonal(i) = 1.0_dp
         call band_add(assembled, equations(i), equations(i), diagonal(i))
      end do
   end subroutine assemble_set

   !> Candidates that touch at u = 0 (|g| within 1e-9 of the model size) or are bonded.
   subroutine touching(model, map, length_scale, set)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: length_scale
      logical, intent(out) :: set(:)
      real(dp) :: gap, gradient(2), hessian(2, 2)
      integer :: c, node
      do c = 1, size(set)
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), [0.0_dp, 0.0_dp], gap, gradient, hessian)
         set(c) = candidate_live(map, c) .and. (model%contacts(c)%bilateral .or. gap <= 1.0e-9_dp*length_scale)
      end do
   end subroutine touching

   !> Reactions r and linearised gaps g = g(0) + a(0)ᵀu of every candidate at unknowns x for `set`:
   !> a reaction unknown in the set, −g/t for a condensed spring in it, 0 out of it.
   !> r, g: one entry per candidate, allocated by the caller (with stat=, docs/contracts.md "Memory").
   subroutine linear_contact_state(model, map, x, set, r, g)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: x(:)
      logical, intent(in) :: set(:)
      real(dp), intent(out) :: r(:), g(:)
      real(dp) :: gap0, gradient(2), hessian(2, 2)
      integer :: c, node, i
      r = 0.0_dp
      g = 0.0_dp
      do c = 1, size(set)
         if (.not. candidate_live(map, c)) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), [0.0_dp, 0.0_dp], gap0, gradient, hessian)
         g(c) = gap0
         do i = 1, 2
            if (map%equation(i, node) > 0) g(c) = g(c) + gradient(i)*x(map%equation(i, node))
         end do
         g(c) = g(c) + bed_deflection(map, c, x)   ! a Pasternak bed point: the gap with the surface
         if (.not. in_set(model, set, c)) cycle   ! a tangential spring acts with its partner
         if (map%candidate_equation(c) > 0) then
            r(c) = x(map%candidate_equation(c))
         else
            r(c) = -g(c)/model%contacts(c)%flexibility
         end if
      end do
   end subroutine linear_contact_state

   !> Iterative refinement of the solution x of K_S x = R − F_aug(0) for `set` (Higham 2002, §12.1):
   !> while the resultant of the residual ρ = R − F_aug(x) exceeds balance_target of the forces, or
   !> complementarity is violated beyond its tolerance, x += K_S⁻¹ρ with the factors of K_S. The
   !> residual takes the elements' forces from their deformations (linear_residual), not K x: a nearly
   !> rigid member (EI large against the bed) moves as a rigid body, and K x cancels terms of size
   !> EI/L³ × its displacement to leave forces smaller by the condition number, so its round-off
   !> does not balance (a floating stiff beam on a bed balanced 0.998 of its load); each element's
   !> forces B0ᵀq are in equilibrium to the last bit, so the resultant of ρ is what the solve left.
   !> A correction that improves neither measure ends the refinement (the round-off floor). Well
   !> conditioned problems meet the target at once and are not touched.
   !> `matrix` is workspace (the contact part of K_S is assembled in it); r, g and worst (the reactions,
   !> gaps and complementarity violation of x, linear_contact_state) are updated with x.
   subroutine refine_solution(model, map, set, applied, factors, matrix, length_scale, zero_nodal, x, r, g, worst, &
                              error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      logical, intent(in) :: set(:)
      real(dp), intent(in) :: applied(:)          !< R without the settlements' load (they move the elements)
      type(band_matrix_t), intent(in) :: factors  !< band LU of K_S
      type(band_matrix_t), intent(inout) :: matrix
      real(dp), intent(in) :: length_scale
      real(dp), intent(in) :: zero_nodal(:, :)   !< (dofs_per_node, n_nodes) zeros: the contacts at u = 0
      real(dp), intent(inout) :: x(:)
      real(dp), intent(inout) :: r(:), g(:)
      real(dp), intent(inout) :: worst
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: rho(:), correction(:, :), trial(:), r_trial(:), g_trial(:), contact_force(:), &
                               zero_r(:), nodal(:, :)
      real(dp) :: balance, balance_trial, worst_trial
      integer :: k, status
      logical :: assembled
      assembled = .false.
      allocate (rho(size(x)), correction(size(x), 1), contact_force(size(x)), trial(size(x)), r_trial(size(r)), &
                g_trial(size(r)), zero_r(size(r)), nodal(dofs_per_node, model%n_nodes), stat=status)
      call allocation_failure(status, 'the vectors of the refinement of the linear solution', &
                              32.0_dp*size(x) + 24.0_dp*size(r) + 8.0_dp*dofs_per_node*model%n_nodes, error_analysis, &
                              error)
      if (allocated(error)) return
      zero_r(:) = 0.0_dp
      do k = 0, max_refinements
         if (k == 0) then
            if (.not. assembled) then
               ! The contact part of K_S and F_aug(0) (the rows of the set at u = 0): F_aug(x) is then
               ! linear_residual's element forces plus these.
               call band_zero(matrix)
               contact_force = 0.0_dp
               if (size(map%candidate_equation) > 0) call assemble_contact(model, map, zero_nodal, zero_r, set, &
                                                                          matrix, contact_force)
               assembled = .true.
            end if
            call linear_residual(model, map, applied, contact_force, matrix, x, nodal, rho)
            balance = resultant_imbalance(model, map, applied, r, rho)
         end if
         if (balance <= balance_target .and. worst <= complementarity_tolerance) return
         if (k == max_refinements) return
         correction(:, 1) = rho
         call band_solve(factors, correction, error)
         if (allocated(error)) return
         trial(:) = x + correction(:, 1)
         call linear_contact_state(model, map, trial, set, r_trial, g_trial)
         worst_trial = complementarity_violation(model, map, length_scale, trial, applied, r_trial, g_trial, set)
         call linear_residual(model, map, applied, contact_force, matrix, trial, nodal, rho)
         balance_trial = resultant_imbalance(model, map, applied, r_trial, rho)
         if (balance_trial >= balance .and. worst_trial >= worst) return
         x = trial
         r = r_trial
         g = g_trial
         worst = worst_trial
         balance = balance_trial
      end do
   end subroutine refine_solution

   !> ρ = R − F_aug(x) of the linear problem: the applied loads R, minus the elements' forces
   !> B0ᵀ Kb (B0 u_e) of their deformations (uniarc_element, linear transformation; u_e with the
   !> prescribed displacements of held DOFs), minus the contact part F_aug(0) + K_c x (`contact_matrix`
   !> K_c, `contact_force` F_aug(0), assembled by uniarc_contact at u = 0 for the set).
   !> nodal: a work array (dofs_per_node, n_nodes) of the caller's, overwritten.
   subroutine linear_residual(model, map, applied, contact_force, contact_matrix, x, nodal, rho)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: applied(:), contact_force(:)
      type(band_matrix_t), intent(in) :: contact_matrix
      real(dp), intent(in) :: x(:)
      real(dp), intent(out) :: nodal(:, :)
      real(dp), intent(out) :: rho(:)
      type(element_response_t) :: response
      integer :: e
      call gather_nodal(map, x, nodal)
      if (allocated(model%prescribed)) nodal = nodal + model%prescribed
      ! y = K_c x into rho (band_product: no function result), then ρ = R − F_aug(0) − K_c x
      call band_product(contact_matrix, x, rho)
      rho = applied - contact_force - rho
      do e = 1, model%n_elements
         call element_response(model, e, element_displacements(model, e, nodal), transformation_linear, response)
         call scatter_add(element_equations(model, map, e), -response%internal_force, rho)
      end do
   end subroutine linear_residual

   !> The resultant of the residual ρ at the free DOFs — forces (Σρ_x, Σρ_y) and the moment about the
   !> nodes' centroid Σ(x ρ_y − y ρ_x + ρ_θ) over a length of the model — relative to the forces that
   !> balance in it: the applied loads' translations and the contact reactions, in absolute value.
   !> A free structure with all its contacts (a floating beam on its bed) is in equilibrium as a whole
   !> exactly when this is zero. Where that scale is 0 (a moment or a settlement alone loads the model)
   !> the ratio is at most huge(): the quotient over the floor tiny() overflowed (a SIGFPE of the Debug
   !> build) once the residual's round-off exceeded ~1e-308·huge, as under a tip moment of 1e100.
   pure real(dp) function resultant_imbalance(model, map, applied, r, rho) result(imbalance)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: applied(:), r(:), rho(:)
      real(dp) :: force(2), moment, centre(2), arm(2), scale, length, residual
      integer :: i, eq
      centre = sum(model%coordinates, dim=2)/max(model%n_nodes, 1)
      length = max(maxval(abs(model%coordinates - spread(centre, 2, model%n_nodes))), tiny(1.0_dp))
      force = 0.0_dp
      moment = 0.0_dp
      scale = sum(abs(r))
      do i = 1, model%n_nodes
         arm = model%coordinates(:, i) - centre
         eq = map%equation(1, i)
         if (eq > 0) then
            force(1) = force(1) + rho(eq)
            moment = moment - arm(2)*rho(eq)
            scale = scale + abs(applied(eq))
         end if
         eq = map%equation(2, i)
         if (eq > 0) then
            force(2) = force(2) + rho(eq)
            moment = moment + arm(1)*rho(eq)
            scale = scale + abs(applied(eq))
         end if
         eq = map%equation(3, i)
         if (eq > 0) moment = moment + rho(eq)
      end do
      residual = max(abs(force(1)), abs(force(2)), abs(moment)/length)
      scale = max(scale, tiny(1.0_dp))
      ! residual/huge underflows harmlessly; if it is below half the scale, the quotient is below huge/2
      if (residual/huge(1.0_dp) < 0.5_dp*scale) then
         imbalance = residual/scale
      else
         imbalance = huge(1.0_dp)
      end if
   end function resultant_imbalance

   !> The candidates whose membership of `set` the refined solution x contradicts, to be exchanged at
   !> once (block principal pivoting, Kostreva 1978; Júdice & Pires 1994): in the set and pulling
   !> (r < 0), or out of it and penetrating (w = g + t r < 0), beyond complementarity_tolerance of the
   !> units of complementarity_violation. The solve after such an exchange is refined like any other,
   !> so the block phase sees the contact edges with the accuracy of the final check, which the LCP's
   !> frames (each refined by one product K_S v of a possibly large v) do not always reach.
   pure subroutine block_exchange(model, map, length_scale, x, reference, r, g, set, flip)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: length_scale, x(:), reference(:), r(:), g(:)
      logical, intent(in) :: set(:)
      logical, intent(out) :: flip(:)   !< (candidates) true: to leave or join the set
      real(dp) :: r_unit, g_unit, w
      integer :: c
      flip = .false.
      if (size(set) == 0) return
      r_unit = max(maxval(abs(r)), norm2(reference), tiny(1.0_dp))
      g_unit = max(maxval(abs(map%metric*x)), 1.0e-12_dp*length_scale, tiny(1.0_dp))
      do c = 1, size(set)
         if (.not. candidate_live(map, c) .or. model%contacts(c)%bilateral) cycle
         w = g(c) + model%contacts(c)%flexibility*r(c)
         if (set(c)) then
            flip(c) = -r(c)/r_unit > complementarity_tolerance
         else
            flip(c) = -w/g_unit > complementarity_tolerance
         end if
      end do
   end subroutine block_exchange

   !> Largest relative violation of complementarity of the unilateral candidates: −r/r_unit for a
   !> pulling contact, −w/g_unit for a penetrating free one (w = g + t r), |r w|/(r_unit g_unit); the
   !> units are the largest reaction (at least ‖R‖) and the largest displacement (at least 1e-12 of
   !> the model size), as in the path following (uniarc_path_contact_set, violation).
   pure real(dp) function complementarity_violation(model, map, length_scale, x, reference, r, g, set) result(worst)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: length_scale, x(:), reference(:), r(:), g(:)
      logical, intent(in) :: set(:)
      real(dp) :: r_unit, g_unit, w
      integer :: c
      worst = 0.0_dp
      if (size(set) == 0) return
      r_unit = max(maxval(abs(r)), norm2(reference), tiny(1.0_dp))
      g_unit = max(maxval(abs(map%metric*x)), 1.0e-12_dp*length_scale, tiny(1.0_dp))
      do c = 1, size(set)
         if (.not. candidate_live(map, c) .or. model%contacts(c)%bilateral) cycle
         w = g(c) + model%contacts(c)%flexibility*r(c)
         if (set(c)) then
            worst = max(worst, -r(c)/r_unit, abs(r(c)*w)/(r_unit*g_unit))
         else
            worst = max(worst, -w/g_unit)
         end if
      end do
   end function complementarity_violation

   !> Prescribed displacements ū of held DOFs (support settlements) as loads on the free DOFs:
   !> K_ff u_f = R_f − K_fp ū, element by element (−k_e ū_e scattered to the free equations; the held
   !> ones have none). Equations of the direct stiffness method (Przemieniecki 1968, §6.7).
   subroutine add_settlement_load(model, map, reference)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(inout) :: reference(:)
      type(element_response_t) :: response
      real(dp), parameter :: at_rest(2*dofs_per_node) = 0.0_dp
      real(dp) :: settled(2*dofs_per_node)
      integer :: e
      do e = 1, model%n_elements
         settled = element_displacements(model, e, model%prescribed)
         if (all(settled == 0.0_dp)) cycle
         call element_response(model, e, at_rest, transformation_linear, response)
         call scatter_add(element_equations(model, map, e), -matmul(response%tangent, settled), reference)
      end do
   end subroutine add_settlement_load

end module uniarc_static_set
