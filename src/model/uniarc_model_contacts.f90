!> The media of a model being built: discrete springs, foundations and obstacles, each made into one
!> contact group of candidates (uniarc_contact_law) on a `model_builder_t` (uniarc_model_builder, whose
!> other procedures build the structure and its loads). Split from the builder as the media grew
!> (plastic limits, Pasternak beds); the same builder, the same rules: entities by internal index,
!> errors as values.
module uniarc_model_contacts
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: integer_to_string
   use uniarc_model, only: contact_candidate_t, contact_group_t, foundation_t, gap_fixed_direction
   use uniarc_contact_law, only: foundation_candidates, obstacle_candidate, initial_gap, spring_flexibility, &
                                 path_coordinates, normals_valid, foundation_straight, foundation_problem, &
                                 foundation_not_open_chain, foundation_no_memory
   use uniarc_model_builder, only: model_builder_t, model_size
   use uniarc_name_table, only: add_name
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
   !> Errors: the candidates refused by the system (error_input: the model does not fit in memory);
   !> nothing is then added.
   subroutine add_springs(builder, name, nodes, directions, stiffness, bilateral, error, yield_force, uplift_force, &
                          uplift_stiffness)
      type(model_builder_t), intent(inout) :: builder
      character(len=*), intent(in) :: name
      integer, intent(in) :: nodes(:)
      real(dp), intent(in) :: directions(:, :)         !< (2, size(nodes))
      real(dp), intent(in) :: stiffness(:)             !< (size(nodes))
      logical, intent(in) :: bilateral
      type(error_t), allocatable, intent(out) :: error
      !> q_u > 0 (force): elastic–perfectly plastic in compression (docs/theory.md §3.9); absent: elastic
      real(dp), intent(in), optional :: yield_force
      !> t_u > 0 (force), with yield_force: an uplift limit too, the spring bonded while elastic
      !> (docs/theory.md §3.9); absent: compression-only
      real(dp), intent(in), optional :: uplift_force
      !> k_u > 0 (force per length), with uplift_force: the stiffness of every spring's uplift branch
      !> (docs/theory.md §3.9, "Two stiffnesses"); absent: k_u = k
      real(dp), intent(in), optional :: uplift_stiffness
      type(contact_candidate_t), allocatable :: candidates(:)
      real(dp), allocatable :: s(:)
      integer :: i, status
      allocate (candidates(size(nodes)), s(size(nodes)), stat=status)
      call allocation_failure(status, 'the candidates of spring group '''//name//'''', &
                              real(storage_size(candidates)/8 + 8, dp)*size(nodes), error_input, error)
      if (allocated(error)) return
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
               ! k_u = k: one stiffness, no kink
               if (present(uplift_stiffness)) then
                  if (uplift_stiffness /= stiffness(i)) &
                     candidates(i)%uplift_flexibility = spring_flexibility(uplift_stiffness)
               end if
            end if
         end if
      end do
      call path_coordinates(builder%coordinates(:, 1:builder%n_nodes), nodes, s)
      candidates%coordinate = s
      call add_contact_group(builder, name, candidates, error)
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
      type(foundation_t), intent(inout) :: foundation   !< unchanged (inout: its elements moved aside)
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out), optional :: status
      integer, intent(out), optional :: bad_node
      type(contact_candidate_t), allocatable :: candidates(:)
      type(foundation_t), allocatable :: grown(:)
      integer, allocatable :: elements(:)
      integer :: outcome, node, refused, f
      real(dp) :: bytes
      character(len=:), allocatable :: problem

      call foundation_candidates(foundation, builder%coordinates(:, 1:builder%n_nodes), &
                                 builder%connectivity(:, 1:builder%n_elements), candidates, outcome, node, bytes)
      if (present(status)) status = outcome
      if (present(bad_node)) bad_node = node
      if (outcome == foundation_no_memory) then
         call allocation_failure(1, 'the candidates of foundation '''//foundation%name//'''', bytes, error_input, error)
         return
      end if
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
         ! the foundations moved, not copied (their element lists are of the model's length)
         allocate (grown(2*size(builder%foundations)))
         do f = 1, builder%n_foundations
            call move_foundation(builder%foundations(f), grown(f))
         end do
         call move_alloc(grown, builder%foundations)
      end if
      ! the description's element list copied with stat= (an assignment of the record is not checked):
      ! moved aside while the rest of the record is copied
      f = builder%n_foundations + 1
      call move_alloc(foundation%elements, elements)
      builder%foundations(f) = foundation
      call move_alloc(elements, foundation%elements)
      allocate (builder%foundations(f)%elements(size(foundation%elements)), stat=refused)
      call allocation_failure(refused, 'the elements of foundation '''//foundation%name//'''', &
                              4.0_dp*size(foundation%elements), error_input, error)
      if (allocated(error)) return
      builder%foundations(f)%elements(:) = foundation%elements
      builder%n_foundations = f
      builder%foundations(f)%group = builder%n_contact_groups + 1
      call add_contact_group(builder, foundation%name, candidates, error)
   end subroutine add_foundation

   !> Foundation `from` moved into `to` (its element list handed over, not copied).
   subroutine move_foundation(from, to)
      type(foundation_t), intent(inout) :: from, to
      integer, allocatable :: elements(:)
      call move_alloc(from%elements, elements)
      to = from   ! its names (a few characters) and scalars; no element list
      call move_alloc(elements, to%elements)
   end subroutine move_foundation


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
      real(dp), allocatable :: s(:)
      real(dp) :: tolerance, gap, factor
      integer :: i, status

      if (present(bad)) bad = 0
      if (present(depth)) depth = 0.0_dp
      tolerance = penetration_tolerance*model_size(builder)
      allocate (candidates(size(nodes)), s(size(nodes)), stat=status)
      call allocation_failure(status, 'the candidates of obstacle '''//name//'''', &
                              real(storage_size(candidates)/8 + 8, dp)*size(nodes), error_input, error)
      if (allocated(error)) return
      do i = 1, size(nodes)
         ! (a polyline's vertices, a few per card line, are copied into each of its candidates)
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
      call path_coordinates(builder%coordinates(:, 1:builder%n_nodes), nodes, s)
      candidates%coordinate = scale*s
      call add_contact_group(builder, name, candidates, error)
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

   !> Append the contact group `name` made of `candidates` (in node order). The candidates kept are
   !> moved when the list grows, not copied (a polyline's carry its vertices). Errors: the grown list or
   !> the group's members refused by the system (error_input: the model does not fit in memory);
   !> nothing is then added.
   subroutine add_contact_group(builder, name, candidates, error)
      type(model_builder_t), intent(inout) :: builder
      character(len=*), intent(in) :: name
      type(contact_candidate_t), intent(inout) :: candidates(:)   !< moved into the list (left without vertices)
      type(error_t), allocatable, intent(out) :: error
      type(contact_candidate_t), allocatable :: grown(:)
      type(contact_group_t), allocatable :: grown_groups(:)
      integer, allocatable :: members(:)
      integer :: first, group, i, status, capacity

      if (.not. allocated(builder%contact_groups)) allocate (builder%contact_groups(4))
      capacity = 0
      if (allocated(builder%contacts)) capacity = size(builder%contacts)
      if (builder%n_contacts + size(candidates) > capacity) then
         capacity = max(16, 2*capacity, builder%n_contacts + size(candidates))
         allocate (grown(capacity), stat=status)
         call allocation_failure(status, 'the contact candidates of the model', &
                                 real(storage_size(grown)/8, dp)*capacity, error_input, error)
         if (allocated(error)) return
         do i = 1, builder%n_contacts
            call move_candidate(builder%contacts(i), grown(i))
         end do
         call move_alloc(grown, builder%contacts)
      end if
      allocate (members(size(candidates)), stat=status)
      call allocation_failure(status, 'the members of contact group '''//name//'''', 4.0_dp*size(candidates), &
                              error_input, error)
      if (allocated(error)) return
      if (builder%n_contact_groups == size(builder%contact_groups)) then
         allocate (grown_groups(2*size(builder%contact_groups)))
         do i = 1, builder%n_contact_groups
            call move_alloc(builder%contact_groups(i)%name, grown_groups(i)%name)
            call move_alloc(builder%contact_groups(i)%candidates, grown_groups(i)%candidates)
         end do
         call move_alloc(grown_groups, builder%contact_groups)
      end if

      builder%n_contact_groups = builder%n_contact_groups + 1
      group = builder%n_contact_groups
      first = builder%n_contacts + 1
      do i = 1, size(candidates)
         call move_candidate(candidates(i), builder%contacts(first + i - 1))
      end do
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
      call add_name(builder%contact_group_names, name, i, status)
      call allocation_failure(status, 'the table of contact group names', 32.0_dp*group, error_input, error)
      if (allocated(error)) return
      do i = 1, size(members)
         members(i) = first + i - 1
      end do
      call move_alloc(members, builder%contact_groups(group)%candidates)
   end subroutine add_contact_group

   !> Candidate `from` moved into `to` (its vertices, if any, handed over, not copied).
   subroutine move_candidate(from, to)
      type(contact_candidate_t), intent(inout) :: from, to
      real(dp), allocatable :: vertices(:, :)
      if (allocated(from%vertices)) call move_alloc(from%vertices, vertices)
      to = from   ! no allocatable component left: no allocation
      if (allocated(vertices)) call move_alloc(vertices, to%vertices)
   end subroutine move_candidate

end module uniarc_model_contacts
