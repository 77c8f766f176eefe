!> Stability of a converged state of the path from its factorised tangent: the inertia (Sylvester's
!> law: negative pivots are negative eigenvalues) and the eigenvalue of least magnitude by inverse
!> iteration, which the critical-point detector (uniarc_critical_points) interpolates between steps;
!> and the lift-off test of contacts that touch without force (`liftoff_stability`); `commit_tangent`
!> computes them all, with the tangent solution K⁻¹R, at a committed state.
module uniarc_path_stability
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_model, only: model_t
   use uniarc_band, only: band_matrix_t, band_solve, band_inertia, band_inertia_from_factors, band_copy, &
                          band_factorize
   use uniarc_dof_map, only: candidate_live
   use uniarc_contact, only: candidate_gap, set_membership
   use uniarc_path_state, only: path_state_t, path_system_t, nodal_displacements, equilibrium_at
   use uniarc_path_contact_set, only: candidate_state, contact_units
   use uniarc_contact_lcp, only: contact_scales_t
   implicit none
   private
   public :: structural_inertia, least_eigenvalue, liftoff_stability, commit_tangent

contains

   !> Negative eigenvalues of the structure at a state whose augmented tangent is `assembled`
   !> (unfactorised) with band LU `factors`, and `n_active` the contact rows of the working set among
   !> them (active(c) and candidate_equation(c) > 0, per candidate). The inertia comes from the LU
   !> factors when they needed no row interchange, else by elimination without interchanges.
   !> status: band_inertia's (nonzero: the system refused the copy of the band it eliminates).
   subroutine structural_inertia(factors, assembled, active, candidate_equation, negative, n_active, status)
      type(band_matrix_t), intent(in) :: factors, assembled
      logical, intent(in) :: active(:)
      integer, intent(in) :: candidate_equation(:)
      integer, intent(out) :: negative, n_active
      integer, intent(out), optional :: status
      logical :: singular, found
      if (present(status)) status = 0
      call band_inertia_from_factors(factors, assembled, negative, singular, found)
      if (.not. found) call band_inertia(assembled, negative, singular, status)
      ! Each contact row of the working set adds one negative pivot to the saddle-point system
      ! (Haynsworth inertia additivity): what remains counts the unstable modes of the structure.
      n_active = count(active .and. candidate_equation > 0)
      negative = max(0, negative - n_active)
   end subroutine structural_inertia

   !> Eigenvalue of least magnitude of a factorised matrix by inverse iteration (Rayleigh quotient of
   !> K⁻¹); used only to place bifurcation points between steps, so a few digits suffice.
   !> `mode` (n) is the start vector and returns the last iterate: started from the mode of the last
   !> converged step, which changes little from step to step, the iteration settles in a few solves.
   !> Returns 0 for an empty matrix, a failed solve or an infinite quotient.
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
      ! after 5 — between the clustered eigenvalues, of their common sign — is what the detector
      ! needs. A warm start from the last mode needs two solves to compare quotients, a cold one three.
      do k = 1, 5
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

   !> Stability with contacts that touch without force (Klarbring 1988; Cottle, Pang & Stone 1992,
   !> §3.8 on copositivity): such a contact is in the working set, so K_S holds it as if bonded, but a
   !> perturbation may open it at no cost. The second variation of the energy is then
   !> δuᵀK_open δu + Σ_weak k_c min(0, a_cᵀδu)² (a rigid contact: a_cᵀδu ≥ 0 on the cone), where
   !> K_open is K_S with the weak contacts released. It is positive for all δu ≠ 0 if K_open is positive
   !> definite. uniarc counts the negative pivots of K_open at such states (`point%liftoff`), with its
   !> least eigenvalue for the locator: conservative, since a negative mode of K_open that would press
   !> into a weak contact is counted too, and never later than the first lift-off — a pinned strut
   !> resting on a tensionless bed buckles at Euler's load, not at the bonded bed's.
   !>
   !> `assembled` is K_S unfactorised (left unchanged: it is copied). Weak: in the working set with a
   !> reaction at most `tolerance` × the force unit (reactions below it are round-off of zero). Not
   !> at the unloaded state (`unloaded`), where every resting contact touches without force and a
   !> structure lying on its medium is neutral, not unstable. Costs one more band LU and inertia count
   !> at the states that have weak contacts, nothing at the others.
   !> memory_error: an allocation of the copy the system refused (error_analysis, allocation_failure).
   subroutine liftoff_stability(model, state, assembled, tolerance, unloaded, memory_error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(band_matrix_t), intent(in) :: assembled
      real(dp), intent(in) :: tolerance
      logical, intent(in) :: unloaded
      type(error_t), allocatable, intent(out) :: memory_error
      type(band_matrix_t) :: open_tangent
      type(contact_scales_t) :: units
      real(dp), allocatable :: nodal(:, :), reaction(:), gap(:), mode(:), released(:)
      logical, allocatable :: weak(:)
      real(dp) :: force_unit, g, gradient(2), hessian(2, 2), mu
      integer :: c, node, row, negative, n_rows, status
      logical :: singular
      type(error_t), allocatable :: error
      state%point%liftoff = .false.
      if (unloaded .or. size(state%map%candidate_equation) == 0) return
      call nodal_displacements(model, state, nodal)
      call candidate_state(model, state%map, state%u, nodal, state%active, reaction, gap)
      units = contact_units(state, state%u, reaction, state%active)
      force_unit = units%force
      allocate (weak(size(reaction)))
      do c = 1, size(reaction)
         weak(c) = state%active(c) .and. candidate_live(state%map, c) .and. .not. model%contacts(c)%bilateral &
                   .and. reaction(c) <= tolerance*force_unit
      end do
      if (.not. any(weak)) return
      call band_copy(assembled, open_tangent, memory_error, error_analysis)
      if (allocated(memory_error)) return
      allocate (released(size(assembled%ab, 2)))
      n_rows = count(state%active .and. state%map%candidate_equation > 0)
      do c = 1, size(weak)
         if (.not. weak(c)) cycle
         node = model%contacts(c)%node
         row = state%map%candidate_equation(c)
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, gradient, hessian)
         ! Released as if leaving the set (its residual is not needed here).
         call set_membership(row, state%map%equation(1:2, node), g, gradient, hessian, &
                             model%contacts(c)%flexibility, reaction(c), .false., open_tangent, released)
         if (row > 0) n_rows = n_rows - 1
      end do
      call band_inertia(open_tangent, negative, singular, status)
      call allocation_failure(status, 'a copy of the tangent with the weak contacts released, for its inertia', &
                              8.0_dp*real(size(open_tangent%ab), dp), error_analysis, memory_error)
      if (allocated(memory_error)) return
      negative = max(0, negative - n_rows)
      call band_factorize(open_tangent, error)
      if (allocated(error)) return
      if (allocated(state%liftoff_mode)) mode = state%liftoff_mode
      mu = least_eigenvalue(open_tangent, mode)
      if (allocated(mode)) state%liftoff_mode = mode
      state%point%neg_pivots = max(state%point%neg_pivots, negative)
      state%point%min_eigenvalue = mu
      state%point%liftoff = .true.
   end subroutine liftoff_stability


   !> Assemble and factorise K_T at the committed state (into `system`, which then holds it); its
   !> residual, K⁻¹R, inertia and least eigenvalue into the state (path_advance's commit, and the
   !> probes of the critical-point locator, uniarc_path_locate).
   !> Errors: a singular tangent (band_factorize, band_solve); a copy of the tangent the system refuses
   !> (error_analysis, out of memory: it ends the run, docs/contracts.md "Memory").
   subroutine commit_tangent(model, state, system, unloaded, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(path_system_t), intent(inout) :: system
      logical, intent(in) :: unloaded   !< the unloaded state of path_initialize
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), internal(:), reference(:), rhs(:, :)
      real(dp) :: element_scale
      integer :: n, status
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
      call band_copy(system%tangent, system%assembled, error)
      if (allocated(error)) return
      state%committed_residual = state%lambda*state%reference - internal
      call band_factorize(system%tangent, error)
      if (allocated(error)) return
      call structural_inertia(system%tangent, system%assembled, state%active, state%map%candidate_equation, &
                              state%point%neg_pivots, state%point%n_active, status)
      call allocation_failure(status, 'a copy of the tangent for its inertia', &
                              8.0_dp*real(size(system%assembled%ab), dp), error_analysis, error)
      if (allocated(error)) return
      rhs(:, 1) = state%reference
      call band_solve(system%tangent, rhs, error)
      if (allocated(error)) return
      system%holds_committed = .true.
      state%tangent_displacement = rhs(:, 1)
      state%point%min_eigenvalue = least_eigenvalue(system%tangent, state%eigenvector)
      call liftoff_stability(model, state, system%assembled, model%analysis%displacement_tolerance, unloaded, error)
   end subroutine commit_tangent

end module uniarc_path_stability
