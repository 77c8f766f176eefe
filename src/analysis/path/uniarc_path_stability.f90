!> Stability of a converged state of the path from its factorised tangent: the inertia (Sylvester's
!> law: negative pivots are negative eigenvalues) and the eigenvalue of least magnitude by inverse
!> iteration, which the critical-point detector (uniarc_critical_points) interpolates between steps;
!> and the lift-off test of contacts that touch without force (`liftoff_stability`); `commit_tangent`
!> computes them all, with the tangent solution K⁻¹R, at a committed state.
module uniarc_path_stability
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_copy, only: copy_array, reserve
   use uniarc_model, only: model_t
   use uniarc_band, only: band_matrix_t, band_solve, band_inertia, band_inertia_from_factors, band_copy, &
                          band_factorize, band_get, band_add
   use uniarc_dof_map, only: candidate_live, bed_deflection
   use uniarc_contact, only: candidate_gap, set_membership
   use uniarc_path_state, only: path_state_t, path_system_t, nodal_displacements, equilibrium_at, hold_floating
   use uniarc_path_contact_set, only: candidate_state, contact_units
   use uniarc_contact_lcp, only: contact_scales_t, degenerate_fraction
   use uniarc_path_element_loads, only: element_load_norm
   implicit none
   private
   public :: structural_inertia, least_eigenvalue, liftoff_stability, commit_tangent, cone_mode

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
      call band_inertia_from_factors(factors, assembled, negative, singular, found, status)
      if (present(status)) then
         if (status /= 0) return
      end if
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
   !> Errors: its work vectors refused by the system (error_analysis, out of memory; mu 0).
   subroutine least_eigenvalue(matrix, mode, mu, memory_error)
      type(band_matrix_t), intent(in) :: matrix
      real(dp), allocatable, intent(inout) :: mode(:)
      real(dp), intent(out) :: mu
      type(error_t), allocatable, intent(out) :: memory_error
      real(dp), allocatable :: x(:, :), y(:)
      real(dp) :: nu, previous
      type(error_t), allocatable :: error
      integer :: k, i, first_check, status
      mu = 0.0_dp
      if (matrix%n == 0) return
      allocate (x(matrix%n, 1), y(matrix%n), stat=status)
      call allocation_failure(status, 'the vectors of the least eigenvalue', 16.0_dp*matrix%n, error_analysis, &
                              memory_error)
      if (allocated(memory_error)) return
      ! No usable last mode (first step, another size, or a zero vector): a fixed generic start.
      if (allocated(mode)) then
         if (size(mode) /= matrix%n .or. .not. (norm2(mode) > 0.0_dp)) deallocate (mode)
      end if
      first_check = 1
      if (.not. allocated(mode)) then
         allocate (mode(matrix%n), stat=status)
         call allocation_failure(status, 'the mode of the least eigenvalue', 8.0_dp*matrix%n, error_analysis, &
                                 memory_error)
         if (allocated(memory_error)) return
         do i = 1, matrix%n
            mode(i) = 1.0_dp + 0.1_dp*sin(real(i, dp))
         end do
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
   end subroutine least_eigenvalue

   !> Stability with contacts that touch without force (docs/theory.md §2.2; Klarbring 1988; Cottle,
   !> Pang & Stone 1992, §3.8 on copositivity). Such a contact (weak: in the working set with a
   !> reaction at most `tolerance` × the force unit) is held by K_S as if bonded, but a perturbation
   !> δu may open it at no cost. The second variation of the energy is the piecewise quadratic
   !> Q(δu) = δuᵀK_open δu + Σ_weak k_c min(0, a_cᵀδu)² (a rigid contact: a_cᵀδu ≥ 0 on the cone), K_open
   !> being K_S with the weak contacts released; the state is stable when Q is positive for δu ≠ 0,
   !> i.e. when the tangent is strictly copositive on the cone of admissible directions. Decided on
   !> the pieces K_J (K_S with the weak contacts outside J released), from J = ∅:
   !> - K_J positive definite: no direction of the piece's region is unstable; the state is stable
   !>   when J = ∅ (Q ≥ δuᵀK_open δu). The count is 0 and the least eigenvalue K_J's: the indicator
   !>   that the critical-point locator interpolates is that of the piece the cone is decided on.
   !> - K_J with one negative eigenvalue and its eigenvector φ (the least eigenvector if its eigenvalue
   !>   is that one, else by negative_eigenpair) opening or leaving every released weak contact (for
   !>   one sign of φ): Q(φ) ≤ φᵀK_Jφ < 0, an admissible
   !>   direction: unstable, the count is K_J's (a lift-off mode).
   !> - φ pressing into some released weak contact for either sign: that direction is excluded (the
   !>   medium resists); those contacts are closed (added to J) and the next piece is tested.
   !> - more than one negative eigenvalue: unstable (conservative: each of them may press).
   !> The count of a state decided on a piece is 0 (stable) or 1 (unstable): copositivity decides
   !> stable or not, and a count beyond one, of a piece or of K_S, is no bifurcation of the unilateral
   !> problem.
   !> Floating rigid motions (docs/theory.md §2.8) that no contact of the piece sees are held in it, as
   !> in the tangent itself: a liner whose first contact touches without force can drift away from it
   !> at no cost, a neutral motion it had before the contact too, not an instability.
   !>
   !> `assembled` is K_S unfactorised (left unchanged: it is copied). Not at the unloaded state
   !> (`unloaded`), where every resting contact touches without force and a structure lying on its
   !> medium is neutral, not unstable. Costs one band LU per piece tested at the states that have weak
   !> contacts, nothing at the others. Sets state%point%liftoff when the count and least eigenvalue
   !> are a piece's other than K_S, with its least eigenvector in state%liftoff_mode.
   !> memory_error: a copy of a piece or a vector of the test that the system refuses (error_analysis,
   !> out of memory: it ends the run, docs/contracts.md "Memory").
   subroutine liftoff_stability(model, state, assembled, tolerance, unloaded, memory_error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(band_matrix_t), intent(in) :: assembled
      real(dp), intent(in) :: tolerance
      logical, intent(in) :: unloaded
      type(error_t), allocatable, intent(out) :: memory_error
      type(contact_scales_t) :: units
      real(dp), allocatable :: nodal(:, :), reaction(:), gap(:), mode(:), along(:), norms(:)
      logical, allocatable :: released(:), pressed_plus(:), pressed_minus(:)
      real(dp), allocatable :: direction(:)
      real(dp) :: force_unit, mu, size_mode, mu_shifted, bytes
      integer :: c, negative, round, negative_shifted, status
      logical :: ok, have_direction
      state%point%liftoff = .false.
      if (unloaded .or. size(state%map%candidate_equation) == 0) return
      call nodal_displacements(model, state, nodal, memory_error)
      if (allocated(memory_error)) return
      allocate (reaction(size(state%active)), gap(size(state%active)), stat=status)
      call allocation_failure(status, 'the reactions and gaps of the lift-off stability test', &
                              16.0_dp*size(state%active), error_analysis, memory_error)
      if (allocated(memory_error)) return
      call candidate_state(model, state%map, state%u, nodal, state%active, reaction, gap, lambda=state%lambda)
      units = contact_units(state, state%u, reaction, state%active)
      force_unit = units%force
      allocate (released(size(reaction)), pressed_plus(size(reaction)), pressed_minus(size(reaction)), &
                along(size(reaction)), norms(size(reaction)), stat=status)
      call allocation_failure(status, 'the contacts of the lift-off stability test', 28.0_dp*size(reaction), &
                              error_analysis, memory_error)
      if (allocated(memory_error)) return
      do c = 1, size(reaction)
         released(c) = state%active(c) .and. candidate_live(state%map, c) .and. .not. model%contacts(c)%bilateral &
                       .and. reaction(c) <= tolerance*force_unit
      end do
      if (.not. any(released)) return
      bytes = 0.0_dp
      call copy_array(state%liftoff_mode, mode, status, bytes)
      call allocation_failure(status, 'the mode of the lift-off stability test', bytes, error_analysis, memory_error)
      if (allocated(memory_error)) return
      do round = 1, count(released)
         call piece_stability(model, state, assembled, nodal, reaction, released, negative, mu, mode, ok, &
                              memory_error)
         if (.not. ok) return
         ! The one negative direction φ of the piece: the least eigenvector when its eigenvalue is the
         ! negative one; else (a positive eigenvalue nearer zero) found by inverse iteration shifted
         ! below it, from a generic start (the warm mode is the positive one's, orthogonal to the
         ! negative one on a symmetric structure). It serves the test only: the point keeps the least
         ! eigenvalue and its mode (the locator's indicator, the warm start, the buckling mode).
         have_direction = .false.
         if (negative == 1 .and. mu < 0.0_dp .and. allocated(mode)) then
            call copy_array(mode, direction, status, bytes)
            call allocation_failure(status, 'the direction of the lift-off stability test', bytes, error_analysis, &
                                    memory_error)
            if (allocated(memory_error)) return
            have_direction = .true.
         else if (negative == 1) then
            if (allocated(direction)) deallocate (direction)
            call piece_stability(model, state, assembled, nodal, reaction, released, negative_shifted, &
                                 mu_shifted, direction, have_direction, memory_error, negative_mode=.true.)
            if (allocated(memory_error)) return
         end if
         if (have_direction) then
            ! Admissible for a sign if it presses no released contact (a_cᵀφ below −1e-6 |a_c| max|φ|:
            ! above it is round-off of an orthogonal motion).
            call normal_motions(model, state, nodal, direction, along, norms)
            size_mode = maxval(abs(state%map%metric*direction))
            pressed_plus = released .and. along < -1.0e-6_dp*norms*size_mode
            pressed_minus = released .and. along > 1.0e-6_dp*norms*size_mode
            if (any(pressed_plus) .and. any(pressed_minus)) then
               ! Excluded for both signs: close the contacts the milder sign presses, test again.
               if (count(pressed_plus) <= count(pressed_minus)) then
                  released = released .and. .not. pressed_plus
               else
                  released = released .and. .not. pressed_minus
               end if
               if (.not. any(released)) return   ! every weak contact closed: K_S itself
               cycle
            end if
         end if
         exit
      end do
      ! On the cone the count says stable (0) or unstable (1). Further negative eigenvalues of a piece,
      ! or of K_S, whose directions press into some contacts that touch without force and pull away
      ! from others, are no bifurcations of the unilateral problem (the strut on its bed: the free
      ! strut's waves m²π²EI/L², m ≥ 2, half of each pressing into the bed; the bonded bed's at 2.0155
      ! and 2.2155, pulling on the bed; docs/theory.md §2.2): not counted.
      state%point%neg_pivots = min(1, max(state%point%neg_pivots, negative))
      state%point%min_eigenvalue = mu
      state%point%liftoff = .true.
      if (allocated(mode)) call move_alloc(mode, state%liftoff_mode)
   end subroutine liftoff_stability

   !> The mode of a lift-off (unilateral) bifurcation put on the cone of admissible directions
   !> (docs/theory.md §2.2, §2.6): at `state`, the contacts of the working set that touch without force
   !> (reaction at most `tolerance` × the force unit, as liftoff_stability finds them; W) may open but
   !> not be pressed, a_cᵀd ≥ 0 for c ∈ W. `mode` (n, augmented) is first signed to open them
   !> (Σ_W a_cᵀφ ≥ 0, the sign the branch switch takes) and then projected onto the cone: the nearest
   !> d to φ in the displacement norm with a_cᵀd ≥ 0 on W — a least-distance problem whose dual is the
   !> LCP y ≥ 0, A Aᵀ y + A φ ≥ 0, complementary (d = φ + Aᵀy), solved by Hildreth's row iteration
   !> (C. Hildreth 1957, Naval Res. Logist. Q. 4, 79–85; Cottle, Pang & Stone 1992, §5.2, projected
   !> Gauss–Seidel), which is exact in one sweep where the a_c of W sit on different nodes (a bed, a
   !> plane) and converges otherwise. The contacts in compression need nothing: the piece's eigenvector
   !> keeps a rigid one's gap (its augmented row) and an elastic one may move either way. A mode that
   !> presses nothing (the strut's half sine at Euler's load) is unchanged; one that presses a part of
   !> W loses that part (its component along those a_c). `pressed` returns the largest pressing
   !> component removed, relative to the mode's largest displacement (0: it was on the cone).
   !> Errors: the arrays of the projection refused by the system (error_analysis, out of memory).
   subroutine cone_mode(model, state, tolerance, mode, pressed, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: tolerance
      real(dp), intent(inout) :: mode(:)
      real(dp), intent(out) :: pressed
      type(error_t), allocatable, intent(out) :: error
      type(contact_scales_t) :: units
      real(dp), allocatable :: nodal(:, :), reaction(:), gap(:), along(:), norms(:), multiplier(:), normal(:, :)
      logical, allocatable :: weak(:)
      real(dp) :: g, hessian(2, 2), size_mode, change, t, updated
      integer :: c, k, node, sweep, status, n
      pressed = 0.0_dp
      n = size(state%active)
      if (n == 0) return
      call nodal_displacements(model, state, nodal, error)
      if (allocated(error)) return
      allocate (reaction(n), gap(n), along(n), norms(n), multiplier(n), normal(2, n), weak(n), stat=status)
      call allocation_failure(status, 'the vectors of the projection of a mode onto the cone', 68.0_dp*n, &
                              error_analysis, error)
      if (allocated(error)) return
      call candidate_state(model, state%map, state%u, nodal, state%active, reaction, gap, lambda=state%lambda)
      units = contact_units(state, state%u, reaction, state%active)
      do c = 1, n
         weak(c) = state%active(c) .and. candidate_live(state%map, c) .and. .not. model%contacts(c)%bilateral &
                   .and. reaction(c) <= tolerance*units%force
         normal(:, c) = 0.0_dp
         if (.not. weak(c)) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, normal(:, c), &
                            hessian, state%lambda)
         ! only the free translations move the gap
         do k = 1, 2
            if (state%map%equation(k, node) == 0) normal(k, c) = 0.0_dp
         end do
      end do
      if (.not. any(weak)) return
      size_mode = maxval(abs(state%map%metric*mode))
      if (.not. (size_mode > 0.0_dp)) return
      along = [(a_dot(c), c=1, n)]
      if (sum(along, mask=weak) < 0.0_dp) mode = -mode
      multiplier = 0.0_dp
      do sweep = 1, 100
         change = 0.0_dp
         do c = 1, n
            if (.not. weak(c)) cycle
            norms(c) = dot_product(normal(:, c), normal(:, c))
            if (.not. (norms(c) > 0.0_dp)) cycle
            t = a_dot(c)/norms(c)
            updated = max(0.0_dp, multiplier(c) - t)
            if (updated /= multiplier(c)) then
               node = model%contacts(c)%node
               do k = 1, 2
                  if (state%map%equation(k, node) > 0) mode(state%map%equation(k, node)) = &
                     mode(state%map%equation(k, node)) + (updated - multiplier(c))*normal(k, c)
               end do
               change = max(change, abs(updated - multiplier(c))*sqrt(norms(c)))
               pressed = max(pressed, abs(updated - multiplier(c))*sqrt(norms(c))/size_mode)
               multiplier(c) = updated
            end if
         end do
         if (change <= 1.0e-14_dp*size_mode) exit
      end do

   contains

      !> a_cᵀ mode for candidate c (its free translations).
      real(dp) function a_dot(c)
         integer, intent(in) :: c
         integer :: j
         a_dot = 0.0_dp
         do j = 1, 2
            if (state%map%equation(j, model%contacts(c)%node) > 0) &
               a_dot = a_dot + normal(j, c)*mode(state%map%equation(j, model%contacts(c)%node))
         end do
      end function a_dot

   end subroutine cone_mode

   !> One piece of the lift-off test: K_S (`assembled`) with the contacts `released` released, the
   !> floating motions no remaining contact sees held; its negative eigenvalues (the contact rows
   !> still in it subtracted, as in structural_inertia) and its eigenvalue of least magnitude `mu` with
   !> its eigenvector `mode` (warm start in, result out). `ok` false: a failed factorisation.
   !> With `negative_mode` (for a piece with one negative eigenvalue that is not the least in
   !> magnitude): `mu` and `mode` are that negative eigenvalue and its eigenvector instead
   !> (negative_eigenpair).
   !> memory_error: a copy or a vector refused by the system (error_analysis, out of memory; ok false).
   subroutine piece_stability(model, state, assembled, nodal, reaction, released, negative, mu, mode, ok, &
                              memory_error, negative_mode)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(band_matrix_t), intent(in) :: assembled
      real(dp), intent(in) :: nodal(:, :), reaction(:)
      logical, intent(in) :: released(:)
      integer, intent(out) :: negative
      real(dp), intent(out) :: mu
      real(dp), allocatable, intent(inout) :: mode(:)
      logical, intent(out) :: ok
      type(error_t), allocatable, intent(out) :: memory_error
      logical, intent(in), optional :: negative_mode
      type(band_matrix_t) :: piece
      real(dp), allocatable :: scratch(:)
      real(dp) :: g, gradient(2), hessian(2, 2)
      integer :: c, node, row, n_rows, status
      logical :: singular
      type(error_t), allocatable :: error
      ok = .false.
      negative = 0
      mu = 0.0_dp
      call band_copy(assembled, piece, memory_error, error_analysis)
      if (allocated(memory_error)) return
      allocate (scratch(size(assembled%ab, 2)), stat=status)
      call allocation_failure(status, 'a vector of the lift-off stability test', 8.0_dp*size(assembled%ab, 2), &
                              error_analysis, memory_error)
      if (allocated(memory_error)) return
      n_rows = count(state%active .and. state%map%candidate_equation > 0)
      do c = 1, size(released)
         if (.not. released(c)) cycle
         node = model%contacts(c)%node
         row = state%map%candidate_equation(c)
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, gradient, hessian, state%lambda)
         g = g + bed_deflection(state%map, c, state%u)
         ! Released as if leaving the set (its residual is not needed here).
         call set_membership(row, state%map%equation(1:2, node), g, gradient, hessian, &
                             model%contacts(c)%flexibility, reaction(c), .false., piece, scratch, &
                             state%map%bed_equation(c))
         if (row > 0) n_rows = n_rows - 1
      end do
      if (allocated(state%floating_equation)) &
         call hold_floating(model, state, state%active, nodal, piece, memory_error, released)
      if (allocated(memory_error)) return
      call band_inertia(piece, negative, singular, status)
      call allocation_failure(status, 'the elimination copy of a piece of the lift-off stability test', &
                              8.0_dp*real(size(piece%ab, 1), dp)*real(size(piece%ab, 2), dp), error_analysis, &
                              memory_error)
      if (allocated(memory_error)) return
      negative = max(0, negative - n_rows)
      if (present(negative_mode)) then
         if (negative_mode .and. negative == 1) then
            call negative_eigenpair(piece, state%map%metric, n_rows, mu, mode, ok, memory_error)
            return
         end if
      end if
      call band_factorize(piece, error)
      if (allocated(error)) return
      call least_eigenvalue(piece, mode, mu, memory_error)
      ok = .not. allocated(memory_error)
   end subroutine piece_stability

   !> The negative eigenvalue `mu` and eigenvector `mode` of an unfactorised piece with exactly one
   !> (on the displacements `metric` = 1; its `n_rows` contact rows add as many negative pivots,
   !> unshifted), when a positive eigenvalue is nearer zero and inverse iteration from zero finds that
   !> one. Shifts σ = −s, s = 1e-12, 1e-11, ..., 100 times the largest diagonal entry, until K − σI has no
   !> negative eigenvalue left (Sylvester's inertia, as band_inertia counts it: σ is below the
   !> negative one), then three bisections between the last two shifts on the same count (Parlett
   !> 1998, The Symmetric Eigenvalue Problem, §3.3, spectrum slicing) and inverse iteration with that
   !> shift, which converges to the negative eigenvalue, the one nearest the shift (§4.2). `ok` false:
   !> no shift found or a failed factorisation.
   !> memory_error: a shifted copy or a vector refused by the system (error_analysis; ok false).
   subroutine negative_eigenpair(piece, metric, n_rows, mu, mode, ok, memory_error)
      type(band_matrix_t), intent(in) :: piece
      real(dp), intent(in) :: metric(:)
      integer, intent(in) :: n_rows
      real(dp), intent(out) :: mu
      real(dp), allocatable, intent(inout) :: mode(:)
      logical, intent(out) :: ok
      type(error_t), allocatable, intent(out) :: memory_error
      type(band_matrix_t) :: shifted
      type(error_t), allocatable :: error
      real(dp) :: scale, below, above, sigma, nu
      integer :: k, i, n
      ok = .false.
      mu = 0.0_dp
      scale = 0.0_dp
      do i = 1, piece%n
         scale = max(scale, abs(band_get(piece, i, i)))
      end do
      if (.not. (scale > 0.0_dp)) return
      ! below: a shift with no eigenvalue under it; above: one with the negative eigenvalue under it.
      above = 0.0_dp
      below = 1.0_dp
      ! The shifted copy allocated once, checked (shifted_copy then reuses its storage).
      call band_copy(piece, shifted, memory_error, error_analysis)
      if (allocated(memory_error)) return
      do k = -12, 2
         sigma = -(10.0_dp**k)*scale
         if (count_below(sigma) == 0) then
            below = sigma
            exit
         end if
         above = sigma
      end do
      if (allocated(memory_error)) return   ! an elimination copy refused (count_below)
      if (below > 0.0_dp) return
      do k = 1, 3
         sigma = 0.5_dp*(below + above)
         if (count_below(sigma) == 0) then
            below = sigma
         else
            above = sigma
         end if
      end do
      if (allocated(memory_error)) return
      ! Shifted just below the negative eigenvalue (within the last bracket), inverse iteration
      ! converges to it: least_eigenvalue on K − σI returns λ − σ.
      call shifted_copy(below)
      call band_factorize(shifted, error)
      if (allocated(error)) return
      call least_eigenvalue(shifted, mode, nu, memory_error)
      if (allocated(memory_error)) return
      mu = nu + below
      ok = mu < 0.0_dp .and. allocated(mode)

   contains

      !> Negative eigenvalues of the piece below σ (its contact rows' pivots subtracted). An elimination
      !> copy refused by the system counts none and leaves memory_error (checked after the search).
      integer function count_below(shift)
         real(dp), intent(in) :: shift
         logical :: singular
         integer :: status
         call shifted_copy(shift)
         call band_inertia(shifted, n, singular, status)
         if (status /= 0 .and. .not. allocated(memory_error)) &
            call allocation_failure(status, 'the elimination copy of a shifted piece of the lift-off stability test', &
                                    8.0_dp*real(size(shifted%ab, 1), dp)*real(size(shifted%ab, 2), dp), &
                                    error_analysis, memory_error)
         count_below = max(0, n - n_rows)
      end function count_below

      subroutine shifted_copy(shift)
         real(dp), intent(in) :: shift
         integer :: j
         call band_copy(piece, shifted)
         do j = 1, piece%n
            if (metric(j) > 0.0_dp) call band_add(shifted, j, j, -shift)
         end do
      end subroutine shifted_copy

   end subroutine negative_eigenpair

   !> a_cᵀv for every candidate (its gap's gradient at its node against v's displacement there) and
   !> |a_c|; v (n) an augmented vector. along, norms: one entry per candidate, allocated by the caller
   !> (with stat=, docs/contracts.md "Memory").
   subroutine normal_motions(model, state, nodal, v, along, norms)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: nodal(:, :), v(:)
      real(dp), intent(out) :: along(:), norms(:)
      real(dp) :: g, gradient(2), hessian(2, 2)
      integer :: c, node, k
      along = 0.0_dp
      norms = 0.0_dp
      do c = 1, size(along)
         if (.not. candidate_live(state%map, c)) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, gradient, hessian, state%lambda)
         norms(c) = norm2(gradient)
         do k = 1, 2
            if (state%map%equation(k, node) > 0) along(c) = along(c) + gradient(k)*v(state%map%equation(k, node))
         end do
      end do
   end subroutine normal_motions

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
      real(dp) :: element_scale, bytes
      integer :: n, status
      system%holds_committed = .false.
      bytes = 0.0_dp
      n = state%map%n_equations
      allocate (internal(n), reference(n), rhs(n, 1), stat=status)
      call allocation_failure(status, 'the vectors of the commit of a step', 24.0_dp*n, error_analysis, error)
      if (allocated(error)) return
      if (status == 0) call reserve(state%reference, n, status, bytes)
      if (status == 0) call reserve(state%committed_residual, n, status, bytes)
      if (status == 0) call reserve(state%tangent_displacement, n, status, bytes)
      call allocation_failure(status, 'a vector of the committed state', bytes, error_analysis, error)
      if (allocated(error)) return
      if (system%holds_converged) then
         ! The attempt's last assembly is this very state (the same u, λ and working set).
         internal = system%converged_internal
         reference = system%converged_reference
         system%holds_converged = .false.
      else
         call nodal_displacements(model, state, nodal, error)
         if (allocated(error)) return
         call equilibrium_at(model, state, system, state%u, state%lambda, state%active, nodal, internal, &
                             reference, element_scale, error)
         if (allocated(error)) return
      end if
      state%reference = reference
      ! The unfactorised tangent and the residual stay for the predictor of the next step (its contact
      ! LCP needs both): the step's first attempt does not assemble and factorise them again.
      call band_copy(system%tangent, system%assembled, error, error_analysis)
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
      call supports_take_load(model, state, error)
      if (allocated(error)) return
      call least_eigenvalue(system%tangent, state%eigenvector, state%point%min_eigenvalue, error)
      if (allocated(error)) return
      call liftoff_stability(model, state, system%assembled, model%analysis%displacement_tolerance, unloaded, error)
   end subroutine commit_tangent

   !> Where the supports take every equivalent nodal force of the step's temperature changes (a bar
   !> heated between held ends), the reference load left on the free DOFs is the round-off of their
   !> cancellation, and so is K⁻¹R: the path goes in λ alone (docs/theory.md §2.7). Near a critical
   !> point that round-off is amplified by 1/μ along the least mode (the heated bar on its bed, 0.74 %
   !> above its bifurcation: ‖K⁻¹R‖ = 7.8e-16 against ψ = 7.6e-4, ‖R‖ = 4.7e-16 against the element
   !> loads' 1e2), past the degenerate_fraction of ψ that marks a load step; the step after it then
   !> followed the mode at a λ the round-off set. So K⁻¹R is set to zero where ‖R‖ over the free DOFs
   !> is at most degenerate_fraction of the element loads' equivalent nodal forces over every DOF
   !> (uniarc_path_element_loads): the same fraction that separates round-off from a response in ψ.
   !> A load that acts on the free DOFs (a force, a buckled bar's heated elements) stays far above.
   !> Errors: the arrays of the element loads refused by the system (error_analysis, out of memory).
   subroutine supports_take_load(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), total(:, :)
      real(dp) :: loads
      integer :: status
      if (.not. allocated(model%thermal_loads)) return
      if (size(model%thermal_loads) == 0) return
      call nodal_displacements(model, state, nodal, error)
      if (allocated(error)) return
      allocate (total(size(nodal, 1), size(nodal, 2)), stat=status)
      call allocation_failure(status, 'the nodal forces of the element loads', 8.0_dp*size(nodal), &
                              error_analysis, error)
      if (allocated(error)) return
      loads = element_load_norm(model, nodal, total)
      if (.not. (loads > 0.0_dp)) return
      if (norm2(state%reference) > degenerate_fraction*loads) return
      state%tangent_displacement = 0.0_dp
   end subroutine supports_take_load

end module uniarc_path_stability
