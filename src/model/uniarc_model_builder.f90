!> The model builder: the one way to make a `model_t` without filling its fields by hand. The deck reader
!> builds every model through it, and tests build small models with it directly.
!>
!> A `model_builder_t` grows as entities are added (capacities double, so building is linear in the
!> model's size); `finish_model` validates the whole and copies it, arrays cut to size, into a
!> `model_t`. Entities refer to each other by internal index (1..n in order of addition): `add_node`
!> makes node n_nodes, `add_element` element n_elements, `add_section` section n_sections; user labels
!> are kept for messages and output. Its components may be read (the deck's checks look up nodes, sets
!> and groups); they are written only by the procedures here and, for the media (springs, foundations,
!> obstacles and their contact groups), by those of uniarc_model_contacts.
!>
!> Usage:
!>
!>     type(model_builder_t) :: b
!>     call add_section(b, 'rib', ea=420.0_dp, ei=1.4_dp)
!>     call add_node(b, 1, [0.0_dp, 0.0_dp]);  call add_node(b, 2, [1.0_dp, 0.0_dp])
!>     call add_element(b, 1, [1, 2], section=1)
!>     call add_support(b, 1, [.true., .true., .true.])
!>     call add_nodal_load(b, 2, dof_uy, -1.0_dp)
!>     call finish_model(b, model, error)
module uniarc_model_builder
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input
   use uniarc_strings, only: integer_to_string
   use uniarc_name_table, only: name_table_t, add_name, find_name
   use uniarc_growth, only: grow_integers, grow_integers_2, grow_reals_2, grow_logicals_2
   use uniarc_memory, only: allocation_failure
   use uniarc_copy, only: copy_array
   use uniarc_model, only: model_t, section_t, node_set_t, element_set_t, distributed_load_t, track_t, &
                           analysis_options_t, output_options_t, contact_candidate_t, contact_group_t, &
                           foundation_t, dofs_per_node, dof_ux, load_fixed_direction, load_pressure, &
                           element_beam_column, thermal_load_t, end_joint_t, &
                           load_pattern_t, move_obstacles, analysis_linear
   use uniarc_builder_type, only: model_builder_t
   use uniarc_builder_loads, only: add_nodal_load, add_line_load, add_pressure, add_thermal_load, &
                                   add_prescribed_displacement, has_prescribed_displacements, take_loads
   implicit none
   private
   public :: model_builder_t, finish_model
   public :: add_section, add_node, add_element, add_to_node_set, add_to_element_set
   public :: add_support, add_nodal_load, add_line_load, add_pressure, add_track
   public :: set_element_kind, element_kind
   public :: set_end_joint
   public :: node_index, element_index, section_index, node_set_index, element_set_index, track_index
   public :: contact_group_index
   public :: unused_node, element_without_section, model_size
   public :: add_thermal_load, add_prescribed_displacement, has_prescribed_displacements
   public :: take_loads
   public :: set_section_weight, set_section_alpha
   public :: remove_support, copy_supports


contains

   ! ================================================================================================
   ! Structure
   ! ================================================================================================

   !> Add a section of axial stiffness `ea` and bending stiffness `ei` (both > 0; force, force × length²);
   !> it becomes section `builder%n_sections`. Names are compared case-insensitively by `section_index`.
   !> `gas` (optional, > 0): the shear stiffness κGA (force) a Timoshenko beam needs.
   !> `status` (optional): nonzero, the stat= of the growth of the list of sections or of their name
   !> table refused by the system (the section is then not added; without it the runtime stops the
   !> program). The list is grown by moving its entries, not copying them.
   pure subroutine add_section(builder, name, ea, ei, gas, status)
      type(model_builder_t), intent(inout) :: builder
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: ea, ei
      real(dp), intent(in), optional :: gas
      integer, intent(out), optional :: status
      type(section_t), allocatable :: grown(:)
      character(len=:), allocatable :: moved
      integer :: index, k
      ! with `status`, each allocation with stat= and a refusal returned before anything changes
      if (present(status)) then
         status = 0
         if (.not. allocated(builder%sections)) allocate (builder%sections(4), stat=status)
         if (status /= 0) return
         if (builder%n_sections == size(builder%sections)) allocate (grown(2*size(builder%sections)), stat=status)
         if (status /= 0) return
         call add_name(builder%section_names, name, index, status)
         if (status /= 0) return
      else
         if (.not. allocated(builder%sections)) allocate (builder%sections(4))
         if (builder%n_sections == size(builder%sections)) allocate (grown(2*size(builder%sections)))
         call add_name(builder%section_names, name, index)
      end if
      if (allocated(grown)) then
         do k = 1, builder%n_sections
            ! the name moved, not copied: the assignment then copies scalars only (allocates nothing)
            call move_alloc(builder%sections(k)%name, moved)
            grown(k) = builder%sections(k)
            call move_alloc(moved, grown(k)%name)
         end do
         call move_alloc(grown, builder%sections)
      end if
      builder%n_sections = builder%n_sections + 1
      builder%sections(builder%n_sections)%name = name
      builder%sections(builder%n_sections)%ea = ea
      builder%sections(builder%n_sections)%ei = ei
      builder%sections(builder%n_sections)%gas = 0.0_dp
      if (present(gas)) builder%sections(builder%n_sections)%gas = gas
   end subroutine add_section

   !> The weight per unit length `weight` (force/length, ≥ 0) of the elements of the last section added,
   !> which *DLOAD WEIGHT takes when the card gives none.
   pure subroutine set_section_weight(builder, weight)
      type(model_builder_t), intent(inout) :: builder
      real(dp), intent(in) :: weight
      builder%sections(builder%n_sections)%has_weight = .true.
      builder%sections(builder%n_sections)%weight = weight
   end subroutine set_section_weight

   !> The coefficient of thermal expansion `alpha` (1/temperature) of the elements of the last section
   !> added, which *TEMPERATURE takes when the card gives none.
   pure subroutine set_section_alpha(builder, alpha)
      type(model_builder_t), intent(inout) :: builder
      real(dp), intent(in) :: alpha
      builder%sections(builder%n_sections)%has_alpha = .true.
      builder%sections(builder%n_sections)%alpha = alpha
   end subroutine set_section_alpha

   !> Add node `label` (a positive integer not used yet) at `point` (x, y): node `builder%n_nodes`, free
   !> and unloaded. With `error` present, a growth of the node arrays that the system refuses is
   !> returned (error_input: the model does not fit in memory, uniarc_memory) and no node is added;
   !> without it (small models of the unit tests) the runtime stops the program.
   subroutine add_node(builder, label, point, error)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: label
      real(dp), intent(in) :: point(2)
      type(error_t), allocatable, intent(out), optional :: error
      integer :: capacity, status
      call start_nodes(builder)
      capacity = size(builder%node_label)
      if (builder%n_nodes == capacity) then
         if (present(error)) then
            call grow_reals_2(builder%coordinates, 2*capacity, status)
            if (status == 0) call grow_reals_2(builder%nodal_load, 2*capacity, status)
            if (status == 0) call grow_logicals_2(builder%fixed, 2*capacity, status)
            if (status == 0) call grow_integers(builder%node_label, 2*capacity, status)
            call allocation_failure(status, 'the nodes of the model', &
                                    real(2*capacity, dp)*(8.0_dp*(2 + dofs_per_node) + 4.0_dp*(dofs_per_node + 1)), &
                                    error_input, error)
            if (allocated(error)) return
         else
            call grow_reals_2(builder%coordinates, 2*capacity)
            call grow_reals_2(builder%nodal_load, 2*capacity)
            call grow_logicals_2(builder%fixed, 2*capacity)
            call grow_integers(builder%node_label, 2*capacity)
         end if
      end if
      call record_label(builder%node_of_label, label, builder%n_nodes + 1, status)
      if (present(error)) then
         call allocation_failure(status, 'the table of node labels', 4.0_dp*max(label, 2*builder%n_nodes), &
                                 error_input, error)
         if (allocated(error)) return
      end if
      builder%n_nodes = builder%n_nodes + 1
      builder%coordinates(:, builder%n_nodes) = point
      builder%node_label(builder%n_nodes) = label
      builder%fixed(:, builder%n_nodes) = .false.
      builder%nodal_load(:, builder%n_nodes) = 0.0_dp
      builder%largest_node_label = max(builder%largest_node_label, label)
   end subroutine add_node

   !> Add element `label` (positive, not used yet) from node `ends(1)` to node `ends(2)` (internal
   !> indices) with section `section` (an index; 0 leaves it without one, which `finish_model` rejects).
   !> `error`: as add_node's, for the element arrays.
   subroutine add_element(builder, label, ends, section, error)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: label, ends(2), section
      type(error_t), allocatable, intent(out), optional :: error
      integer :: capacity, status
      call start_elements(builder)
      capacity = size(builder%element_label)
      if (builder%n_elements == capacity) then
         if (present(error)) then
            call grow_integers_2(builder%connectivity, 2*capacity, status)
            if (status == 0) call grow_integers_2(builder%load_index, 2*capacity, status)
            if (status == 0) call grow_integers(builder%element_label, 2*capacity, status)
            if (status == 0) call grow_integers(builder%element_section, 2*capacity, status)
            call allocation_failure(status, 'the elements of the model', 4.0_dp*real(2*capacity, dp)* &
                                    (size(builder%connectivity, 1) + size(builder%load_index, 1) + 2), &
                                    error_input, error)
            if (allocated(error)) return
         else
            call grow_integers_2(builder%connectivity, 2*capacity)
            call grow_integers_2(builder%load_index, 2*capacity)
            call grow_integers(builder%element_label, 2*capacity)
            call grow_integers(builder%element_section, 2*capacity)
         end if
      end if
      call record_label(builder%element_of_label, label, builder%n_elements + 1, status)
      if (present(error)) then
         call allocation_failure(status, 'the table of element labels', 4.0_dp*max(label, 2*builder%n_elements), &
                                 error_input, error)
         if (allocated(error)) return
      end if
      builder%n_elements = builder%n_elements + 1
      builder%connectivity(:, builder%n_elements) = ends
      builder%element_label(builder%n_elements) = label
      builder%element_section(builder%n_elements) = section
      builder%load_index(:, builder%n_elements) = 0
      builder%largest_element_label = max(builder%largest_element_label, label)
   end subroutine add_element

   !> Make the elements `elements` (internal indices) of kind `kind` (element_beam_column or
   !> element_truss of uniarc_model); elements never set are beam-columns. Only non-default kinds need
   !> setting: a model of beams only keeps no kind array.
   !> status (optional): the stat= of the growth of the kind array (nonzero: refused by the system, the
   !> kinds left as they were; for uniarc_memory, allocation_failure); absent, a refusal stops the program.
   pure subroutine set_element_kind(builder, elements, kind, status)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: elements(:)
      integer, intent(in) :: kind
      integer, intent(out), optional :: status
      integer, allocatable :: grown(:)
      integer :: capacity, n, k, stat
      if (present(status)) status = 0
      if (size(elements) == 0) return
      if (kind == element_beam_column .and. .not. allocated(builder%element_kind)) return
      capacity = 0
      if (allocated(builder%element_kind)) capacity = size(builder%element_kind)
      if (maxval(elements) > capacity) then
         ! grown with stat= (no array function result of the kinds: element_kind asks for one)
         n = max(maxval(elements), 2*capacity)
         if (present(status)) then
            allocate (grown(n), stat=stat)
            status = stat
            if (stat /= 0) return
         else
            allocate (grown(n))
         end if
         grown(:) = element_beam_column
         k = min(capacity, n)
         if (k > 0) grown(1:k) = builder%element_kind(1:k)
         call move_alloc(grown, builder%element_kind)
      end if
      builder%element_kind(elements) = kind
   end subroutine set_element_kind

   !> Put the joint `joint` (a hinge or a rotational spring, uniarc_model end_joint_t) between end `end`
   !> (1 or 2) of element `element` (internal index) and its node; joints never set are rigid.
   !> status: the stat= of the growth of the joints' array (nonzero: refused by the system, the joints
   !> left as they were; for uniarc_memory, allocation_failure).
   pure subroutine set_end_joint(builder, element, end, joint, status)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: element, end
      type(end_joint_t), intent(in) :: joint
      integer, intent(out) :: status
      type(end_joint_t), allocatable :: grown(:, :)
      integer :: capacity
      status = 0
      capacity = 0
      if (allocated(builder%end_joints)) capacity = size(builder%end_joints, 2)
      if (element > capacity) then
         allocate (grown(2, max(element, 2*capacity)), stat=status)
         if (status /= 0) return
         if (capacity > 0) grown(:, 1:capacity) = builder%end_joints
         call move_alloc(grown, builder%end_joints)
      end if
      builder%end_joints(end, element) = joint
   end subroutine set_end_joint

   !> The kind of element e (internal index): that set by set_element_kind, the beam-column for the
   !> others (a scalar: no array of the model's length is made for a question about one element).
   pure integer function element_kind(builder, e)
      type(model_builder_t), intent(in) :: builder
      integer, intent(in) :: e
      element_kind = element_beam_column
      if (.not. allocated(builder%element_kind)) return
      if (e <= size(builder%element_kind)) element_kind = builder%element_kind(e)
   end function element_kind

   !> Add `members` (node indices) to node set `name` (created if new), skipping nodes already in it.
   !> Errors: an allocation the system refuses (error_input, uniarc_memory: allocation_failure); the
   !> set is then as before.
   subroutine add_to_node_set(builder, name, members, error)
      type(model_builder_t), intent(inout) :: builder
      character(len=*), intent(in) :: name
      integer, intent(in) :: members(:)
      type(error_t), allocatable, intent(out) :: error
      type(node_set_t), allocatable :: grown(:)
      integer :: set, k, status
      if (.not. allocated(builder%node_sets)) allocate (builder%node_sets(8))
      set = node_set_index(builder, name)
      if (set == 0) then
         if (builder%n_node_sets == size(builder%node_sets)) then
            allocate (grown(2*size(builder%node_sets)), stat=status)
            call allocation_failure(status, 'the list of node sets', 64.0_dp*size(builder%node_sets), &
                                    error_input, error)
            if (allocated(error)) return
            ! moved, not copied: a copy of every set's members would double them for a moment
            do k = 1, builder%n_node_sets
               call move_alloc(builder%node_sets(k)%name, grown(k)%name)
               call move_alloc(builder%node_sets(k)%nodes, grown(k)%nodes)
            end do
            call move_alloc(grown, builder%node_sets)
         end if
         builder%n_node_sets = builder%n_node_sets + 1
         set = builder%n_node_sets
         builder%node_sets(set)%name = name
         call add_name(builder%node_set_names, name, k, status)
         call allocation_failure(status, 'the table of node set names', 32.0_dp*set, error_input, error)
         if (allocated(error)) return
         allocate (builder%node_sets(set)%nodes(0))
      end if
      call merge_members(builder%node_sets(set)%nodes, members, builder%n_nodes, 'node set '''//name//'''', error)
   end subroutine add_to_node_set

   !> Add `members` (element indices) to element set `name` (created if new), skipping elements already
   !> in it. Errors: as add_to_node_set.
   subroutine add_to_element_set(builder, name, members, error)
      type(model_builder_t), intent(inout) :: builder
      character(len=*), intent(in) :: name
      integer, intent(in) :: members(:)
      type(error_t), allocatable, intent(out) :: error
      type(element_set_t), allocatable :: grown(:)
      integer :: set, k, status
      if (.not. allocated(builder%element_sets)) allocate (builder%element_sets(8))
      set = element_set_index(builder, name)
      if (set == 0) then
         if (builder%n_element_sets == size(builder%element_sets)) then
            allocate (grown(2*size(builder%element_sets)), stat=status)
            call allocation_failure(status, 'the list of element sets', &
                                    64.0_dp*size(builder%element_sets), error_input, error)
            if (allocated(error)) return
            do k = 1, builder%n_element_sets   ! moved, not copied (add_to_node_set)
               call move_alloc(builder%element_sets(k)%name, grown(k)%name)
               call move_alloc(builder%element_sets(k)%elements, grown(k)%elements)
            end do
            call move_alloc(grown, builder%element_sets)
         end if
         builder%n_element_sets = builder%n_element_sets + 1
         set = builder%n_element_sets
         builder%element_sets(set)%name = name
         call add_name(builder%element_set_names, name, k, status)
         call allocation_failure(status, 'the table of element set names', 32.0_dp*set, error_input, error)
         if (allocated(error)) return
         allocate (builder%element_sets(set)%elements(0))
      end if
      call merge_members(builder%element_sets(set)%elements, members, builder%n_elements, &
                         'element set '''//name//'''', error)
   end subroutine add_to_element_set

   ! ================================================================================================
   ! Supports, loads, tracked displacements
   ! ================================================================================================

   !> Hold the DOFs of `node` where `held` (ux, uy, rz) is true; supports accumulate.
   pure subroutine add_support(builder, node, held)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: node
      logical, intent(in) :: held(dofs_per_node)
      builder%fixed(:, node) = builder%fixed(:, node) .or. held
   end subroutine add_support

   !> Release the DOFs `held` of `node` (an analysis step's *BOUNDARY, REMOVE): they are free from then on.
   pure subroutine remove_support(builder, node, held)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: node
      logical, intent(in) :: held(dofs_per_node)
      builder%fixed(:, node) = builder%fixed(:, node) .and. .not. held
   end subroutine remove_support

   !> The DOFs held so far in `fixed` (dofs_per_node, n_nodes; none before the first node); `status`:
   !> the stat= of its allocation (nonzero: refused, `fixed` unallocated). A subroutine, not a function:
   !> gfortran -O2 does not check the allocation of an array function result and crashes when refused.
   pure subroutine copy_supports(builder, fixed, status)
      type(model_builder_t), intent(in) :: builder
      logical, allocatable, intent(out) :: fixed(:, :)
      integer, intent(out) :: status
      allocate (fixed(dofs_per_node, builder%n_nodes), stat=status)
      if (status == 0 .and. builder%n_nodes > 0) fixed = builder%fixed(:, 1:builder%n_nodes)
   end subroutine copy_supports

   !> Add the path-file column `name` holding scale × u(dof) of `node` (dof_ux, dof_uy or dof_rz).
   !> `status` (optional): nonzero, the stat= of the growth of the list of tracks or of their name
   !> table refused by the system (the track is then not added; without it the runtime stops the
   !> program). The list is grown by moving its entries, not copying them.
   pure subroutine add_track(builder, name, node, dof, scale, status)
      type(model_builder_t), intent(inout) :: builder
      character(len=*), intent(in) :: name
      integer, intent(in) :: node, dof
      real(dp), intent(in) :: scale
      integer, intent(out), optional :: status
      type(track_t), allocatable :: grown(:)
      character(len=:), allocatable :: moved
      integer :: index, k
      ! with `status`, each allocation with stat= and a refusal returned before anything changes
      if (present(status)) then
         status = 0
         if (.not. allocated(builder%tracks)) allocate (builder%tracks(4), stat=status)
         if (status /= 0) return
         if (builder%n_tracks == size(builder%tracks)) allocate (grown(2*size(builder%tracks)), stat=status)
         if (status /= 0) return
         call add_name(builder%track_names, name, index, status)
         if (status /= 0) return
      else
         if (.not. allocated(builder%tracks)) allocate (builder%tracks(4))
         if (builder%n_tracks == size(builder%tracks)) allocate (grown(2*size(builder%tracks)))
         call add_name(builder%track_names, name, index)
      end if
      if (allocated(grown)) then
         do k = 1, builder%n_tracks
            ! the name moved, not copied: the assignment then copies scalars only (allocates nothing)
            call move_alloc(builder%tracks(k)%name, moved)
            grown(k) = builder%tracks(k)
            call move_alloc(moved, grown(k)%name)
         end do
         call move_alloc(grown, builder%tracks)
      end if
      builder%n_tracks = builder%n_tracks + 1
      builder%tracks(builder%n_tracks) = track_t(name=name, node=node, dof=dof, scale=scale)
   end subroutine add_track


   ! ================================================================================================
   ! The model
   ! ================================================================================================

   !> Validate what was built and copy it into `model`, arrays cut to size; `origin` (default '') is
   !> the file the model was read from, for messages.
   !>
   !> Errors (category error_input; `model` is then not to be used): no element; a node in no element
   !> (its DOFs would make the stiffness singular); an element without a section or with a node index
   !> out of range.
   subroutine finish_model(builder, model, error, origin)
      type(model_builder_t), intent(in) :: builder
      type(model_t), intent(out) :: model
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: origin
      integer :: n, e, bad, i, k, status
      real(dp) :: bytes

      n = builder%n_nodes
      e = builder%n_elements
      if (e == 0) then
         call make_error(error, 'model: expected at least one element, found none', error_input)
         return
      end if
      if (any(builder%connectivity(:, 1:e) < 1 .or. builder%connectivity(:, 1:e) > n)) then
         call make_error(error, 'model: expected elements between defined nodes, found a node index out ' // &
                         'of 1 to '//integer_to_string(n), error_input)
         return
      end if
      bad = element_without_section(builder)
      if (bad > 0) then
         call make_error(error, 'model: expected a section for every element, found element '// &
                         integer_to_string(builder%element_label(bad))//' without one', error_input)
         return
      end if
      bad = unused_node(builder)
      if (bad < 0) call allocation_failure(-bad, 'the nodes in use', 4.0_dp*n, error_input, error)
      if (allocated(error)) return
      if (bad > 0) then
         call make_error(error, 'model: expected every node in an element, found node '// &
                         integer_to_string(builder%node_label(bad))//' in none', error_input)
         return
      end if

      model%deck_path = ''
      if (present(origin)) model%deck_path = origin
      model%title = ''
      if (allocated(builder%title)) model%title = builder%title
      model%n_nodes = n
      model%n_elements = e
      ! The arrays that grow with the model, allocated with stat= (a copy by assignment would stop the
      ! run, or crash inside the copy of a derived type, when the system refuses the memory).
      allocate (model%coordinates(2, n), model%node_label(n), model%fixed(dofs_per_node, n), &
                model%nodal_load(dofs_per_node, n), model%connectivity(2, e), model%element_label(e), &
                model%element_section(e), stat=status)
      call allocation_failure(status, 'the nodes and elements of the model', 56.0_dp*n + 16.0_dp*e, &
                              error_input, error)
      if (allocated(error)) return
      model%coordinates = builder%coordinates(:, 1:n)
      model%node_label = builder%node_label(1:n)
      model%fixed = builder%fixed(:, 1:n)
      model%nodal_load = builder%nodal_load(:, 1:n)
      model%connectivity = builder%connectivity(:, 1:e)
      model%element_label = builder%element_label(1:e)
      model%element_section = builder%element_section(1:e)
      if (allocated(builder%element_kind)) then
         ! allocated with stat= and filled in place (an array function result is not checked)
         allocate (model%element_kind(e), stat=status)
         call allocation_failure(status, 'the element kinds of the model', 4.0_dp*e, error_input, error)
         if (allocated(error)) return
         model%element_kind(:) = element_beam_column
         k = min(size(builder%element_kind), e)
         model%element_kind(1:k) = builder%element_kind(1:k)
      end if
      if (allocated(builder%end_joints)) then
         allocate (model%end_joints(2, e), stat=status)
         call allocation_failure(status, 'the end joints of the model', &
                                 real(storage_size(model%end_joints)/8, dp)*2*e, error_input, error)
         if (allocated(error)) return
         model%end_joints(:, 1:min(e, size(builder%end_joints, 2))) = &
            builder%end_joints(:, 1:min(e, size(builder%end_joints, 2)))
      end if
      model%sections = builder%sections(1:builder%n_sections)
      ! the media's lists allocated with stat= (the candidates are of the model's length); the arrays
      ! their records hold are copied with stat= below, not by an assignment of the records
      allocate (model%node_sets(builder%n_node_sets), model%element_sets(builder%n_element_sets), &
                model%distributed_loads(builder%n_loads), model%tracks(builder%n_tracks), &
                model%contacts(builder%n_contacts), model%contact_groups(builder%n_contact_groups), &
                model%foundations(builder%n_foundations), stat=status)
      call allocation_failure(status, 'the contact candidates of the model', &
                              real(storage_size(builder%contacts)/8, dp)*builder%n_contacts, error_input, error)
      if (allocated(error)) return
      do i = 1, builder%n_node_sets
         call copy_set(builder%node_sets(i)%nodes, builder%node_sets(i)%name, 'node', model%node_sets(i)%nodes, &
                       model%node_sets(i)%name, error)
         if (allocated(error)) return
      end do
      do i = 1, builder%n_element_sets
         call copy_set(builder%element_sets(i)%elements, builder%element_sets(i)%name, 'element', &
                       model%element_sets(i)%elements, model%element_sets(i)%name, error)
         if (allocated(error)) return
      end do
      if (builder%n_loads > 0) model%distributed_loads = builder%loads(1:builder%n_loads)
      if (builder%n_tracks > 0) model%tracks = builder%tracks(1:builder%n_tracks)
      ! a candidate's record: its scalars and a polyline's few vertices
      if (builder%n_contacts > 0) model%contacts(:) = builder%contacts(1:builder%n_contacts)
      bytes = 0.0_dp
      do i = 1, builder%n_contact_groups
         model%contact_groups(i)%name = builder%contact_groups(i)%name
         call copy_array(builder%contact_groups(i)%candidates, model%contact_groups(i)%candidates, status, bytes)
         call allocation_failure(status, 'the members of contact group '''//builder%contact_groups(i)%name// &
                                 ''' in the model', bytes, error_input, error)
         if (allocated(error)) return
      end do
      do i = 1, builder%n_foundations
         call copy_foundation(builder%foundations(i), model%foundations(i), status, bytes)
         call allocation_failure(status, 'the elements of foundation '''//builder%foundations(i)%name// &
                                 ''' in the model', bytes, error_input, error)
         if (allocated(error)) return
      end do
      model%analysis = builder%analysis
      model%output = builder%output
      ! one record of 40 bytes per element at most, allocated with stat= and copied in place
      allocate (model%thermal_loads(builder%n_thermal), stat=status)
      call allocation_failure(status, 'the temperature changes of the model', 40.0_dp*builder%n_thermal, &
                              error_input, error)
      if (allocated(error)) return
      do i = 1, builder%n_thermal
         model%thermal_loads(i) = builder%thermal(i)
      end do
      if (builder%n_prescribed > 0) then
         allocate (model%prescribed(dofs_per_node, n), stat=status)
         call allocation_failure(status, 'the prescribed displacements of the model', 8.0_dp*dofs_per_node*n, &
                                 error_input, error)
         if (allocated(error)) return
         model%prescribed = 0.0_dp
         do i = 1, builder%n_prescribed
            model%prescribed(builder%prescribed_dof(i), builder%prescribed_node(i)) = &
               model%prescribed(builder%prescribed_dof(i), builder%prescribed_node(i)) + builder%prescribed_value(i)
         end do
      end if
      ! A deck without steps: its obstacle moves scale with λ along a path, are applied whole (λ = 1)
      ! by a linear static analysis (docs/theory.md §3.11).
      if (allocated(builder%moves)) call move_obstacles(model, builder%moves, 1.0_dp, &
                                                        own=builder%analysis%kind /= analysis_linear)
   end subroutine finish_model

   !> `dst` the foundation `src`: its element list with stat= (status, and its size in bytes), the rest
   !> (names of a few characters, scalars) by assignment with no element list to copy. Every component
   !> of foundation_t but `elements` is named here: one added to the type must be added too.
   subroutine copy_foundation(src, dst, status, bytes)
      type(foundation_t), intent(in) :: src
      type(foundation_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      if (allocated(src%name)) dst%name = src%name
      if (allocated(src%element_set)) dst%element_set = src%element_set
      dst%law = src%law
      dst%modulus = src%modulus
      dst%side = src%side
      dst%direction = src%direction
      dst%bilateral = src%bilateral
      dst%gap = src%gap
      dst%scale = src%scale
      dst%group = src%group
      dst%tangential_modulus = src%tangential_modulus
      dst%tangential_law = src%tangential_law
      dst%bearing_limit = src%bearing_limit
      dst%uplift_limit = src%uplift_limit
      dst%uplift_modulus = src%uplift_modulus
      dst%shear_modulus = src%shear_modulus
      dst%continues = src%continues
      call copy_array(src%elements, dst%elements, status, bytes)
   end subroutine copy_foundation

   !> `copy`, `copy_name` := `members`, `name` of a `kind` ('node', 'element') set, the members allocated
   !> with stat= (error_input when the system refuses them).
   subroutine copy_set(members, name, kind, copy, copy_name, error)
      integer, intent(in) :: members(:)
      character(len=*), intent(in) :: name, kind
      integer, allocatable, intent(out) :: copy(:)
      character(len=:), allocatable, intent(out) :: copy_name
      type(error_t), allocatable, intent(inout) :: error
      integer :: status
      copy_name = name
      allocate (copy(size(members)), stat=status)
      call allocation_failure(status, 'the members of '//kind//' set '''//name//''' in the model', &
                              4.0_dp*size(members), error_input, error)
      if (status == 0) copy = members
   end subroutine copy_set

   ! ================================================================================================
   ! Look-ups
   ! ================================================================================================

   !> Index of the node labelled `label`, 0 if there is none.
   pure integer function node_index(builder, label) result(index)
      type(model_builder_t), intent(in) :: builder
      integer, intent(in) :: label
      index = 0
      if (builder%n_nodes == 0) return
      index = label_index(builder%node_of_label, builder%node_label(1:builder%n_nodes), label)
   end function node_index

   !> Index of the element labelled `label`, 0 if there is none.
   pure integer function element_index(builder, label) result(index)
      type(model_builder_t), intent(in) :: builder
      integer, intent(in) :: label
      index = 0
      if (builder%n_elements == 0) return
      index = label_index(builder%element_of_label, builder%element_label(1:builder%n_elements), label)
   end function element_index

   !> Index of the section called `name` (case-insensitive), 0 if there is none; O(1) expected time.
   pure integer function section_index(builder, name) result(index)
      type(model_builder_t), intent(in) :: builder
      character(len=*), intent(in) :: name
      index = find_name(builder%section_names, name)
   end function section_index

   !> Index of the node set called `name` (case-insensitive), 0 if there is none; O(1) expected time.
   pure integer function node_set_index(builder, name) result(index)
      type(model_builder_t), intent(in) :: builder
      character(len=*), intent(in) :: name
      index = find_name(builder%node_set_names, name)
   end function node_set_index

   !> Index of the contact group called `name` (case-insensitive), 0 if there is none; O(1) expected time.
   pure integer function contact_group_index(builder, name) result(index)
      type(model_builder_t), intent(in) :: builder
      character(len=*), intent(in) :: name
      index = find_name(builder%contact_group_names, name)
   end function contact_group_index

   !> Index of the track called `name` (case-insensitive), 0 if there is none; O(1) expected time.
   pure integer function track_index(builder, name) result(index)
      type(model_builder_t), intent(in) :: builder
      character(len=*), intent(in) :: name
      index = find_name(builder%track_names, name)
   end function track_index

   !> Index of the element set called `name` (case-insensitive), 0 if there is none; O(1) expected time.
   pure integer function element_set_index(builder, name) result(index)
      type(model_builder_t), intent(in) :: builder
      character(len=*), intent(in) :: name
      index = find_name(builder%element_set_names, name)
   end function element_set_index

   !> The first node (index) that no element uses, 0 if every node is used.
   !> Negative: its work array (one flag per node) refused by the system, minus the stat=.
   pure integer function unused_node(builder) result(node)
      type(model_builder_t), intent(in) :: builder
      logical, allocatable :: used(:)
      integer :: i, status
      node = 0
      allocate (used(builder%n_nodes), stat=status)
      if (status /= 0) then
         node = -abs(status)
         return
      end if
      used = .false.
      do i = 1, builder%n_elements
         used(builder%connectivity(:, i)) = .true.
      end do
      do i = 1, builder%n_nodes
         if (.not. used(i)) then
            node = i
            return
         end if
      end do
   end function unused_node

   !> The first element (index) without a valid section, 0 if every element has one.
   pure integer function element_without_section(builder) result(element)
      type(model_builder_t), intent(in) :: builder
      integer :: i
      element = 0
      do i = 1, builder%n_elements
         if (builder%element_section(i) < 1 .or. builder%element_section(i) > builder%n_sections) then
            element = i
            return
         end if
      end do
   end function element_without_section

   !> The diagonal of the box around the nodes added so far (0 without nodes): the length that obstacle
   !> tolerances scale.
   pure real(dp) function model_size(builder)
      type(model_builder_t), intent(in) :: builder
      if (builder%n_nodes == 0) then
         model_size = 0.0_dp
      else
         model_size = norm2(maxval(builder%coordinates(:, 1:builder%n_nodes), dim=2) - &
                            minval(builder%coordinates(:, 1:builder%n_nodes), dim=2))
      end if
   end function model_size

   ! ================================================================================================
   ! Tables
   ! ================================================================================================

   pure subroutine start_nodes(builder)
      type(model_builder_t), intent(inout) :: builder
      if (allocated(builder%node_label)) return
      allocate (builder%coordinates(2, 64), builder%node_label(64), builder%fixed(dofs_per_node, 64), &
                builder%nodal_load(dofs_per_node, 64))
   end subroutine start_nodes

   pure subroutine start_elements(builder)
      type(model_builder_t), intent(inout) :: builder
      if (allocated(builder%element_label)) return
      allocate (builder%connectivity(2, 64), builder%element_label(64), builder%element_section(64), &
                builder%load_index(3, 64))
   end subroutine start_elements

   !> The entry labelled `label`: from the direct table when it covers the label, else by a scan of
   !> `labels`.
   pure integer function label_index(table, labels, label) result(index)
      integer, allocatable, intent(in) :: table(:)
      integer, intent(in) :: labels(:)
      integer, intent(in) :: label
      integer :: i
      index = 0
      if (allocated(table)) then
         if (label >= 1 .and. label <= size(table)) then
            index = table(label)
            return
         end if
      end if
      do i = 1, size(labels)
         if (labels(i) == label) then
            index = i
            return
         end if
      end do
   end function label_index

   !> Remember that `label` is entry `index`, so that label look-ups are O(1) instead of a scan.
   !> Labels are kept in a direct table while they stay below 4 × (entries) + 1000; a table that would
   !> grow larger than that (very sparse labels) is dropped and look-ups fall back to the scan.
   !> status: the stat= of a growth the system refused (0 otherwise); the table is then dropped, as a
   !> sparse one is, so that look-ups stay right (by the scan).
   pure subroutine record_label(table, label, index, status)
      integer, allocatable, intent(inout) :: table(:)
      integer, intent(in) :: label, index
      integer, intent(out) :: status
      integer, allocatable :: grown(:)
      integer :: capacity
      status = 0
      if (.not. allocated(table)) then
         if (index > 1) return                   ! the table was dropped: stay with the scan
         allocate (table(1024), source=0)
      end if
      if (label > size(table)) then
         capacity = max(2*size(table), label)
         if (capacity > 4*index + 1000) then
            deallocate (table)
            return
         end if
         allocate (grown(capacity), stat=status)
         if (status /= 0) then
            deallocate (table)
            return
         end if
         grown = 0
         grown(1:size(table)) = table
         call move_alloc(grown, table)
      end if
      if (label >= 1) table(label) = index
   end subroutine record_label

   !> Append to `set` the entries of `members` (indices 1..n) that are not in it yet, in their order.
   !> `name` names the set in the error of an allocation the system refuses (error_input); `set` is
   !> then unchanged.
   subroutine merge_members(set, members, n, name, error)
      integer, allocatable, intent(inout) :: set(:)
      integer, intent(in) :: members(:)
      integer, intent(in) :: n
      character(len=*), intent(in) :: name
      type(error_t), allocatable, intent(out) :: error
      logical, allocatable :: present(:)
      integer, allocatable :: added(:), merged(:)
      integer :: i, count, status
      allocate (present(n), added(size(members)), stat=status)
      call allocation_failure(status, 'the work arrays of the members of '//name, &
                              4.0_dp*(real(n, dp) + size(members)), error_input, error)
      if (allocated(error)) return
      present = .false.
      present(set) = .true.
      count = 0
      do i = 1, size(members)
         if (present(members(i))) cycle
         present(members(i)) = .true.
         count = count + 1
         added(count) = members(i)
      end do
      allocate (merged(size(set) + count), stat=status)
      call allocation_failure(status, 'the members of '//name, 4.0_dp*(size(set) + count), error_input, &
                              error)
      if (allocated(error)) return
      merged(1:size(set)) = set
      merged(size(set) + 1:) = added(1:count)
      call move_alloc(merged, set)
   end subroutine merge_members

end module uniarc_model_builder
