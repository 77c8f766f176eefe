!> Equation numbering: which DOFs are unknowns, in which order, and the half-bandwidth that follows.
!>
!> Supports are applied by elimination: a held DOF gets no equation (number 0) and is skipped when element
!> matrices are scattered, so no penalty number ever enters the stiffness. Nodes are ordered to keep the
!> band narrow: the creation order (which follows a generated arc or line) or reverse Cuthill–McKee
!> (George & Liu 1981, ch. 4) from a pseudo-peripheral node, whichever gives the smaller bandwidth.
module uniarc_dof_map
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, dofs_per_node, gap_fixed_direction
   use uniarc_error, only: error_t, error_input
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: integer_to_string
   implicit none
   private
   public :: dof_map_t, build_dof_map, element_equations, node_adjacency, reverse_cuthill_mckee
   public :: ordering_bandwidth, candidate_live, bed_point, bed_deflection, candidate_held_normal

   !> The equation numbering of a model.
   type :: dof_map_t
      integer :: n_equations = 0
      integer :: half_bandwidth = 0       !< max |i − j| over coupled equations
      integer, allocatable :: equation(:, :)  !< (3, n_nodes): equation number, 0 if held
      integer, allocatable :: node_order(:)   !< nodes in elimination order
      logical :: reordered = .false.          !< true if reverse Cuthill–McKee was chosen
      integer, allocatable :: candidate_equation(:)  !< (n_contacts): equation of its reaction, 0 if none
      !> (n_contacts): a spring whose reaction is condensed into the stiffness (no equation; its
      !> reaction is −g/t in contact, docs/theory.md §3.1). A candidate with neither an equation nor this
      !> flag is inert (both translations of its node held).
      logical, allocatable :: condensed(:)
      !> (n_contacts): equation of the surface deflection of a Pasternak bed point (0 if none), numbered
      !> right after the candidate's reaction; a displacement (metric 1) whose row is the bed's
      !> equilibrium K_b d = r (docs/theory.md §3.10)
      integer, allocatable :: bed_equation(:)
      real(dp), allocatable :: metric(:)      !< (n_equations): 1 for a displacement, 0 for a reaction
   end type dof_map_t

contains

   !> Number the free DOFs of `model` node by node in the order that gives the smaller bandwidth.
   !>
   !> A rigid or stiff contact candidate adds one unknown, its reaction, numbered right after the DOFs
   !> of its node: the contact rows of the augmented (saddle-point) system then stay inside the band,
   !> and elimination without interchanges meets the node's DOFs before the reaction (see
   !> docs/theory.md §3). A spring no stiffer than the structure at its node (k_c ≤ the node's stiffness
   !> scale, `node_stiffness`) needs no unknown: in contact its reaction −g/t is a function of the
   !> displacements and its stiffness a aᵀ/t enters K directly (static condensation of the reaction
   !> row; `condensed`). That keeps the matrix at three unknowns per node — a ring of 1e5 nodes has
   !> 3e5 equations and a half-bandwidth of 8 instead of 4e5 and 10, which more than halves a band LU —
   !> while a stiff spring (k up to 1e20) keeps the augmented row, where its flexibility t sits on the
   !> diagonal instead of a penalty k in K. A candidate whose node has both translations held can never
   !> move and gets no equation (inert); so does a rigid one whose gap moves only along held DOFs
   !> (`candidate_held_normal`: a rigid plane under a roller's held UY), whose reaction row would be
   !> zero — the support carries what the contact would.
   !> A point of a Pasternak bed (`bed_point`) has a rigid contact with the bed's surface: its reaction
   !> and, right after it, the surface's deflection (`bed_equation`), even under a held node.
   !> Errors: an allocation the system refuses (uniarc_memory: allocation_failure), of category
   !> `category` — error_input (exit code 2, the model does not fit in memory) by default,
   !> error_analysis once the analysis has started; `map` is then incomplete.
   subroutine build_dof_map(model, map, error, category)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(out) :: map
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in), optional :: category
      integer, allocatable :: start(:), neighbours(:), natural(:), rcm(:), first_candidate(:), next_candidate(:)
      real(dp), allocatable :: stiffness(:)
      real(dp) :: stiffest   ! the flexibility of a candidate's stiffer elastic branch
      integer :: i, k, node, next, c, n_candidates, status, rcm_bandwidth, natural_bandwidth, refusal_category
      n_candidates = 0
      if (allocated(model%contacts)) n_candidates = size(model%contacts)
      call node_adjacency(model, start, neighbours, status)
      if (status == 0) allocate (natural(model%n_nodes), stat=status)
      if (status == 0) call reverse_cuthill_mckee(model%n_nodes, start, neighbours, rcm, status)
      if (status == 0) then
         do i = 1, model%n_nodes   ! in place: no array constructor of the nodes' length
            natural(i) = i
         end do
         call ordering_bandwidth(rcm, start, neighbours, rcm_bandwidth, status)
      end if
      if (status == 0) call ordering_bandwidth(natural, start, neighbours, natural_bandwidth, status)
      if (status == 0) then
         deallocate (start, neighbours)
         allocate (first_candidate(model%n_nodes), next_candidate(n_candidates), &
                   map%equation(dofs_per_node, model%n_nodes), map%candidate_equation(n_candidates), &
                   map%condensed(n_candidates), map%bed_equation(n_candidates), stat=status)
      end if
      if (status == 0 .and. n_candidates > 0) allocate (stiffness(model%n_nodes), stat=status)
      if (status /= 0) then
         ! The numbering's arrays: adjacency (2 per element end), orderings and lists of the nodes,
         ! the equation numbers and the candidates' lists (4 bytes each), the nodes' stiffness scales.
         refusal_category = error_input
         if (present(category)) refusal_category = category
         call allocation_failure(status, 'the DOF numbering of '//integer_to_string(model%n_nodes)//' nodes and '// &
                                 integer_to_string(n_candidates)//' contact candidates', &
                                 4.0_dp*(4.0_dp*model%n_elements + 10.0_dp*model%n_nodes + 3.0_dp*n_candidates) + &
                                 8.0_dp*model%n_nodes, refusal_category, error)
         return
      end if
      map%reordered = rcm_bandwidth < natural_bandwidth
      if (map%reordered) then
         call move_alloc(rcm, map%node_order)
      else
         call move_alloc(natural, map%node_order)
      end if
      ! Candidates of each node as linked lists, so that numbering stays O(nodes + candidates).
      first_candidate = 0
      next_candidate = 0
      do c = n_candidates, 1, -1
         next_candidate(c) = first_candidate(model%contacts(c)%node)
         first_candidate(model%contacts(c)%node) = c
      end do
      map%equation = 0
      map%candidate_equation = 0
      map%condensed = .false.
      map%bed_equation = 0
      if (n_candidates > 0) then
         call node_stiffness(model, stiffness)
         do c = 1, n_candidates
            associate (candidate => model%contacts(c))
               if (model%fixed(1, candidate%node) .and. model%fixed(2, candidate%node)) cycle
               if (candidate_held_normal(model, c)) cycle
               ! a moving obstacle keeps its row: its ∂g/∂λ is that row's reference load (theory §3.11)
               ! a spring with its own uplift stiffness (KU=) is condensed where both its branches are
               ! as soft as its node: the smaller flexibility, the stiffer branch, decides
               stiffest = candidate%flexibility
               if (candidate%uplift_flexibility > 0.0_dp) stiffest = min(stiffest, candidate%uplift_flexibility)
               map%condensed(c) = candidate%flexibility > 0.0_dp .and. candidate%gap_rate == 0.0_dp .and. &
                                  all(candidate%motion == 0.0_dp) .and. &
                                  stiffest*stiffness(candidate%node) >= 1.0_dp
            end associate
         end do
      end if
      next = 0
      do i = 1, model%n_nodes
         node = map%node_order(i)
         do k = 1, dofs_per_node
            if (model%fixed(k, node)) cycle
            next = next + 1
            map%equation(k, node) = next
         end do
         c = first_candidate(node)
         do while (c > 0)
            if (bed_point(model, c)) then
               ! a Pasternak bed point: its reaction and the bed's deflection there, even under a held
               ! node (the bed goes on deforming beside it)
               map%candidate_equation(c) = next + 1
               map%bed_equation(c) = next + 2
               next = next + 2
            else if (.not. (model%fixed(1, node) .and. model%fixed(2, node) .or. map%condensed(c) .or. &
                            candidate_held_normal(model, c))) then
               next = next + 1
               map%candidate_equation(c) = next
            end if
            c = next_candidate(c)
         end do
      end do
      map%n_equations = next
      allocate (map%metric(next), stat=status)
      if (status /= 0) then
         refusal_category = error_input
         if (present(category)) refusal_category = category
         call allocation_failure(status, 'the metric of the DOF numbering ('//integer_to_string(next)//' equations)', &
                                 8.0_dp*next, refusal_category, error)
         return
      end if
      map%metric = 0.0_dp
      do i = 1, model%n_nodes
         do k = 1, dofs_per_node
            if (map%equation(k, i) > 0) map%metric(map%equation(k, i)) = 1.0_dp
         end do
      end do
      do c = 1, n_candidates
         if (map%bed_equation(c) > 0) map%metric(map%bed_equation(c)) = 1.0_dp
      end do
      map%half_bandwidth = 0
      do i = 1, model%n_elements
         map%half_bandwidth = max(map%half_bandwidth, spread_of(element_equations(model, map, i)))
      end do
      do c = 1, n_candidates
         if (map%candidate_equation(c) == 0) cycle
         node = model%contacts(c)%node
         map%half_bandwidth = max(map%half_bandwidth, &
                                  spread_of([map%equation(:, node), map%candidate_equation(c), map%bed_equation(c)]))
         ! the shear layer couples a bed point to its neighbours
         associate (candidate => model%contacts(c))
            if (candidate%bed_previous > 0) map%half_bandwidth = max(map%half_bandwidth, &
               spread_of([map%bed_equation(c), map%bed_equation(candidate%bed_previous)]))
            if (candidate%bed_next > 0) map%half_bandwidth = max(map%half_bandwidth, &
               spread_of([map%bed_equation(c), map%bed_equation(candidate%bed_next)]))
         end associate
      end do
   end subroutine build_dof_map

   !> True if candidate c is rigid (no flexibility, not a Pasternak bed point) with a fixed-direction
   !> gap g = g0 + n·u whose normal n has no component on a free translation of its node (at most 1e-12:
   !> the round-off of an angle's cosine, 6e-17 at 90°): the gap never changes, the reaction's row of the
   !> augmented system (docs/theory.md §3.2) would be zero and the matrix singular. Such a candidate
   !> can never move: it gets no equation and takes no part in the contact (the support along n holds
   !> the node; uniarc_run_checks warns of it). A rigid plane under a roller's held UY, for example.
   pure logical function candidate_held_normal(model, c)
      type(model_t), intent(in) :: model
      integer, intent(in) :: c
      integer :: k
      candidate_held_normal = .false.
      associate (candidate => model%contacts(c))
         if (candidate%gap_kind /= gap_fixed_direction .or. candidate%flexibility /= 0.0_dp .or. &
             candidate%bed_stiffness(2) > 0.0_dp .or. candidate%tangential) return
         do k = 1, 2
            if (.not. model%fixed(k, candidate%node) .and. abs(candidate%direction(k)) > 1.0e-12_dp) return
         end do
      end associate
      candidate_held_normal = .true.
   end function candidate_held_normal

   !> True if candidate c is a point of a Pasternak bed (its deflection is an unknown).
   pure logical function bed_point(model, c)
      type(model_t), intent(in) :: model
      integer, intent(in) :: c
      bed_point = model%contacts(c)%bed_stiffness(2) > 0.0_dp
   end function bed_point

   !> True if candidate c takes part in the analysis: it has a reaction equation or is condensed.
   pure logical function candidate_live(map, c)
      type(dof_map_t), intent(in) :: map
      integer, intent(in) :: c
      candidate_live = map%candidate_equation(c) > 0 .or. map%condensed(c)
   end function candidate_live

   !> The surface deflection d of candidate c's Pasternak bed in unknowns x (0 for other candidates):
   !> the gap with the surface is g(u) + d (docs/theory.md §3.10).
   pure real(dp) function bed_deflection(map, c, x)
      type(dof_map_t), intent(in) :: map
      integer, intent(in) :: c
      real(dp), intent(in) :: x(:)
      bed_deflection = 0.0_dp
      if (map%bed_equation(c) > 0) bed_deflection = x(map%bed_equation(c))
   end function bed_deflection

   !> Stiffness scale of each node (n_nodes): Σ over its elements of EA/L + 12 EI/L³, the size of the
   !> translational diagonal of the elastic stiffness there (Przemieniecki 1968, §5.2). A spring up to
   !> this stiffness changes the conditioning of K by a factor of two at most.
   pure subroutine node_stiffness(model, stiffness)
      type(model_t), intent(in) :: model
      real(dp), intent(out) :: stiffness(model%n_nodes)
      real(dp) :: d(2), length
      integer :: e, s
      stiffness = 0.0_dp
      do e = 1, model%n_elements
         s = model%element_section(e)
         if (s < 1) cycle
         d = model%coordinates(:, model%connectivity(2, e)) - model%coordinates(:, model%connectivity(1, e))
         length = norm2(d)
         if (.not. (length > 0.0_dp)) cycle
         stiffness(model%connectivity(:, e)) = stiffness(model%connectivity(:, e)) + &
                                               model%sections(s)%ea/length + 12.0_dp*model%sections(s)%ei/length**3
      end do
   end subroutine node_stiffness

   !> Steering vector of element `e`: the 6 equation numbers of its two nodes (0 where held).
   pure function element_equations(model, map, e) result(equations)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      integer, intent(in) :: e
      integer :: equations(2*dofs_per_node)
      equations(1:3) = map%equation(:, model%connectivity(1, e))
      equations(4:6) = map%equation(:, model%connectivity(2, e))
   end function element_equations

   !> Node adjacency through elements in compressed form: neighbours(start(i):start(i+1)-1) of node i.
   !> status: that of the allocations (nonzero: refused, the arrays incomplete).
   pure subroutine node_adjacency(model, start, neighbours, status)
      type(model_t), intent(in) :: model
      integer, allocatable, intent(out) :: start(:), neighbours(:)
      integer, intent(out) :: status
      integer, allocatable :: degree(:), fill(:)
      integer :: e, a, b
      allocate (degree(model%n_nodes), fill(model%n_nodes), start(model%n_nodes + 1), stat=status)
      if (status /= 0) return
      degree = 0
      do e = 1, model%n_elements
         a = model%connectivity(1, e)
         b = model%connectivity(2, e)
         degree(a) = degree(a) + 1
         degree(b) = degree(b) + 1
      end do
      start(1) = 1
      do a = 1, model%n_nodes
         start(a + 1) = start(a) + degree(a)
      end do
      allocate (neighbours(start(model%n_nodes + 1) - 1), stat=status)
      if (status /= 0) return
      fill = start(1:model%n_nodes)
      do e = 1, model%n_elements
         a = model%connectivity(1, e)
         b = model%connectivity(2, e)
         neighbours(fill(a)) = b
         fill(a) = fill(a) + 1
         neighbours(fill(b)) = a
         fill(b) = fill(b) + 1
      end do
   end subroutine node_adjacency

   !> Largest distance in `order` between two adjacent nodes (the node half-bandwidth of the ordering).
   !> status: that of the allocation of the nodes' positions (nonzero: refused, bandwidth 0).
   pure subroutine ordering_bandwidth(order, start, neighbours, bandwidth, status)
      integer, intent(in) :: order(:), start(:), neighbours(:)
      integer, intent(out) :: bandwidth, status
      integer, allocatable :: position(:)
      integer :: i, k
      bandwidth = 0
      allocate (position(size(order)), stat=status)
      if (status /= 0) return
      do i = 1, size(order)
         position(order(i)) = i
      end do
      do i = 1, size(order)
         do k = start(i), start(i + 1) - 1
            bandwidth = max(bandwidth, abs(position(i) - position(neighbours(k))))
         end do
      end do
   end subroutine ordering_bandwidth

   !> Reverse Cuthill–McKee ordering of each connected component, started from a pseudo-peripheral
   !> node found by repeated breadth-first level structures (George & Liu 1981, §4.3–4.4).
   !> status: that of the allocations (nonzero: refused, `order` incomplete).
   pure subroutine reverse_cuthill_mckee(n, start, neighbours, order, status)
      integer, intent(in) :: n, start(:), neighbours(:)
      integer, allocatable, intent(out) :: order(:)
      integer, intent(out) :: status
      logical, allocatable :: placed(:)
      integer, allocatable :: queue(:), level(:)   ! the work arrays of level_depth
      integer :: seed, filled, head, node, k, candidate, depth, new_depth, i
      allocate (order(n), placed(n), queue(n), level(n), stat=status)
      if (status /= 0) return
      placed = .false.
      filled = 0
      do seed = 1, n
         if (placed(seed)) cycle
         ! Pseudo-peripheral start: move to a node of least degree in the last level while depth grows.
         node = seed
         call level_depth(node, depth, candidate, queue, level)
         do
            call level_depth(candidate, new_depth, k, queue, level)
            if (new_depth <= depth) exit
            node = candidate
            depth = new_depth
            candidate = k
         end do
         ! Cuthill–McKee: breadth first, neighbours in increasing degree.
         head = filled + 1
         filled = filled + 1
         order(filled) = node
         placed(node) = .true.
         do while (head <= filled)
            node = order(head)
            head = head + 1
            do
               candidate = 0
               do k = start(node), start(node + 1) - 1
                  i = neighbours(k)
                  if (placed(i)) cycle
                  if (candidate == 0) then
                     candidate = i
                  else if (degree_of(i) < degree_of(candidate)) then
                     candidate = i
                  end if
               end do
               if (candidate == 0) exit
               filled = filled + 1
               order(filled) = candidate
               placed(candidate) = .true.
            end do
         end do
      end do
      do i = 1, n/2
         k = order(i)
         order(i) = order(n + 1 - i)
         order(n + 1 - i) = k
      end do

   contains

      pure integer function degree_of(i)
         integer, intent(in) :: i
         degree_of = start(i + 1) - start(i)
      end function degree_of

      !> Depth of the level structure rooted at `root` within its component (unplaced nodes only),
      !> and a node of least degree in its last level.
      !> queue, level (n): work arrays.
      pure subroutine level_depth(root, depth_out, last_node, queue, level)
         integer, intent(in) :: root
         integer, intent(out) :: depth_out, last_node
         integer, intent(inout) :: queue(:), level(:)
         integer :: qhead, qtail, v, kk, w
         level = -1
         level(root) = 0
         queue(1) = root
         qhead = 1
         qtail = 1
         do while (qhead <= qtail)
            v = queue(qhead)
            qhead = qhead + 1
            do kk = start(v), start(v + 1) - 1
               w = neighbours(kk)
               if (placed(w) .or. level(w) >= 0) cycle
               level(w) = level(v) + 1
               qtail = qtail + 1
               queue(qtail) = w
            end do
         end do
         depth_out = level(queue(qtail))
         last_node = queue(qtail)
         do kk = 1, qtail
            v = queue(kk)
            if (level(v) == depth_out .and. degree_of(v) < degree_of(last_node)) last_node = v
         end do
      end subroutine level_depth

   end subroutine reverse_cuthill_mckee

   pure integer function spread_of(equations)
      integer, intent(in) :: equations(:)
      spread_of = 0
      if (count(equations > 0) < 2) return
      spread_of = maxval(equations, mask=equations > 0) - minval(equations, mask=equations > 0)
   end function spread_of

end module uniarc_dof_map
