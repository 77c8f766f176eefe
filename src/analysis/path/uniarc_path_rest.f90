!> A structure held only by its contacts whose working set lets it float at the end of a step
!> (docs/theory.md §2.8, "A working set that lets go"): unloaded to zero, the contacts that carried it
!> open together (or all but one, which touches without force and holds nothing but its own point),
!> and the converged state is an equilibrium wherever the structure floats. The Newton iterations left
!> it where the predictor of the last set put it (a beam on a bed unloaded to zero rose 7.2e-5 above
!> its bed, tilted by 1.5e-5; issue 16). The path's limit as λ reaches that state rests on the
!> contacts the load pushed it against just before: this module puts it there. The step's rigid
!> motion along the floating motions U that no contact of the set holds is taken out (x − x_n ⟂ U in
!> the metric, as the static analysis takes its solution, §2.8), then the rigid motion d = U Uᵀp that
!> the push p just before drives (−sign(Δλ) R: λ came from where λR pressed the contacts) moves it to
!> the first contact it closes; the contacts that touch there join the working set at zero force.
!> A contact of the set that carries nothing (its reaction within Newton's force tolerance of the
!> force scale: zero to the accuracy of the equilibrium) holds nothing either: a ring unloaded to zero
!> on its bed was left held only by two contacts at the bed's ends with reactions of 3e-17, 5.6e-3
!> above the bed, and the reload failed (issue 16, second review); such a state is at rest on the
!> contacts that carry something and on those it touches after the rest, not on the ones it drifted to.
module uniarc_path_rest
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_model, only: model_t, dofs_per_node
   use uniarc_dof_map, only: dof_map_t, candidate_live
   use uniarc_band, only: band_allocate
   use uniarc_assembly, only: gather_nodal
   use uniarc_contact_law, only: candidate_gap
   use uniarc_contact_plastic, only: slip_shift
   use uniarc_floating_subspace, only: orthonormal_motions, unheld_motions
   use uniarc_path_state, only: path_state_t, path_system_t, equilibrium_at, masked_norm
   implicit none
   private
   public :: rest_on_contacts, move_rigidly

   !> A candidate whose gap (with its slip) is at most this fraction of the model's size touches: the
   !> tolerance of the first working set (uniarc_path_contact_set, touching_candidates).
   real(dp), parameter :: touch_fraction = 1.0e-9_dp
   !> The load pushes along an unheld floating motion v when its work on v, |Rᵀv|/max|v|, exceeds this
   !> fraction of Σ|R_i| (the rigid approach's test, uniarc_path_approach: a self-equilibrated load
   !> leaves round-off, ~1e-16 of it).
   real(dp), parameter :: push_tolerance = 1.0e-9_dp
   !> A candidate whose gap the motion d changes by less than this fraction of max|d| neither closes
   !> nor opens along it (a normal square to d, to round-off: the rigid approach's slope test).
   real(dp), parameter :: slope_tolerance = 1.0e-12_dp
   !> Passes of the rest (Newton on the nearest gap along d): one for a translation onto a
   !> fixed-direction gap and one to confirm it; a rotation's second-order error, θ², falls below the
   !> touch tolerance by the third (θ ~ 1e-5 in the decks of issue 16).
   integer, parameter :: rest_passes = 8
   !> The rest never moves the structure along the push by more than this many times its own size
   !> (state%length_scale): a contact farther than that along the push is not one the structure left
   !> in the step (a step's motion is a fraction of the size), and the structure is floating away.
   real(dp), parameter :: rest_reach = 1.0_dp

contains

   !> The committed state `state`, just converged by a step of Δλ = `dlambda` from the displacements
   !> `before` (n_equations), at rest on its contacts: `x` (n_equations) and `active` (candidates) are
   !> the state to commit instead, and `rested` says whether there is one. Nothing to do (rested
   !> false) unless the structure has floating motions, some of which no candidate of the working set
   !> that carries a force sees (unheld_motions over `carrying`; a yielding or bonded candidate of the
   !> set sees them too, a unilateral one whose reaction is within Newton's force tolerance of the
   !> force scale does not), and the reference load does work along them; nor where the push closes
   !> no contact within rest_reach of the structure's size (rest_along), or the state at rest is
   !> further from equilibrium than the converged one (its residual above both Newton's force
   !> tolerance and the converged residual). The set at rest: the carrying candidates and those that
   !> touch there.
   !> Errors (error_analysis, out of memory): the work arrays and the band matrix of the test.
   subroutine rest_on_contacts(model, state, before, dlambda, x, active, rested, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: before(:), dlambda
      real(dp), allocatable, intent(out) :: x(:)
      logical, allocatable, intent(out) :: active(:)
      logical, intent(out) :: rested
      type(error_t), allocatable, intent(out) :: error
      type(path_system_t) :: work
      real(dp), allocatable :: basis(:, :), unheld(:, :), nodal(:, :), internal(:), reference(:), push(:), d(:), &
                               drift(:)
      real(dp) :: element_scale, roundoff, residual_before, residual_after, scale, gap, part
      real(dp) :: gradient(2), hessian(2, 2)
      logical :: pushed
      logical, allocatable :: carrying(:)
      integer :: n, m, i, c, node, contact, status, round
      rested = .false.
      if (.not. allocated(state%floating_motion) .or. .not. allocated(state%active)) return
      if (size(state%floating_motion, 2) == 0 .or. dlambda == 0.0_dp) return
      if (.not. allocated(model%contacts) .or. .not. allocated(state%slip)) return
      if (.not. allocated(state%reactions)) return
      n = state%map%n_equations
      m = size(state%active)
      allocate (x(n), active(m), carrying(m), internal(n), reference(n), push(n), d(n), drift(n), &
                nodal(dofs_per_node, model%n_nodes), stat=status)
      call allocation_failure(status, 'the vectors of the rest on the contacts', 64.0_dp*n + 8.0_dp*m, &
                              error_analysis, error)
      if (allocated(error)) return
      call band_allocate(work%tangent, n, state%map%half_bandwidth, state%map%half_bandwidth, error)
      if (allocated(error)) return
      call gather_nodal(state%map, state%u, nodal)
      call equilibrium_at(model, state, work, state%u, state%lambda, state%active, nodal, internal, reference, &
                          element_scale, error, roundoff)
      if (allocated(error)) return
      residual_before = masked_norm(state%map, state%lambda*reference - internal)
      scale = max(state%load_norm, norm2(state%lambda*reference), element_scale)
      ! A unilateral candidate of the set holds a motion only if it carries a force: a reaction within
      ! Newton's force tolerance of the force scale is zero to the accuracy of the converged
      ! equilibrium (the residual is only known to that), and a contact that touches with no force
      ! holds nothing but its own point (the rings of issue 16 were held by reactions of 3e-17 and
      ! 2.4e-14 against a scale of 0.1). A bonded candidate holds in tension too, and a yielding one
      ! carries its limit force: both count whatever their reaction.
      do c = 1, m
         carrying(c) = state%active(c)
         if (.not. carrying(c) .or. model%contacts(c)%bilateral .or. model%contacts(c)%tangential) cycle
         if (allocated(state%yielding)) then
            if (state%yielding(c)) cycle
         end if
         carrying(c) = abs(state%reactions(c)) > model%analysis%force_tolerance*scale
      end do
      call orthonormal_motions(state%map, state%floating_motion, basis, error)
      if (allocated(error)) return
      call unheld_motions(model, state%map, carrying, basis, unheld, error)
      if (allocated(error)) return
      if (size(unheld, 2) == 0) return
      ! the push just before the step's end: λ came from the side where λR did work against the contacts
      push(:) = -sign(1.0_dp, dlambda)*reference
      x(:) = state%u
      ! the set at rest: the carrying candidates, and those that touch where the structure comes to rest
      active(:) = carrying
      ! Resting on one contact may leave a motion about it free (a tilted beam on its lower end): the
      ! push then turns it about that contact onto the next, at most once per floating motion.
      do round = 1, size(basis, 2)
         if (round > 1) then
            call unheld_motions(model, state%map, active, basis, unheld, error)
            if (allocated(error)) return
            if (size(unheld, 2) == 0) exit
         end if
         ! d = U Uᵀp, the rigid motion of the unheld span that p drives (U orthonormal in the metric)
         d(:) = 0.0_dp
         pushed = .false.
         do i = 1, size(unheld, 2)
            d(:) = d + dot_product(push, unheld(:, i))*unheld(:, i)
            if (abs(dot_product(push, unheld(:, i)))/maxval(abs(unheld(:, i))) > push_tolerance*sum(abs(push))) &
               pushed = .true.
         end do
         if (.not. pushed) exit
         if (round == 1) then
            ! the step's rigid motion along the unheld motions, Σ_i (U_iᵀ M Δx) U_i, taken out as the
            ! exact rigid motion it linearises (a linearised rotation θ stretches every element by h θ²/2)
            drift(:) = 0.0_dp
            do i = 1, size(unheld, 2)
               part = sum(state%map%metric*unheld(:, i)*(state%u - before))
               drift(:) = drift - part*state%map%metric*unheld(:, i)
            end do
            call move_rigidly(model, state%map, drift, x)
         end if
         call rest_along(model, state%map, d, state%slip, state%length_scale, state%lambda, x, contact)
         if (contact == 0) then
            if (round == 1) return
            exit
         end if
         rested = .true.
         call gather_nodal(state%map, x, nodal)
         do c = 1, m
            if (active(c) .or. .not. candidate_live(state%map, c)) cycle
            if (model%contacts(c)%tangential .or. model%contacts(c)%bilateral) cycle
            node = model%contacts(c)%node
            call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, gradient, &
                               hessian, state%lambda)
            if (model%contacts(c)%plastic) gap = gap + slip_shift(model, c, state%slip)
            active(c) = gap <= touch_fraction*state%length_scale
         end do
      end do
      if (.not. rested) return
      rested = .false.
      call gather_nodal(state%map, x, nodal)
      call equilibrium_at(model, state, work, x, state%lambda, active, nodal, internal, reference, element_scale, &
                          error, roundoff)
      if (allocated(error)) return
      residual_after = masked_norm(state%map, state%lambda*reference - internal)
      scale = max(state%load_norm, norm2(state%lambda*reference), element_scale)
      if (residual_after > max(model%analysis%force_tolerance*scale, roundoff, residual_before)) return
      rested = .true.
   end subroutine rest_on_contacts

   !> x (n_equations) moved by the exact plane rigid motion whose linearisation is d (n_equations): d
   !> a rigid motion of the reference configuration to first order, d(P) = (a − θY, b + θX) at a node
   !> P = (X, Y) and θ on its rotation, fitted by least squares over the free DOFs (exact for a
   !> combination of floating motions). The rotation θ is taken about the current position p_A of an
   !> anchor node — the first with a held translation (its support then stays where it is: d vanishes
   !> there), else the first node — which moves by d there: p' = p_A + R(θ)(p − p_A) + d(A), and each
   !> rotation DOF by θ. The equations that are not a node's (reactions, bed surfaces) are left.
   pure subroutine move_rigidly(model, map, d, x)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: d(:)
      real(dp), intent(inout) :: x(:)
      real(dp) :: normal(3, 3), right(3), row(3), rigid(3), anchor_shift(2), anchor(2), p(2), q(2), c, s, pivot
      integer :: node, i, k, anchor_node, e
      normal = 0.0_dp
      right = 0.0_dp
      do node = 1, model%n_nodes
         do i = 1, 3
            e = map%equation(i, node)
            if (e <= 0) cycle
            select case (i)
            case (1)
               row = [1.0_dp, 0.0_dp, -model%coordinates(2, node)]
            case (2)
               row = [0.0_dp, 1.0_dp, model%coordinates(1, node)]
            case default
               row = [0.0_dp, 0.0_dp, 1.0_dp]
            end select
            do k = 1, 3
               normal(:, k) = normal(:, k) + row*row(k)
            end do
            right = right + row*d(e)
         end do
      end do
      ! (a, b, θ) by Gaussian elimination of the 3 × 3 normal equations; an unknown no DOF sees (a
      ! structure whose x is held everywhere: a = 0) has a zero row and is left at zero
      do k = 1, 3
         pivot = normal(k, k)
         if (.not. abs(pivot) > 0.0_dp) cycle
         do i = k + 1, 3
            c = normal(i, k)/pivot
            normal(i, :) = normal(i, :) - c*normal(k, :)
            right(i) = right(i) - c*right(k)
         end do
      end do
      rigid = 0.0_dp
      do k = 3, 1, -1
         if (.not. abs(normal(k, k)) > 0.0_dp) cycle
         rigid(k) = (right(k) - dot_product(normal(k, k + 1:3), rigid(k + 1:3)))/normal(k, k)
      end do
      anchor_node = 1
      do node = 1, model%n_nodes
         if (map%equation(1, node) <= 0 .or. map%equation(2, node) <= 0) then
            anchor_node = node
            exit
         end if
      end do
      anchor = model%coordinates(1:2, anchor_node)
      do i = 1, 2
         if (map%equation(i, anchor_node) > 0) anchor(i) = anchor(i) + x(map%equation(i, anchor_node))
      end do
      anchor_shift = [rigid(1) - rigid(3)*model%coordinates(2, anchor_node), &
                      rigid(2) + rigid(3)*model%coordinates(1, anchor_node)]
      c = cos(rigid(3))
      s = sin(rigid(3))
      do node = 1, model%n_nodes
         p = model%coordinates(1:2, node)
         do i = 1, 2
            if (map%equation(i, node) > 0) p(i) = p(i) + x(map%equation(i, node))
         end do
         q = [c*(p(1) - anchor(1)) - s*(p(2) - anchor(2)), s*(p(1) - anchor(1)) + c*(p(2) - anchor(2))]
         q = anchor + q + anchor_shift
         do i = 1, 2
            e = map%equation(i, node)
            if (e > 0) x(e) = q(i) - model%coordinates(i, node)
         end do
         e = map%equation(3, node)
         if (e > 0) x(e) = x(e) + rigid(3)
      end do
   end subroutine move_rigidly

   !> x (n_equations) moved rigidly along the motion d (n_equations, a rigid motion: move_rigidly) by
   !> the amount s that brings the nearest unilateral candidate closing along d to a zero gap (its
   !> slip included), none being pushed through its obstacle on the other side; s of either sign (a
   !> state that the step left through a contact comes back out of it). The gaps are followed by
   !> their tangent along d from where the last pass landed (Newton's method on the gap: a rotation and
   !> a curved obstacle are met to the touch tolerance within a few passes, a translation on a
   !> fixed-direction gap in one). `contact` returns the candidate met; 0 (x partly moved, to be
   !> dropped) when none closes along d, a bonded candidate holds d, or the rest is not admissible.
   pure subroutine rest_along(model, map, d, slip, length_scale, lambda, x, contact)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: d(:), slip(:), length_scale, lambda
      real(dp), intent(inout) :: x(:)
      integer, intent(out) :: contact
      real(dp) :: u(2), v(2), gap, gradient(2), hessian(2, 2), slope, s_close, s_open, size_d
      integer :: pass, c, node, i, nearest
      contact = 0
      size_d = 0.0_dp
      do node = 1, model%n_nodes
         do i = 1, 2
            if (map%equation(i, node) > 0) size_d = max(size_d, abs(d(map%equation(i, node))))
         end do
      end do
      if (.not. size_d > 0.0_dp) return
      do pass = 1, rest_passes
         s_close = huge(1.0_dp)
         s_open = -huge(1.0_dp)
         nearest = 0
         do c = 1, size(model%contacts)
            if (.not. candidate_live(map, c) .or. model%contacts(c)%tangential) cycle
            node = model%contacts(c)%node
            u = 0.0_dp
            v = 0.0_dp
            do i = 1, 2
               if (map%equation(i, node) > 0) then
                  u(i) = x(map%equation(i, node))
                  v(i) = d(map%equation(i, node))
               end if
            end do
            call candidate_gap(model%contacts(c), model%coordinates(:, node), u, gap, gradient, hessian, lambda)
            if (model%contacts(c)%plastic) gap = gap + slip_shift(model, c, slip)
            slope = dot_product(gradient, v)
            if (model%contacts(c)%bilateral) then
               if (abs(slope) > slope_tolerance*size_d) then
                  contact = 0
                  return
               end if
               cycle
            end if
            if (slope < -slope_tolerance*size_d) then
               if (gap/(-slope) < s_close) then
                  s_close = gap/(-slope)
                  nearest = c
               end if
            else if (slope > slope_tolerance*size_d) then
               s_open = max(s_open, -gap/slope)
            end if
         end do
         if (nearest == 0 .or. s_close*size_d < s_open*size_d - touch_fraction*length_scale) then
            contact = 0
            return
         end if
         ! (no contact within the structure's reach along d: it is not resting but floating away)
         if (abs(s_close)*size_d > rest_reach*length_scale) then
            contact = 0
            return
         end if
         call move_rigidly(model, map, s_close*d, x)
         contact = nearest
         if (abs(s_close)*size_d <= touch_fraction*length_scale) return
      end do
   end subroutine rest_along

end module uniarc_path_rest


