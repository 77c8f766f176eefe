!> The media of a model being built: discrete springs, foundations and obstacles, each made into one
!> contact group of candidates (uniarc_contact_law) on a `model_builder_t` (uniarc_model_builder, whose
!> other procedures build the structure and its loads). Split from the builder as the media grew
!> (plastic limits, Pasternak beds); the same builder, the same rules: entities by internal index,
!> errors as values.
module uniarc_model_contacts
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input
   use uniarc_strings, only: integer_to_string
   use uniarc_model, only: contact_candidate_t, contact_group_t, foundation_t, gap_fixed_direction
   use uniarc_contact_law, only: foundation_candidates, obstacle_candidate, initial_gap, spring_flexibility, &
                                 path_coordinates, normals_valid, foundation_straight, foundation_problem, &
                                 foundation_not_open_chain
   use uniarc_model_builder, only: model_builder_t, model_size
   implicit none
   private
   public :: add_springs, add_foundation, add_obstacle, add_move
   public :: penetration_tolerance

   !> Initial gap (× the model's size) below which a node is taken as penetrating an obstacle: round-off
   !> of a node placed exactly on the surface stays far below it.
   real(dp), parameter :: penetration_tolerance = 1.0e-9_dp

contains

   !> Add a group `name` of discrete springs: at `nodes(i)` a spring of stiffness `stiffness(i)` > 0
   !> (force per length) pushing along the unit `directions(:, i)`, gap g = n·u; coordinates the
   !> cumulative distance between the nodes in order.
   pure subroutine add_springs(builder, name, nodes, directions, stiffness, bilateral, yield_force, uplift_force)
      type(model_builder_t), intent(inout) :: builder
      character(len=*), intent(in) :: name
      integer, intent(in) :: nodes(:)
      real(dp), intent(in) :: directions(:, :)         !< (2, size(nodes))
      real(dp), intent(in) :: stiffness(:)             !< (size(nodes))
      logical, intent(in) :: bilateral
      !> q_u > 0 (force): elastic–perfectly plastic in compression (docs/theory.md §3.9); absent: elastic
      real(dp), intent(in), optional :: yield_force
      !> t_u > 0 (force), with yield_force: an uplift limit too, the spring bonded while elastic
      !> (docs/theory.md §3.9); absent: compression-only
      real(dp), intent(in), optional :: uplift_force
      type(contact_candidate_t), allocatable :: candidates(:)
      integer :: i
      allocate (candidates(size(nodes)))
      do i = 1, size(nodes)
         candidates(i)%node = nodes(i)
         candidates(i)%gap_kind = gap_fixed_direction
         candidates(i)%direction = directions(:, i)
         candidates(i)%offset = 0.0_dp
         candidates(i)%flexibility = spring_flexibility(stiffness(i))
         candidates(i)%bilateral = bilateral
         if (present(yield_force)) then
            candidates(i)%plastic = .true.
            candidates(i)%yield_force = yield_force
            if (present(uplift_force)) then
               candidates(i)%uplift_force = uplift_force
               candidates(i)%bilateral = .true.
            end if
         end if
      end do
      candidates%coordinate = path_coordinates(builder%coordinates(:, 1:builder%n_nodes), nodes)
      call add_contact_group(builder, name, candidates)
   end subroutine add_springs

   !> Add a foundation as described (`foundation%elements` internal indices; its name names its group):
   !> the model keeps the description, and its candidates are derived by `foundation_candidates`.
   !>
   !> Errors (category error_input): a side (not side_direction) on a set whose nodal normals are not
   !> defined, or inner/outer on a straight set. Then `status` (if present) is the contact law's code
   !> (normals_branch, normals_opposed, normals_folded, foundation_straight, foundation_not_open_chain)
   !> and `bad_node` the node concerned (0 for the last two), and nothing is added. A Pasternak bed
   !> (G_p > 0) must lie on one open chain of elements.
   subroutine add_foundation(builder, foundation, error, status, bad_node)
      type(model_builder_t), intent(inout) :: builder
      type(foundation_t), intent(in) :: foundation
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out), optional :: status
      integer, intent(out), optional :: bad_node
      type(contact_candidate_t), allocatable :: candidates(:)
      type(foundation_t), allocatable :: grown(:)
      integer :: outcome, node
      character(len=:), allocatable :: problem

      call foundation_candidates(foundation, builder%coordinates(:, 1:builder%n_nodes), &
                                 builder%connectivity(:, 1:builder%n_elements), candidates, outcome, node)
      if (present(status)) status = outcome
      if (present(bad_node)) bad_node = node
      if (outcome /= normals_valid) then
         if (outcome == foundation_straight .or. outcome == foundation_not_open_chain) then
            problem = foundation_problem(outcome)
         else
            problem = 'at node '//integer_to_string(builder%node_label(node))//', '//foundation_problem(outcome)
         end if
         call make_error(error, 'foundation '''//foundation%name//''': '//problem, error_input)
         return
      end if

      if (.not. allocated(builder%foundations)) allocate (builder%foundations(2))
      if (builder%n_foundations == size(builder%foundations)) then
         allocate (grown(2*size(builder%foundations)))
         grown(1:builder%n_foundations) = builder%foundations(1:builder%n_foundations)
         call move_alloc(grown, builder%foundations)
      end if
      builder%n_foundations = builder%n_foundations + 1
      builder%foundations(builder%n_foundations) = foundation
      builder%foundations(builder%n_foundations)%group = builder%n_contact_groups + 1
      call add_contact_group(builder, foundation%name, candidates)
   end subroutine add_foundation

   !> Add an obstacle group `name`: one candidate per node of `nodes` facing the obstacle of kind
   !> `gap_kind` (`obstacle_candidate`: a plane through `point` with unit `normal` to the free side, or a
   !> circle of centre `point` and `radius`). `stiffness` > 0 makes it elastic, a spring per node, the
   !> first and the last node's multiplied by `end_factor`; 0 makes it rigid. Coordinates: scale × the
   !> cumulative distance between the nodes.
   !>
   !> Error (category error_input): a node starting inside the obstacle (initial gap below
   !> −penetration_tolerance × `model_size`); then `bad` (if present) is its index in `nodes` and `depth`
   !> how far inside it is, and nothing is added.
   !> An ellipse (gap_ellipse_inside/outside) takes `semi_axes` (a along `normal`, b across), a polyline
   !> (gap_polyline) its `vertices` (2, n ≥ 2).
   subroutine add_obstacle(builder, name, gap_kind, point, normal, radius, nodes, stiffness, end_factor, &
                                scale, error, bad, depth, semi_axes, vertices)
      type(model_builder_t), intent(inout) :: builder
      character(len=*), intent(in) :: name
      integer, intent(in) :: gap_kind
      real(dp), intent(in) :: point(2), normal(2), radius
      integer, intent(in) :: nodes(:)
      real(dp), intent(in) :: stiffness, end_factor, scale
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out), optional :: bad
      real(dp), intent(out), optional :: depth
      real(dp), intent(in), optional :: semi_axes(2)
      real(dp), intent(in), optional :: vertices(:, :)
      type(contact_candidate_t), allocatable :: candidates(:)
      real(dp) :: tolerance, gap, factor
      integer :: i

      if (present(bad)) bad = 0
      if (present(depth)) depth = 0.0_dp
      tolerance = penetration_tolerance*model_size(builder)
      allocate (candidates(size(nodes)))
      do i = 1, size(nodes)
         candidates(i) = obstacle_candidate(gap_kind, point, normal, radius, nodes(i), builder%coordinates(:, nodes(i)), &
                                            semi_axes, vertices)
         gap = initial_gap(candidates(i), builder%coordinates(:, nodes(i)))
         if (gap < -tolerance) then
            if (present(bad)) bad = i
            if (present(depth)) depth = -gap
            call make_error(error, 'obstacle '''//name//''': node '//integer_to_string(builder%node_label(nodes(i)))// &
                            ' starts inside it', error_input)
            return
         end if
         if (stiffness > 0.0_dp) then
            factor = 1.0_dp
            if (i == 1 .or. i == size(nodes)) factor = end_factor
            candidates(i)%flexibility = spring_flexibility(factor*stiffness)
         end if
      end do
      candidates%coordinate = scale*path_coordinates(builder%coordinates(:, 1:builder%n_nodes), nodes)
      call add_contact_group(builder, name, candidates)
   end subroutine add_obstacle

   !> Translate the obstacle of contact group `group` by `d` (2) in the load pattern being read (*MOVE):
   !> moves of one group add up; taken into the analysis step's pattern with its loads (take_loads), or
   !> into the model of a deck without steps (finish_model).
   pure subroutine add_move(builder, group, d)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: group
      real(dp), intent(in) :: d(2)
      real(dp), allocatable :: grown(:, :)
      if (.not. allocated(builder%moves)) allocate (builder%moves(2, builder%n_contact_groups), source=0.0_dp)
      if (size(builder%moves, 2) < builder%n_contact_groups) then
         allocate (grown(2, builder%n_contact_groups), source=0.0_dp)
         grown(:, 1:size(builder%moves, 2)) = builder%moves
         call move_alloc(grown, builder%moves)
      end if
      builder%moves(:, group) = builder%moves(:, group) + d
   end subroutine add_move

   !> Append the contact group `name` made of `candidates` (in node order).
   pure subroutine add_contact_group(builder, name, candidates)
      type(model_builder_t), intent(inout) :: builder
      character(len=*), intent(in) :: name
      type(contact_candidate_t), intent(in) :: candidates(:)
      type(contact_candidate_t), allocatable :: grown(:)
      type(contact_group_t), allocatable :: grown_groups(:)
      integer :: first, group, i

      if (.not. allocated(builder%contacts)) allocate (builder%contacts(max(16, size(candidates))))
      if (.not. allocated(builder%contact_groups)) allocate (builder%contact_groups(4))
      if (builder%n_contacts + size(candidates) > size(builder%contacts)) then
         allocate (grown(max(2*size(builder%contacts), builder%n_contacts + size(candidates))))
         grown(1:builder%n_contacts) = builder%contacts(1:builder%n_contacts)
         call move_alloc(grown, builder%contacts)
      end if
      if (builder%n_contact_groups == size(builder%contact_groups)) then
         allocate (grown_groups(2*size(builder%contact_groups)))
         grown_groups(1:builder%n_contact_groups) = builder%contact_groups(1:builder%n_contact_groups)
         call move_alloc(grown_groups, builder%contact_groups)
      end if

      builder%n_contact_groups = builder%n_contact_groups + 1
      group = builder%n_contact_groups
      first = builder%n_contacts + 1
      builder%contacts(first:first + size(candidates) - 1) = candidates
      builder%contacts(first:first + size(candidates) - 1)%group = group
      ! a partner (a tangential spring's radial candidate) is given within `candidates`: made global
      where (builder%contacts(first:first + size(candidates) - 1)%partner > 0) &
         builder%contacts(first:first + size(candidates) - 1)%partner = &
         builder%contacts(first:first + size(candidates) - 1)%partner + first - 1
      ! so are a Pasternak bed point's neighbours on its bed
      where (builder%contacts(first:first + size(candidates) - 1)%bed_previous > 0) &
         builder%contacts(first:first + size(candidates) - 1)%bed_previous = &
         builder%contacts(first:first + size(candidates) - 1)%bed_previous + first - 1
      where (builder%contacts(first:first + size(candidates) - 1)%bed_next > 0) &
         builder%contacts(first:first + size(candidates) - 1)%bed_next = &
         builder%contacts(first:first + size(candidates) - 1)%bed_next + first - 1
      builder%n_contacts = builder%n_contacts + size(candidates)
      builder%contact_groups(group)%name = name
      builder%contact_groups(group)%candidates = [(i, i = first, builder%n_contacts)]
   end subroutine add_contact_group

end module uniarc_model_contacts
