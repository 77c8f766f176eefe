!> The input deck reader: turns a deck (docs/input.md) into a `model_t`.
!>
!> The deck is walked card by card; `dispatch` is the one `select case` over the keywords, with one
!> subroutine per card, so that a new card is one case and one subroutine. The cards come in families,
!> one module each: structure (uniarc_deck_mesh), supports and loads (uniarc_deck_loads), foundations and
!> obstacles (uniarc_deck_contact), analysis and output (uniarc_deck_analysis); *HEADING and *PARAMETER
!> are read here. Each card subroutine first checks its options (`check_options` with the list of names
!> it knows), then reads its data lines into a `deck_t` (uniarc_deck_state, a local of `read_deck`,
!> never module state), whose model builder (uniarc_model_builder) makes the model after the whole-deck
!> checks.
module uniarc_deck
   use uniarc_kinds, only: dp
   use uniarc_foreign, only: interrupt_signal
   use uniarc_memory, only: allocation_failure
   use uniarc_error, only: error_t, make_error, error_input, add_context
   use uniarc_strings, only: field_t, is_name, same_text, integer_to_string
   use uniarc_growth, only: grow_integers
   use uniarc_expression, only: evaluate_expression, set_parameter, find_parameter, is_reserved_name
   use uniarc_deck_source, only: source_t, card_t, read_source, next_card, raise, raise_plain, clip, &
                                 check_options, field_real
   use uniarc_model, only: model_t, analysis_nonlinear, control_arclength
   use uniarc_model_builder, only: finish_model, unused_node, element_without_section, element_kind
   use uniarc_deck_element, only: restrain_truss_nodes, read_release, check_moment_limit_analysis
   use uniarc_deck_state, only: parameter_override_t, deck_t
   use uniarc_deck_mesh, only: read_section, read_node, read_element, read_generator, read_node_set, &
                               read_element_set
   use uniarc_deck_loads, only: read_boundary, read_concentrated_load, read_distributed_load, read_temperature, &
                                check_prescribed_nodes
   use uniarc_deck_contact, only: read_foundation, read_spring, read_obstacle
   use uniarc_deck_move, only: read_move
   use uniarc_deck_analysis, only: read_track, read_static, read_path, read_output, check_track_names
   use uniarc_deck_steps, only: check_step_placement, read_step, read_end_step, finish_steps, take_steps
   use uniarc_deck_imperfection, only: read_imperfection
   implicit none
   private
   public :: parameter_override_t, read_deck

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
      type(deck_t) :: deck
      type(card_t) :: card
      integer :: position
      logical :: found

      call read_source(path, source, error)
      if (allocated(error)) return
      deck%overrides = overrides
      allocate (deck%override_used(size(overrides)), source=.false.)
      allocate (deck%parameter_line(8))

      position = 1
      do
         ! A SIGINT or SIGTERM stops the reading (the caller exits 130/143, docs/contracts.md, "Interrupts").
         if (interrupted(error)) return
         call next_card(source, position, card, found, error)
         if (allocated(error)) return
         if (.not. found) exit
         call dispatch(source, card, deck, error)
         if (allocated(error)) then
            ! a model that does not fit while its card is read (uniarc_memory: allocation_failure): at the card
            if (index(error%message, 'the model does not fit in memory') == 1) &
               call add_context(error, path//':'//integer_to_string(card%line))
            return
         end if
      end do

      call finish_steps(source, deck, error)
      if (allocated(error)) return
      call check_whole_deck(source, deck, error)
      if (allocated(error)) then
         if (index(error%message, 'the model does not fit in memory') == 1) call add_context(error, path)
         return
      end if
      call check_prescribed_nodes(source, deck, error)
      if (allocated(error)) return
      call finish_model(deck%model, model, error, origin=source%path)
      if (allocated(error)) then
         if (index(error%message, 'the model does not fit in memory') == 1) call add_context(error, path)
         return
      end if
      if (deck%n_steps > 0) then
         call take_steps(deck, model%steps, error)
         if (allocated(error)) then
            call add_context(error, path)
            return
         end if
         model%analysis = model%steps(1)%analysis
         model%fixed = model%steps(1)%fixed   ! the supports of the first step (the builder's: the last's)
      end if
   end subroutine read_deck

   !> The card dispatch: one case per keyword, one subroutine per card.
   subroutine dispatch(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error

      call check_step_placement(source, card, deck, error)
      if (allocated(error)) return
      select case (card%keyword)
      case ('STEP')
         call read_step(source, card, deck, error)
      case ('END STEP')
         call read_end_step(source, card, deck, error)
      case ('HEADING')
         call read_heading(source, card, deck, error)
      case ('PARAMETER')
         call read_parameter(source, card, deck, error)
      case ('SECTION')
         call read_section(source, card, deck, error)
      case ('NODE')
         call read_node(source, card, deck, error)
      case ('ELEMENT')
         call read_element(source, card, deck, error)
      case ('ARC', 'RING', 'LINE')
         call read_generator(source, card, deck, error)
      case ('NSET')
         call read_node_set(source, card, deck, error)
      case ('ELSET')
         call read_element_set(source, card, deck, error)
      case ('BOUNDARY')
         call read_boundary(source, card, deck, error)
      case ('CLOAD')
         call read_concentrated_load(source, card, deck, error)
      case ('DLOAD')
         call read_distributed_load(source, card, deck, error)
      case ('TEMPERATURE')
         call read_temperature(source, card, deck, error)
      case ('TRACK')
         call read_track(source, card, deck, error)
      case ('FOUNDATION')
         call read_foundation(source, card, deck, error)
      case ('SPRING')
         call read_spring(source, card, deck, error)
      case ('OBSTACLE')
         call read_obstacle(source, card, deck, error)
      case ('MOVE')
         call read_move(source, card, deck, error)
      case ('RELEASE')
         call read_release(source, card, deck, error)
      case ('PATH')
         call read_path(source, card, deck, error)
      case ('STATIC')
         call read_static(source, card, deck, error)
      case ('OUTPUT')
         call read_output(source, card, deck, error)
      case ('IMPERFECTION')
         call read_imperfection(source, card, deck, error)
      case default
         call raise(source, card%line, card%column, 'expected a known card (*HEADING, *PARAMETER, *SECTION, ' // &
                    '*NODE, *ELEMENT, *ARC, *RING, *LINE, *NSET, *ELSET, *BOUNDARY, *CLOAD, *DLOAD, *TRACK, ' // &
                    '*FOUNDATION, *SPRING, *OBSTACLE, *MOVE, *RELEASE, *STATIC, *PATH, *OUTPUT, *IMPERFECTION, *STEP, *END STEP), found ''*'// &
                    clip(card%keyword)//'''', error)
      end select
   end subroutine dispatch

   !> *HEADING: the data lines, joined by blanks, are the title.
   subroutine read_heading(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, length, first, last

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      ! the length first, then one allocation: a title of many lines is joined in linear time
      length = 0
      do i = 1, card%n_data
         associate (text => source%lines(card%data_lines(i))%text)
            if (length > 0) length = length + 1
            length = length + len_trim(text) - verify(text, ' ') + 1
         end associate
      end do
      if (allocated(deck%model%title)) deallocate (deck%model%title)
      allocate (character(len=length) :: deck%model%title)
      length = 0
      do i = 1, card%n_data
         associate (text => source%lines(card%data_lines(i))%text)
            first = verify(text, ' ')
            last = len_trim(text)
            if (length > 0) then
               deck%model%title(length + 1:length + 1) = ' '
               length = length + 1
            end if
            deck%model%title(length + 1:length + last - first + 1) = text(first:last)
            length = length + last - first + 1
         end associate
      end do
   end subroutine read_heading

   !> *PARAMETER: `name = expression` lines. A `-D name=value` replaces the expression where the deck
   !> defines `name`, so later parameters built on it follow the override.
   !> True, with `error` allocated, when a SIGINT or SIGTERM has arrived (uniarc_foreign:
   !> interrupt_signal): the reading of the deck stops; the caller (main) reports the interrupt.
   logical function interrupted(error)
      type(error_t), allocatable, intent(inout) :: error
      interrupted = interrupt_signal() /= 0
      if (interrupted) call make_error(error, 'the reading of the deck was interrupted by a signal', error_input)
   end function interrupted

   subroutine read_parameter(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, line, equals, first, k, column, existing, status
      character(len=:), allocatable :: text, name, message
      type(field_t) :: field
      real(dp) :: value

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      do i = 1, card%n_data
         if (interrupted(error)) return
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
         existing = find_parameter(deck%parameters, name)
         if (existing > 0) then
            call raise(source, line, first, 'expected a new parameter name, found '''//clip(name)// &
                       ''' (defined at line '//integer_to_string(deck%parameter_line(existing))//')', error)
            return
         end if

         k = find_override(deck, name)
         if (k > 0) then
            call mark_overrides_used(deck, name)
            call evaluate_expression(deck%overrides(k)%value, deck%parameters, value, error, column)
            if (allocated(error)) then
               message = error%message
               call make_error(error, '-D '//deck%overrides(k)%name//'='//deck%overrides(k)%value// &
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
            call field_real(source, deck%parameters, line, field, 'an expression', value, error)
            if (allocated(error)) return
         end if
         call set_parameter(deck%parameters, name, value, status)
         call allocation_failure(status, 'the table of parameters', 48.0_dp*(deck%parameters%names%count + 1), &
                                 error_input, error)
         if (allocated(error)) return
         call grow_integers(deck%parameter_line, deck%parameters%names%count, status)
         call allocation_failure(status, 'the deck positions of the parameters', &
                                 8.0_dp*deck%parameters%names%count, error_input, error)
         if (allocated(error)) return
         deck%parameter_line(deck%parameters%names%count) = line
      end do
   end subroutine read_parameter

   !> Checks that need the whole deck: every -D used, at least one element, no node outside every
   !> element (it would make the stiffness singular), every element with a section; the rotation of a
   !> node that only trusses use is held (uniarc_deck_element).
   subroutine check_whole_deck(source, deck, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, bad, status, n
      real(dp), allocatable :: loads(:, :)
      integer, allocatable :: load_line(:), load_column(:), kinds(:)

      do i = 1, size(deck%overrides)
         if (.not. deck%override_used(i)) then
            call make_error(error, '-D '//deck%overrides(i)%name//': no *PARAMETER of that name in '// &
                            source%path, error_input)
            return
         end if
      end do
      if (deck%model%n_elements == 0) then
         call raise_plain(source, 'expected at least one element (*ELEMENT, *ARC, *RING or *LINE), found none', &
                          error)
         return
      end if
      call check_computed_imperfection(source, deck, error)
      if (allocated(error)) return
      if (deck%n_steps > 0) then
         call check_moment_limit_analysis(source, deck, deck%steps(1)%analysis%kind /= analysis_nonlinear, error)
      else
         call check_moment_limit_analysis(source, deck, deck%model%analysis%kind /= analysis_nonlinear, error)
      end if
      if (allocated(error)) return
      call check_plastic_analysis(source, deck, error)
      if (allocated(error)) return
      call check_track_names(source, deck, error)
      if (allocated(error)) return
      bad = unused_node(deck%model)
      if (bad < 0) then
         call allocation_failure(-bad, 'the nodes in use', 4.0_dp*deck%model%n_nodes, error_input, error)
         return
      end if
      if (bad > 0) then
         call raise(source, deck%node_line(bad), deck%node_column(bad), 'expected every node in an ' // &
                    'element, found node '//integer_to_string(deck%model%node_label(bad))//' in none', error)
         return
      end if
      if (allocated(deck%stop_track)) then
         do i = 1, deck%model%n_tracks
            if (same_text(deck%model%tracks(i)%name, deck%stop_track)) deck%model%analysis%stop_track = i
         end do
         if (deck%model%analysis%stop_track == 0) then
            call raise(source, deck%stop_track_line, deck%stop_track_column, 'expected the name of a '// &
                       '*TRACK, found '''//clip(deck%stop_track)//'''', error)
            return
         end if
      end if
      call check_path_has_load(source, deck, error)
      if (allocated(error)) return
      bad = element_without_section(deck%model)
      if (bad > 0) then
         call raise_plain(source, 'expected a section for every element, found element '// &
                          integer_to_string(deck%model%element_label(bad))//' without one', error)
         return
      end if
      associate (model => deck%model)
         ! The check's arrays allocated with stat= and filled in place (function results, merged
         ! arrays and reallocations on assignment of the model's length are not checked).
         n = model%n_nodes
         allocate (loads(size(model%nodal_load, 1), n), load_line(n), load_column(n), kinds(model%n_elements), &
                   stat=status)
         if (status == 0) call grow_integers(deck%moment_line, n, status)
         if (status == 0) call grow_integers(deck%moment_column, n, status)
         call allocation_failure(status, 'the arrays of the truss nodes'' check', &
                                 8.0_dp*size(model%nodal_load, 1)*n + 16.0_dp*n + 4.0_dp*model%n_elements, &
                                 error_input, error)
         if (allocated(error)) return
         ! The nodal loads of every analysis step count as the model's (a moment on a truss node).
         loads(:, :) = abs(model%nodal_load(:, 1:n))
         do i = 1, deck%n_steps
            loads(:, :) = loads + abs(deck%steps(i)%loads%nodal_load)
         end do
         ! A moment that such a node cannot carry is reported at its first *CLOAD line, else (no line
         ! recorded) at the node's own line.
         load_line(:) = merge(deck%moment_line(1:n), deck%node_line(1:n), deck%moment_line(1:n) > 0)
         load_column(:) = merge(deck%moment_column(1:n), deck%node_column(1:n), deck%moment_line(1:n) > 0)
         do i = 1, model%n_elements
            kinds(i) = element_kind(model, i)
         end do
         call restrain_truss_nodes(source, model%connectivity(:, 1:model%n_elements), &
                                   kinds, model%node_label(1:n), &
                                   load_line, load_column, &
                                   model%fixed(:, 1:model%n_nodes), loads, error, &
                                   joints=model%end_joints)
      end associate
   end subroutine check_whole_deck

   !> A *PATH deck without analysis steps whose load pattern is all zero — no force, no distributed
   !> load, no temperature change, prescribed displacements and *MOVE translations of zero — has
   !> nothing for λ to scale: refused at its *PATH card (exit code 2), as a step without a load is at
   !> its *END STEP. (A load that the supports take whole, or a restrained temperature change, is a
   !> load: the path's start judges those.)
   subroutine check_path_has_load(source, deck, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(in) :: deck
      type(error_t), allocatable, intent(out) :: error
      logical :: loaded
      if (deck%n_steps > 0 .or. deck%model%analysis%kind /= analysis_nonlinear .or. deck%analysis_line == 0) return
      associate (model => deck%model)
         loaded = any(model%nodal_load(:, 1:model%n_nodes) /= 0.0_dp) .or. model%n_loads > 0 .or. model%n_thermal > 0
         if (model%n_prescribed > 0) loaded = loaded .or. any(model%prescribed_value(1:model%n_prescribed) /= 0.0_dp)
         if (allocated(model%moves)) loaded = loaded .or. any(model%moves /= 0.0_dp)
      end associate
      if (.not. loaded) call raise(source, deck%analysis_line, max(deck%analysis_column, 1), 'expected a load for the path '// &
                                   'to follow (*CLOAD, *DLOAD, *TEMPERATURE, a prescribed displacement or an obstacle '// &
                                   'moved, not all zero), found none: lambda would scale nothing', error)
   end subroutine check_path_has_load

   !> *IMPERFECTION without FILE= (uniarc_deck_imperfection): the first run that computes the mode
   !> traces the deck's own path under arc-length control, and moves the nodes after the contact
   !> candidates were built from them, so it needs *PATH with CONTROL=ARCLENGTH and no contact card.
   subroutine check_computed_imperfection(source, deck, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(in) :: deck
      type(error_t), allocatable, intent(out) :: error
      if (deck%model%analysis%imperfection_bifurcation == 0) return
      if (deck%model%analysis%kind /= analysis_nonlinear .or. deck%model%analysis%control /= control_arclength) then
         call raise(source, deck%imperfection_line, 1, 'expected *PATH, CONTROL=ARCLENGTH with *IMPERFECTION '// &
                    'without FILE= (its mode comes from the path of the perfect structure), found another '// &
                    'analysis', error)
      else if (deck%model%n_contacts > 0) then
         call raise(source, deck%imperfection_line, 1, 'expected FILE= on *IMPERFECTION in a deck with contact '// &
                    'cards (a mode computed in a first run would move the nodes after the contacts were built '// &
                    'from them: write it with *OUTPUT, MODES and read it back)', error)
      end if
   end subroutine check_computed_imperfection

   !> A bearing limit (QU= of *FOUNDATION or *SPRING) makes a plastic slip, a history that the path
   !> following commits step by step (docs/theory.md §3.9): it needs *PATH, not the linear *STATIC.
   subroutine check_plastic_analysis(source, deck, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(in) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: kind
      if (deck%plastic_line == 0) return
      kind = deck%model%analysis%kind
      if (deck%n_steps > 0) kind = deck%steps(1)%analysis%kind
      if (kind == analysis_nonlinear) return
      call raise(source, deck%plastic_line, deck%plastic_column, 'expected *PATH with a bearing limit QU= (the '// &
                 'plastic slip is a history that the path follows), found *STATIC or no analysis card', error)
   end subroutine check_plastic_analysis

   !> Mark every override of parameter `name` used: of several -D of one name, the last is applied
   !> (find_override) and none is reported as unknown.
   pure subroutine mark_overrides_used(deck, name)
      type(deck_t), intent(inout) :: deck
      character(len=*), intent(in) :: name
      integer :: i
      do i = 1, size(deck%overrides)
         if (same_text(deck%overrides(i)%name, name)) deck%override_used(i) = .true.
      end do
   end subroutine mark_overrides_used

   !> Index of the override of parameter `name`, 0 if there is none (the last -D of a name wins).
   pure integer function find_override(deck, name) result(index)
      type(deck_t), intent(in) :: deck
      character(len=*), intent(in) :: name
      integer :: i
      index = 0
      do i = 1, size(deck%overrides)
         if (same_text(deck%overrides(i)%name, name)) index = i
      end do
   end function find_override

end module uniarc_deck
