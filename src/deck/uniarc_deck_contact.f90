!> Geometry of the deck's foundation and obstacle cards (*FOUNDATION, *SPRING, *OBSTACLE).
!>
!> Pure helpers on the initial geometry: which nodes an element set touches and in which order, the
!> length of element set each node carries (Winkler lumping), the nodal normals of a chain of elements,
!> which side of a curved set is concave, and the arc length along a list of nodes. uniarc_deck turns
!> their results into `contact_candidate_t` records and positioned messages; nothing here knows the deck.
module uniarc_deck_contact
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: chain_nodes, tributary_lengths, nodal_left_normals, total_turning, path_coordinates
   public :: normals_valid, normals_branch, normals_opposed, normals_folded

   !> Outcomes of `nodal_left_normals`.
   integer, parameter :: normals_valid = 0    !< every node has a normal
   integer, parameter :: normals_branch = 1   !< a node joins more than two elements of the set
   integer, parameter :: normals_opposed = 2  !< two elements of the set both start, or both end, at a node
   integer, parameter :: normals_folded = 3   !< two elements fold back on each other: no mean normal

   !> Length of the mean of two unit normals under which they are taken as opposite (a fold of the set).
   real(dp), parameter :: fold_tolerance = 1.0e-9_dp

contains

   !> The nodes of the elements `elements`, in order along the elements' direction (node1 → node2).
   !>
   !> Each chain of consecutive elements (one's node2 is the next one's node1) is walked from its first
   !> node; chains come in the order of the first of their elements in `elements`. A closed chain (a
   !> ring) starts at node1 of its first listed element. Elements that do not form chains (opposed
   !> directions, branches) still contribute each of their nodes once, in the order met.
   pure function chain_nodes(n_nodes, connectivity, elements) result(nodes)
      integer, intent(in) :: n_nodes                  !< number of nodes of the model
      integer, intent(in) :: connectivity(:, :)       !< (2, n_elements) internal node indices
      integer, intent(in) :: elements(:)              !< the set's elements
      integer, allocatable :: nodes(:)
      integer, allocatable :: incoming(:), outgoing(:)
      logical, allocatable :: added(:)
      integer :: i, end, node, start, previous, current, count, steps

      allocate (incoming(n_nodes), outgoing(n_nodes), source=0)
      allocate (added(n_nodes), source=.false.)
      do i = 1, size(elements)
         if (outgoing(connectivity(1, elements(i))) == 0) outgoing(connectivity(1, elements(i))) = elements(i)
         if (incoming(connectivity(2, elements(i))) == 0) incoming(connectivity(2, elements(i))) = elements(i)
      end do

      allocate (nodes(2*size(elements)))
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
               nodes(count) = current
               added(current) = .true.
               if (outgoing(current) == 0) exit
               current = connectivity(2, outgoing(current))
            end do
         end do
      end do
      nodes = nodes(1:count)
   end function chain_nodes

   !> Winkler lumping: for each of `nodes`, half the sum of the initial lengths of its adjacent elements
   !> that are in `elements` (the length of foundation the node carries; an end node gets half an element).
   pure function tributary_lengths(coordinates, connectivity, elements, nodes) result(lengths)
      real(dp), intent(in) :: coordinates(:, :)       !< (2, n_nodes) initial positions
      integer, intent(in) :: connectivity(:, :)       !< (2, n_elements)
      integer, intent(in) :: elements(:)
      integer, intent(in) :: nodes(:)
      real(dp), allocatable :: lengths(:)
      real(dp), allocatable :: per_node(:)
      real(dp) :: half
      integer :: i

      allocate (per_node(size(coordinates, 2)), source=0.0_dp)
      do i = 1, size(elements)
         associate (ends => connectivity(:, elements(i)))
            half = 0.5_dp*norm2(coordinates(:, ends(2)) - coordinates(:, ends(1)))
            per_node(ends(1)) = per_node(ends(1)) + half
            per_node(ends(2)) = per_node(ends(2)) + half
         end associate
      end do
      lengths = per_node(nodes)
   end function tributary_lengths

   !> The unit nodal normals of a chain of elements: at each of `nodes`, the normalised mean of the
   !> left normals (tangent node1 → node2 turned by +90°) of its adjacent elements in `elements`.
   !>
   !> `status` is `normals_valid`, or says why the normal of node `nodes(bad)` is not defined: more than
   !> two adjacent elements, two adjacent elements of opposed direction, or a fold (mean normal ~ 0).
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

      allocate (sum_normals(2, size(coordinates, 2)), source=0.0_dp)
      allocate (starting(size(coordinates, 2)), ending(size(coordinates, 2)), source=0)
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
   pure function total_turning(coordinates, connectivity, elements) result(turning)
      real(dp), intent(in) :: coordinates(:, :)       !< (2, n_nodes)
      integer, intent(in) :: connectivity(:, :)       !< (2, n_elements)
      integer, intent(in) :: elements(:)
      real(dp) :: turning
      integer, allocatable :: incoming(:), outgoing(:)
      real(dp) :: t_in(2), t_out(2)
      integer :: i, node

      allocate (incoming(size(coordinates, 2)), outgoing(size(coordinates, 2)), source=0)
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

   end function total_turning

   !> Arc length along `nodes` in the initial geometry: 0 at the first node, then the cumulative
   !> distance between consecutive nodes of the list.
   pure function path_coordinates(coordinates, nodes) result(s)
      real(dp), intent(in) :: coordinates(:, :)       !< (2, n_nodes)
      integer, intent(in) :: nodes(:)
      real(dp), allocatable :: s(:)
      integer :: i
      allocate (s(size(nodes)))
      if (size(nodes) == 0) return
      s(1) = 0.0_dp
      do i = 2, size(nodes)
         s(i) = s(i - 1) + norm2(coordinates(:, nodes(i)) - coordinates(:, nodes(i - 1)))
      end do
   end function path_coordinates

end module uniarc_deck_contact
