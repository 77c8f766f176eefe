!> Linear static analysis: K u = λ R_r with λ = 1 on the initial geometry, with unilateral contact as
!> one linear complementarity problem (the paper's Eq. 31 at λ = 1, the bedded-beam analysis of
!> linings and footings).
!>
!> With contact candidates the unknowns are the augmented ones of the path following (displacements
!> and the reactions of the rigid or stiff candidates, uniarc_contact), the gaps are linearised at
!> u = 0 (g_c ≈ g_c(0) + a_c(0)ᵀu: the small-displacement contact of a linear analysis) and the
!> structure's stiffness is the linear K (uniarc_assembly). The LCP
!>     w = g(0) + A u + T r ≥ 0,   r ≥ 0,   wᵀr = 0,   K u = R + Aᵀ r
!> is solved by the project's contact LCP (uniarc_contact_lcp: the implicit operator of the augmented
!> matrix K_S of a working set S, block pivoting then Lemke) as one load step from the unloaded state
!> with the load constraint δλ = 1; the equations of the set it selects are then solved once.
!> Prescribed displacements of held DOFs (support settlements) load the free DOFs by −K_fp ū
!> (add_settlement_load) and are reported as the displacements of those DOFs (docs/theory.md §3.6).
module uniarc_linear_static
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, add_context, make_error, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_model, only: model_t, dofs_per_node
   use uniarc_dof_map, only: dof_map_t, build_dof_map, candidate_live, element_equations, bed_deflection
   use uniarc_band, only: band_matrix_t, band_allocate, band_factorize, band_solve, band_inertia, band_copy
   use uniarc_assembly, only: assemble_linear_stiffness, assemble_reference_load, gather_nodal, scatter_add
   use uniarc_element, only: element_response_t, element_response, element_displacements, transformation_linear
   use uniarc_contact, only: candidate_gap, assemble_contact, in_set, bed_values
   use uniarc_path_mechanism, only: find_mechanism
   use uniarc_contact_lcp, only: contact_linearization_t, contact_selection_t, select_contact_set, &
                                 constraint_load
   implicit none
   private
   public :: solve_linear_static

   !> Rounds of LCP and solve: the LCP of a linear problem is solved in one; a second round only
   !> confirms a set that round-off of the first left in doubt.
   integer, parameter :: max_rounds = 4
   !> Complementarity accepted within this fraction of the force and gap units (the LCP solver's own
   !> acceptance tolerance, uniarc_lcp_implicit, with a decade of room for the final solve's round-off).
   real(dp), parameter :: complementarity_tolerance = 1.0e-8_dp

contains

   !> Solve the linear problem with its contacts.
   !> Out: `displacement` (3, n_nodes) nodal displacements; `negative_pivots`, the negative pivots of
   !> the structure's stiffness with the contact rows of the final set accounted for (non-zero: the
   !> supports and contacts leave a mechanism or K is not positive definite); optional `reactions`
   !> (one per candidate, force ≥ 0, exactly 0 out of contact), `active` (the candidates in contact or
   !> bonded), `lcp_pivots` (pivots the contact LCP spent), `lcp_residual` (largest relative violation
   !> of complementarity of the linearised gaps, docs/theory.md §3.4).
   !> Errors: a mechanism (input: the model moves as a rigid body with every contact closed,
   !> uniarc_path_mechanism); a singular matrix (analysis: the supports and the contacts of the set do not hold the
   !> structure); a contact LCP that is not solved (analysis).
   subroutine solve_linear_static(model, displacement, negative_pivots, error, reactions, active, lcp_pivots, &
                                  lcp_residual, deflections)
      type(model_t), intent(in) :: model
      real(dp), allocatable, intent(out) :: displacement(:, :)
      integer, intent(out) :: negative_pivots
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable, intent(out), optional :: reactions(:)
      logical, allocatable, intent(out), optional :: active(:)
      integer, intent(out), optional :: lcp_pivots
      real(dp), intent(out), optional :: lcp_residual
      !> (n_contacts) the Pasternak beds' surface deflections under each candidate (0 for the others)
      real(dp), allocatable, intent(out), optional :: deflections(:)
      type(dof_map_t) :: map
      type(band_matrix_t) :: assembled, factors
      type(contact_linearization_t) :: lin
      type(contact_selection_t) :: selection
      real(dp), allocatable :: residual(:), reference(:), rhs(:, :), x(:), r(:), g(:), zero_nodal(:, :)
      logical, allocatable :: set(:)
      logical :: singular
      real(dp) :: length_scale, worst
      integer :: n, round, pivots, c, status

      call build_dof_map(model, map, error, error_analysis)
      if (allocated(error)) return
      n = map%n_equations
      length_scale = max(maxval(model%coordinates) - minval(model%coordinates), tiny(1.0_dp))
      allocate (zero_nodal(dofs_per_node, model%n_nodes), reference(n), residual(n), rhs(n, 2), &
                set(size(map%candidate_equation)), stat=status)
      call allocation_failure(status, 'the load and residual vectors of the linear analysis', &
                              8.0_dp*(dofs_per_node*model%n_nodes + 4.0_dp*n) + 4.0_dp*size(map%candidate_equation), &
                              error_analysis, error)
      if (allocated(error)) return
      zero_nodal = 0.0_dp
      call assemble_reference_load(model, map, .true., reference)
      if (allocated(model%prescribed)) call add_settlement_load(model, map, reference)
      ! The first working set: candidates that touch at u = 0, and the bonded ones (as the path
      ! following starts): it holds what the contacts hold, so K_S is regular for a structure that
      ! rests on its medium without supports.
      ! A model that can move as a rigid body even with every contact closed is a mechanism: refused
      ! (error_input, exit 2) before any solve, by the path following's start-up test
      ! (uniarc_path_mechanism: relative pivot test, then the rigid-body test).
      set = [(candidate_live(map, c), c=1, size(set))]
      call assemble_set(model, map, zero_nodal, set, assembled, residual, error)
      if (allocated(error)) return
      call find_mechanism(model, map, assembled, error)
      if (allocated(error)) return
      call touching(model, map, length_scale, set)
      pivots = 0
      worst = 0.0_dp
      do round = 1, max_rounds
         call assemble_set(model, map, zero_nodal, set, assembled, residual, error)
         if (allocated(error)) return
         call band_copy(assembled, factors, error)
         if (allocated(error)) return
         call band_factorize(factors, error)
         if (allocated(error)) then
            call add_context(error, 'linear static analysis (are the supports and contacts enough to hold '// &
                             'the structure?)')
            return
         end if
         rhs(:, 1) = residual
         rhs(:, 2) = reference
         call band_solve(factors, rhs, error)
         if (allocated(error)) return
         x = rhs(:, 1) + rhs(:, 2)
         call linear_contact_state(model, map, x, set, r, g)
         worst = complementarity_violation(model, map, length_scale, x, reference, r, g, set)
         if (worst <= complementarity_tolerance) exit
         if (round == max_rounds) then
            call make_error(error, 'linear static analysis: the contact set did not settle after the contact LCP', &
                            error_analysis)
            return
         end if
         ! The LCP of one load step δλ = 1 from the unloaded state: x = 0, λ = 0, residual = −F_aug(0).
         if (allocated(lin%x)) deallocate (lin%x)
         allocate (lin%x(n), source=0.0_dp)
         lin%nodal = zero_nodal
         lin%residual = residual
         lin%reference = reference
         lin%du_residual = rhs(:, 1)
         lin%du_tangent = rhs(:, 2)
         lin%constraint%kind = constraint_load
         lin%constraint%target = 1.0_dp
         lin%units%force = max(norm2(reference), tiny(1.0_dp))
         lin%units%gap = max(maxval(abs(map%metric*x)), 1.0e-6_dp*length_scale)
         call select_contact_set(model, map, lin, set, assembled, factors, selection, error)
         pivots = pivots + selection%report%pivots
         if (allocated(error)) then
            call add_context(error, 'linear static analysis')
            return
         end if
         set = selection%active
      end do

      ! Inertia of the final K_S: each contact row of the set adds one negative pivot to the
      ! saddle-point matrix (Haynsworth inertia additivity); what remains belongs to the structure.
      call band_inertia(assembled, negative_pivots, singular, status)
      call allocation_failure(status, 'a copy of the stiffness matrix for its inertia', &
                              8.0_dp*real(size(assembled%ab), dp), error_analysis, error)
      if (allocated(error)) return
      negative_pivots = max(0, negative_pivots - count(set .and. map%candidate_equation > 0))
      allocate (displacement(dofs_per_node, model%n_nodes), stat=status)
      call allocation_failure(status, 'the nodal displacements', 8.0_dp*dofs_per_node*model%n_nodes, error_analysis, &
                              error)
      if (allocated(error)) return
      call gather_nodal(map, x, displacement)
      if (allocated(model%prescribed)) displacement = displacement + model%prescribed
      if (present(reactions)) reactions = r
      if (present(active)) active = set
      if (present(lcp_pivots)) lcp_pivots = pivots
      if (present(lcp_residual)) lcp_residual = worst
      if (present(deflections)) deflections = bed_values(map, x)
   end subroutine solve_linear_static

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

   !> K_S (linear K with the contact rows of `set`, unfactorised) and its residual −F_aug at u = 0,
   !> r = 0: g_c(0) on the rows of the candidates in the set, the force of condensed springs in it.
   subroutine assemble_set(model, map, zero_nodal, set, assembled, residual, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: zero_nodal(:, :)
      logical, intent(in) :: set(:)
      type(band_matrix_t), intent(inout) :: assembled
      real(dp), intent(out) :: residual(:)
      type(error_t), allocatable, intent(out) :: error   !< a band matrix that cannot be allocated (band_allocate)
      real(dp), allocatable :: internal(:), no_reactions(:)
      integer :: status
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
   subroutine linear_contact_state(model, map, x, set, r, g)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: x(:)
      logical, intent(in) :: set(:)
      real(dp), allocatable, intent(out) :: r(:), g(:)
      real(dp) :: gap0, gradient(2), hessian(2, 2)
      integer :: c, node, i
      allocate (r(size(set)), source=0.0_dp)
      allocate (g(size(set)), source=0.0_dp)
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

end module uniarc_linear_static
