!> The input deck reader: turns a deck (docs/input.md) into a `model_t`.
!>
!> The deck is walked card by card; `dispatch` is the one `select case` over the keywords, with one
!> subroutine per card, so that a new card is one case and one subroutine. Each card subroutine first
!> checks its options (`check_options` with the list of names it knows), then reads its data lines.
!> Everything the cards build is kept in a `builder_t` (a local of `read_deck`, never module state)
!> with growing arrays, and copied to the model at the end after the whole-deck checks.
module uniarc_deck
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input
   use uniarc_strings, only: field_t, to_upper, is_name, same_text, integer_to_string, real_to_string
   use uniarc_expression, only: parameter_table_t, evaluate_expression, set_parameter, find_parameter, &
                                is_reserved_name, sin_degrees, cos_degrees
   use uniarc_deck_source, only: source_t, card_t, read_source, next_card, raise, raise_plain, clip, &
                                 check_options, option_index, require_option, data_fields, &
                                 require_field_count, field_real, field_integer
   use uniarc_model, only: model_t, section_t, node_set_t, element_set_t, distributed_load_t, track_t, &
                           dof_ux, dof_uy, dof_rz, load_fixed_direction, load_pressure, &
                           analysis_options_t, output_options_t, analysis_nonlinear, control_load, control_displacement, &
                           control_arclength, iteration_chan, iteration_cylindrical, iteration_riks, &
                           contact_candidate_t, contact_group_t, gap_fixed_direction, gap_circle_inside, &
                           gap_circle_outside
   use uniarc_deck_element, only: read_element_type, record_element_kind, element_kinds, restrain_truss_nodes
   use uniarc_deck_contact, only: chain_nodes, tributary_lengths, nodal_left_normals, total_turning, &
                                  path_coordinates, normals_valid, normals_branch, normals_opposed
   implicit none
   private
   public :: parameter_override_t, read_deck

   !> A `-D name=value` of the command line: replaces the deck's definition of parameter `name`.
   type :: parameter_override_t
      character(len=:), allocatable :: name
      character(len=:), allocatable :: value   !< an expression, evaluated where the deck defines `name`
   end type parameter_override_t

   !> Relative tolerance under which a generated node is the same as an existing one (× generator size).
   real(dp), parameter :: merge_tolerance = 1.0e-9_dp

   !> Relative size under which an element's length is round-off of its coordinates, i.e. zero.
   real(dp), parameter :: zero_length_tolerance = 1.0e-12_dp

   !> Initial gap (× the model's size) below which a node is taken as penetrating an obstacle: round-off
   !> of a node placed exactly on the surface stays far below it.
   real(dp), parameter :: penetration_tolerance = 1.0e-9_dp

   !> Total turning (sum of cross products of unit tangents) under which a set counts as straight, so
   !> that it has no concave side.
   real(dp), parameter :: straight_tolerance = 1.0e-9_dp

   !> Everything the cards have built so far.
   type :: builder_t
      type(parameter_table_t) :: parameters
      integer, allocatable :: parameter_line(:)       !< line that defined each parameter
      type(parameter_override_t), allocatable :: overrides(:)
      logical, allocatable :: override_used(:)
      character(len=:), allocatable :: title
      integer :: analysis_line = 0                    !< line of the analysis card, 0 if none yet

      integer :: n_nodes = 0
      real(dp), allocatable :: coordinates(:, :)
      integer, allocatable :: node_label(:)
      integer, allocatable :: node_line(:), node_column(:)   !< where the node was defined
      logical, allocatable :: fixed(:, :)
      real(dp), allocatable :: nodal_load(:, :)
      integer :: largest_node_label = 0
      integer, allocatable :: node_of_label(:)        !< label → index (0: none), for labels up to its size

      integer :: n_elements = 0
      integer, allocatable :: connectivity(:, :)
      integer, allocatable :: element_label(:)
      integer, allocatable :: element_section(:)
      integer, allocatable :: element_kind(:)         !< kinds given by *ELEMENT, TYPE= (uniarc_deck_element)
      integer, allocatable :: load_index(:, :)        !< (3, element): fixed, pressure, follower record
      integer :: largest_element_label = 0
      integer, allocatable :: element_of_label(:)     !< label → index (0: none), for labels up to its size

      integer :: n_sections = 0
      type(section_t), allocatable :: sections(:)
      integer :: n_node_sets = 0
      type(node_set_t), allocatable :: node_sets(:)
      integer :: n_element_sets = 0
      type(element_set_t), allocatable :: element_sets(:)
      integer :: n_loads = 0
      type(distributed_load_t), allocatable :: loads(:)
      integer :: n_tracks = 0
      type(track_t), allocatable :: tracks(:)
      integer :: n_contacts = 0
      type(contact_candidate_t), allocatable :: contacts(:)
      integer :: n_contact_groups = 0
      type(contact_group_t), allocatable :: contact_groups(:)

      type(analysis_options_t) :: analysis            !< linear static unless a *PATH card says otherwise
      character(len=:), allocatable :: stop_track     !< *PATH stop_track, resolved at the end
      integer :: stop_track_line = 0, stop_track_column = 0

      type(output_options_t) :: output                !< extra result files (*OUTPUT)
      integer :: vtk_line = 0                         !< line of the *OUTPUT, VTK card, 0 if none yet
   end type builder_t

contains

   !> Read the deck `path` into `model`, with the command-line parameter `overrides`.
   !>
   !> On failure `error` (category error_input) says where and what was expected; `model` is then
   !> not to be used.
   subroutine read_deck(path, overrides, model, error)
      character(len=*), intent(in) :: path
      type(parameter_override_t), intent(in) :: overrides(:)
      type(model_t), intent(out) :: model
      type(error_t), allocatable, intent(out) :: error
      type(source_t) :: source
      type(builder_t) :: builder
      type(card_t) :: card
      integer :: position
      logical :: found

      call read_source(path, source, error)
      if (allocated(error)) return
      call start_builder(builder, overrides)

      position = 1
      do
         call next_card(source, position, card, found, error)
         if (allocated(error)) return
         if (.not. found) exit
         call dispatch(source, card, builder, error)
         if (allocated(error)) return
      end do

      call check_whole_deck(source, builder, error)
      if (allocated(error)) return
      call finish_model(source, builder, model)
   end subroutine read_deck

   !> The card dispatch: one case per keyword, one subroutine per card.
   subroutine dispatch(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error

      select case (card%keyword)
      case ('HEADING')
         call read_heading(source, card, builder, error)
      case ('PARAMETER')
         call read_parameter(source, card, builder, error)
      case ('SECTION')
         call read_section(source, card, builder, error)
      case ('NODE')
         call read_node(source, card, builder, error)
      case ('ELEMENT')
         call read_element(source, card, builder, error)
      case ('ARC', 'RING', 'LINE')
         call read_generator(source, card, builder, error)
      case ('NSET')
         call read_node_set(source, card, builder, error)
      case ('ELSET')
         call read_element_set(source, card, builder, error)
      case ('BOUNDARY')
         call read_boundary(source, card, builder, error)
      case ('CLOAD')
         call read_concentrated_load(source, card, builder, error)
      case ('DLOAD')
         call read_distributed_load(source, card, builder, error)
      case ('TRACK')
         call read_track(source, card, builder, error)
      case ('FOUNDATION')
         call read_foundation(source, card, builder, error)
      case ('SPRING')
         call read_spring(source, card, builder, error)
      case ('OBSTACLE')
         call read_obstacle(source, card, builder, error)
      case ('PATH')
         call read_path(source, card, builder, error)
      case ('STATIC')
         call read_static(source, card, builder, error)
      case ('OUTPUT')
         call read_output(source, card, builder, error)
      case default
         call raise(source, card%line, card%column, 'expected a known card (*HEADING, *PARAMETER, *SECTION, ' // &
                    '*NODE, *ELEMENT, *ARC, *RING, *LINE, *NSET, *ELSET, *BOUNDARY, *CLOAD, *DLOAD, *TRACK, ' // &
                    '*FOUNDATION, *SPRING, *OBSTACLE, *STATIC, *PATH, *OUTPUT), found ''*'//card%keyword//'''', error)
      end select
   end subroutine dispatch

   ! ================================================================================================
   ! Cards
   ! ================================================================================================

   !> *HEADING: the data lines, joined by blanks, are the title.
   subroutine read_heading(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: i
      character(len=:), allocatable :: text

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      builder%title = ''
      do i = 1, card%n_data
         text = trim(adjustl(source%lines(card%data_lines(i))%text))
         if (len(builder%title) > 0) builder%title = builder%title//' '
         builder%title = builder%title//text
      end do
   end subroutine read_heading

   !> *PARAMETER: `name = expression` lines. A `-D name=value` replaces the expression where the deck
   !> defines `name`, so later parameters built on it follow the override.
   subroutine read_parameter(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: i, line, equals, first, k, column, existing
      character(len=:), allocatable :: text, name, message
      type(field_t) :: field
      real(dp) :: value

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      do i = 1, card%n_data
         line = card%data_lines(i)
         text = source%lines(line)%text
         first = verify(text, ' ')
         equals = index(text, '=')
         if (equals == 0) then
            call raise(source, line, len_trim(text) + 1, 'expected ''name = expression'', found no ''=''', error)
            return
         end if
         name = trim(adjustl(text(1:equals - 1)))
         if (.not. is_name(name)) then
            call raise(source, line, first, 'expected a parameter name (a letter, then letters, digits, _), ' // &
                       'found '''//clip(name)//'''', error)
            return
         end if
         if (is_reserved_name(name)) then
            call raise(source, line, first, 'expected a name that is not pi or a function, found '''// &
                       name//'''', error)
            return
         end if
         existing = find_parameter(builder%parameters, name)
         if (existing > 0) then
            call raise(source, line, first, 'expected a new parameter name, found '''//name// &
                       ''' (defined at line '//integer_to_string(builder%parameter_line(existing))//')', error)
            return
         end if

         k = find_override(builder, name)
         if (k > 0) then
            builder%override_used(k) = .true.
            call evaluate_expression(builder%overrides(k)%value, builder%parameters, value, error, column)
            if (allocated(error)) then
               message = error%message
               call make_error(error, '-D '//builder%overrides(k)%name//'='//builder%overrides(k)%value// &
                               ': column '//integer_to_string(column)//' of the value: '//message, error_input)
               return
            end if
         else
            field%text = trim(text(equals + 1:))
            field%column = equals + 1
            if (len(field%text) > 0) then
               field%column = equals + verify(field%text, ' ')
               field%text = trim(adjustl(field%text))
            end if
            ! a trailing comma is allowed on every data line
            if (len(field%text) > 0) then
               if (field%text(len(field%text):) == ',') field%text = trim(field%text(1:len(field%text) - 1))
            end if
            call field_real(source, builder%parameters, line, field, 'an expression', value, error)
            if (allocated(error)) return
         end if
         call set_parameter(builder%parameters, name, value)
         call grow_integers(builder%parameter_line, builder%parameters%count)
         builder%parameter_line(builder%parameters%count) = line
      end do
   end subroutine read_parameter

   !> *SECTION, NAME=s [, STIFFNESS | TYPE=STIFFNESS|MATERIAL]: data `E, A, I` (material form, the
   !> default) or `EA, EI` (stiffness form). Every value must be positive.
   subroutine read_section(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: name_option, type_option, line, i, n_values
      logical :: stiffness_form
      type(field_t), allocatable :: fields(:)
      real(dp) :: values(3)
      character(len=2), parameter :: material_names(3) = ['E ', 'A ', 'I ']
      character(len=2), parameter :: stiffness_names(2) = ['EA', 'EI']
      character(len=:), allocatable :: name, what

      call check_options(source, card, [character(len=9) :: 'NAME=', 'TYPE=', 'STIFFNESS'], error)
      if (allocated(error)) return
      call require_option(source, card, 'NAME', name_option, error)
      if (allocated(error)) return
      name = card%options(name_option)%value
      if (.not. is_name(name)) then
         call raise(source, card%line, card%options(name_option)%value_column, &
                    'expected a section name (a letter, then letters, digits, _), found '''//clip(name)//'''', error)
         return
      end if
      if (find_section(builder, name) > 0) then
         call raise(source, card%line, card%options(name_option)%value_column, &
                    'expected a new section name, found '''//name//''' again', error)
         return
      end if
      stiffness_form = option_index(card, 'STIFFNESS') > 0
      type_option = option_index(card, 'TYPE')
      if (type_option > 0) then
         select case (to_upper(card%options(type_option)%value))
         case ('STIFFNESS')
            stiffness_form = .true.
         case ('MATERIAL')
            if (stiffness_form) then
               call raise(source, card%line, card%options(type_option)%value_column, &
                          'expected TYPE=STIFFNESS with the flag STIFFNESS, found ''MATERIAL''', error)
               return
            end if
         case default
            call raise(source, card%line, card%options(type_option)%value_column, &
                       'expected TYPE=STIFFNESS or TYPE=MATERIAL, found '''// &
                       clip(card%options(type_option)%value)//'''', error)
            return
         end select
      end if
      call require_one_data_line(source, card, error)
      if (allocated(error)) return

      line = card%data_lines(1)
      call data_fields(source, line, fields)
      if (stiffness_form) then
         n_values = 2
         call require_field_count(source, line, fields, 2, 2, 'EA, EI', error)
      else
         n_values = 3
         call require_field_count(source, line, fields, 3, 3, 'E, A, I', error)
      end if
      if (allocated(error)) return
      do i = 1, n_values
         if (stiffness_form) then
            what = trim(stiffness_names(i))
         else
            what = trim(material_names(i))
         end if
         call field_real(source, builder%parameters, line, fields(i), what, values(i), error)
         if (allocated(error)) return
         if (.not. values(i) > 0.0_dp) then
            call raise(source, line, fields(i)%column, 'expected a positive '//what//', found '// &
                       real_to_string(values(i)), error)
            return
         end if
      end do

      if (.not. allocated(builder%sections)) allocate (builder%sections(4))
      if (builder%n_sections == size(builder%sections)) call grow_sections(builder%sections)
      builder%n_sections = builder%n_sections + 1
      associate (section => builder%sections(builder%n_sections))
         section%name = name
         if (stiffness_form) then
            section%ea = values(1)
            section%ei = values(2)
         else
            section%ea = values(1)*values(2)
            section%ei = values(1)*values(3)
         end if
      end associate
   end subroutine read_section

   !> *NODE [, NSET=name]: lines `label, x, y`.
   subroutine read_node(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: i, line, label, existing, set_option
      type(field_t), allocatable :: fields(:)
      real(dp) :: x, y
      integer, allocatable :: created(:)

      call check_options(source, card, [character(len=5) :: 'NSET='], error)
      if (allocated(error)) return
      set_option = option_index(card, 'NSET')
      if (set_option > 0) then
         call check_set_name(source, card%line, card%options(set_option)%value_column, &
                             card%options(set_option)%value, error)
         if (allocated(error)) return
      end if
      allocate (created(card%n_data))
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 3, 3, 'label, x, y', error)
         if (allocated(error)) return
         call field_integer(source, builder%parameters, line, fields(1), 'a node label', label, error)
         if (allocated(error)) return
         if (label < 1) then
            call raise(source, line, fields(1)%column, 'expected a positive node label, found '// &
                       integer_to_string(label), error)
            return
         end if
         existing = find_node(builder, label)
         if (existing > 0) then
            call raise(source, line, fields(1)%column, 'expected a new node label, found '// &
                       integer_to_string(label)//' (defined at line '// &
                       integer_to_string(builder%node_line(existing))//')', error)
            return
         end if
         call field_real(source, builder%parameters, line, fields(2), 'x', x, error)
         if (allocated(error)) return
         call field_real(source, builder%parameters, line, fields(3), 'y', y, error)
         if (allocated(error)) return
         call add_node(builder, label, [x, y], line, fields(1)%column)
         created(i) = builder%n_nodes
      end do
      if (set_option > 0) call add_to_node_set(builder, card%options(set_option)%value, created)
   end subroutine read_node

   !> *ELEMENT, SECTION=s [, ELSET=name] [, TYPE=BEAM|TRUSS]: lines `label, node1, node2` (node labels).
   subroutine read_element(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, label, existing, section, set_option, kind
      integer :: ends(2), node_labels(2)
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: created(:)

      call check_options(source, card, [character(len=8) :: 'SECTION=', 'ELSET=', 'TYPE='], error)
      if (allocated(error)) return
      call read_element_type(source, card, kind, error)
      if (allocated(error)) return
      call card_section(source, card, builder, section, error)
      if (allocated(error)) return
      set_option = option_index(card, 'ELSET')
      if (set_option > 0) then
         call check_set_name(source, card%line, card%options(set_option)%value_column, &
                             card%options(set_option)%value, error)
         if (allocated(error)) return
      end if
      allocate (created(card%n_data))
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 3, 3, 'label, node1, node2', error)
         if (allocated(error)) return
         call field_integer(source, builder%parameters, line, fields(1), 'an element label', label, error)
         if (allocated(error)) return
         if (label < 1) then
            call raise(source, line, fields(1)%column, 'expected a positive element label, found '// &
                       integer_to_string(label), error)
            return
         end if
         existing = find_element(builder, label)
         if (existing > 0) then
            call raise(source, line, fields(1)%column, 'expected a new element label, found '// &
                       integer_to_string(label), error)
            return
         end if
         do j = 1, 2
            call field_integer(source, builder%parameters, line, fields(j + 1), 'a node label', &
                               node_labels(j), error)
            if (allocated(error)) return
            ends(j) = find_node(builder, node_labels(j))
            if (ends(j) == 0) then
               call raise(source, line, fields(j + 1)%column, 'expected a defined node label, found '// &
                          integer_to_string(node_labels(j)), error)
               return
            end if
         end do
         if (is_zero_length(builder, ends)) then
            call raise(source, line, fields(2)%column, 'expected an element of nonzero length, found nodes '// &
                       integer_to_string(node_labels(1))//' and '//integer_to_string(node_labels(2))// &
                       ' at the same point', error)
            return
         end if
         call add_element(builder, label, ends, section)
         created(i) = builder%n_elements
      end do
      call record_element_kind(builder%element_kind, created, kind)
      if (set_option > 0) call add_to_element_set(builder, card%options(set_option)%value, created)
   end subroutine read_element

   !> *ARC, *RING and *LINE, ELSET=name, SECTION=s: one data line that generates nodes and elements.
   !>
   !> ARC `xc, yc, R, theta_start, theta_end, n` (degrees, counter-clockwise from +x); RING `xc, yc, R,
   !> n [, theta_start]` (closed); LINE `x1, y1, x2, y2, n`. A generated node within merge_tolerance ×
   !> the generator's size (R, or the line's length) of an existing node is that node, so generators
   !> that meet are connected. Makes the element set `name` and node sets `name`, `name_start`,
   !> `name_end` (not for a ring) and `name_mid` (for an even n).
   subroutine read_generator(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: set_option, section, line, n, i, field_n, nodes_layout
      type(field_t), allocatable :: fields(:)
      real(dp) :: values(5), size_scale, angle, sweep, tolerance
      real(dp), allocatable :: points(:, :)
      integer, allocatable :: nodes(:), elements(:), candidates(:)
      character(len=:), allocatable :: name, layout
      logical :: closed

      call check_options(source, card, [character(len=8) :: 'ELSET=', 'SECTION='], error)
      if (allocated(error)) return
      call require_option(source, card, 'ELSET', set_option, error)
      if (allocated(error)) return
      name = card%options(set_option)%value
      call check_generator_sets(source, card, builder, name, error)
      if (allocated(error)) return
      call card_section(source, card, builder, section, error)
      if (allocated(error)) return
      call require_one_data_line(source, card, error)
      if (allocated(error)) return

      line = card%data_lines(1)
      call data_fields(source, line, fields)
      closed = card%keyword == 'RING'
      select case (card%keyword)
      case ('ARC')
         layout = 'xc, yc, R, theta_start, theta_end, n_elements'
         call require_field_count(source, line, fields, 6, 6, layout, error)
         field_n = 6
      case ('RING')
         layout = 'xc, yc, R, n_elements [, theta_start]'
         call require_field_count(source, line, fields, 4, 5, layout, error)
         field_n = 4
      case default
         layout = 'x1, y1, x2, y2, n_elements'
         call require_field_count(source, line, fields, 5, 5, layout, error)
         field_n = 5
      end select
      if (allocated(error)) return
      values = 0.0_dp
      do i = 1, size(fields)
         if (i == field_n) cycle
         call field_real(source, builder%parameters, line, fields(i), 'a number', values(min(i, 5)), error)
         if (allocated(error)) return
      end do
      call field_integer(source, builder%parameters, line, fields(field_n), 'the number of elements', n, error)
      if (allocated(error)) return
      if (n < 1 .or. (closed .and. n < 3)) then
         call raise(source, line, fields(field_n)%column, 'expected at least '// &
                    merge('3', '1', closed)//' elements, found '//integer_to_string(n), error)
         return
      end if

      nodes_layout = n + 1
      if (closed) nodes_layout = n
      allocate (points(2, nodes_layout))
      select case (card%keyword)
      case ('ARC', 'RING')
         if (.not. values(3) > 0.0_dp) then
            call raise(source, line, fields(3)%column, 'expected a positive radius R, found '// &
                       real_to_string(values(3)), error)
            return
         end if
         size_scale = values(3)
         if (closed) then
            sweep = 360.0_dp
         else
            sweep = values(5) - values(4)
            if (.not. abs(sweep) > 0.0_dp .or. abs(sweep) > 360.0_dp) then
               call raise(source, line, fields(5)%column, 'expected theta_end different from theta_start ' // &
                          'by at most 360 degrees, found a sweep of '//real_to_string(sweep), error)
               return
            end if
         end if
         do i = 1, nodes_layout
            ! closed: the fifth field (default 0) is the start angle
            if (closed) then
               angle = values(5) + sweep*real(i - 1, dp)/real(n, dp)
            else
               angle = values(4) + sweep*real(i - 1, dp)/real(n, dp)
            end if
            points(:, i) = values(1:2) + values(3)*[cos_degrees(angle), sin_degrees(angle)]
         end do
      case default
         size_scale = norm2(values(3:4) - values(1:2))
         if (.not. size_scale > 0.0_dp) then
            call raise(source, line, fields(3)%column, 'expected a line of nonzero length, found both ends at (' // &
                       real_to_string(values(1))//', '//real_to_string(values(2))//')', error)
            return
         end if
         do i = 1, nodes_layout
            points(:, i) = values(1:2) + (values(3:4) - values(1:2))*(real(i - 1, dp)/real(n, dp))
         end do
         ! the last point exactly at the given end, so that a following generator can start there
         points(:, nodes_layout) = values(3:4)
      end select

      ! Merging candidates: the existing nodes in the generator's bounding box (few, typically the
      ! shared ends), and the generator's own first node (an arc of 360 degrees ends on it). Other own
      ! nodes cannot coincide, so the search stays linear in the size of the deck.
      tolerance = merge_tolerance*size_scale
      candidates = nodes_in_box(builder, minval(points, dim=2) - tolerance, maxval(points, dim=2) + tolerance)
      allocate (nodes(nodes_layout), elements(n))
      do i = 1, nodes_layout
         nodes(i) = find_coincident_node(builder, candidates, points(:, i), tolerance)
         if (nodes(i) == 0 .and. i > 1) then
            nodes(i) = find_coincident_node(builder, nodes(1:1), points(:, i), tolerance)
         end if
         if (nodes(i) == 0) then
            call add_node(builder, builder%largest_node_label + 1, points(:, i), line, fields(1)%column)
            nodes(i) = builder%n_nodes
         end if
      end do
      do i = 1, n
         associate (ends => [nodes(i), nodes(modulo(i, nodes_layout) + 1)])
            if (ends(1) == ends(2)) then
               call raise(source, line, fields(field_n)%column, 'expected elements of nonzero length, found ' // &
                          'element '//integer_to_string(i)//' of '//integer_to_string(n)// &
                          ' with both ends at one node', error)
               return
            end if
            call add_element(builder, builder%largest_element_label + 1, ends, section)
         end associate
         elements(i) = builder%n_elements
      end do

      call add_to_element_set(builder, name, elements)
      call add_to_node_set(builder, name, nodes)
      call add_to_node_set(builder, name//'_start', nodes(1:1))
      if (.not. closed) call add_to_node_set(builder, name//'_end', nodes(n + 1:n + 1))
      if (modulo(n, 2) == 0) call add_to_node_set(builder, name//'_mid', nodes(n/2 + 1:n/2 + 1))
   end subroutine read_generator

   !> *NSET, NSET=name [, GENERATE]: node labels and node-set names, or `first, last [, step]` lines.
   subroutine read_node_set(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: set_option
      integer, allocatable :: members(:)

      call check_options(source, card, [character(len=8) :: 'NSET=', 'GENERATE'], error)
      if (allocated(error)) return
      call require_option(source, card, 'NSET', set_option, error)
      if (allocated(error)) return
      call check_set_name(source, card%line, card%options(set_option)%value_column, &
                          card%options(set_option)%value, error)
      if (allocated(error)) return
      call read_set_members(source, card, builder, .true., option_index(card, 'GENERATE') > 0, members, error)
      if (allocated(error)) return
      call add_to_node_set(builder, card%options(set_option)%value, members)
   end subroutine read_node_set

   !> *ELSET, ELSET=name [, GENERATE]: element labels and element-set names, or `first, last [, step]`.
   subroutine read_element_set(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: set_option
      integer, allocatable :: members(:)

      call check_options(source, card, [character(len=8) :: 'ELSET=', 'GENERATE'], error)
      if (allocated(error)) return
      call require_option(source, card, 'ELSET', set_option, error)
      if (allocated(error)) return
      call check_set_name(source, card%line, card%options(set_option)%value_column, &
                          card%options(set_option)%value, error)
      if (allocated(error)) return
      call read_set_members(source, card, builder, .false., option_index(card, 'GENERATE') > 0, members, error)
      if (allocated(error)) return
      call add_to_element_set(builder, card%options(set_option)%value, members)
   end subroutine read_element_set

   !> *BOUNDARY: lines `target, type` with a named type, or `target, first_dof [, last_dof]`.
   subroutine read_boundary(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, first_dof, last_dof
      logical :: held(3), named
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: nodes(:)

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 2, 3, 'target, type or target, first_dof, last_dof', error)
         if (allocated(error)) return
         call resolve_nodes(source, builder, line, fields(1), nodes, error)
         if (allocated(error)) return

         named = .true.
         held = .false.
         select case (to_upper(fields(2)%text))
         case ('FIXED', 'ENCASTRE')
            held = [.true., .true., .true.]
         case ('PINNED')
            held = [.true., .true., .false.]
         case ('ROLLER_X')
            held(dof_uy) = .true.
         case ('ROLLER_Y')
            held(dof_ux) = .true.
         case ('XSYMM')
            held(dof_ux) = .true.
            held(dof_rz) = .true.
         case ('YSYMM')
            held(dof_uy) = .true.
            held(dof_rz) = .true.
         case default
            named = .false.
         end select
         if (named) then
            if (size(fields) > 2) then
               call raise(source, line, fields(3)%column, 'expected no field after '''// &
                          to_upper(fields(2)%text)//''', found '''//clip(fields(3)%text)//'''', error)
               return
            end if
         else
            if (is_name(fields(2)%text) .and. find_parameter(builder%parameters, fields(2)%text) == 0) then
               call raise(source, line, fields(2)%column, 'expected FIXED, PINNED, ROLLER_X, ROLLER_Y, ' // &
                          'XSYMM, YSYMM or a DOF 1 to 3, found '''//clip(fields(2)%text)//'''', error)
               return
            end if
            call read_dof(source, builder, line, fields(2), first_dof, error)
            if (allocated(error)) return
            last_dof = first_dof
            if (size(fields) > 2) then
               call read_dof(source, builder, line, fields(3), last_dof, error)
               if (allocated(error)) return
               if (last_dof < first_dof) then
                  call raise(source, line, fields(3)%column, 'expected a last DOF not below the first (' // &
                             integer_to_string(first_dof)//'), found '//integer_to_string(last_dof), error)
                  return
               end if
            end if
            held(first_dof:last_dof) = .true.
         end if
         do j = 1, size(nodes)
            builder%fixed(:, nodes(j)) = builder%fixed(:, nodes(j)) .or. held
         end do
      end do
   end subroutine read_boundary

   !> *CLOAD: lines `target, dof, value` with dof 1|2|3 or FX|FY|MZ; loads on one node are summed.
   subroutine read_concentrated_load(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, dof
      real(dp) :: value
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: nodes(:)

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 3, 3, 'target, dof, value', error)
         if (allocated(error)) return
         call resolve_nodes(source, builder, line, fields(1), nodes, error)
         if (allocated(error)) return
         select case (to_upper(fields(2)%text))
         case ('FX')
            dof = dof_ux
         case ('FY')
            dof = dof_uy
         case ('MZ')
            dof = dof_rz
         case default
            if (is_name(fields(2)%text) .and. find_parameter(builder%parameters, fields(2)%text) == 0) then
               call raise(source, line, fields(2)%column, 'expected FX, FY, MZ or a DOF 1 to 3, found '''// &
                          clip(fields(2)%text)//'''', error)
               return
            end if
            call read_dof(source, builder, line, fields(2), dof, error)
            if (allocated(error)) return
         end select
         call field_real(source, builder%parameters, line, fields(3), 'a load value', value, error)
         if (allocated(error)) return
         do j = 1, size(nodes)
            builder%nodal_load(dof, nodes(j)) = builder%nodal_load(dof, nodes(j)) + value
         end do
      end do
   end subroutine read_concentrated_load

   !> *DLOAD [, FOLLOWER]: lines `elset, type, value` with type PX, PY (per unit initial length, global)
   !> or P (normal pressure along the element's left normal). FOLLOWER is only for P.
   !>
   !> Loads of one kind on one element are summed into one record: an element has at most one fixed-
   !> direction record, one pressure record and one follower-pressure record.
   subroutine read_distributed_load(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, slot, record, kind
      logical :: follower
      real(dp) :: value
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: elements(:)
      character(len=:), allocatable :: load_type

      call check_options(source, card, [character(len=8) :: 'FOLLOWER'], error)
      if (allocated(error)) return
      follower = option_index(card, 'FOLLOWER') > 0
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 3, 3, 'elset, type, value', error)
         if (allocated(error)) return
         call resolve_elements(source, builder, line, fields(1), elements, error)
         if (allocated(error)) return
         load_type = to_upper(fields(2)%text)
         select case (load_type)
         case ('PX', 'PY')
            if (follower) then
               call raise(source, line, fields(2)%column, 'expected type P with FOLLOWER, found '''// &
                          load_type//'''', error)
               return
            end if
            kind = load_fixed_direction
            slot = 1
         case ('P')
            kind = load_pressure
            slot = 2
            if (follower) slot = 3
         case default
            call raise(source, line, fields(2)%column, 'expected a load type PX, PY or P, found '''// &
                       clip(fields(2)%text)//'''', error)
            return
         end select
         call field_real(source, builder%parameters, line, fields(3), 'a load value', value, error)
         if (allocated(error)) return
         do j = 1, size(elements)
            record = builder%load_index(slot, elements(j))
            if (record == 0) then
               call add_load(builder, elements(j), kind, slot == 3)
               record = builder%n_loads
               builder%load_index(slot, elements(j)) = record
            end if
            select case (load_type)
            case ('PX')
               builder%loads(record)%qx = builder%loads(record)%qx + value
            case ('PY')
               builder%loads(record)%qy = builder%loads(record)%qy + value
            case default
               builder%loads(record)%pressure = builder%loads(record)%pressure + value
            end select
         end do
      end do
   end subroutine read_distributed_load

   !> *TRACK: lines `name, target, component [, scale]`; the target is one node, component UX|UY|RZ.
   subroutine read_track(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, dof
      real(dp) :: scale
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: nodes(:)
      type(track_t), allocatable :: grown(:)

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 3, 4, 'name, target, component [, scale]', error)
         if (allocated(error)) return
         if (.not. is_name(fields(1)%text)) then
            call raise(source, line, fields(1)%column, 'expected a track name (a letter, then letters, ' // &
                       'digits, _), found '''//clip(fields(1)%text)//'''', error)
            return
         end if
         do j = 1, builder%n_tracks
            if (same_text(builder%tracks(j)%name, fields(1)%text)) then
               call raise(source, line, fields(1)%column, 'expected a new track name, found '''// &
                          fields(1)%text//''' again', error)
               return
            end if
         end do
         call resolve_nodes(source, builder, line, fields(2), nodes, error)
         if (allocated(error)) return
         if (size(nodes) /= 1) then
            call raise(source, line, fields(2)%column, 'expected a single node, found the set '''// &
                       fields(2)%text//''' of '//integer_to_string(size(nodes))//' nodes', error)
            return
         end if
         select case (to_upper(fields(3)%text))
         case ('UX')
            dof = dof_ux
         case ('UY')
            dof = dof_uy
         case ('RZ')
            dof = dof_rz
         case default
            call raise(source, line, fields(3)%column, 'expected a component UX, UY or RZ, found '''// &
                       clip(fields(3)%text)//'''', error)
            return
         end select
         scale = 1.0_dp
         if (size(fields) == 4) then
            call field_real(source, builder%parameters, line, fields(4), 'a scale', scale, error)
            if (allocated(error)) return
         end if

         if (.not. allocated(builder%tracks)) allocate (builder%tracks(4))
         if (builder%n_tracks == size(builder%tracks)) then
            allocate (grown(2*size(builder%tracks)))
            grown(1:builder%n_tracks) = builder%tracks(1:builder%n_tracks)
            call move_alloc(grown, builder%tracks)
         end if
         builder%n_tracks = builder%n_tracks + 1
         builder%tracks(builder%n_tracks)%name = fields(1)%text
         builder%tracks(builder%n_tracks)%node = nodes(1)
         builder%tracks(builder%n_tracks)%dof = dof
         builder%tracks(builder%n_tracks)%scale = scale
      end do
   end subroutine read_track

   !> *FOUNDATION, ELSET=set, MODULUS=K, SIDE=INNER|OUTER|LEFT|RIGHT or DIRECTION=angle [, BILATERAL]
   !> [, NAME=name] [, SCALE=s]: a Winkler foundation along an element set, lumped to its nodes.
   !>
   !> Node stiffness k = K × (half the initial length of the node's adjacent elements in the set): a
   !> Winkler bed (Kerr 1964) lumped onto the nodes by the trapezoidal rule for ∫ K w δw ds, i.e. a
   !> diagonal foundation matrix C_b in the paper's Eq. (7), Δr_b = C_b Δu_b; flexibility 1/k.
   !> The reaction direction n (the direction in which the foundation pushes, toward the free side) is
   !> fixed (DIRECTION) or the nodal normal of the set on the side away from the foundation (SIDE; the
   !> concave side of INNER/OUTER from the sign of the set's total turning). Gap g = n·u (offset 0).
   subroutine read_foundation(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: set_option, modulus_option, side_option, direction_option, status, bad, i
      real(dp) :: modulus, scale, angle, turning, sign
      integer, allocatable :: elements(:), nodes(:)
      real(dp), allocatable :: lengths(:), normals(:, :), s(:)
      type(field_t) :: field
      type(contact_candidate_t), allocatable :: candidates(:)
      character(len=:), allocatable :: name, side

      call check_options(source, card, [character(len=10) :: 'ELSET=', 'MODULUS=', 'SIDE=', 'DIRECTION=', &
                                        'BILATERAL', 'NAME=', 'SCALE='], error)
      if (allocated(error)) return
      call contact_group_name(source, card, builder, 'foundation', name, error)
      if (allocated(error)) return
      call require_option(source, card, 'ELSET', set_option, error)
      if (allocated(error)) return
      field = option_field(card, set_option)
      call resolve_elements(source, builder, card%line, field, elements, error)
      if (allocated(error)) return
      if (size(elements) == 0) then
         call raise(source, card%line, field%column, 'expected an element set with elements, found '''// &
                    field%text//''' empty', error)
         return
      end if
      call require_option(source, card, 'MODULUS', modulus_option, error)
      if (allocated(error)) return
      call option_real(source, card, builder, modulus_option, 'a modulus', modulus, error)
      if (allocated(error)) return
      ! MODULUS = 0 is no foundation (a group without candidates), so that a sweep over k can start at 0.
      if (modulus < 0.0_dp .or. .not. modulus < huge(1.0_dp)) then
         call raise(source, card%line, card%options(modulus_option)%value_column, &
                    'expected a MODULUS >= 0 (0: no foundation), found '//real_to_string(modulus), error)
         return
      end if
      call contact_scale(source, card, builder, scale, error)
      if (allocated(error)) return
      side_option = option_index(card, 'SIDE')
      direction_option = option_index(card, 'DIRECTION')
      if (side_option > 0 .and. direction_option > 0) then
         call raise(source, card%line, card%options(direction_option)%column, 'expected one of SIDE= ' // &
                    'and DIRECTION= on *FOUNDATION, found both', error)
         return
      else if (side_option == 0 .and. direction_option == 0) then
         call raise(source, card%line, card%column, 'expected SIDE=INNER|OUTER|LEFT|RIGHT or ' // &
                    'DIRECTION=angle on *FOUNDATION, found neither', error)
         return
      end if
      if (card%n_data > 0) then
         call raise(source, card%data_lines(1), verify(source%lines(card%data_lines(1))%text, ' '), &
                    'expected no data line after *FOUNDATION (all is in its options), found one', error)
         return
      end if

      associate (coordinates => builder%coordinates(:, 1:builder%n_nodes), &
                 connectivity => builder%connectivity(:, 1:builder%n_elements))
         nodes = chain_nodes(builder%n_nodes, connectivity, elements)
         lengths = tributary_lengths(coordinates, connectivity, elements, nodes)
         allocate (normals(2, size(nodes)))
         if (direction_option > 0) then
            call option_real(source, card, builder, direction_option, 'an angle in degrees', angle, error)
            if (allocated(error)) return
            normals = spread([cos_degrees(angle), sin_degrees(angle)], 2, size(nodes))
         else
            side = to_upper(card%options(side_option)%value)
            if (side /= 'LEFT' .and. side /= 'RIGHT' .and. side /= 'INNER' .and. side /= 'OUTER') then
               call raise(source, card%line, card%options(side_option)%value_column, 'expected SIDE=INNER, ' // &
                          'OUTER, LEFT or RIGHT, found '''//clip(card%options(side_option)%value)//'''', error)
               return
            end if
            call nodal_left_normals(coordinates, connectivity, elements, nodes, normals, status, bad)
            if (status /= normals_valid) then
               call raise(source, card%line, card%options(set_option)%value_column, 'expected a chain of ' // &
                          'elements running one way for SIDE= (use DIRECTION= otherwise), found at node '// &
                          integer_to_string(builder%node_label(nodes(bad)))//' '// &
                          normals_problem(status), error)
               return
            end if
            ! sign: +1 when the foundation is on the right (n = + left normal), -1 on the left
            select case (side)
            case ('LEFT')
               sign = -1.0_dp
            case ('RIGHT')
               sign = 1.0_dp
            case default
               turning = total_turning(coordinates, connectivity, elements)
               if (abs(turning) <= straight_tolerance) then
                  call raise(source, card%line, card%options(side_option)%value_column, 'expected a curved ' // &
                             'element set for SIDE='//side//' (no concave side on a straight one: use ' // &
                             'SIDE=LEFT|RIGHT or DIRECTION=angle), found '''//field%text//''' straight', error)
                  return
               end if
               ! turning > 0: the set turns counter-clockwise, its concave side is the left one
               sign = merge(-1.0_dp, 1.0_dp, turning > 0.0_dp)
               if (side == 'OUTER') sign = -sign
            end select
            normals = sign*normals
         end if
         s = scale*path_coordinates(coordinates, nodes)
      end associate

      allocate (candidates(size(nodes)))
      do i = 1, size(nodes)
         candidates(i)%node = nodes(i)
         candidates(i)%gap_kind = gap_fixed_direction
         candidates(i)%direction = normals(:, i)
         candidates(i)%offset = 0.0_dp
         if (modulus > 0.0_dp) candidates(i)%flexibility = 1.0_dp/(modulus*lengths(i))
         candidates(i)%bilateral = option_index(card, 'BILATERAL') > 0
         candidates(i)%coordinate = s(i)
      end do
      if (.not. modulus > 0.0_dp) deallocate (candidates)
      if (.not. allocated(candidates)) allocate (candidates(0))
      call add_contact_group(builder, name, candidates)
   end subroutine read_foundation

   !> What is wrong at a node whose normal `nodal_left_normals` could not make.
   pure function normals_problem(status) result(text)
      integer, intent(in) :: status
      character(len=:), allocatable :: text
      select case (status)
      case (normals_branch)
         text = 'more than two elements of the set'
      case (normals_opposed)
         text = 'two elements of the set running in opposite directions'
      case default
         text = 'two elements of the set folded back on each other'
      end select
   end function normals_problem

   !> *SPRING [, BILATERAL] [, NAME=name]: lines `target, angle_deg, k`, a discrete spring of stiffness k
   !> at each node of the target pushing the node along the direction `angle` (gap g = n·u, offset 0).
   subroutine read_spring(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, count
      real(dp) :: angle, stiffness
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: nodes(:)
      real(dp), allocatable :: s(:)
      type(contact_candidate_t), allocatable :: candidates(:), grown(:)
      character(len=:), allocatable :: name

      call check_options(source, card, [character(len=9) :: 'BILATERAL', 'NAME='], error)
      if (allocated(error)) return
      call contact_group_name(source, card, builder, 'spring', name, error)
      if (allocated(error)) return
      if (card%n_data == 0) then
         call raise(source, card%line, len_trim(source%lines(card%line)%text) + 1, 'expected data lines ' // &
                    '`target, angle, k` after *SPRING, found none', error)
         return
      end if
      allocate (candidates(8))
      count = 0
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 3, 3, 'target, angle, k', error)
         if (allocated(error)) return
         call resolve_nodes(source, builder, line, fields(1), nodes, error)
         if (allocated(error)) return
         call field_real(source, builder%parameters, line, fields(2), 'an angle in degrees', angle, error)
         if (allocated(error)) return
         call field_real(source, builder%parameters, line, fields(3), 'a stiffness k', stiffness, error)
         if (allocated(error)) return
         if (.not. stiffness > 0.0_dp) then
            call raise(source, line, fields(3)%column, 'expected a positive stiffness k, found '// &
                       real_to_string(stiffness), error)
            return
         end if
         if (count + size(nodes) > size(candidates)) then
            allocate (grown(max(2*size(candidates), count + size(nodes))))
            grown(1:count) = candidates(1:count)
            call move_alloc(grown, candidates)
         end if
         do j = 1, size(nodes)
            count = count + 1
            candidates(count)%node = nodes(j)
            candidates(count)%gap_kind = gap_fixed_direction
            candidates(count)%direction = [cos_degrees(angle), sin_degrees(angle)]
            candidates(count)%offset = 0.0_dp
            candidates(count)%flexibility = 1.0_dp/stiffness
            candidates(count)%bilateral = option_index(card, 'BILATERAL') > 0
         end do
      end do
      candidates = candidates(1:count)
      nodes = candidates%node
      s = path_coordinates(builder%coordinates(:, 1:builder%n_nodes), nodes)
      candidates%coordinate = s
      call add_contact_group(builder, name, candidates)
   end subroutine read_spring

   !> *OBSTACLE, TYPE=PLANE|CIRCLE, NSET=set [, SIDE=INSIDE|OUTSIDE] [, STIFFNESS=k] [, END_FACTOR=f]
   !> [, NAME=name] [, SCALE=s]: a rigid (or, with STIFFNESS, elastic) obstacle for every node of the set.
   !>
   !> PLANE `px, py, angle`: the line through p whose normal n = (cos, sin) points to the free side;
   !> g = n·(x0 − p) + n·u. CIRCLE `xc, yc, R`: g = R − |x − c| (INSIDE a cavity, the default) or
   !> |x − c| − R (OUTSIDE a cylinder). A node that starts inside the obstacle is an error.
   subroutine read_obstacle(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: type_option, set_option, side_option, stiffness_option, factor_option, line, i, gap_kind
      real(dp) :: values(3), scale, stiffness, end_factor, normal(2), gap, tolerance, factor
      type(field_t) :: field
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: nodes(:)
      real(dp), allocatable :: s(:)
      type(contact_candidate_t), allocatable :: candidates(:)
      character(len=:), allocatable :: name, kind, layout, surface
      character(len=5), parameter :: plane_names(3) = ['px   ', 'py   ', 'angle']
      character(len=5), parameter :: circle_names(3) = ['xc   ', 'yc   ', 'R    ']

      call check_options(source, card, [character(len=11) :: 'TYPE=', 'NSET=', 'SIDE=', 'STIFFNESS=', &
                                        'END_FACTOR=', 'NAME=', 'SCALE='], error)
      if (allocated(error)) return
      call contact_group_name(source, card, builder, 'obstacle', name, error)
      if (allocated(error)) return
      call require_option(source, card, 'TYPE', type_option, error)
      if (allocated(error)) return
      kind = to_upper(card%options(type_option)%value)
      if (kind /= 'PLANE' .and. kind /= 'CIRCLE') then
         call raise(source, card%line, card%options(type_option)%value_column, 'expected TYPE=PLANE or ' // &
                    'TYPE=CIRCLE, found '''//clip(card%options(type_option)%value)//'''', error)
         return
      end if
      call require_option(source, card, 'NSET', set_option, error)
      if (allocated(error)) return
      field = option_field(card, set_option)
      call resolve_nodes(source, builder, card%line, field, nodes, error)
      if (allocated(error)) return
      if (size(nodes) == 0) then
         call raise(source, card%line, field%column, 'expected a node set with nodes, found '''// &
                    field%text//''' empty', error)
         return
      end if

      gap_kind = gap_fixed_direction
      if (kind == 'CIRCLE') gap_kind = gap_circle_inside
      side_option = option_index(card, 'SIDE')
      if (side_option > 0) then
         if (kind /= 'CIRCLE') then
            call raise(source, card%line, card%options(side_option)%column, 'expected SIDE= only with ' // &
                       'TYPE=CIRCLE (a plane''s free side is its normal''s), found it with TYPE='//kind, error)
            return
         end if
         select case (to_upper(card%options(side_option)%value))
         case ('INSIDE')
            gap_kind = gap_circle_inside
         case ('OUTSIDE')
            gap_kind = gap_circle_outside
         case default
            call raise(source, card%line, card%options(side_option)%value_column, 'expected SIDE=INSIDE ' // &
                       'or SIDE=OUTSIDE, found '''//clip(card%options(side_option)%value)//'''', error)
            return
         end select
      end if

      stiffness = 0.0_dp
      stiffness_option = option_index(card, 'STIFFNESS')
      if (stiffness_option > 0) then
         call option_real(source, card, builder, stiffness_option, 'a stiffness', stiffness, error)
         if (allocated(error)) return
         ! STIFFNESS=0 is the rigid obstacle, so that a sweep over k (-D k=...) can include it.
         if (stiffness < 0.0_dp .or. .not. stiffness < huge(1.0_dp)) then
            call raise(source, card%line, card%options(stiffness_option)%value_column, 'expected a ' // &
                       'STIFFNESS >= 0 (0 or none: a rigid obstacle), found '// &
                       real_to_string(stiffness), error)
            return
         end if
      end if
      end_factor = 1.0_dp
      factor_option = option_index(card, 'END_FACTOR')
      if (factor_option > 0) then
         if (stiffness_option == 0) then
            call raise(source, card%line, card%options(factor_option)%column, 'expected END_FACTOR= only ' // &
                       'with STIFFNESS= (a rigid obstacle has no stiffness to scale), found it alone', error)
            return
         end if
         call option_real(source, card, builder, factor_option, 'a factor', end_factor, error)
         if (allocated(error)) return
         if (.not. end_factor > 0.0_dp) then
            call raise(source, card%line, card%options(factor_option)%value_column, 'expected a positive ' // &
                       'END_FACTOR, found '//real_to_string(end_factor), error)
            return
         end if
      end if
      call contact_scale(source, card, builder, scale, error)
      if (allocated(error)) return

      call require_one_data_line(source, card, error)
      if (allocated(error)) return
      line = card%data_lines(1)
      call data_fields(source, line, fields)
      if (kind == 'PLANE') then
         layout = 'px, py, angle'
      else
         layout = 'xc, yc, R'
      end if
      call require_field_count(source, line, fields, 3, 3, layout, error)
      if (allocated(error)) return
      do i = 1, 3
         if (kind == 'PLANE') then
            call field_real(source, builder%parameters, line, fields(i), trim(plane_names(i)), values(i), error)
         else
            call field_real(source, builder%parameters, line, fields(i), trim(circle_names(i)), values(i), error)
         end if
         if (allocated(error)) return
      end do
      if (kind == 'CIRCLE' .and. .not. values(3) > 0.0_dp) then
         call raise(source, line, fields(3)%column, 'expected a positive radius R, found '// &
                    real_to_string(values(3)), error)
         return
      end if

      tolerance = penetration_tolerance*model_size(builder)
      normal = [cos_degrees(values(3)), sin_degrees(values(3))]
      allocate (candidates(size(nodes)))
      do i = 1, size(nodes)
         associate (x0 => builder%coordinates(:, nodes(i)))
            select case (gap_kind)
            case (gap_fixed_direction)
               gap = dot_product(normal, x0 - values(1:2))
               surface = 'the plane'
            case (gap_circle_inside)
               gap = values(3) - norm2(x0 - values(1:2))
               surface = 'the circular cavity'
            case default
               gap = norm2(x0 - values(1:2)) - values(3)
               surface = 'the cylinder'
            end select
         end associate
         if (gap < -tolerance) then
            call raise(source, line, fields(1)%column, 'expected every node of '''//field%text// &
                       ''' clear of '//surface//', found node '//integer_to_string(builder%node_label(nodes(i)))// &
                       ' inside it by '//real_to_string(-gap), error)
            return
         end if
         candidates(i)%node = nodes(i)
         candidates(i)%gap_kind = gap_kind
         if (gap_kind == gap_fixed_direction) then
            candidates(i)%direction = normal
            candidates(i)%offset = gap
         else
            candidates(i)%centre = values(1:2)
            candidates(i)%radius = values(3)
         end if
         if (stiffness_option > 0) then
            factor = 1.0_dp
            if (i == 1 .or. i == size(nodes)) factor = end_factor
            if (stiffness > 0.0_dp) candidates(i)%flexibility = 1.0_dp/(factor*stiffness)
         end if
      end do
      s = scale*path_coordinates(builder%coordinates(:, 1:builder%n_nodes), nodes)
      candidates%coordinate = s
      call add_contact_group(builder, name, candidates)
   end subroutine read_obstacle

   !> *STATIC: a linear static analysis (also what a deck without an analysis card gets).
   subroutine read_static(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      call require_analysis_once(source, card, builder, error)
      if (allocated(error)) return
      if (card%n_data > 0) then
         call raise(source, card%data_lines(1), verify(source%lines(card%data_lines(1))%text, ' '), &
                    'expected no data line after *STATIC, found one', error)
         return
      end if
   end subroutine read_static

   !> *PATH: a nonlinear analysis that follows the equilibrium path (docs/input.md, docs/theory.md §2).
   !> Options CONTROL=, ITERATION=, NODE= and DOF= (displacement control); data lines `key = value`.
   subroutine read_path(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: i, k, line, equals, first
      integer, allocatable :: nodes(:)
      character(len=:), allocatable :: text, key
      type(field_t) :: field
      real(dp) :: value

      call check_options(source, card, [character(len=10) :: 'CONTROL=', 'ITERATION=', 'NODE=', 'DOF='], error)
      if (allocated(error)) return
      call require_analysis_once(source, card, builder, error)
      if (allocated(error)) return
      builder%analysis%kind = analysis_nonlinear
      k = option_index(card, 'CONTROL')
      if (k > 0) then
         select case (to_upper(card%options(k)%value))
         case ('ARCLENGTH', 'ARC_LENGTH')
            builder%analysis%control = control_arclength
         case ('LOAD')
            builder%analysis%control = control_load
         case ('DISPLACEMENT')
            builder%analysis%control = control_displacement
         case default
            call raise(source, card%line, card%options(k)%value_column, 'expected CONTROL=ARCLENGTH, '// &
                       'LOAD or DISPLACEMENT, found '''//clip(card%options(k)%value)//'''', error)
            return
         end select
      end if
      k = option_index(card, 'ITERATION')
      if (k > 0) then
         select case (to_upper(card%options(k)%value))
         case ('CHAN')
            builder%analysis%iteration = iteration_chan
         case ('CYLINDRICAL')
            builder%analysis%iteration = iteration_cylindrical
         case ('RIKS')
            builder%analysis%iteration = iteration_riks
         case default
            call raise(source, card%line, card%options(k)%value_column, 'expected ITERATION=CHAN, '// &
                       'CYLINDRICAL or RIKS, found '''//clip(card%options(k)%value)//'''', error)
            return
         end select
      end if
      if (builder%analysis%control == control_displacement) then
         call require_option(source, card, 'NODE', k, error)
         if (allocated(error)) return
         field%text = card%options(k)%value
         field%column = card%options(k)%value_column
         call resolve_nodes(source, builder, card%line, field, nodes, error)
         if (allocated(error)) return
         if (size(nodes) /= 1) then
            call raise(source, card%line, field%column, 'expected a single node to control, found '// &
                       integer_to_string(size(nodes))//' nodes', error)
            return
         end if
         builder%analysis%control_node = nodes(1)
         call require_option(source, card, 'DOF', k, error)
         if (allocated(error)) return
         select case (to_upper(card%options(k)%value))
         case ('UX', '1')
            builder%analysis%control_dof = dof_ux
         case ('UY', '2')
            builder%analysis%control_dof = dof_uy
         case ('RZ', '3')
            builder%analysis%control_dof = dof_rz
         case default
            call raise(source, card%line, card%options(k)%value_column, 'expected DOF=UX, UY or RZ, '// &
                       'found '''//clip(card%options(k)%value)//'''', error)
            return
         end select
      end if

      do i = 1, card%n_data
         line = card%data_lines(i)
         text = source%lines(line)%text
         first = verify(text, ' ')
         equals = index(text, '=')
         if (equals == 0) then
            call raise(source, line, first, 'expected a line `key = value` (see docs/input.md, *PATH)', error)
            return
         end if
         key = to_upper(trim(adjustl(text(:equals - 1))))
         field%column = equals + verify(text(equals + 1:)//'x', ' ')
         field%text = trim(adjustl(text(equals + 1:)))
         if (key == 'STOP_TRACK') then
            if (.not. is_name(field%text)) then
               call raise(source, line, field%column, 'expected the name of a *TRACK, found '''// &
                          clip(field%text)//'''', error)
               return
            end if
            builder%stop_track = field%text
            builder%stop_track_line = line
            builder%stop_track_column = field%column
            cycle
         end if
         call field_real(source, builder%parameters, line, field, 'a value for '//key, value, error)
         if (allocated(error)) return
         call set_path_value(source, line, first, field%column, key, value, builder%analysis, error)
         if (allocated(error)) return
      end do
      if (.not. abs(builder%analysis%first_increment) > 0.0_dp) then
         call raise(source, card%line, card%column, 'expected a data line `increment = value` '// &
                    '(the first load increment, non-zero) after *PATH', error)
         return
      end if
      if (allocated(builder%stop_track) .and. .not. builder%analysis%stop_value > 0.0_dp) then
         call raise(source, builder%stop_track_line, builder%stop_track_column, 'expected a positive '// &
                    '`stop_value = ...` with stop_track', error)
         return
      end if
   end subroutine read_path

   !> One `key = value` of *PATH into the analysis options (keys in docs/input.md).
   subroutine set_path_value(source, line, key_column, value_column, key, value, analysis, error)
      type(source_t), intent(in) :: source
      integer, intent(in) :: line, key_column, value_column
      character(len=*), intent(in) :: key
      real(dp), intent(in) :: value
      type(analysis_options_t), intent(inout) :: analysis
      type(error_t), allocatable, intent(out) :: error
      select case (key)
      case ('INCREMENT')
         analysis%first_increment = value
         return
      case ('STOP_VALUE')
         analysis%stop_value = value
         return
      case ('MIN_INCREMENT', 'MAX_INCREMENT', 'LAMBDA_MAX', 'TOLERANCE', 'FORCE_TOLERANCE', &
            'DISPLACEMENT_TOLERANCE', 'STEPS', 'ITERATIONS', 'MAX_ITERATIONS', 'MAX_CUTS', 'SHAPE_EVERY')
         if (.not. value > 0.0_dp) then
            call raise(source, line, value_column, 'expected a positive value for '//key//', found '// &
                       real_to_string(value), error)
            return
         end if
      case default
         call raise(source, line, key_column, 'expected one of the keys increment, min_increment, '// &
                    'max_increment, steps, lambda_max, stop_track, stop_value, tolerance, force_tolerance, '// &
                    'displacement_tolerance, iterations, max_iterations, max_cuts, shape_every; found '''// &
                    clip(key)//'''', error)
         return
      end select
      select case (key)
      case ('STEPS', 'ITERATIONS', 'MAX_ITERATIONS', 'MAX_CUTS', 'SHAPE_EVERY')
         if (abs(value - anint(value)) > 0.0_dp .or. value > real(huge(1), dp)) then
            call raise(source, line, value_column, 'expected a whole number for '//key//', found '// &
                       real_to_string(value), error)
            return
         end if
      end select
      select case (key)
      case ('MIN_INCREMENT')
         analysis%min_increment = value
      case ('MAX_INCREMENT')
         analysis%max_increment = value
      case ('LAMBDA_MAX')
         analysis%lambda_max = value
      case ('TOLERANCE')
         analysis%force_tolerance = value
         analysis%displacement_tolerance = value
      case ('FORCE_TOLERANCE')
         analysis%force_tolerance = value
      case ('DISPLACEMENT_TOLERANCE')
         analysis%displacement_tolerance = value
      case ('STEPS')
         analysis%max_steps = nint(value)
      case ('ITERATIONS')
         analysis%desired_iterations = nint(value)
      case ('MAX_ITERATIONS')
         analysis%max_iterations = nint(value)
      case ('MAX_CUTS')
         analysis%max_cuts = nint(value)
      case ('SHAPE_EVERY')
         analysis%shape_every = nint(value)
      end select
   end subroutine set_path_value

   !> *OUTPUT, FORMAT [, EVERY=n]: an extra result file format (docs/input.md). The format is the card's
   !> one option without a value, so that further formats are further names here; VTK is the first
   !> (ParaView snapshots, uniarc_vtk). EVERY= is the snapshot interval in steps; without it the
   !> snapshots are those of the shape file. Step 0 and the last step are always written.
   subroutine read_output(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      integer :: i, k, every
      character(len=:), allocatable :: format_name
      integer :: format_column

      ! The format first, so that an unknown one gets a message about formats, not about options.
      format_name = ''
      format_column = card%column
      do i = 1, size(card%options)
         if (card%options(i)%has_value .or. card%options(i)%name == 'EVERY') cycle
         select case (card%options(i)%name)
         case ('VTK')
            if (len(format_name) == 0) then
               format_name = card%options(i)%name
               format_column = card%options(i)%column
            end if
         case default
            call raise(source, card%line, card%options(i)%column, 'expected an output format (VTK) on '// &
                       '*OUTPUT, found '''//clip(card%options(i)%name)//'''', error)
            return
         end select
      end do
      call check_options(source, card, [character(len=6) :: 'VTK', 'EVERY='], error)
      if (allocated(error)) return
      if (len(format_name) == 0) then
         call raise(source, card%line, card%column, 'expected an output format after *OUTPUT '// &
                    '(*OUTPUT, VTK), found none', error)
         return
      end if
      if (card%n_data > 0) then
         call raise(source, card%data_lines(1), verify(source%lines(card%data_lines(1))%text, ' '), &
                    'expected no data line after *OUTPUT, found one', error)
         return
      end if
      if (builder%vtk_line > 0) then
         call raise(source, card%line, format_column, 'expected one *OUTPUT, VTK card, found another '// &
                    'after the one at line '//integer_to_string(builder%vtk_line), error)
         return
      end if
      builder%vtk_line = card%line
      builder%output%vtk = .true.
      builder%output%vtk_every = 0
      k = option_index(card, 'EVERY')
      if (k > 0) then
         call field_integer(source, builder%parameters, card%line, option_field(card, k), &
                            'a number of steps for EVERY=', every, error)
         if (allocated(error)) return
         if (every <= 0) then
            call raise(source, card%line, card%options(k)%value_column, 'expected a positive number '// &
                       'of steps for EVERY=, found '//integer_to_string(every), error)
            return
         end if
         builder%output%vtk_every = every
      end if
   end subroutine read_output

   ! ================================================================================================
   ! Shared pieces of the cards
   ! ================================================================================================

   !> A deck describes one analysis: a second analysis card is an error.
   subroutine require_analysis_once(source, card, builder, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      if (builder%analysis_line > 0) then
         call raise(source, card%line, card%column, 'expected one analysis card, found *'//card%keyword// &
                    ' after the one at line '//integer_to_string(builder%analysis_line), error)
         return
      end if
      builder%analysis_line = card%line
   end subroutine require_analysis_once

   !> An option's value as a field (text and column), to be read like a data field.
   pure function option_field(card, k) result(field)
      type(card_t), intent(in) :: card
      integer, intent(in) :: k
      type(field_t) :: field
      field%text = card%options(k)%value
      field%column = card%options(k)%value_column
   end function option_field

   !> The value of option `k` of the card, an expression; `what` names it when it is empty.
   subroutine option_real(source, card, builder, k, what, value, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(in) :: builder
      integer, intent(in) :: k
      character(len=*), intent(in) :: what
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      call field_real(source, builder%parameters, card%line, option_field(card, k), what, value, error)
   end subroutine option_real

   !> The SCALE= option of a contact card (default 1): the factor from arc length to the coordinate of
   !> the contact-region output. Zero would make every coordinate 0, so it must not be.
   subroutine contact_scale(source, card, builder, scale, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(in) :: builder
      real(dp), intent(out) :: scale
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      scale = 1.0_dp
      k = option_index(card, 'SCALE')
      if (k == 0) return
      call option_real(source, card, builder, k, 'a scale', scale, error)
      if (allocated(error)) return
      if (.not. abs(scale) > 0.0_dp) then
         call raise(source, card%line, card%options(k)%value_column, 'expected a non-zero SCALE, found '// &
                    real_to_string(scale), error)
      end if
   end subroutine contact_scale

   !> The name of the contact group a card makes: its NAME= option, or `default_stem_<index>` with the
   !> group's index. Either must be new among the contact groups (case-insensitive).
   subroutine contact_group_name(source, card, builder, default_stem, name, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(in) :: builder
      character(len=*), intent(in) :: default_stem
      character(len=:), allocatable, intent(out) :: name
      type(error_t), allocatable, intent(out) :: error
      integer :: k, column, i
      k = option_index(card, 'NAME')
      if (k > 0) then
         name = card%options(k)%value
         column = card%options(k)%value_column
         if (.not. is_name(name)) then
            call raise(source, card%line, column, 'expected a contact group name (a letter, then letters, ' // &
                       'digits, _), found '''//clip(name)//'''', error)
            return
         end if
      else
         name = default_stem//'_'//integer_to_string(builder%n_contact_groups + 1)
         column = card%column
      end if
      do i = 1, builder%n_contact_groups
         if (same_text(builder%contact_groups(i)%name, name)) then
            if (k > 0) then
               call raise(source, card%line, column, 'expected a new contact group name, found '''// &
                          name//''' again', error)
            else
               call raise(source, card%line, column, 'expected a new contact group name, found the ' // &
                          'default name '''//name//''' already taken (give this card a NAME=)', error)
            end if
            return
         end if
      end do
   end subroutine contact_group_name

   !> Cards with exactly one data line (sections, generators).
   subroutine require_one_data_line(source, card, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(error_t), allocatable, intent(out) :: error
      if (card%n_data == 0) then
         call raise(source, card%line, len_trim(source%lines(card%line)%text) + 1, &
                    'expected a data line after *'//card%keyword//', found none', error)
      else if (card%n_data > 1) then
         call raise(source, card%data_lines(2), verify(source%lines(card%data_lines(2))%text, ' '), &
                    'expected a new card (*'//card%keyword//' takes one data line), found a second data line', &
                    error)
      end if
   end subroutine require_one_data_line

   !> The section named by the card's SECTION= option, which must be defined by an earlier *SECTION.
   subroutine card_section(source, card, builder, section, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(in) :: builder
      integer, intent(out) :: section
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      section = 0
      call require_option(source, card, 'SECTION', k, error)
      if (allocated(error)) return
      section = find_section(builder, card%options(k)%value)
      if (section == 0) then
         call raise(source, card%line, card%options(k)%value_column, &
                    'expected a section defined by an earlier *SECTION, found '''// &
                    clip(card%options(k)%value)//'''', error)
      end if
   end subroutine card_section

   !> A set name must be a name (letters, digits, _), so that it cannot be mistaken for a label.
   subroutine check_set_name(source, line, column, name, error)
      type(source_t), intent(in) :: source
      integer, intent(in) :: line, column
      character(len=*), intent(in) :: name
      type(error_t), allocatable, intent(out) :: error
      if (.not. is_name(name)) then
         call raise(source, line, column, 'expected a set name (a letter, then letters, digits, _), found '''// &
                    clip(name)//'''', error)
      end if
   end subroutine check_set_name

   !> The sets a generator makes must all be new.
   subroutine check_generator_sets(source, card, builder, name, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(in) :: builder
      character(len=*), intent(in) :: name
      type(error_t), allocatable, intent(out) :: error
      integer :: k, i
      character(len=6), parameter :: suffixes(4) = ['      ', '_start', '_end  ', '_mid  ']
      k = option_index(card, 'ELSET')
      call check_set_name(source, card%line, card%options(k)%value_column, name, error)
      if (allocated(error)) return
      if (find_element_set_index(builder, name) > 0) then
         call raise(source, card%line, card%options(k)%value_column, 'expected a new element set name, found '''// &
                    name//''' again', error)
         return
      end if
      do i = 1, size(suffixes)
         if (find_node_set_index(builder, name//trim(suffixes(i))) > 0) then
            call raise(source, card%line, card%options(k)%value_column, 'expected a name whose node sets ' // &
                       'are new, found the node set '''//name//trim(suffixes(i))//''' already defined', error)
            return
         end if
      end do
   end subroutine check_generator_sets

   !> Members of an *NSET (nodes = true) or *ELSET card, as internal indices.
   subroutine read_set_members(source, card, builder, nodes, generate, members, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(builder_t), intent(in) :: builder
      logical, intent(in) :: nodes, generate
      integer, allocatable, intent(out) :: members(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, count, first, last, step, label, index
      integer, allocatable :: found(:)
      type(field_t), allocatable :: fields(:)
      character(len=:), allocatable :: kind

      kind = merge('node   ', 'element', nodes)
      kind = trim(kind)
      allocate (members(16))
      count = 0
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         if (generate) then
            call require_field_count(source, line, fields, 2, 3, 'first, last [, step]', error)
            if (allocated(error)) return
            call field_integer(source, builder%parameters, line, fields(1), 'a first label', first, error)
            if (allocated(error)) return
            call field_integer(source, builder%parameters, line, fields(2), 'a last label', last, error)
            if (allocated(error)) return
            step = 1
            if (size(fields) == 3) then
               call field_integer(source, builder%parameters, line, fields(3), 'a step', step, error)
               if (allocated(error)) return
               if (step < 1) then
                  call raise(source, line, fields(3)%column, 'expected a positive step, found '// &
                             integer_to_string(step), error)
                  return
               end if
            end if
            if (last < first) then
               call raise(source, line, fields(2)%column, 'expected a last label not below the first (' // &
                          integer_to_string(first)//'), found '//integer_to_string(last), error)
               return
            end if
            do label = first, last, step
               if (nodes) then
                  index = find_node(builder, label)
               else
                  index = find_element(builder, label)
               end if
               if (index == 0) then
                  call raise(source, line, fields(1)%column, 'expected defined '//kind//' labels, found '// &
                             integer_to_string(label)//' undefined in '//integer_to_string(first)//' to '// &
                             integer_to_string(last), error)
                  return
               end if
               call append(members, count, [index])
            end do
         else
            if (size(fields) == 0) cycle
            do j = 1, size(fields)
               if (nodes) then
                  call resolve_nodes(source, builder, line, fields(j), found, error)
               else
                  call resolve_elements(source, builder, line, fields(j), found, error)
               end if
               if (allocated(error)) return
               call append(members, count, found)
            end do
         end if
      end do
      members = members(1:count)
   end subroutine read_set_members

   !> The nodes a target field names: a node-set name or a node label (an integer expression).
   subroutine resolve_nodes(source, builder, line, field, nodes, error)
      type(source_t), intent(in) :: source
      type(builder_t), intent(in) :: builder
      integer, intent(in) :: line
      type(field_t), intent(in) :: field
      integer, allocatable, intent(out) :: nodes(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: set, label, index

      if (is_name(field%text)) then
         set = find_node_set_index(builder, field%text)
         if (set > 0) then
            nodes = builder%node_sets(set)%nodes
            return
         end if
         if (find_parameter(builder%parameters, field%text) == 0) then
            call raise(source, line, field%column, 'expected a node label or a node set defined above, found '''// &
                       clip(field%text)//'''', error)
            return
         end if
      end if
      call field_integer(source, builder%parameters, line, field, 'a node label or a node set', label, error)
      if (allocated(error)) return
      index = find_node(builder, label)
      if (index == 0) then
         call raise(source, line, field%column, 'expected a defined node label, found '// &
                    integer_to_string(label), error)
         return
      end if
      nodes = [index]
   end subroutine resolve_nodes

   !> The elements a target field names: an element-set name or an element label.
   subroutine resolve_elements(source, builder, line, field, elements, error)
      type(source_t), intent(in) :: source
      type(builder_t), intent(in) :: builder
      integer, intent(in) :: line
      type(field_t), intent(in) :: field
      integer, allocatable, intent(out) :: elements(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: set, label, index

      if (is_name(field%text)) then
         set = find_element_set_index(builder, field%text)
         if (set > 0) then
            elements = builder%element_sets(set)%elements
            return
         end if
         if (find_parameter(builder%parameters, field%text) == 0) then
            call raise(source, line, field%column, 'expected an element label or an element set defined above, ' // &
                       'found '''//clip(field%text)//'''', error)
            return
         end if
      end if
      call field_integer(source, builder%parameters, line, field, 'an element label or an element set', &
                         label, error)
      if (allocated(error)) return
      index = find_element(builder, label)
      if (index == 0) then
         call raise(source, line, field%column, 'expected a defined element label, found '// &
                    integer_to_string(label), error)
         return
      end if
      elements = [index]
   end subroutine resolve_elements

   !> A DOF field: an integer expression 1 (ux), 2 (uy) or 3 (rz).
   subroutine read_dof(source, builder, line, field, dof, error)
      type(source_t), intent(in) :: source
      type(builder_t), intent(in) :: builder
      integer, intent(in) :: line
      type(field_t), intent(in) :: field
      integer, intent(out) :: dof
      type(error_t), allocatable, intent(out) :: error
      call field_integer(source, builder%parameters, line, field, 'a DOF', dof, error)
      if (allocated(error)) return
      if (dof < 1 .or. dof > 3) then
         call raise(source, line, field%column, 'expected a DOF 1 (ux), 2 (uy) or 3 (rz), found '// &
                    integer_to_string(dof), error)
      end if
   end subroutine read_dof

   ! ================================================================================================
   ! The whole deck
   ! ================================================================================================

   !> Checks that need the whole deck: every -D used, at least one element, no node outside every
   !> element (it would make the stiffness singular), every element with a section; the rotation of a
   !> node that only trusses use is held (uniarc_deck_element).
   subroutine check_whole_deck(source, builder, error)
      type(source_t), intent(in) :: source
      type(builder_t), intent(inout) :: builder
      type(error_t), allocatable, intent(out) :: error
      logical, allocatable :: used(:)
      integer :: i

      do i = 1, size(builder%overrides)
         if (.not. builder%override_used(i)) then
            call make_error(error, '-D '//builder%overrides(i)%name//': no *PARAMETER of that name in '// &
                            source%path, error_input)
            return
         end if
      end do
      if (builder%n_elements == 0) then
         call raise_plain(source, 'expected at least one element (*ELEMENT, *ARC, *RING or *LINE), found none', &
                          error)
         return
      end if
      allocate (used(builder%n_nodes), source=.false.)
      do i = 1, builder%n_elements
         used(builder%connectivity(:, i)) = .true.
      end do
      do i = 1, builder%n_nodes
         if (.not. used(i)) then
            call raise(source, builder%node_line(i), builder%node_column(i), 'expected every node in an ' // &
                       'element, found node '//integer_to_string(builder%node_label(i))//' in none', error)
            return
         end if
      end do
      if (allocated(builder%stop_track)) then
         do i = 1, builder%n_tracks
            if (same_text(builder%tracks(i)%name, builder%stop_track)) builder%analysis%stop_track = i
         end do
         if (builder%analysis%stop_track == 0) then
            call raise(source, builder%stop_track_line, builder%stop_track_column, 'expected the name of a '// &
                       '*TRACK, found '''//clip(builder%stop_track)//'''', error)
            return
         end if
      end if
      do i = 1, builder%n_elements
         if (builder%element_section(i) == 0) then
            call raise_plain(source, 'expected a section for every element, found element '// &
                             integer_to_string(builder%element_label(i))//' without one', error)
            return
         end if
      end do
      call restrain_truss_nodes(source, builder%connectivity(:, 1:builder%n_elements), &
                                element_kinds(builder%element_kind, builder%n_elements), &
                                builder%node_label(1:builder%n_nodes), builder%node_line(1:builder%n_nodes), &
                                builder%node_column(1:builder%n_nodes), builder%element_label(1:builder%n_elements), &
                                builder%loads(1:builder%n_loads), builder%fixed(:, 1:builder%n_nodes), &
                                builder%nodal_load(:, 1:builder%n_nodes), error)
   end subroutine check_whole_deck

   !> Copy what the cards built into the model, arrays cut to size.
   subroutine finish_model(source, builder, model)
      type(source_t), intent(in) :: source
      type(builder_t), intent(in) :: builder
      type(model_t), intent(inout) :: model
      integer :: n, e

      n = builder%n_nodes
      e = builder%n_elements
      model%deck_path = source%path
      model%title = builder%title
      model%n_nodes = n
      model%n_elements = e
      model%coordinates = builder%coordinates(:, 1:n)
      model%node_label = builder%node_label(1:n)
      model%fixed = builder%fixed(:, 1:n)
      model%nodal_load = builder%nodal_load(:, 1:n)
      model%connectivity = builder%connectivity(:, 1:e)
      model%element_label = builder%element_label(1:e)
      model%element_section = builder%element_section(1:e)
      model%element_kind = element_kinds(builder%element_kind, e)
      model%sections = builder%sections(1:builder%n_sections)
      if (builder%n_node_sets > 0) then
         model%node_sets = builder%node_sets(1:builder%n_node_sets)
      else
         allocate (model%node_sets(0))
      end if
      if (builder%n_element_sets > 0) then
         model%element_sets = builder%element_sets(1:builder%n_element_sets)
      else
         allocate (model%element_sets(0))
      end if
      if (builder%n_loads > 0) then
         model%distributed_loads = builder%loads(1:builder%n_loads)
      else
         allocate (model%distributed_loads(0))
      end if
      if (builder%n_tracks > 0) then
         model%tracks = builder%tracks(1:builder%n_tracks)
      else
         allocate (model%tracks(0))
      end if
      if (builder%n_contacts > 0) then
         model%contacts = builder%contacts(1:builder%n_contacts)
      else
         allocate (model%contacts(0))
      end if
      if (builder%n_contact_groups > 0) then
         model%contact_groups = builder%contact_groups(1:builder%n_contact_groups)
      else
         allocate (model%contact_groups(0))
      end if
      model%analysis = builder%analysis
      model%output = builder%output
   end subroutine finish_model

   ! ================================================================================================
   ! The builder's tables
   ! ================================================================================================

   subroutine start_builder(builder, overrides)
      type(builder_t), intent(out) :: builder
      type(parameter_override_t), intent(in) :: overrides(:)
      builder%overrides = overrides
      allocate (builder%override_used(size(overrides)), source=.false.)
      allocate (builder%parameter_line(8))
      builder%title = ''
      allocate (builder%coordinates(2, 64), builder%node_label(64), builder%node_line(64), &
                builder%node_column(64), builder%fixed(3, 64), builder%nodal_load(3, 64))
      allocate (builder%connectivity(2, 64), builder%element_label(64), builder%element_section(64), &
                builder%load_index(3, 64))
      allocate (builder%sections(4), builder%node_sets(8), builder%element_sets(8), builder%loads(16))
   end subroutine start_builder

   !> Index of the override of parameter `name`, 0 if there is none (the last -D of a name wins).
   pure integer function find_override(builder, name) result(index)
      type(builder_t), intent(in) :: builder
      character(len=*), intent(in) :: name
      integer :: i
      index = 0
      do i = 1, size(builder%overrides)
         if (same_text(builder%overrides(i)%name, name)) index = i
      end do
   end function find_override

   subroutine add_node(builder, label, point, line, column)
      type(builder_t), intent(inout) :: builder
      integer, intent(in) :: label
      real(dp), intent(in) :: point(2)
      integer, intent(in) :: line, column
      integer :: capacity
      capacity = size(builder%node_label)
      if (builder%n_nodes == capacity) then
         call grow_real_2(builder%coordinates, 2*capacity)
         call grow_real_2(builder%nodal_load, 2*capacity)
         call grow_logical_2(builder%fixed, 2*capacity)
         call grow_integers(builder%node_label, 2*capacity)
         call grow_integers(builder%node_line, 2*capacity)
         call grow_integers(builder%node_column, 2*capacity)
      end if
      builder%n_nodes = builder%n_nodes + 1
      builder%coordinates(:, builder%n_nodes) = point
      builder%node_label(builder%n_nodes) = label
      builder%node_line(builder%n_nodes) = line
      builder%node_column(builder%n_nodes) = column
      builder%fixed(:, builder%n_nodes) = .false.
      builder%nodal_load(:, builder%n_nodes) = 0.0_dp
      builder%largest_node_label = max(builder%largest_node_label, label)
      call record_label(builder%node_of_label, label, builder%n_nodes)
   end subroutine add_node

   subroutine add_element(builder, label, ends, section)
      type(builder_t), intent(inout) :: builder
      integer, intent(in) :: label, ends(2), section
      integer :: capacity
      capacity = size(builder%element_label)
      if (builder%n_elements == capacity) then
         call grow_integers_2(builder%connectivity, 2*capacity)
         call grow_integers_2(builder%load_index, 2*capacity)
         call grow_integers(builder%element_label, 2*capacity)
         call grow_integers(builder%element_section, 2*capacity)
      end if
      builder%n_elements = builder%n_elements + 1
      builder%connectivity(:, builder%n_elements) = ends
      builder%element_label(builder%n_elements) = label
      builder%element_section(builder%n_elements) = section
      builder%load_index(:, builder%n_elements) = 0
      builder%largest_element_label = max(builder%largest_element_label, label)
      call record_label(builder%element_of_label, label, builder%n_elements)
   end subroutine add_element

   subroutine add_load(builder, element, kind, follower)
      type(builder_t), intent(inout) :: builder
      integer, intent(in) :: element, kind
      logical, intent(in) :: follower
      type(distributed_load_t), allocatable :: grown(:)
      if (builder%n_loads == size(builder%loads)) then
         allocate (grown(2*size(builder%loads)))
         grown(1:builder%n_loads) = builder%loads(1:builder%n_loads)
         call move_alloc(grown, builder%loads)
      end if
      builder%n_loads = builder%n_loads + 1
      builder%loads(builder%n_loads) = distributed_load_t(element=element, kind=kind, follower=follower)
   end subroutine add_load

   !> Append the contact group `name` made of `candidates` (in node order) to the builder.
   pure subroutine add_contact_group(builder, name, candidates)
      type(builder_t), intent(inout) :: builder
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
      builder%n_contacts = builder%n_contacts + size(candidates)
      builder%contact_groups(group)%name = name
      builder%contact_groups(group)%candidates = [(i, i = first, builder%n_contacts)]
   end subroutine add_contact_group

   !> The diagonal of the box around the nodes defined so far: the length that obstacle tolerances scale.
   pure real(dp) function model_size(builder)
      type(builder_t), intent(in) :: builder
      if (builder%n_nodes == 0) then
         model_size = 0.0_dp
      else
         model_size = norm2(maxval(builder%coordinates(:, 1:builder%n_nodes), dim=2) - &
                            minval(builder%coordinates(:, 1:builder%n_nodes), dim=2))
      end if
   end function model_size

   !> Add `members` to node set `name` (created if new), skipping nodes already in it.
   subroutine add_to_node_set(builder, name, members)
      type(builder_t), intent(inout) :: builder
      character(len=*), intent(in) :: name
      integer, intent(in) :: members(:)
      type(node_set_t), allocatable :: grown(:)
      integer :: set
      set = find_node_set_index(builder, name)
      if (set == 0) then
         if (builder%n_node_sets == size(builder%node_sets)) then
            allocate (grown(2*size(builder%node_sets)))
            grown(1:builder%n_node_sets) = builder%node_sets(1:builder%n_node_sets)
            call move_alloc(grown, builder%node_sets)
         end if
         builder%n_node_sets = builder%n_node_sets + 1
         set = builder%n_node_sets
         builder%node_sets(set)%name = name
         allocate (builder%node_sets(set)%nodes(0))
      end if
      call merge_members(builder%node_sets(set)%nodes, members, builder%n_nodes)
   end subroutine add_to_node_set

   !> Add `members` to element set `name` (created if new), skipping elements already in it.
   subroutine add_to_element_set(builder, name, members)
      type(builder_t), intent(inout) :: builder
      character(len=*), intent(in) :: name
      integer, intent(in) :: members(:)
      type(element_set_t), allocatable :: grown(:)
      integer :: set
      set = find_element_set_index(builder, name)
      if (set == 0) then
         if (builder%n_element_sets == size(builder%element_sets)) then
            allocate (grown(2*size(builder%element_sets)))
            grown(1:builder%n_element_sets) = builder%element_sets(1:builder%n_element_sets)
            call move_alloc(grown, builder%element_sets)
         end if
         builder%n_element_sets = builder%n_element_sets + 1
         set = builder%n_element_sets
         builder%element_sets(set)%name = name
         allocate (builder%element_sets(set)%elements(0))
      end if
      call merge_members(builder%element_sets(set)%elements, members, builder%n_elements)
   end subroutine add_to_element_set

   !> Append to `set` the entries of `members` (indices 1..n) that are not in it yet, in their order.
   pure subroutine merge_members(set, members, n)
      integer, allocatable, intent(inout) :: set(:)
      integer, intent(in) :: members(:)
      integer, intent(in) :: n
      logical, allocatable :: present(:)
      integer, allocatable :: added(:)
      integer :: i, count
      allocate (present(n), source=.false.)
      present(set) = .true.
      allocate (added(size(members)))
      count = 0
      do i = 1, size(members)
         if (present(members(i))) cycle
         present(members(i)) = .true.
         count = count + 1
         added(count) = members(i)
      end do
      set = [set, added(1:count)]
   end subroutine merge_members

   pure integer function find_node(builder, label) result(index)
      type(builder_t), intent(in) :: builder
      integer, intent(in) :: label
      integer :: i
      index = 0
      if (allocated(builder%node_of_label)) then
         if (label >= 1 .and. label <= size(builder%node_of_label)) then
            index = builder%node_of_label(label)
            return
         end if
      end if
      do i = 1, builder%n_nodes
         if (builder%node_label(i) == label) then
            index = i
            return
         end if
      end do
   end function find_node

   pure integer function find_element(builder, label) result(index)
      type(builder_t), intent(in) :: builder
      integer, intent(in) :: label
      integer :: i
      index = 0
      if (allocated(builder%element_of_label)) then
         if (label >= 1 .and. label <= size(builder%element_of_label)) then
            index = builder%element_of_label(label)
            return
         end if
      end if
      do i = 1, builder%n_elements
         if (builder%element_label(i) == label) then
            index = i
            return
         end if
      end do
   end function find_element

   !> The node among `candidates` nearest to `point` if it is within `tolerance`, else 0.
   pure integer function find_coincident_node(builder, candidates, point, tolerance) result(index)
      type(builder_t), intent(in) :: builder
      integer, intent(in) :: candidates(:)
      real(dp), intent(in) :: point(2), tolerance
      real(dp) :: distance, best
      integer :: i
      index = 0
      best = huge(1.0_dp)
      do i = 1, size(candidates)
         distance = norm2(builder%coordinates(:, candidates(i)) - point)
         if (distance <= tolerance .and. distance < best) then
            best = distance
            index = candidates(i)
         end if
      end do
   end function find_coincident_node

   !> The nodes inside the box [lower, upper].
   pure function nodes_in_box(builder, lower, upper) result(nodes)
      type(builder_t), intent(in) :: builder
      real(dp), intent(in) :: lower(2), upper(2)
      integer, allocatable :: nodes(:)
      integer :: i, count
      allocate (nodes(builder%n_nodes))
      count = 0
      do i = 1, builder%n_nodes
         if (all(builder%coordinates(:, i) >= lower .and. builder%coordinates(:, i) <= upper)) then
            count = count + 1
            nodes(count) = i
         end if
      end do
      nodes = nodes(1:count)
   end function nodes_in_box

   !> An element is of zero length when its ends are one node or lie within round-off of each other.
   pure logical function is_zero_length(builder, ends)
      type(builder_t), intent(in) :: builder
      integer, intent(in) :: ends(2)
      real(dp) :: scale
      scale = maxval(abs(builder%coordinates(:, ends)))
      is_zero_length = norm2(builder%coordinates(:, ends(2)) - builder%coordinates(:, ends(1))) <= &
                       zero_length_tolerance*scale
   end function is_zero_length

   pure integer function find_section(builder, name) result(index)
      type(builder_t), intent(in) :: builder
      character(len=*), intent(in) :: name
      integer :: i
      index = 0
      do i = 1, builder%n_sections
         if (same_text(builder%sections(i)%name, name)) index = i
      end do
   end function find_section

   pure integer function find_node_set_index(builder, name) result(index)
      type(builder_t), intent(in) :: builder
      character(len=*), intent(in) :: name
      integer :: i
      index = 0
      do i = 1, builder%n_node_sets
         if (same_text(builder%node_sets(i)%name, name)) index = i
      end do
   end function find_node_set_index

   pure integer function find_element_set_index(builder, name) result(index)
      type(builder_t), intent(in) :: builder
      character(len=*), intent(in) :: name
      integer :: i
      index = 0
      do i = 1, builder%n_element_sets
         if (same_text(builder%element_sets(i)%name, name)) index = i
      end do
   end function find_element_set_index

   ! ------------------------------------------------------------------------------------------------
   ! Growing arrays
   ! ------------------------------------------------------------------------------------------------

   !> Append `values` to `list(1:count)`, doubling its capacity when needed.
   pure subroutine append(list, count, values)
      integer, allocatable, intent(inout) :: list(:)
      integer, intent(inout) :: count
      integer, intent(in) :: values(:)
      if (count + size(values) > size(list)) call grow_integers(list, max(2*size(list), count + size(values)))
      list(count + 1:count + size(values)) = values
      count = count + size(values)
   end subroutine append

   !> Make sure `list` holds at least `needed` entries, keeping its contents.
   pure subroutine grow_integers(list, needed)
      integer, allocatable, intent(inout) :: list(:)
      integer, intent(in) :: needed
      integer, allocatable :: grown(:)
      if (size(list) >= needed) return
      allocate (grown(max(needed, 2*size(list))), source=0)
      grown(1:size(list)) = list
      call move_alloc(grown, list)
   end subroutine grow_integers

   pure subroutine grow_integers_2(array, columns)
      integer, allocatable, intent(inout) :: array(:, :)
      integer, intent(in) :: columns
      integer, allocatable :: grown(:, :)
      allocate (grown(size(array, 1), columns), source=0)
      grown(:, 1:size(array, 2)) = array
      call move_alloc(grown, array)
   end subroutine grow_integers_2

   !> Remember that `label` is entry `index`, so that label look-ups are O(1) instead of a scan.
   !> Labels are kept in a direct table while they stay below 4 × (entries) + 1000; a table that would
   !> grow larger than that (very sparse labels) is dropped and look-ups fall back to the scan.
   pure subroutine record_label(table, label, index)
      integer, allocatable, intent(inout) :: table(:)
      integer, intent(in) :: label, index
      integer, allocatable :: grown(:)
      integer :: capacity
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
         allocate (grown(capacity), source=0)
         grown(1:size(table)) = table
         call move_alloc(grown, table)
      end if
      if (label >= 1) table(label) = index
   end subroutine record_label

   pure subroutine grow_real_2(array, columns)
      real(dp), allocatable, intent(inout) :: array(:, :)
      integer, intent(in) :: columns
      real(dp), allocatable :: grown(:, :)
      allocate (grown(size(array, 1), columns), source=0.0_dp)
      grown(:, 1:size(array, 2)) = array
      call move_alloc(grown, array)
   end subroutine grow_real_2

   pure subroutine grow_logical_2(array, columns)
      logical, allocatable, intent(inout) :: array(:, :)
      integer, intent(in) :: columns
      logical, allocatable :: grown(:, :)
      allocate (grown(size(array, 1), columns), source=.false.)
      grown(:, 1:size(array, 2)) = array
      call move_alloc(grown, array)
   end subroutine grow_logical_2

   pure subroutine grow_sections(sections)
      type(section_t), allocatable, intent(inout) :: sections(:)
      type(section_t), allocatable :: grown(:)
      allocate (grown(2*size(sections)))
      grown(1:size(sections)) = sections
      call move_alloc(grown, sections)
   end subroutine grow_sections

end module uniarc_deck
