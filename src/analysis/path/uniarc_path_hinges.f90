!> The mechanisms of a structure whose joints at their moment limit (`*RELEASE, MY=`, docs/theory.md
!> §1.11) are hinges, for the collapse certificate (uniarc_path_collapse, docs/theory.md §3.9): the
!> floating motions of §2.8 are rigid motions of the whole structure; with hinges the structure is a
!> chain of rigid parts, each moving rigidly, which must agree in translation where they meet. A fold
!> at a joint under a point load on a yielding bed is such a mechanism, and its load by the virtual work
!> of the hinges and the media is the upper bound of limit analysis (Neal 1977, ch. 2).
!>
!> The parts are the components of the elements joined at nodes where both ends are rigid to the node
!> (an elastic joint is rigid to a mechanism: it holds as an elastic contact does); a part C moves by
!> (a_C − θ_C Y, b_C + θ_C X) at a point (X, Y) of the initial geometry (small rotations). The motion of
!> every part is the unknown z (3 per part); the rows are the agreement of the parts' translations at
!> each node where several meet and the supports (a held translation, a held rotation of a node rigid to
!> a part). The caller takes the null space of the rows (the mechanisms, in z) and turns each into the
!> motion of the equations (motion_of) and the hinges' rotations (hinge_rotation).
module uniarc_path_hinges
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, end_joint_t, end_joints_of
   use uniarc_dof_map, only: dof_map_t
   implicit none
   private
   public :: hinge_parts_t, hinge_parts, motion_of, hinge_rotation

   !> The parts of a structure cut at its hinges.
   type :: hinge_parts_t
      integer :: n_parts = 0
      integer, allocatable :: part(:)         !< (n_elements) the part of each element
      integer, allocatable :: node_part(:)    !< (n_nodes) the part a node is rigid to (0: none: only hinged ends)
      integer, allocatable :: any_part(:)     !< (n_nodes) a part that meets the node (0: no element)
      real(dp), allocatable :: rows(:, :)     !< (n_rows, 3 n_parts) the agreement and support rows
   end type hinge_parts_t

contains

   !> The parts of `model` cut at the element ends `hinge` (2, n_elements), and their rows. `status`
   !> 0, or the stat= of an array the system refused (parts then incomplete); n_parts > max_parts
   !> (nothing else built): more parts than the caller's certificate can enumerate.
   subroutine hinge_parts(model, map, hinge, max_parts, parts, status)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      logical, intent(in) :: hinge(:, :)
      integer, intent(in) :: max_parts
      type(hinge_parts_t), intent(out) :: parts
      integer, intent(out) :: status
      integer, allocatable :: parent(:), first(:)
      integer :: e, i, n, r, c, k, root, n_rows
      allocate (parent(model%n_elements), first(model%n_nodes), parts%part(model%n_elements), &
                parts%node_part(model%n_nodes), parts%any_part(model%n_nodes), stat=status)
      if (status /= 0) return
      do e = 1, model%n_elements
         parent(e) = e
      end do
      ! union of the elements rigid to a common node (first(n): the first element rigid to node n)
      first = 0
      do e = 1, model%n_elements
         do i = 1, 2
            if (hinge(i, e)) cycle
            n = model%connectivity(i, e)
            if (first(n) == 0) then
               first(n) = e
            else
               call unite(first(n), e)
            end if
         end do
      end do
      parts%part = 0
      do e = 1, model%n_elements
         root = find(e)
         if (parts%part(root) == 0) then
            parts%n_parts = parts%n_parts + 1
            parts%part(root) = parts%n_parts
         end if
      end do
      do e = 1, model%n_elements
         parts%part(e) = parts%part(find(e))
      end do
      if (parts%n_parts > max_parts) return
      parts%node_part = 0
      parts%any_part = 0
      do e = 1, model%n_elements
         do i = 1, 2
            n = model%connectivity(i, e)
            if (.not. hinge(i, e)) parts%node_part(n) = parts%part(e)
            if (parts%any_part(n) == 0) parts%any_part(n) = parts%part(e)
         end do
      end do
      ! rows: 2 per (element end, node) whose part differs from the node's first part, 1 per held
      ! translation of a node, 1 per held rotation of a node rigid to a part
      n_rows = 0
      do e = 1, model%n_elements
         do i = 1, 2
            if (parts%part(e) /= parts%any_part(model%connectivity(i, e))) n_rows = n_rows + 2
         end do
      end do
      do n = 1, model%n_nodes
         if (parts%any_part(n) == 0) cycle
         do k = 1, 2
            if (map%equation(k, n) <= 0) n_rows = n_rows + 1
         end do
         if (parts%node_part(n) > 0 .and. map%equation(3, n) <= 0) n_rows = n_rows + 1
      end do
      allocate (parts%rows(n_rows, 3*parts%n_parts), source=0.0_dp, stat=status)
      if (status /= 0) return
      r = 0
      do e = 1, model%n_elements
         do i = 1, 2
            n = model%connectivity(i, e)
            c = parts%any_part(n)
            if (parts%part(e) == c) cycle
            ! translation of part(e) at the node minus that of part c
            do k = 1, 2
               r = r + 1
               call translation_row(parts%rows(r, :), parts%part(e), k, model%coordinates(:, n), 1.0_dp)
               call translation_row(parts%rows(r, :), c, k, model%coordinates(:, n), -1.0_dp)
            end do
         end do
      end do
      do n = 1, model%n_nodes
         c = parts%any_part(n)
         if (c == 0) cycle
         do k = 1, 2
            if (map%equation(k, n) > 0) cycle
            r = r + 1
            call translation_row(parts%rows(r, :), c, k, model%coordinates(:, n), 1.0_dp)
         end do
         if (parts%node_part(n) > 0 .and. map%equation(3, n) <= 0) then
            r = r + 1
            parts%rows(r, 3*parts%node_part(n)) = 1.0_dp
         end if
      end do

   contains

      recursive integer function find(x) result(root_of)
         integer, intent(in) :: x
         if (parent(x) == x) then
            root_of = x
         else
            root_of = find(parent(x))
            parent(x) = root_of
         end if
      end function find

      subroutine unite(x, y)
         integer, intent(in) :: x, y
         integer :: rx, ry
         rx = find(x)
         ry = find(y)
         if (rx /= ry) parent(ry) = rx
      end subroutine unite

   end subroutine hinge_parts

   !> row += sign × the k-th translation (1: x, 2: y) of part p at the point `at` (initial geometry):
   !> x: a_p − θ_p Y, y: b_p + θ_p X.
   pure subroutine translation_row(row, p, k, at, sign)
      real(dp), intent(inout) :: row(:)
      integer, intent(in) :: p, k
      real(dp), intent(in) :: at(2), sign
      row(3*(p - 1) + k) = row(3*(p - 1) + k) + sign
      if (k == 1) then
         row(3*p) = row(3*p) - sign*at(2)
      else
         row(3*p) = row(3*p) + sign*at(1)
      end if
   end subroutine translation_row

   !> The motion (n_equations) of the parts' motion z (3 n_parts): every node translated as a part
   !> that meets it (they agree when z satisfies the rows), turned as the part it is rigid to (0 for a
   !> node with only hinged ends: its rotation is indeterminate, and no load or contact reads it here).
   pure subroutine motion_of(model, map, parts, z, motion)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(hinge_parts_t), intent(in) :: parts
      real(dp), intent(in) :: z(:)
      real(dp), intent(out) :: motion(:)
      integer :: n, c
      motion = 0.0_dp
      do n = 1, model%n_nodes
         c = parts%any_part(n)
         if (c == 0) cycle
         if (map%equation(1, n) > 0) motion(map%equation(1, n)) = z(3*c - 2) - z(3*c)*model%coordinates(2, n)
         if (map%equation(2, n) > 0) motion(map%equation(2, n)) = z(3*c - 1) + z(3*c)*model%coordinates(1, n)
         if (parts%node_part(n) > 0 .and. map%equation(3, n) > 0) motion(map%equation(3, n)) = z(3*parts%node_part(n))
      end do
   end subroutine motion_of

   !> The turn of the joint at end i of element e (node minus member end, as the joint's Δθ of §1.11)
   !> in the parts' motion z; `known` false when the node is rigid to no part (all its ends hinged: its
   !> rotation, and so the turn, is not fixed by z).
   pure subroutine hinge_rotation(model, parts, e, i, z, turn, known)
      type(model_t), intent(in) :: model
      type(hinge_parts_t), intent(in) :: parts
      integer, intent(in) :: e, i
      real(dp), intent(in) :: z(:)
      real(dp), intent(out) :: turn
      logical, intent(out) :: known
      integer :: node_part
      node_part = parts%node_part(model%connectivity(i, e))
      known = node_part > 0
      turn = 0.0_dp
      if (known) turn = z(3*node_part) - z(3*parts%part(e))
   end subroutine hinge_rotation

end module uniarc_path_hinges
