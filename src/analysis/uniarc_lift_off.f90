!> Lift-off: a load that no contact can hold (docs/theory.md §3.12).
!>
!> A structure that rests only on tensionless media (beds, springs, obstacles) has rigid motions that
!> its supports leave free and only the contacts hold (uniarc_path_mechanism, floating_motions). Along
!> each such motion v_j the structure stores no energy, so equilibrium asks the contact reactions
!> r ≥ 0 alone to balance the load's work there:
!>
!>     Σ_c r_c (a_c·v_j) + b_j = 0  for every j,    r ≥ 0,                                   (1)
!>
!> a_c the gradient of candidate c's gap (a reaction pushes along it), b_j = v_jᵀ(λR − F) the work of
!> the unbalanced load along v_j. (1) has no solution exactly when (Farkas' lemma) some combination
!> v = Σ_j c_j v_j opens or keeps every gap (a_c·v ≥ 0) while the load does positive work on it
!> (bᵀc > 0): the load lifts the structure off every contact that could hold it, and the contact LCP
!> of the step is infeasible (for its copositive-plus M, Lemke's method then ends in a secondary ray,
!> Cottle, Pang & Stone 1992, §4.4, Theorem 4.4.13). `lifting_motion` decides (1) by non-negative least
!> squares, min ‖B r + b‖ over r ≥ 0 (B(j, c) = a_c·v_j; Lawson & Hanson 1974, Ch. 23): its residual
!> c = B r* + b is 0 when (1) holds, and is otherwise the lifting combination itself (Bᵀc ≥ 0 by the
!> optimality conditions, bᵀc = ‖c‖² > 0 by complementarity).
module uniarc_lift_off
   use uniarc_kinds, only: dp
   use uniarc_strings, only: integer_to_string
   use uniarc_model, only: model_t
   use uniarc_dof_map, only: dof_map_t, candidate_live
   use uniarc_contact_law, only: candidate_gap
   implicit none
   private
   public :: lifting_motion, describe_lift_off

   !> (1) is taken as violated when the least residual exceeds this share of ‖b‖ + ‖B‖‖r*‖: a
   !> balance that holds leaves the round-off of sums of products (a few ε per term), a lift-off an
   !> O(1) share (the whole load when no contact sees the motion); 1e-6 separates the two by
   !> orders of magnitude either side.
   real(dp), parameter :: balance_tolerance = 1.0e-6_dp

contains

   !> Whether the reactions of the contacts can balance the load along the free motions (module
   !> header, (1)).
   !>
   !> In: gap_rates (k, m), B(j, c) = a_c·v_j, the rate of candidate c's gap along free motion j
   !> (length per unit of the motion's coordinate); work (k), b_j, the unbalanced load's work along
   !> motion j (force times length per unit of the coordinate). k ≥ 0, m ≥ 0.
   !> Out: lifts, .true. when no r ≥ 0 balances the load; combination (k), c = B r* + b, the motion
   !> (in the coordinates of the v_j) along which every gap opens and the load does work (0 when
   !> `lifts` is false); status, 0, or the stat= of a work array (of length m, or the passive set's
   !> square) the system refused — then lifts is false and nothing is decided (the caller keeps its
   !> own message; docs/contracts.md, "Memory"). The least-squares problem always has a solution.
   !> Source: Lawson & Hanson (1974), Solving Least Squares Problems, Ch. 23 (algorithm NNLS).
   pure subroutine lifting_motion(gap_rates, work, lifts, combination, status)
      real(dp), intent(in) :: gap_rates(:, :), work(:)
      logical, intent(out) :: lifts
      real(dp), intent(out) :: combination(:)
      integer, intent(out) :: status
      real(dp), allocatable :: r(:), z(:), gradient(:)
      logical, allocatable :: passive(:)
      real(dp) :: size_b, size_e, alpha, tolerance
      integer :: k, m, iteration, inner, t, c
      k = size(gap_rates, 1)
      m = size(gap_rates, 2)
      lifts = .false.
      combination = 0.0_dp
      status = 0
      size_b = norm2(work)
      if (k == 0 .or. size_b == 0.0_dp) return
      allocate (r(m), z(m), gradient(m), passive(m), stat=status)
      if (status /= 0) return
      r = 0.0_dp
      z = 0.0_dp
      passive = .false.
      size_e = 0.0_dp
      do c = 1, m
         size_e = max(size_e, norm2(gap_rates(:, c)))
      end do
      ! Lawson & Hanson: grow the passive set P (r_P > 0) by the column of the steepest descent of
      ! ½‖B r + b‖², solve the least squares on P, step back to the boundary where a component of
      ! the solution would turn negative.
      tolerance = 1.0e3_dp*epsilon(1.0_dp)*size_e*size_b
      do iteration = 1, 3*m + 3
         combination = matmul(gap_rates, r) + work
         do c = 1, m
            gradient(c) = -dot_product(gap_rates(:, c), combination)
         end do
         if (.not. any(.not. passive .and. gradient > tolerance)) exit
         t = maxloc(gradient, 1, mask=.not. passive)
         passive(t) = .true.
         do inner = 1, 3*m + 3
            call least_squares(gap_rates, -work, passive, z, status)
            if (status /= 0) then
               combination = 0.0_dp
               return
            end if
            if (all(z > 0.0_dp .or. .not. passive)) exit
            ! the step to the first component reaching 0 (a dependent column, z = 0 at r = 0: none)
            alpha = 1.0_dp
            do c = 1, m
               if (passive(c) .and. z(c) <= 0.0_dp) alpha = min(alpha, r(c)/max(r(c) - z(c), tiny(1.0_dp)))
            end do
            r = r + alpha*(z - r)
            where (passive .and. r <= tiny(1.0_dp)) passive = .false.
            where (.not. passive) r = 0.0_dp
         end do
         r = merge(z, 0.0_dp, passive)
      end do
      combination = matmul(gap_rates, r) + work
      lifts = norm2(combination) > balance_tolerance*(size_b + size_e*norm2(r))
      if (.not. lifts) combination = 0.0_dp
   end subroutine lifting_motion

   !> z_P = argmin ‖E_P z − f‖ over the columns of `passive` (z = 0 elsewhere), by modified
   !> Gram–Schmidt (E has few rows: a column that adds no direction to the ones before it gets 0).
   !> status: 0, or the stat= of the work arrays the system refused (z is then 0).
   pure subroutine least_squares(e, f, passive, z, status)
      real(dp), intent(in) :: e(:, :), f(:)
      logical, intent(in) :: passive(:)
      real(dp), intent(out) :: z(:)
      integer, intent(out) :: status
      real(dp), allocatable :: q(:, :), upper(:, :), rhs(:)
      integer, allocatable :: columns(:), kept(:)
      real(dp) :: v(size(e, 1)), length
      integer :: i, j, p, n_kept
      z = 0.0_dp
      p = count(passive)
      allocate (columns(p), q(size(e, 1), p), upper(p, p), rhs(p), kept(p), stat=status)
      if (status /= 0) return
      i = 0
      do j = 1, size(passive)
         if (.not. passive(j)) cycle
         i = i + 1
         columns(i) = j
      end do
      upper = 0.0_dp
      n_kept = 0
      do i = 1, p
         v = e(:, columns(i))
         do j = 1, n_kept
            upper(j, n_kept + 1) = dot_product(q(:, j), v)
            v = v - upper(j, n_kept + 1)*q(:, j)
         end do
         length = norm2(v)
         if (length <= 1.0e-10_dp*max(norm2(e(:, columns(i))), tiny(1.0_dp))) cycle
         n_kept = n_kept + 1
         kept(n_kept) = columns(i)
         upper(n_kept, n_kept) = length
         q(:, n_kept) = v/length
      end do
      do j = 1, n_kept
         rhs(j) = dot_product(q(:, j), f)
      end do
      do i = n_kept, 1, -1
         rhs(i) = (rhs(i) - dot_product(upper(i, i + 1:n_kept), rhs(i + 1:n_kept)))/upper(i, i)
      end do
      z(kept(1:n_kept)) = rhs(1:n_kept)
   end subroutine least_squares

   !> The lift-off test (1) of the module header for a model: `message` says in the user's terms
   !> that the load lifts the structure off every contact that could hold it, and along which
   !> motion; unallocated when the contacts can balance the load (or no motion is free).
   !>
   !> In: motions (n, k), the rigid motions that only the unilateral contacts hold (n =
   !> map%n_equations; floating_motions); nodal (dofs_per_node, n_nodes), the displacements at
   !> which the gaps' gradients are taken; unbalanced (n), λR − F with every unilateral candidate
   !> open (the load the contacts would have to carry).
   !> Its arrays (of the candidates' and the equations' length) are allocated with stat=: one the
   !> system refuses leaves `message` unallocated (the caller's own message stands; docs/contracts.md,
   !> "Memory").
   subroutine describe_lift_off(model, map, motions, nodal, unbalanced, message)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: motions(:, :), nodal(:, :), unbalanced(:)
      character(len=:), allocatable, intent(out) :: message
      real(dp), allocatable :: rates(:, :), motion(:)
      real(dp) :: gap, gradient(2), hessian(2, 2)
      real(dp), allocatable :: c_motion(:)
      real(dp) :: work(size(motions, 2))
      logical :: lifts, opening
      real(dp) :: travel
      logical, allocatable :: unilateral(:)
      integer, allocatable :: which(:)
      integer :: c, j, i, node, d, largest, label, k, m, status
      character(len=2), parameter :: names(3) = ['UX', 'UY', 'RZ']
      k = size(motions, 2)
      if (k == 0 .or. .not. allocated(model%contacts)) return
      m = size(map%candidate_equation)
      allocate (unilateral(m), stat=status)
      if (status /= 0) return
      do c = 1, m
         unilateral(c) = candidate_live(map, c) .and. .not. model%contacts(c)%bilateral
      end do
      allocate (which(count(unilateral)), stat=status)
      if (status /= 0) return
      i = 0
      do c = 1, m
         if (.not. unilateral(c)) cycle
         i = i + 1
         which(i) = c
      end do
      allocate (rates(k, size(which)), c_motion(k), motion(size(motions, 1)), stat=status)
      if (status /= 0) return
      do i = 1, size(which)
         c = which(i)
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, gradient, hessian)
         do j = 1, k
            rates(j, i) = 0.0_dp
            do d = 1, 2
               if (map%equation(d, node) > 0) rates(j, i) = rates(j, i) + gradient(d)*motions(map%equation(d, node), j)
            end do
         end do
      end do
      ! b_j = v_jᵀ(λR − F), column by column (no transposed copy of the motions)
      do j = 1, k
         work(j) = dot_product(motions(:, j), unbalanced)
      end do
      call lifting_motion(rates, work, lifts, c_motion, status)
      if (status /= 0 .or. .not. lifts) return
      motion(:) = matmul(motions, c_motion)
      largest = maxloc(abs(map%metric*motion), 1)
      ! Along the motion no gap closes. Where some open it lifts the structure off; where none opens
      ! (to 1e-6 of the motion's largest translation at a candidate: round-off of the rates) it slides
      ! along every contact — a ring spun in a circular cavity — which frictionless contacts cannot resist.
      opening = .false.
      travel = 0.0_dp
      do i = 1, size(which)
         node = model%contacts(which(i))%node
         do d = 1, 2
            if (map%equation(d, node) > 0) travel = max(travel, abs(motion(map%equation(d, node))))
         end do
      end do
      do i = 1, size(which)
         if (dot_product(rates(:, i), c_motion) > 1.0e-6_dp*travel) opening = .true.
      end do
      label = 0
      d = 0
      do node = 1, size(map%equation, 2)
         d = findloc(map%equation(:, node), largest, 1)
         if (d > 0) then
            label = node
            if (allocated(model%node_label)) label = model%node_label(node)
            exit
         end if
      end do
      if (opening) then
         message = 'no equilibrium exists: the load lifts the structure off every contact that could hold it '// &
                   '(the supports leave it free to move as a rigid body, largest at node '//integer_to_string(label)// &
                   ', '//trim(names(max(d, 1)))//', and along that motion no gap closes while the load does work '// &
                   'on it: the contact problem has no solution); hold the structure with supports (*BOUNDARY) or '// &
                   'reverse the load'
      else
         message = 'no equilibrium exists: the load drives the structure along a rigid motion that slides along '// &
                   'every contact it touches (largest at node '//integer_to_string(label)//', '// &
                   trim(names(max(d, 1)))//'; no gap opens or closes along it, and frictionless contacts take no '// &
                   'force along their surface: the contact problem has no solution); hold the structure with '// &
                   'supports (*BOUNDARY) against that motion, or give the load no component along it'
      end if
   end subroutine describe_lift_off

end module uniarc_lift_off
