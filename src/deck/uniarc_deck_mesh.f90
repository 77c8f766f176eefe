!> The structure cards of the deck: sections, nodes, elements, the mesh generators (*ARC, *RING,
!> *LINE) and the node and element sets (docs/input.md). Each reads one card into the model builder.
module uniarc_deck_mesh
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_input
   use uniarc_strings, only: field_t, to_upper, is_name, integer_to_string, real_to_string, counted
   use uniarc_growth, only: append_integers
   use uniarc_expression, only: sin_degrees, cos_degrees
   use uniarc_deck_source, only: source_t, card_t, raise, clip, check_options, option_index, require_option, &
                                 data_fields, require_field_count, field_real, field_integer
   use uniarc_model_builder, only: model_builder_t, add_section, add_element, add_to_node_set, add_to_element_set, &
                                   node_index, element_index, section_index, node_set_index, element_set_index, &
                                  set_element_kind, set_section_weight, set_section_alpha
   use uniarc_deck_element, only: read_element_type, check_element_section
   use uniarc_memory, only: memory_shortfall, model_memory_bytes, allocation_failure
   use uniarc_deck_state, only: deck_t, add_deck_node, require_one_data_line, resolve_nodes, resolve_elements, &
                                option_real
   implicit none
   private
   public :: read_section, read_node, read_element, read_generator, read_node_set, read_element_set

   !> Relative tolerance under which a generated node is the same as an existing one (× generator size).
   real(dp), parameter :: merge_tolerance = 1.0e-9_dp

   !> Relative size under which an element's length is round-off of its coordinates, i.e. zero.
   real(dp), parameter :: zero_length_tolerance = 1.0e-12_dp

contains

   !> *SECTION, NAME=s [, STIFFNESS | TYPE=STIFFNESS|MATERIAL]: data `E, A, I [, G, kappa]` (material
   !> form, the default) or `EA, EI [, GAs]` (stiffness form); the optional shear data give the shear
   !> stiffness κGA of a Timoshenko beam (`*ELEMENT, TYPE=TIMOSHENKO`). Every value must be positive.
   subroutine read_section(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: name_option, type_option, line, i, n_values
      logical :: stiffness_form
      type(field_t), allocatable :: fields(:)
      real(dp) :: values(5)
      character(len=5), parameter :: material_names(5) = ['E    ', 'A    ', 'I    ', 'G    ', 'kappa']
      character(len=3), parameter :: stiffness_names(3) = ['EA ', 'EI ', 'GAs']
      real(dp), parameter :: stiffness_limit = 1.0e100_dp
      real(dp), parameter :: stiffness_floor = 1.0e-100_dp
      real(dp) :: stiffnesses(3)
      integer :: n_stiffnesses, column, status
      character(len=:), allocatable :: name, what

      call check_options(source, card, [character(len=9) :: 'NAME=', 'TYPE=', 'STIFFNESS', 'WEIGHT=', 'ALPHA='], &
                         error)
      if (allocated(error)) return
      call require_option(source, card, 'NAME', name_option, error)
      if (allocated(error)) return
      name = card%options(name_option)%value
      if (.not. is_name(name)) then
         call raise(source, card%line, card%options(name_option)%value_column, &
                    'expected a section name (a letter, then letters, digits, _), found '''//clip(name)//'''', error)
         return
      end if
      if (section_index(deck%model, name) > 0) then
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
         call require_field_count(source, line, fields, 2, 3, 'EA, EI [, GAs]', error)
      else
         call require_field_count(source, line, fields, 3, 5, 'E, A, I [, G, kappa]', error)
         if (.not. allocated(error) .and. size(fields) == 4) &
            call raise(source, line, fields(4)%column, 'expected G and kappa together (E, A, I, G, kappa), ' // &
                       'found G alone', error)
      end if
      if (allocated(error)) return
      n_values = size(fields)
      do i = 1, n_values
         if (stiffness_form) then
            what = trim(stiffness_names(i))
         else
            what = trim(material_names(i))
         end if
         call field_real(source, deck%parameters, line, fields(i), what, values(i), error)
         if (allocated(error)) return
         if (.not. values(i) > 0.0_dp) then
            call raise(source, line, fields(i)%column, 'expected a positive '//what//', found '// &
                       real_to_string(values(i)), error)
            return
         end if
      end do

      ! Stiffnesses beyond 1e100 overflow double precision in the equations (12 EI/L^3 and the squares of
      ! the convergence test; docs/contracts.md, "Non-finite results").
      ! Stiffnesses below 1e-100 underflow them: with lengths from 1e-100 to 1e100 (uniarc_check) EA/L
      ! and GAs/L stay above 1e-200, and the ratios the analysis forms of a load or a spring to them
      ! (displacements, flexibilities, EA = 1e-300 gave 1e300 and overflowed) stay finite.
      n_stiffnesses = 2
      if (stiffness_form) then
         stiffnesses = values(1:3)
         if (n_values == 3) n_stiffnesses = 3
      else
         stiffnesses = [values(1)*values(2), values(1)*values(3), 0.0_dp]
         if (n_values == 5) then
            stiffnesses(3) = values(5)*values(4)*values(2)
            n_stiffnesses = 3
         end if
      end if
      do i = 1, n_stiffnesses
         if (.not. (stiffnesses(i) >= stiffness_floor .and. stiffnesses(i) <= stiffness_limit)) then
            column = fields(i)%column
            if (.not. stiffness_form) column = fields(merge(i + 1, 4, i < 3))%column
            call raise(source, line, column, 'expected '// &
                       trim(stiffness_names(i))//' from 1e-100 to 1e100 (beyond, the stiffnesses overflow or '// &
                       'underflow the equations in double precision: rescale the units), found '// &
                       real_to_string(stiffnesses(i)), error)
            return
         end if
      end do
      if (stiffness_form .and. n_values == 3) then
         call add_section(deck%model, name, ea=values(1), ei=values(2), gas=values(3), status=status)
      else if (stiffness_form) then
         call add_section(deck%model, name, ea=values(1), ei=values(2), status=status)
      else if (n_values == 5) then
         call add_section(deck%model, name, ea=values(1)*values(2), ei=values(1)*values(3), &
                          gas=values(5)*values(4)*values(2), status=status)
      else
         call add_section(deck%model, name, ea=values(1)*values(2), ei=values(1)*values(3), status=status)
      end if
      call allocation_failure(status, 'the list of sections and its name table', &
                              96.0_dp*(deck%model%n_sections + 1), error_input, error)
      if (allocated(error)) return
      call read_section_loads(source, card, deck, error)
   end subroutine read_section

   !> The options WEIGHT=w (weight per unit length, ≥ 0, at most 1e100) and ALPHA=a (coefficient of
   !> thermal expansion) of *SECTION, for the section just added: *DLOAD WEIGHT and *TEMPERATURE take
   !> them where their own field is absent or empty.
   subroutine read_section_loads(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      real(dp) :: value
      k = option_index(card, 'WEIGHT')
      if (k > 0) then
         call option_real(source, card, deck, k, 'a weight per unit length', value, error)
         if (allocated(error)) return
         if (.not. (value >= 0.0_dp .and. value <= 1.0e100_dp)) then
            call raise(source, card%line, card%options(k)%value_column, 'expected a weight per unit length '// &
                       'from 0 to 1e100 (its direction is the angle of *DLOAD WEIGHT), found '// &
                       real_to_string(value), error)
            return
         end if
         call set_section_weight(deck%model, value)
      end if
      k = option_index(card, 'ALPHA')
      if (k > 0) then
         call option_real(source, card, deck, k, 'a coefficient of thermal expansion', value, error)
         if (allocated(error)) return
         if (.not. abs(value) <= 1.0e100_dp) then
            call raise(source, card%line, card%options(k)%value_column, 'expected a coefficient of thermal '// &
                       'expansion at most 1e100 in magnitude, found '//real_to_string(value), error)
            return
         end if
         call set_section_alpha(deck%model, value)
      end if
   end subroutine read_section_loads

   !> *NODE [, NSET=name]: lines `label, x, y`.
   subroutine read_node(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
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
         call field_integer(source, deck%parameters, line, fields(1), 'a node label', label, error)
         if (allocated(error)) return
         if (label < 1) then
            call raise(source, line, fields(1)%column, 'expected a positive node label, found '// &
                       integer_to_string(label), error)
            return
         end if
         existing = node_index(deck%model, label)
         if (existing > 0) then
            call raise(source, line, fields(1)%column, 'expected a new node label, found '// &
                       integer_to_string(label)//' (defined at line '// &
                       integer_to_string(deck%node_line(existing))//')', error)
            return
         end if
         call field_real(source, deck%parameters, line, fields(2), 'x', x, error)
         if (allocated(error)) return
         call field_real(source, deck%parameters, line, fields(3), 'y', y, error)
         if (allocated(error)) return
         call add_deck_node(deck, label, [x, y], line, fields(1)%column, error)
         if (allocated(error)) return
         created(i) = deck%model%n_nodes
      end do
      if (set_option > 0) call add_to_node_set(deck%model, card%options(set_option)%value, created, error)
   end subroutine read_node

   !> *ELEMENT, SECTION=s [, ELSET=name] [, TYPE=BEAM|TRUSS|TIMOSHENKO]: lines `label, node1, node2` (node labels).
   subroutine read_element(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, label, existing, section, set_option, kind, status
      integer :: ends(2), node_labels(2)
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: created(:)

      call check_options(source, card, [character(len=8) :: 'SECTION=', 'ELSET=', 'TYPE='], error)
      if (allocated(error)) return
      call read_element_type(source, card, kind, error)
      if (allocated(error)) return
      call card_section(source, card, deck, section, error)
      if (allocated(error)) return
      call check_element_section(source, card, kind, deck%model%sections(section), error)
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
         call field_integer(source, deck%parameters, line, fields(1), 'an element label', label, error)
         if (allocated(error)) return
         if (label < 1) then
            call raise(source, line, fields(1)%column, 'expected a positive element label, found '// &
                       integer_to_string(label), error)
            return
         end if
         existing = element_index(deck%model, label)
         if (existing > 0) then
            call raise(source, line, fields(1)%column, 'expected a new element label, found '// &
                       integer_to_string(label), error)
            return
         end if
         do j = 1, 2
            call field_integer(source, deck%parameters, line, fields(j + 1), 'a node label', &
                               node_labels(j), error)
            if (allocated(error)) return
            ends(j) = node_index(deck%model, node_labels(j))
            if (ends(j) == 0) then
               call raise(source, line, fields(j + 1)%column, 'expected a defined node label, found '// &
                          integer_to_string(node_labels(j)), error)
               return
            end if
         end do
         if (is_zero_length(deck%model, ends)) then
            call raise(source, line, fields(2)%column, 'expected an element of nonzero length, found nodes '// &
                       integer_to_string(node_labels(1))//' and '//integer_to_string(node_labels(2))// &
                       ' at the same point', error)
            return
         end if
         call add_element(deck%model, label, ends, section, error)
         if (allocated(error)) return
         created(i) = deck%model%n_elements
      end do
      call set_element_kind(deck%model, created, kind, status)
      call allocation_failure(status, 'the element kinds', 8.0_dp*deck%model%n_elements, error_input, error)
      if (allocated(error)) return
      if (set_option > 0) call add_to_element_set(deck%model, card%options(set_option)%value, created, error)
   end subroutine read_element

   !> *ARC, *RING and *LINE, ELSET=name, SECTION=s [, TYPE=BEAM|TRUSS|TIMOSHENKO]: one data line that generates nodes and elements.
   !>
   !> ARC `xc, yc, R, theta_start, theta_end, n` (degrees, counter-clockwise from +x); RING `xc, yc, R,
   !> n [, theta_start]` (closed); LINE `x1, y1, x2, y2, n`. A generated node within merge_tolerance ×
   !> the generator's size (R, or the line's length) of an existing node is that node, so generators
   !> that meet are connected. Makes the element set `name` and node sets `name`, `name_start`,
   !> `name_end` (not for a ring) and `name_mid` (for an even n).
   subroutine read_generator(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: set_option, section, line, n, i, field_n, nodes_layout, kind, status
      type(field_t), allocatable :: fields(:)
      real(dp) :: values(5), size_scale, angle, sweep, tolerance
      real(dp), allocatable :: points(:, :)
      integer, allocatable :: nodes(:), elements(:), candidates(:)
      character(len=:), allocatable :: name, layout, shortfall
      logical :: closed

      call check_options(source, card, [character(len=8) :: 'ELSET=', 'SECTION=', 'TYPE='], error)
      if (allocated(error)) return
      call read_element_type(source, card, kind, error)
      if (allocated(error)) return
      call require_option(source, card, 'ELSET', set_option, error)
      if (allocated(error)) return
      name = card%options(set_option)%value
      call check_generator_sets(source, card, deck, name, error)
      if (allocated(error)) return
      call card_section(source, card, deck, section, error)
      if (allocated(error)) return
      call check_element_section(source, card, kind, deck%model%sections(section), error)
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
         call field_real(source, deck%parameters, line, fields(i), 'a number', values(min(i, 5)), error)
         if (allocated(error)) return
      end do
      call field_integer(source, deck%parameters, line, fields(field_n), 'the number of elements', n, error)
      if (allocated(error)) return
      if (n < 1 .or. (closed .and. n < 3)) then
         call raise(source, line, fields(field_n)%column, 'expected at least '// &
                    counted(merge(3, 1, closed), 'element')//', found '//integer_to_string(n), error)
         return
      end if

      ! A generator whose analysis cannot fit in memory is refused before its arrays grow (uniarc_memory;
      ! a chain of n elements: n + 1 nodes, 3 equations each, half bandwidth 5).
      call memory_shortfall(model_memory_bytes(real(n, dp) + 1.0_dp, real(n, dp), 3.0_dp*(real(n, dp) + 1.0_dp), &
                                               5.0_dp, 0.0_dp), shortfall)
      if (allocated(shortfall)) then
         call raise(source, line, fields(field_n)%column, 'expected a number of elements whose analysis fits in '// &
                    'memory: '//integer_to_string(n)//' elements '//shortfall, error)
         return
      end if
      nodes_layout = n + 1
      if (closed) nodes_layout = n
      allocate (points(2, nodes_layout), stat=status)
      call allocation_failure(status, 'the points of the generator', 16.0_dp*nodes_layout, error_input, error)
      if (allocated(error)) return
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
      call nodes_in_box(deck%model, minval(points, dim=2) - tolerance, maxval(points, dim=2) + tolerance, &
                        candidates, status)
      call allocation_failure(status, 'the nodes in the bounding box of the generator', 4.0_dp*deck%model%n_nodes, &
                              error_input, error)
      if (allocated(error)) return
      allocate (nodes(nodes_layout), elements(n), stat=status)
      call allocation_failure(status, 'the node and element numbers of the generator', &
                              4.0_dp*(real(nodes_layout, dp) + n), error_input, error)
      if (allocated(error)) return
      do i = 1, nodes_layout
         nodes(i) = find_coincident_node(deck%model, candidates, points(:, i), tolerance)
         if (nodes(i) == 0 .and. i > 1) then
            nodes(i) = find_coincident_node(deck%model, nodes(1:1), points(:, i), tolerance)
         end if
         if (nodes(i) == 0) then
            call add_deck_node(deck, deck%model%largest_node_label + 1, points(:, i), line, fields(1)%column, error)
            if (allocated(error)) return
            nodes(i) = deck%model%n_nodes
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
            call add_element(deck%model, deck%model%largest_element_label + 1, ends, section, error)
            if (allocated(error)) return
         end associate
         elements(i) = deck%model%n_elements
      end do

      call set_element_kind(deck%model, elements, kind, status)
      call allocation_failure(status, 'the element kinds', 8.0_dp*deck%model%n_elements, error_input, error)
      if (allocated(error)) return
      call add_to_element_set(deck%model, name, elements, error)
      if (.not. allocated(error)) call add_to_node_set(deck%model, name, nodes, error)
      if (.not. allocated(error)) call add_to_node_set(deck%model, name//'_start', nodes(1:1), error)
      if (.not. closed .and. .not. allocated(error)) &
         call add_to_node_set(deck%model, name//'_end', nodes(n + 1:n + 1), error)
      if (modulo(n, 2) == 0 .and. .not. allocated(error)) &
         call add_to_node_set(deck%model, name//'_mid', nodes(n/2 + 1:n/2 + 1), error)
   end subroutine read_generator

   !> *NSET, NSET=name [, GENERATE]: node labels and node-set names, or `first, last [, step]` lines.
   subroutine read_node_set(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
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
      call read_set_members(source, card, deck, .true., option_index(card, 'GENERATE') > 0, members, error)
      if (allocated(error)) return
      call add_to_node_set(deck%model, card%options(set_option)%value, members, error)
   end subroutine read_node_set

   !> *ELSET, ELSET=name [, GENERATE]: element labels and element-set names, or `first, last [, step]`.
   subroutine read_element_set(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
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
      call read_set_members(source, card, deck, .false., option_index(card, 'GENERATE') > 0, members, error)
      if (allocated(error)) return
      call add_to_element_set(deck%model, card%options(set_option)%value, members, error)
   end subroutine read_element_set

   !> The section named by the card's SECTION= option, which must be defined by an earlier *SECTION.
   subroutine card_section(source, card, deck, section, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(in) :: deck
      integer, intent(out) :: section
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      section = 0
      call require_option(source, card, 'SECTION', k, error)
      if (allocated(error)) return
      section = section_index(deck%model, card%options(k)%value)
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
   subroutine check_generator_sets(source, card, deck, name, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(in) :: deck
      character(len=*), intent(in) :: name
      type(error_t), allocatable, intent(out) :: error
      integer :: k, i
      character(len=6), parameter :: suffixes(4) = ['      ', '_start', '_end  ', '_mid  ']
      k = option_index(card, 'ELSET')
      call check_set_name(source, card%line, card%options(k)%value_column, name, error)
      if (allocated(error)) return
      if (element_set_index(deck%model, name) > 0) then
         call raise(source, card%line, card%options(k)%value_column, 'expected a new element set name, found '''// &
                    name//''' again', error)
         return
      end if
      do i = 1, size(suffixes)
         if (node_set_index(deck%model, name//trim(suffixes(i))) > 0) then
            call raise(source, card%line, card%options(k)%value_column, 'expected a name whose node sets ' // &
                       'are new, found the node set '''//name//trim(suffixes(i))//''' already defined', error)
            return
         end if
      end do
   end subroutine check_generator_sets

   !> Members of an *NSET (nodes = true) or *ELSET card, as internal indices.
   subroutine read_set_members(source, card, deck, nodes, generate, members, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(in) :: deck
      logical, intent(in) :: nodes, generate
      integer, allocatable, intent(out) :: members(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, count, first, last, step, label, index, status
      integer, allocatable :: found(:), trimmed(:)
      type(field_t), allocatable :: fields(:)
      character(len=:), allocatable :: kind

      kind = merge('node   ', 'element', nodes)
      kind = trim(kind)
      allocate (members(16))
      count = 0
      status = 0
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         if (generate) then
            call require_field_count(source, line, fields, 2, 3, 'first, last [, step]', error)
            if (allocated(error)) return
            call field_integer(source, deck%parameters, line, fields(1), 'a first label', first, error)
            if (allocated(error)) return
            call field_integer(source, deck%parameters, line, fields(2), 'a last label', last, error)
            if (allocated(error)) return
            step = 1
            if (size(fields) == 3) then
               call field_integer(source, deck%parameters, line, fields(3), 'a step', step, error)
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
                  index = node_index(deck%model, label)
               else
                  index = element_index(deck%model, label)
               end if
               if (index == 0) then
                  call raise(source, line, fields(1)%column, 'expected defined '//kind//' labels, found '// &
                             integer_to_string(label)//' undefined in '//integer_to_string(first)//' to '// &
                             integer_to_string(last), error)
                  return
               end if
               call append_integers(members, count, [index], status)
               if (status /= 0) exit
            end do
         else
            if (size(fields) == 0) cycle
            do j = 1, size(fields)
               if (nodes) then
                  call resolve_nodes(source, deck, line, fields(j), found, error)
               else
                  call resolve_elements(source, deck, line, fields(j), found, error)
               end if
               if (allocated(error)) return
               call append_integers(members, count, found, status)
               if (status /= 0) exit
            end do
         end if
         if (status /= 0) then
            ! the list of members doubles when it grows (uniarc_growth: append_integers)
            call allocation_failure(status, 'the members of '//kind//' set '''// &
                                    card%options(option_index(card, trim(merge('NSET ', 'ELSET', nodes))))%value//'''', &
                                    8.0_dp*count, error_input, error)
            return
         end if
      end do
      ! the list trimmed to its members, allocated with stat= (an assignment would reallocate unchecked)
      allocate (trimmed(count), stat=status)
      call allocation_failure(status, 'the members of '//kind//' set '''// &
                              card%options(option_index(card, trim(merge('NSET ', 'ELSET', nodes))))%value//'''', &
                              4.0_dp*count, error_input, error)
      if (allocated(error)) return
      trimmed(:) = members(1:count)
      call move_alloc(trimmed, members)
   end subroutine read_set_members

   !> The node among `candidates` nearest to `point` if it is within `tolerance`, else 0.
   pure integer function find_coincident_node(model, candidates, point, tolerance) result(index)
      type(model_builder_t), intent(in) :: model
      integer, intent(in) :: candidates(:)
      real(dp), intent(in) :: point(2), tolerance
      real(dp) :: distance, best
      integer :: i
      index = 0
      best = huge(1.0_dp)
      do i = 1, size(candidates)
         distance = norm2(model%coordinates(:, candidates(i)) - point)
         if (distance <= tolerance .and. distance < best) then
            best = distance
            index = candidates(i)
         end if
      end do
   end function find_coincident_node

   !> The nodes inside the box [lower, upper]. status: the stat= of its allocations (nonzero: refused
   !> by the system, `nodes` then unusable; for uniarc_memory, allocation_failure).
   pure subroutine nodes_in_box(model, lower, upper, nodes, status)
      type(model_builder_t), intent(in) :: model
      real(dp), intent(in) :: lower(2), upper(2)
      integer, allocatable, intent(out) :: nodes(:)
      integer, intent(out) :: status
      integer, allocatable :: kept(:)
      integer :: i, count
      allocate (nodes(model%n_nodes), stat=status)
      if (status /= 0) return
      count = 0
      do i = 1, model%n_nodes
         if (all(model%coordinates(:, i) >= lower .and. model%coordinates(:, i) <= upper)) then
            count = count + 1
            nodes(count) = i
         end if
      end do
      allocate (kept(count), stat=status)
      if (status /= 0) return
      kept(:) = nodes(1:count)
      call move_alloc(kept, nodes)
   end subroutine nodes_in_box

   !> An element is of zero length when its ends are one node or lie within round-off of each other.
   pure logical function is_zero_length(model, ends)
      type(model_builder_t), intent(in) :: model
      integer, intent(in) :: ends(2)
      real(dp) :: scale
      scale = maxval(abs(model%coordinates(:, ends)))
      is_zero_length = norm2(model%coordinates(:, ends(2)) - model%coordinates(:, ends(1))) <= &
                       zero_length_tolerance*scale
   end function is_zero_length

end module uniarc_deck_mesh
