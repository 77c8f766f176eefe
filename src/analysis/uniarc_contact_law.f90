!> The contact laws: how a unilateral medium's gap follows from the displacements, and how a
!> foundation's description becomes per-node contact candidates.
!>
!> The one place for (docs/input.md, "Foundations and obstacles"; docs/theory.md §3):
!> - the gap g of every obstacle shape and its derivatives ∂g/∂u, ∂²g/∂u² (`candidate_gap`), which the
!>   analysis uses at every iteration and the deck reader at u = 0 to find nodes that start inside an
!>   obstacle (`obstacle_candidate`, `initial_gap`);
!> - the Winkler foundation law (Winkler 1867, Kerr 1964): the modulus K lumped onto the nodes by the
!>   trapezoidal rule for ∫ K w δw ds, a diagonal foundation matrix C_b in the paper's Eq. (7)
!>   (Silveira, Nogueira & Gonçalves 2013), i.e. a spring k = K × (tributary length) per node whose
!>   flexibility 1/k is the candidate's T_cc (`winkler_flexibility`, `foundation_candidates`);
!> - the geometry of a foundation's element set on which that rests: the nodes in chain order, their
!>   tributary lengths and nodal normals, the side that is concave, the arc length along the nodes.
!>
!> Everything is pure, works on the initial geometry passed in, and reports problems as status codes
!> that the caller (the model builder, the deck) turns into messages.
module uniarc_contact_law
   use uniarc_kinds, only: dp
   use uniarc_model, only: contact_candidate_t, foundation_t, foundation_pasternak, gap_fixed_direction, &
                           gap_circle_inside, &
                           gap_circle_outside, side_left, side_right, side_inner, side_outer, side_direction, &
                           gap_ellipse_inside, gap_ellipse_outside, gap_polyline, tangential_contact
   use uniarc_obstacle_shapes, only: ellipse_gap, polyline_gap
   implicit none
   private
   public :: candidate_gap, initial_gap, obstacle_candidate
   public :: winkler_flexibility, spring_flexibility, foundation_candidates
   public :: chain_nodes, tributary_lengths, nodal_left_normals, total_turning, path_coordinates
   public :: normals_valid, normals_branch, normals_opposed, normals_folded, foundation_straight
   public :: foundation_not_open_chain, foundation_no_memory, pasternak_bed, open_chain
   public :: foundation_problem

   !> Outcomes of `nodal_left_normals` and `foundation_candidates`.
   integer, parameter :: normals_valid = 0        !< every node has a normal
   integer, parameter :: normals_branch = 1       !< a node joins more than two elements of the set
   integer, parameter :: normals_opposed = 2      !< two elements of the set both start, or both end, at a node
   integer, parameter :: normals_folded = 3       !< two elements fold back on each other: no mean normal
   integer, parameter :: foundation_straight = 4  !< SIDE inner/outer on a straight set: no concave side
   !> a Pasternak bed (G_p > 0) on a set that is not one open chain of elements (a ring, branches, gaps)
   integer, parameter :: foundation_not_open_chain = 5
   !> a work array or the candidates refused by the system (`foundation_candidates`' `bytes` its size;
   !> the caller's error: out of memory, uniarc_memory)
   integer, parameter :: foundation_no_memory = 6

   !> Length of the mean of two unit normals under which they are taken as opposite (a fold of the set).
   real(dp), parameter :: fold_tolerance = 1.0e-9_dp

   !> Total turning (sum of cross products of unit tangents) under which a set counts as straight, so
   !> that it has no concave side.
   real(dp), parameter :: straight_tolerance = 1.0e-9_dp

contains

   ! ================================================================================================
   ! Gaps
   ! ================================================================================================

   !> Gap g, its gradient a = ∂g/∂u (2) and Hessian h = ∂²g/∂u² (2×2) of a candidate whose node has
   !> initial position x0 and displacement u (translations), lengths in the model's unit.
   !>
   !> Fixed direction: g = g0 + n·u (a = n, h = 0). Circle of centre c and radius R, with d = x0 + u − c
   !> and e = d/|d|: inside a cavity g = R − |d| (a = −e, h = −(I − e eᵀ)/|d|), outside a cylinder
   !> g = |d| − R (a = e, h = (I − e eᵀ)/|d|). Ellipse (inside or outside) and polyline: the signed
   !> distance to the surface and its derivatives (uniarc_obstacle_shapes: ellipse_gap, polyline_gap).
   !>
   !> A moving curved obstacle (contact_candidate_t%motion = d ≠ 0, *MOVE; docs/theory.md §3.11) at load
   !> factor `lambda` stands translated by λ d: its gap is the shape's at the shifted point x0 + u − λ d,
   !> exactly, with a and h there. `rate` (optional): ∂g/∂λ at the state, gap_rate − a·d (a plane's
   !> constant gap_rate, which the callers add as λ gap_rate; a curved obstacle's −a·d). Without
   !> `lambda` the curved obstacle stands where the step began (λ = 0).
   pure subroutine candidate_gap(candidate, x0, u, gap, gradient, hessian, lambda, rate)
      type(contact_candidate_t), intent(in) :: candidate
      real(dp), intent(in) :: x0(2), u(2)
      real(dp), intent(out) :: gap, gradient(2), hessian(2, 2)
      real(dp), intent(in), optional :: lambda
      real(dp), intent(out), optional :: rate
      real(dp) :: x(2)
      x = x0 + u
      if (present(lambda) .and. any(candidate%motion /= 0.0_dp)) x = x - lambda*candidate%motion
      call shape_gap(candidate, x, u, gap, gradient, hessian)
      if (present(rate)) rate = candidate%gap_rate - dot_product(gradient, candidate%motion)
   end subroutine candidate_gap

   !> candidate_gap's shapes at the point x (2) = x0 + u, shifted for a moving curved obstacle (a plane's
   !> gap g0 + n·u is of u itself).
   pure subroutine shape_gap(candidate, x, u, gap, gradient, hessian)
      type(contact_candidate_t), intent(in) :: candidate
      real(dp), intent(in) :: x(2), u(2)
      real(dp), intent(out) :: gap, gradient(2), hessian(2, 2)
      real(dp) :: d(2), distance, n(2), projector(2, 2)
      hessian = 0.0_dp
      select case (candidate%gap_kind)
      case (gap_circle_inside, gap_circle_outside)
         d = x - candidate%centre
         ! At the centre itself the normal is undefined (n = 0 there) and the curvature term 1/distance
         ! of the Hessian would overflow with any reaction: floored at ε R, a node a radius deep in the
         ! obstacle, where no equilibrium is sought and the step fails as any other instead.
         distance = max(norm2(d), epsilon(1.0_dp)*candidate%radius, tiny(1.0_dp))
         n = d/distance
         projector = reshape([1.0_dp - n(1)**2, -n(1)*n(2), -n(1)*n(2), 1.0_dp - n(2)**2], [2, 2])
         if (candidate%gap_kind == gap_circle_inside) then
            gap = candidate%radius - distance
            gradient = -n
            hessian = -projector/distance
         else
            gap = distance - candidate%radius
            gradient = n
            hessian = projector/distance
         end if
      case (gap_ellipse_inside, gap_ellipse_outside)
         call ellipse_gap(candidate%centre, candidate%axis, candidate%semi_axes, x, &
                          candidate%gap_kind == gap_ellipse_inside, gap, gradient, hessian)
      case (gap_polyline)
         call polyline_gap(candidate%vertices, x, gap, gradient, hessian)
      case default
         gap = candidate%offset + dot_product(candidate%direction, u)
         gradient = candidate%direction
      end select
   end subroutine shape_gap

   !> The gap of a candidate in the initial geometry (u = 0): negative when its node starts inside the
   !> obstacle.
   pure real(dp) function initial_gap(candidate, x0) result(gap)
      type(contact_candidate_t), intent(in) :: candidate
      real(dp), intent(in) :: x0(2)             !< initial position of the candidate's node
      real(dp) :: gradient(2), hessian(2, 2)
      call candidate_gap(candidate, x0, [0.0_dp, 0.0_dp], gap, gradient, hessian)
   end function initial_gap

   !> The candidate of a node at initial position `x0` facing an obstacle of kind `gap_kind`.
   !>
   !> gap_fixed_direction: the line through `point` whose unit normal `normal` points to the free side;
   !> the candidate's offset is the initial gap n·(x0 − p). gap_circle_inside, gap_circle_outside: the
   !> circle of centre `point` and radius `radius` (> 0). gap_ellipse_inside, gap_ellipse_outside: the
   !> ellipse of centre `point`, semi-axes `semi_axes` (a along the unit direction `normal`, b across).
   !> gap_polyline: the polyline through `vertices` (2, n ≥ 2), free side on its left. Flexibility 0
   !> (rigid), group and coordinate are left to the caller.
   pure function obstacle_candidate(gap_kind, point, normal, radius, node, x0, semi_axes, vertices) &
      result(candidate)
      integer, intent(in) :: gap_kind
      real(dp), intent(in) :: point(2)          !< a point of the plane, or the circle's centre
      real(dp), intent(in) :: normal(2)         !< plane: unit normal toward the free side (else unused)
      real(dp), intent(in) :: radius            !< circle: radius (else unused)
      integer, intent(in) :: node               !< the node (internal index)
      real(dp), intent(in) :: x0(2)             !< its initial position
      real(dp), intent(in), optional :: semi_axes(2)    !< ellipse: a, b (> 0)
      real(dp), intent(in), optional :: vertices(:, :)  !< polyline: (2, n ≥ 2)
      type(contact_candidate_t) :: candidate
      candidate%node = node
      candidate%gap_kind = gap_kind
      select case (gap_kind)
      case (gap_fixed_direction)
         candidate%direction = normal
         candidate%offset = dot_product(normal, x0 - point)
      case (gap_ellipse_inside, gap_ellipse_outside)
         candidate%centre = point
         candidate%axis = normal
         if (present(semi_axes)) candidate%semi_axes = semi_axes
      case (gap_polyline)
         if (present(vertices)) candidate%vertices = vertices
      case default
         candidate%centre = point
         candidate%radius = radius
      end select
   end function obstacle_candidate

   ! ================================================================================================
   ! Foundation laws
   ! ================================================================================================

   !> Flexibility 1/k of a discrete spring of stiffness k > 0 (force per length).
   pure real(dp) function spring_flexibility(stiffness) result(flexibility)
      real(dp), intent(in) :: stiffness
      flexibility = 1.0_dp/stiffness
   end function spring_flexibility

   !> Winkler lumping: the flexibility 1/k of the node spring k = K × L of a bed of modulus K > 0 (force
   !> per unit length per unit deflection) over the tributary length L > 0 the node carries.
   pure real(dp) function winkler_flexibility(modulus, length) result(flexibility)
      real(dp), intent(in) :: modulus, length
      flexibility = 1.0_dp/(modulus*length)
   end function winkler_flexibility

   !> The contact candidates of a foundation: one per node of its element set, in chain order
   !> (`chain_nodes`), with gap g = g0 + n·u, the Winkler flexibility of the node's tributary length,
   !> and the coordinate scale × (arc length along the nodes). A foundation of modulus 0 has none.
   !> With a tangential modulus K_t > 0 the nodes get a second candidate each, after the radial ones in
   !> the same order: a tangential spring K_t × (tributary length) along t = n turned by +90°, bonded
   !> (tangential_bonded) or with `partner` = the index of its radial candidate in `candidates`
   !> (tangential_contact).
   !>
   !> n is the foundation's direction (side_direction) or ± the nodal left normal: −(left normal) for a
   !> bed on the left, + on the right; for side_inner/side_outer the concave side is the left one when
   !> the set's total turning is positive (counter-clockwise). `status` is normals_valid, or says why not:
   !> a normal of node `nodes(bad)` undefined (normals_branch, normals_opposed, normals_folded; `bad`
   !> indexes the chain's nodes, see `chain_nodes`), or foundation_straight; foundation_no_memory with
   !> `bytes` (optional) the size of the array refused. The group is left to the caller.
   pure subroutine foundation_candidates(foundation, coordinates, connectivity, candidates, status, bad_node, bytes)
      type(foundation_t), intent(in) :: foundation
      real(dp), intent(in) :: coordinates(:, :)          !< (2, n_nodes) initial positions
      integer, intent(in) :: connectivity(:, :)          !< (2, n_elements) internal node indices
      type(contact_candidate_t), allocatable, intent(out) :: candidates(:)
      integer, intent(out) :: status
      integer, intent(out) :: bad_node                   !< the node (internal index) of a normal problem, else 0
      real(dp), intent(out), optional :: bytes           !< with foundation_no_memory: the size refused
      integer, allocatable :: nodes(:)
      real(dp), allocatable :: lengths(:), normals(:, :), s(:), arc(:)
      real(dp) :: turning, sign, size_asked
      integer :: i, bad, n, refused
      logical :: is_open

      allocate (candidates(0))
      status = normals_valid
      bad_node = 0
      if (present(bytes)) bytes = 0.0_dp
      ! Every array allocated with stat= (work of the model's length; docs/contracts.md, "Memory").
      size_asked = 16.0_dp*size(coordinates, 2)
      call chain_nodes(size(coordinates, 2), connectivity, foundation%elements, nodes, refused)
      if (refused == 0) then
         size_asked = 8.0_dp*size(coordinates, 2)
         call tributary_lengths(coordinates, connectivity, foundation%elements, nodes, lengths, refused)
      end if
      if (refused == 0) then
         size_asked = 32.0_dp*size(nodes)
         allocate (normals(2, size(nodes)), s(size(nodes)), arc(size(nodes)), stat=refused)
      end if
      if (refused /= 0) then
         call no_memory(size_asked, status, bytes)
         return
      end if
      if (foundation%side == side_direction) then
         do i = 1, size(nodes)
            normals(:, i) = foundation%direction
         end do
      else
         call nodal_left_normals(coordinates, connectivity, foundation%elements, nodes, normals, status, bad)
         if (status == foundation_no_memory) then
            call no_memory(16.0_dp*size(coordinates, 2), status, bytes)
            return
         end if
         if (status /= normals_valid) then
            bad_node = nodes(bad)
            return
         end if
         ! sign: +1 when the foundation is on the right (n = + left normal), -1 on the left
         select case (foundation%side)
         case (side_left)
            sign = -1.0_dp
         case (side_right)
            sign = 1.0_dp
         case default
            call total_turning(coordinates, connectivity, foundation%elements, turning, refused)
            if (refused /= 0) then
               call no_memory(8.0_dp*size(coordinates, 2), status, bytes)
               return
            end if
            if (abs(turning) <= straight_tolerance) then
               status = foundation_straight
               return
            end if
            ! turning > 0: the set turns counter-clockwise, its concave side is the left one
            sign = merge(-1.0_dp, 1.0_dp, turning > 0.0_dp)
            if (foundation%side == side_outer) sign = -sign
         end select
         normals = sign*normals
      end if
      if (.not. foundation%modulus > 0.0_dp) return
      call path_coordinates(coordinates, nodes, arc)
      s = foundation%scale*arc

      deallocate (candidates)
      n = size(nodes)
      allocate (candidates(merge(2*n, n, foundation%tangential_modulus > 0.0_dp)), stat=refused)
      if (refused /= 0) then
         allocate (candidates(0))
         call no_memory(real(storage_size(candidates)/8, dp)*merge(2*n, n, foundation%tangential_modulus > 0.0_dp), status, bytes)
         return
      end if
      do i = 1, n
         candidates(i)%node = nodes(i)
         candidates(i)%gap_kind = gap_fixed_direction
         candidates(i)%direction = normals(:, i)
         candidates(i)%offset = foundation%gap
         candidates(i)%flexibility = winkler_flexibility(foundation%modulus, lengths(i))
         candidates(i)%bilateral = foundation%bilateral
         candidates(i)%coordinate = s(i)
         ! A bearing limit q_u per unit length is lumped as the modulus is: q_u × (tributary length).
         if (foundation%bearing_limit > 0.0_dp) then
            candidates(i)%plastic = .true.
            candidates(i)%yield_force = foundation%bearing_limit*lengths(i)
            ! an uplift limit t_u per unit length likewise; the spring is then bonded while elastic
            if (foundation%uplift_limit > 0.0_dp) then
               candidates(i)%uplift_force = foundation%uplift_limit*lengths(i)
               candidates(i)%bilateral = .true.
               ! its own uplift modulus k_u (KU=), lumped as the bearing modulus is (k_u = k: one
               ! stiffness, no kink)
               if (foundation%uplift_modulus > 0.0_dp .and. foundation%uplift_modulus /= foundation%modulus) &
                  candidates(i)%uplift_flexibility = winkler_flexibility(foundation%uplift_modulus, lengths(i))
            end if
         end if
      end do
      if (foundation%law == foundation_pasternak .and. foundation%shear_modulus > 0.0_dp) then
         ! The shear layer couples the nodes: one open chain, the bed's unknowns in its order.
         call open_chain(size(coordinates, 2), connectivity, foundation%elements, nodes, is_open, refused)
         if (refused /= 0) then
            deallocate (candidates)
            allocate (candidates(0))
            call no_memory(8.0_dp*size(coordinates, 2), status, bytes)
            return
         end if
         if (.not. is_open) then
            status = foundation_not_open_chain
            deallocate (candidates)
            allocate (candidates(0))
            return
         end if
         call pasternak_bed(foundation%modulus, foundation%shear_modulus, foundation%continues, lengths, &
                            arc, candidates(1:n))
      end if
      if (.not. foundation%tangential_modulus > 0.0_dp) return
      ! Tangential springs (the tangential subgrade modulus of bedded-beam lining models): at each node
      ! a spring k_t = K_t × L along the tangent t = n turned by +90°, lumped as the radial bed; gap
      ! g = t·u, so the force −k_t (t·u) t opposes the tangential displacement. Never a variable of the
      ! contact LCP (bilateral): bonded, or following its radial partner i (local index here; the
      ! builder makes it global) in and out of the working set.
      do i = 1, n
         candidates(n + i)%node = nodes(i)
         candidates(n + i)%gap_kind = gap_fixed_direction
         candidates(n + i)%direction = [-normals(2, i), normals(1, i)]
         candidates(n + i)%offset = 0.0_dp
         candidates(n + i)%flexibility = winkler_flexibility(foundation%tangential_modulus, lengths(i))
         candidates(n + i)%bilateral = .true.
         candidates(n + i)%tangential = .true.
         if (foundation%tangential_law == tangential_contact) candidates(n + i)%partner = i
         candidates(n + i)%coordinate = s(i)
      end do
   end subroutine foundation_candidates

   !> The outcome of an allocation the system refused: foundation_no_memory and the size asked.
   pure subroutine no_memory(asked, status, bytes)
      real(dp), intent(in) :: asked
      integer, intent(out) :: status
      real(dp), intent(out), optional :: bytes
      status = foundation_no_memory
      if (present(bytes)) bytes = asked
   end subroutine no_memory

   !> The Pasternak bed (Pasternak 1954; Kerr 1964) on the n points of one open chain (`candidates`, in
   !> chain order, already Winkler candidates of modulus K): the surface deflection w (into the bed)
   !> with K w − G_p w'' = p along the arc length s, discretised by linear elements between consecutive
   !> points (Galerkin, docs/theory.md §3.10):
   !>     K_b = K × diag(tributary lengths)                 (Winkler's part lumped as Winkler's bed)
   !>         + G_p/h [1 −1; −1 1] per element of length h  (the shear layer, consistent)
   !>         + √(K G_p) at each end point where the bed continues (the semi-infinite bed beyond it:
   !>           w = w_end exp(−|x|/ℓ), ℓ = √(G_p/K), whose shear force G_p w' = √(K G_p) w_end; Kerr
   !>           1964, Selvadurai 1979 §2.5); nothing where it ends with the set (the natural condition
   !>           G_p w' = 0 of a free shear layer, which is also w' = 0 at a symmetry plane)
   !> Each candidate becomes a rigid contact with the surface (flexibility 0) and gets its row of K_b
   !> and its neighbours (local indices, made global by the builder). Units: K force/length², G_p
   !> force, lengths in the model's unit; K_b force/length.
   pure subroutine pasternak_bed(modulus, shear_modulus, continues, lengths, s, candidates)
      real(dp), intent(in) :: modulus                  !< K > 0
      real(dp), intent(in) :: shear_modulus            !< G_p > 0
      logical, intent(in) :: continues(2)              !< the bed goes on beyond (first, last) point
      real(dp), intent(in) :: lengths(:)               !< (n) tributary lengths
      real(dp), intent(in) :: s(:)                     !< (n) arc length at the points
      type(contact_candidate_t), intent(inout) :: candidates(:)   !< (n)
      real(dp) :: coupling, end_stiffness
      integer :: i, n
      n = size(candidates)
      end_stiffness = sqrt(modulus*shear_modulus)
      do i = 1, n
         candidates(i)%flexibility = 0.0_dp
         candidates(i)%bed_stiffness = [0.0_dp, modulus*lengths(i), 0.0_dp]
         candidates(i)%bed_previous = 0
         candidates(i)%bed_next = 0
      end do
      do i = 1, n - 1
         coupling = shear_modulus/(s(i + 1) - s(i))
         candidates(i)%bed_stiffness(2) = candidates(i)%bed_stiffness(2) + coupling
         candidates(i + 1)%bed_stiffness(2) = candidates(i + 1)%bed_stiffness(2) + coupling
         candidates(i)%bed_stiffness(3) = -coupling
         candidates(i + 1)%bed_stiffness(1) = -coupling
         candidates(i)%bed_next = i + 1
         candidates(i + 1)%bed_previous = i
      end do
      if (continues(1)) candidates(1)%bed_stiffness(2) = candidates(1)%bed_stiffness(2) + end_stiffness
      if (continues(2)) candidates(n)%bed_stiffness(2) = candidates(n)%bed_stiffness(2) + end_stiffness
   end subroutine pasternak_bed

   !> Whether `nodes` (the chain order of `elements`, `chain_nodes`) is one open chain: n − 1 elements,
   !> each from a node to the next one in that order.
   !> status: the stat= of its work arrays (0: `is_open` set).
   pure subroutine open_chain(n_nodes, connectivity, elements, nodes, is_open, status)
      integer, intent(in) :: n_nodes                  !< number of nodes of the model
      integer, intent(in) :: connectivity(:, :)       !< (2, n_elements)
      integer, intent(in) :: elements(:)
      integer, intent(in) :: nodes(:)
      logical, intent(out) :: is_open
      integer, intent(out) :: status
      integer, allocatable :: position(:)
      logical, allocatable :: linked(:)
      integer :: i, p
      is_open = .false.
      status = 0
      if (size(nodes) /= size(elements) + 1) return
      allocate (position(n_nodes), linked(size(nodes)), stat=status)
      if (status /= 0) return
      position = 0
      linked = .false.
      do i = 1, size(nodes)
         position(nodes(i)) = i
      end do
      do i = 1, size(elements)
         p = position(connectivity(1, elements(i)))
         if (p == 0 .or. p == size(nodes)) return
         if (linked(p) .or. position(connectivity(2, elements(i))) /= p + 1) return
         linked(p) = .true.
      end do
      is_open = .true.
   end subroutine open_chain

   !> What a `foundation_candidates` status other than normals_valid means, for messages: what is wrong
   !> at the node concerned (branch, opposed, folded), or with the whole set (foundation_straight).
   pure function foundation_problem(status) result(text)
      integer, intent(in) :: status
      character(len=:), allocatable :: text
      select case (status)
      case (normals_branch)
         text = 'more than two elements of the set'
      case (normals_opposed)
         text = 'two elements of the set running in opposite directions'
      case (foundation_straight)
         text = 'a straight element set, which has no concave side'
      case (foundation_not_open_chain)
         text = 'a set that is not one open chain of elements (a Pasternak bed couples consecutive nodes '// &
                'along one open line: no ring, branch or second chain)'
      case default
         text = 'two elements of the set folded back on each other'
      end select
   end function foundation_problem

   ! ================================================================================================
   ! Geometry of a foundation's element set
   ! ================================================================================================


   !> The nodes of the elements `elements`, in order along the elements' direction (node1 → node2).
   !>
   !> Each chain of consecutive elements (one's node2 is the next one's node1) is walked from its first
   !> node; chains come in the order of the first of their elements in `elements`. A closed chain (a
   !> ring) starts at node1 of its first listed element. Elements that do not form chains (opposed
   !> directions, branches) still contribute each of their nodes once, in the order met.
   !> status: the stat= of an allocation the system refused (0: `nodes` complete).
   pure subroutine chain_nodes(n_nodes, connectivity, elements, nodes, status)
      integer, intent(in) :: n_nodes                  !< number of nodes of the model
      integer, intent(in) :: connectivity(:, :)       !< (2, n_elements) internal node indices
      integer, intent(in) :: elements(:)              !< the set's elements
      integer, allocatable, intent(out) :: nodes(:)
      integer, intent(out) :: status
      integer, allocatable :: incoming(:), outgoing(:), found(:)
      logical, allocatable :: added(:)
      integer :: i, end, node, start, previous, current, count, steps

      allocate (incoming(n_nodes), outgoing(n_nodes), added(n_nodes), found(2*size(elements)), stat=status)
      if (status /= 0) return
      incoming = 0
      outgoing = 0
      added = .false.
      do i = 1, size(elements)
         if (outgoing(connectivity(1, elements(i))) == 0) outgoing(connectivity(1, elements(i))) = elements(i)
         if (incoming(connectivity(2, elements(i))) == 0) incoming(connectivity(2, elements(i))) = elements(i)
      end do

      count = 0
      do i = 1, size(elements)
         do end = 1, 2
            node = connectivity(end, elements(i))
            if (added(node)) cycle
            ! back to where this chain starts: a node nothing enters, a node already taken, or, round a
            ! closed chain, the node itself
            start = node
            do steps = 1, size(elements)
               if (incoming(start) == 0) exit
               previous = connectivity(1, incoming(start))
               if (added(previous)) exit
               if (previous == node) then
                  start = node
                  exit
               end if
               start = previous
            end do
            current = start
            do
               if (added(current)) exit
               count = count + 1
               found(count) = current
               added(current) = .true.
               if (outgoing(current) == 0) exit
               current = connectivity(2, outgoing(current))
            end do
         end do
      end do
      allocate (nodes(count), stat=status)
      if (status /= 0) return
      nodes(:) = found(1:count)
   end subroutine chain_nodes

   !> Tributary lengths: for each of `nodes`, half the sum of the initial lengths of its adjacent elements
   !> that are in `elements` (the length of foundation the node carries; an end node gets half an element).
   !> status: the stat= of an allocation the system refused (0: `lengths` (size(nodes)) complete).
   pure subroutine tributary_lengths(coordinates, connectivity, elements, nodes, lengths, status)
      real(dp), intent(in) :: coordinates(:, :)       !< (2, n_nodes) initial positions
      integer, intent(in) :: connectivity(:, :)       !< (2, n_elements)
      integer, intent(in) :: elements(:)
      integer, intent(in) :: nodes(:)
      real(dp), allocatable, intent(out) :: lengths(:)
      integer, intent(out) :: status
      real(dp), allocatable :: per_node(:)
      real(dp) :: half
      integer :: i

      allocate (per_node(size(coordinates, 2)), lengths(size(nodes)), stat=status)
      if (status /= 0) return
      per_node = 0.0_dp
      do i = 1, size(elements)
         associate (ends => connectivity(:, elements(i)))
            half = 0.5_dp*norm2(coordinates(:, ends(2)) - coordinates(:, ends(1)))
            per_node(ends(1)) = per_node(ends(1)) + half
            per_node(ends(2)) = per_node(ends(2)) + half
         end associate
      end do
      lengths(:) = per_node(nodes)
   end subroutine tributary_lengths

   !> The unit nodal normals of a chain of elements: at each of `nodes`, the normalised mean of the
   !> left normals (tangent node1 → node2 turned by +90°) of its adjacent elements in `elements`.
   !>
   !> `status` is `normals_valid`, or says why the normal of node `nodes(bad)` is not defined: more than
   !> two adjacent elements, two adjacent elements of opposed direction, or a fold (mean normal ~ 0);
   !> foundation_no_memory when its work arrays are refused by the system (`bad` 0).
   pure subroutine nodal_left_normals(coordinates, connectivity, elements, nodes, normals, status, bad)
      real(dp), intent(in) :: coordinates(:, :)       !< (2, n_nodes)
      integer, intent(in) :: connectivity(:, :)       !< (2, n_elements)
      integer, intent(in) :: elements(:)
      integer, intent(in) :: nodes(:)
      real(dp), intent(out) :: normals(:, :)          !< (2, size(nodes))
      integer, intent(out) :: status
      integer, intent(out) :: bad                     !< index into `nodes` of the offending node, 0 if none
      real(dp), allocatable :: sum_normals(:, :)
      integer, allocatable :: starting(:), ending(:)
      real(dp) :: tangent(2), length
      integer :: i, node

      bad = 0
      allocate (sum_normals(2, size(coordinates, 2)), starting(size(coordinates, 2)), ending(size(coordinates, 2)), &
                stat=status)
      if (status /= 0) then
         status = foundation_no_memory
         return
      end if
      sum_normals = 0.0_dp
      starting = 0
      ending = 0
      do i = 1, size(elements)
         associate (ends => connectivity(:, elements(i)))
            tangent = coordinates(:, ends(2)) - coordinates(:, ends(1))
            tangent = tangent/norm2(tangent)
            sum_normals(:, ends) = sum_normals(:, ends) + spread([-tangent(2), tangent(1)], 2, 2)
            starting(ends(1)) = starting(ends(1)) + 1
            ending(ends(2)) = ending(ends(2)) + 1
         end associate
      end do

      status = normals_valid
      bad = 0
      normals = 0.0_dp
      do i = 1, size(nodes)
         node = nodes(i)
         if (starting(node) + ending(node) > 2) then
            status = normals_branch
         else if (starting(node) > 1 .or. ending(node) > 1) then
            status = normals_opposed
         else
            ! two unit normals: their sum is 2 cos(half the angle between them) long
            length = norm2(sum_normals(:, node))
            if (length <= fold_tolerance) then
               status = normals_folded
            else
               normals(:, i) = sum_normals(:, node)/length
               cycle
            end if
         end if
         bad = i
         return
      end do
   end subroutine nodal_left_normals

   !> Total turning of a chain of elements: the sum, over the nodes where one element of `elements` ends
   !> and another starts, of the cross product t_in × t_out of their unit tangents. Positive when the
   !> chain turns counter-clockwise, i.e. when its centre of curvature, its concave side, is on its left.
   !> status: the stat= of its work arrays refused by the system (0: `turning` set).
   pure subroutine total_turning(coordinates, connectivity, elements, turning, status)
      real(dp), intent(in) :: coordinates(:, :)       !< (2, n_nodes)
      integer, intent(in) :: connectivity(:, :)       !< (2, n_elements)
      integer, intent(in) :: elements(:)
      real(dp), intent(out) :: turning
      integer, intent(out) :: status
      integer, allocatable :: incoming(:), outgoing(:)
      real(dp) :: t_in(2), t_out(2)
      integer :: i, node

      turning = 0.0_dp
      allocate (incoming(size(coordinates, 2)), outgoing(size(coordinates, 2)), stat=status)
      if (status /= 0) return
      incoming = 0
      outgoing = 0
      do i = 1, size(elements)
         if (outgoing(connectivity(1, elements(i))) == 0) outgoing(connectivity(1, elements(i))) = elements(i)
         if (incoming(connectivity(2, elements(i))) == 0) incoming(connectivity(2, elements(i))) = elements(i)
      end do
      turning = 0.0_dp
      do node = 1, size(coordinates, 2)
         if (incoming(node) == 0 .or. outgoing(node) == 0) cycle
         t_in = unit_tangent(incoming(node))
         t_out = unit_tangent(outgoing(node))
         turning = turning + (t_in(1)*t_out(2) - t_in(2)*t_out(1))
      end do

   contains

      pure function unit_tangent(e) result(t)
         integer, intent(in) :: e
         real(dp) :: t(2)
         t = coordinates(:, connectivity(2, e)) - coordinates(:, connectivity(1, e))
         t = t/norm2(t)
      end function unit_tangent

   end subroutine total_turning

   !> Arc length along `nodes` in the initial geometry: 0 at the first node, then the cumulative
   !> distance between consecutive nodes of the list.
   pure subroutine path_coordinates(coordinates, nodes, s)
      real(dp), intent(in) :: coordinates(:, :)       !< (2, n_nodes)
      integer, intent(in) :: nodes(:)
      real(dp), intent(out) :: s(:)                   !< (size(nodes)) the caller's
      integer :: i
      if (size(nodes) == 0) return
      s(1) = 0.0_dp
      do i = 2, size(nodes)
         s(i) = s(i - 1) + norm2(coordinates(:, nodes(i)) - coordinates(:, nodes(i - 1)))
      end do
   end subroutine path_coordinates

end module uniarc_contact_law
