!> The support and load cards of the deck: *BOUNDARY (with prescribed displacements), *CLOAD, *DLOAD
!> (with intensities that vary with position, and self-weight) and *TEMPERATURE (docs/input.md). Loads
!> are reference loads, multiplied by the load parameter λ of the analysis.
module uniarc_deck_loads
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_input
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: field_t, to_upper, is_name, integer_to_string, real_to_string
   use uniarc_expression, only: find_parameter, parameter_table_t, set_parameter, sin_degrees, cos_degrees
   use uniarc_deck_source, only: source_t, card_t, raise, clip, check_options, option_index, data_fields, &
                                 require_field_count, field_real
   use uniarc_model, only: dof_ux, dof_uy, dof_rz, element_truss
   use uniarc_model_builder, only: add_support, add_nodal_load, add_line_load, add_pressure, element_kind, &
                                   add_thermal_load, add_prescribed_displacement, remove_support
   use uniarc_deck_state, only: deck_t, resolve_nodes, resolve_elements, read_dof, option_real
   use uniarc_growth, only: grow_integers
   use uniarc_builder_loads, only: thermal_excess
   implicit none
   private
   public :: read_boundary, read_concentrated_load, read_distributed_load, read_temperature
   public :: check_prescribed_nodes

contains

   !> *BOUNDARY [, REMOVE]: lines `target, type` with a named type, or `target, first_dof [, last_dof
   !> [, value]]`; a value prescribes the displacement of the held DOFs (a support settlement, scaled by
   !> λ like the loads, under *STATIC and *PATH). Inside a *STEP (nonlinear steps): the supports it
   !> adds hold their DOFs where they are when the step begins, a value moves them from there, and
   !> REMOVE (no values) releases held DOFs, whose reactions the step ramps down (docs/theory.md §2.10).
   !> Outside the steps, a value in a deck with steps is a load outside them (refused at *STEP).
   subroutine read_boundary(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, k, line, first_dof, last_dof, c, status
      logical :: held(3), named, remove, both(3)
      character(len=2), parameter :: dof_names(3) = ['UX', 'UY', 'RZ']
      real(dp) :: settlement
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: nodes(:)

      call check_options(source, card, [character(len=6) :: 'REMOVE'], error)
      if (allocated(error)) return
      remove = option_index(card, 'REMOVE') > 0
      if (remove .and. .not. deck%in_step) then
         call raise(source, card%line, card%options(option_index(card, 'REMOVE'))%column, 'expected REMOVE '// &
                    'inside a *STEP (a support is removed in an analysis step; before the steps, leave it out)', &
                    error)
         return
      end if
      if (remove) then
         ! the step's first REMOVE card, for the message of a step that its removals leave a mechanism
         associate (step => deck%steps(deck%n_steps + 1))
            if (step%remove_line == 0) then
               step%remove_line = card%line
               step%remove_column = card%options(option_index(card, 'REMOVE'))%column
               step%remove_text = source%lines(card%line)%text
            end if
         end associate
      end if
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 2, 4, 'target, type or target, first_dof, last_dof, value', &
                                  error)
         if (allocated(error)) return
         call resolve_nodes(source, deck, line, fields(1), nodes, error)
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
            if (is_name(fields(2)%text) .and. find_parameter(deck%parameters, fields(2)%text) == 0) then
               call raise(source, line, fields(2)%column, 'expected FIXED, PINNED, ROLLER_X, ROLLER_Y, ' // &
                          'XSYMM, YSYMM or a DOF 1 to 3, found '''//clip(fields(2)%text)//'''', error)
               return
            end if
            call read_dof(source, deck, line, fields(2), first_dof, error)
            if (allocated(error)) return
            last_dof = first_dof
            if (size(fields) > 2) then
               call read_dof(source, deck, line, fields(3), last_dof, error)
               if (allocated(error)) return
               if (last_dof < first_dof) then
                  call raise(source, line, fields(3)%column, 'expected a last DOF not below the first (' // &
                             integer_to_string(first_dof)//'), found '//integer_to_string(last_dof), error)
                  return
               end if
            end if
            held(first_dof:last_dof) = .true.
            if (size(fields) > 3 .and. remove) then
               call raise(source, line, fields(4)%column, 'expected no value with REMOVE (a removed support '// &
                          'is released, not moved), found '''//clip(fields(4)%text)//'''', error)
               return
            end if
            if (size(fields) > 3) then
               call field_real(source, deck%parameters, line, fields(4), 'a prescribed displacement', settlement, &
                               error)
               if (allocated(error)) return
               call check_magnitude(source, line, fields(4), settlement, error)
               if (allocated(error)) return
               do j = 1, size(nodes)
                  do k = first_dof, last_dof
                     call add_prescribed_displacement(deck%model, nodes(j), k, settlement, status)
                     call allocation_failure(status, 'the prescribed displacements of the model', &
                                             16.0_dp*deck%model%n_prescribed, error_input, error)
                     if (allocated(error)) return
                  end do
                  deck%n_prescribed = deck%n_prescribed + 1
                  call grow_integers(deck%prescribed_node, deck%n_prescribed, status)
                  if (status == 0) call grow_integers(deck%prescribed_line, deck%n_prescribed, status)
                  if (status == 0) call grow_integers(deck%prescribed_column, deck%n_prescribed, status)
                  call allocation_failure(status, 'the list of prescribed displacements', &
                                          24.0_dp*deck%n_prescribed, error_input, error)
                  if (allocated(error)) return
                  deck%prescribed_node(deck%n_prescribed) = nodes(j)
                  deck%prescribed_line(deck%n_prescribed) = line
                  deck%prescribed_column(deck%n_prescribed) = fields(4)%column
               end do
               if (.not. deck%in_step .and. deck%loose_load_line == 0) then
                  deck%loose_load_line = line
                  deck%loose_load_column = fields(4)%column
               end if
            end if
         end if
         do j = 1, size(nodes)
            if (deck%in_step) then
               ! A support changed in a step: the node may not be a contact candidate (its gap is
               ! evaluated on the solved displacements, which do not include a held node's).
               do c = 1, deck%model%n_contacts
                  if (deck%model%contacts(c)%node /= nodes(j)) cycle
                  call raise(source, line, fields(1)%column, 'expected no support changed in a step at node '// &
                             integer_to_string(deck%model%node_label(nodes(j)))//', a contact candidate (its '// &
                             'gap would not see the support''s displacement)', error)
                  return
               end do
            end if
            if (deck%in_step) then
               ! A DOF is added or removed in a step, not both: a support added and removed in one
               ! step (or removed and added again) is no change and no load.
               if (remove) then
                  both = held .and. deck%model%fixed(:, nodes(j)) .and. .not. deck%step_start_fixed(:, nodes(j))
               else
                  both = held .and. deck%step_start_fixed(:, nodes(j)) .and. .not. deck%model%fixed(:, nodes(j))
               end if
               if (any(both)) then
                  call raise(source, line, fields(2)%column, 'expected a DOF either added or removed in a step, '// &
                             'found '//trim(dof_names(findloc(both, .true., 1)))//' of node '// &
                             integer_to_string(deck%model%node_label(nodes(j)))//' '// &
                             trim(merge('added by this step''s *BOUNDARY and now removed        ', &
                                        'removed by this step''s *BOUNDARY, REMOVE and now added', remove))// &
                             ' (a support changes once per step; change it again in a later step)', error)
                  return
               end if
            end if
            if (remove) then
               if (.not. all(deck%model%fixed(:, nodes(j)) .or. .not. held)) then
                  call raise(source, line, fields(2)%column, 'expected held DOFs to remove, found a free one '// &
                             'at node '//integer_to_string(deck%model%node_label(nodes(j))), error)
                  return
               end if
               call remove_support(deck%model, nodes(j), held)
            else
               call add_support(deck%model, nodes(j), held)
            end if
         end do
      end do
   end subroutine read_boundary

   !> *CLOAD: lines `target, dof, value` with dof 1|2|3 or FX|FY|MZ; loads on one node are summed.
   subroutine read_concentrated_load(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, dof, status
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
         call resolve_nodes(source, deck, line, fields(1), nodes, error)
         if (allocated(error)) return
         select case (to_upper(fields(2)%text))
         case ('FX')
            dof = dof_ux
         case ('FY')
            dof = dof_uy
         case ('MZ')
            dof = dof_rz
         case default
            if (is_name(fields(2)%text) .and. find_parameter(deck%parameters, fields(2)%text) == 0) then
               call raise(source, line, fields(2)%column, 'expected FX, FY, MZ or a DOF 1 to 3, found '''// &
                          clip(fields(2)%text)//'''', error)
               return
            end if
            call read_dof(source, deck, line, fields(2), dof, error)
            if (allocated(error)) return
         end select
         call field_real(source, deck%parameters, line, fields(3), 'a load value', value, error)
         if (allocated(error)) return
         call check_magnitude(source, line, fields(3), value, error)
         if (allocated(error)) return
         do j = 1, size(nodes)
            call add_nodal_load(deck%model, nodes(j), dof, value)
            if (dof == dof_rz .and. value /= 0.0_dp) then
               call grow_integers(deck%moment_line, nodes(j), status)
               if (status == 0) call grow_integers(deck%moment_column, nodes(j), status)
               call allocation_failure(status, 'the deck positions of the moments', 16.0_dp*nodes(j), error_input, &
                                       error)
               if (allocated(error)) return
               if (deck%moment_line(nodes(j)) == 0) then
                  deck%moment_line(nodes(j)) = line
                  deck%moment_column(nodes(j)) = fields(2)%column
               end if
            end if
         end do
      end do
   end subroutine read_concentrated_load

   !> *DLOAD [, FOLLOWER] [, XC=xc, YC=yc]: lines `elset, type, value` with type PX, PY (per unit
   !> initial length, global) or P (normal pressure along the element's left normal), and
   !> `elset, WEIGHT, w [, angle]` (self-weight w per unit initial length, acting in the direction
   !> `angle`, degrees from +x, default 270: down). FOLLOWER is only for P.
   !>
   !> The value (and the angle) may use the position of the element: x, y (its midpoint on the initial
   !> chord), s (the arc length along the target's elements, in their order, to that midpoint) and
   !> theta (degrees, atan2 of the midpoint about the centre (XC, YC), default the origin). It is
   !> evaluated at each element's midpoint and taken as uniform on the element (the midpoint rule: the
   !> load resultants converge as h²); the names x, y, s, theta shadow deck parameters of those names
   !> here. Loads of one kind on one element are summed into one record: an element has at most one
   !> fixed-direction record, one pressure record and one follower-pressure record.
   subroutine read_distributed_load(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, centre_option, status
      logical :: follower
      real(dp) :: value, angle, centre(2)
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: elements(:)
      character(len=:), allocatable :: load_type
      type(parameter_table_t) :: table
      real(dp), allocatable :: position(:, :)

      call check_options(source, card, [character(len=8) :: 'FOLLOWER', 'XC=', 'YC='], error)
      if (allocated(error)) return
      follower = option_index(card, 'FOLLOWER') > 0
      centre = 0.0_dp
      centre_option = option_index(card, 'XC')
      if (centre_option > 0) call option_real(source, card, deck, centre_option, 'a coordinate', centre(1), error)
      if (allocated(error)) return
      centre_option = option_index(card, 'YC')
      if (centre_option > 0) call option_real(source, card, deck, centre_option, 'a coordinate', centre(2), error)
      if (allocated(error)) return
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         if (size(fields) >= 2) then
            if (to_upper(fields(2)%text) == 'WEIGHT') then
               call require_field_count(source, line, fields, 2, 4, 'elset, WEIGHT, weight per length, angle', error)
            else
               call require_field_count(source, line, fields, 3, 3, 'elset, type, value', error)
            end if
         else
            call require_field_count(source, line, fields, 3, 3, 'elset, type, value', error)
         end if
         if (allocated(error)) return
         call resolve_elements(source, deck, line, fields(1), elements, error)
         if (allocated(error)) return
         ! A truss, pinned at both ends, has no transverse stiffness over its span: it takes loads at
         ! its nodes only.
         do j = 1, size(elements)
            if (element_kind(deck%model, elements(j)) == element_truss) then
               call raise(source, line, fields(1)%column, 'expected beam elements for a distributed load, '// &
                          'found truss element '//integer_to_string(deck%model%element_label(elements(j)))// &
                          ' (a truss takes loads at its nodes: *CLOAD)', error)
               return
            end if
         end do
         load_type = to_upper(fields(2)%text)
         select case (load_type)
         case ('PX', 'PY', 'WEIGHT')
            if (follower) then
               call raise(source, line, fields(2)%column, 'expected type P with FOLLOWER, found '''// &
                          load_type//'''', error)
               return
            end if
         case ('P')
            continue
         case default
            call raise(source, line, fields(2)%column, 'expected a load type PX, PY, P or WEIGHT, found '''// &
                       clip(fields(2)%text)//'''', error)
            return
         end select
         call element_positions(deck, elements, centre, position, error)
         if (allocated(error)) return
         table = deck%parameters
         do j = 1, size(elements)
            call set_parameter(table, 'x', position(1, j))
            call set_parameter(table, 'y', position(2, j))
            call set_parameter(table, 's', position(3, j))
            call set_parameter(table, 'theta', position(4, j))
            if (load_type == 'WEIGHT' .and. section_default(fields, 3)) then
               ! the section's weight (*SECTION, WEIGHT=, within 1e100 there)
               call section_value(source, deck, line, fields, 3, elements(j), .true., value, error)
               if (allocated(error)) return
            else
               call field_real(source, table, line, fields(3), 'a load value', value, error, &
                              where_evaluated(deck, elements(j), position(:, j)))
               if (allocated(error)) return
               call check_magnitude(source, line, fields(3), value, error, &
                                    where_evaluated(deck, elements(j), position(:, j)))
               if (allocated(error)) return
               if (load_type == 'WEIGHT' .and. .not. (value >= 0.0_dp)) then
                  ! a weight is a magnitude, as *SECTION, WEIGHT= is: its direction is the angle
                  call raise(source, line, fields(3)%column, 'expected a weight per unit length >= 0 (its '// &
                             'direction is the angle field, default 270: down), found '//real_to_string(value)// &
                             ' at element '//integer_to_string(deck%model%element_label(elements(j))), error)
                  return
               end if
            end if
            select case (load_type)
            case ('PX')
               call add_line_load(deck%model, elements(j), dof_ux, value, status)
            case ('PY')
               call add_line_load(deck%model, elements(j), dof_uy, value, status)
            case ('WEIGHT')
               angle = 270.0_dp
               if (size(fields) > 3) call field_real(source, table, line, fields(4), 'an angle in degrees', angle, error, &
                                                    where_evaluated(deck, elements(j), position(:, j)))
               if (allocated(error)) return
               call add_line_load(deck%model, elements(j), dof_ux, value*cos_degrees(angle), status)
               if (status == 0) &
                  call add_line_load(deck%model, elements(j), dof_uy, value*sin_degrees(angle), status)
            case default
               call add_pressure(deck%model, elements(j), value, follower, status)
            end select
            call allocation_failure(status, 'the distributed load records', 64.0_dp*deck%model%n_loads, &
                                    error_input, error)
            if (allocated(error)) return
         end do
      end do
   end subroutine read_distributed_load

   !> Position variables of the elements `elements` (in that order) at their midpoints on the initial
   !> chord: (x, y, s, theta) per element (4, n); s the arc length along the list to the midpoint,
   !> theta = atan2(y − yc, x − xc) in degrees, (−180, 180]. `position` is allocated here (4, n).
   !> Errors: `position` refused by the system (error_input: the model does not fit in memory).
   subroutine element_positions(deck, elements, centre, position, error)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: elements(:)
      real(dp), intent(in) :: centre(2)
      real(dp), allocatable, intent(out) :: position(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: ends(2, 2), middle(2), length, travelled
      real(dp), parameter :: degrees = 180.0_dp/acos(-1.0_dp)
      integer :: j, status
      allocate (position(4, size(elements)), stat=status)
      call allocation_failure(status, 'the positions of the elements of a line', 32.0_dp*size(elements), &
                              error_input, error)
      if (allocated(error)) return
      travelled = 0.0_dp
      do j = 1, size(elements)
         ends(:, 1) = deck%model%coordinates(:, deck%model%connectivity(1, elements(j)))
         ends(:, 2) = deck%model%coordinates(:, deck%model%connectivity(2, elements(j)))
         middle = 0.5_dp*(ends(:, 1) + ends(:, 2))
         length = norm2(ends(:, 2) - ends(:, 1))
         position(1:2, j) = middle
         position(3, j) = travelled + 0.5_dp*length
         position(4, j) = 0.0_dp
         if (any(middle /= centre)) position(4, j) = degrees*atan2(middle(2) - centre(2), middle(1) - centre(1))
         travelled = travelled + length
      end do
   end subroutine element_positions

   !> *TEMPERATURE: lines `elset, alpha, dT [, dT_difference, depth]`: a temperature change dT at the
   !> elements' axis (axial strain alpha dT) and, optionally, a difference dT_left − dT_right between the
   !> faces (left: the side of the left normal) over the depth h (curvature −alpha dT_difference/h), with
   !> the coefficient of thermal expansion alpha of the elements' material. Reference loads scaled by λ;
   !> the values may use x, y, s, theta as in *DLOAD (no XC/YC: theta about the origin).
   subroutine read_temperature(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, status, nodes(2)
      real(dp) :: alpha, delta_t, difference, depth, length
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: elements(:)
      type(parameter_table_t) :: table
      real(dp), allocatable :: position(:, :)
      character(len=:), allocatable :: what
      logical :: axial

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 3, 5, 'elset, alpha, dT, dT_difference, depth', error)
         if (allocated(error)) return
         if (size(fields) == 4) then
            call raise(source, line, fields(4)%column + len(fields(4)%text), &
                       'expected the depth h after the temperature difference', error)
            return
         end if
         call resolve_elements(source, deck, line, fields(1), elements, error)
         if (allocated(error)) return
         call element_positions(deck, elements, [0.0_dp, 0.0_dp], position, error)
         if (allocated(error)) return
         table = deck%parameters
         do j = 1, size(elements)
            call set_parameter(table, 'x', position(1, j))
            call set_parameter(table, 'y', position(2, j))
            call set_parameter(table, 's', position(3, j))
            call set_parameter(table, 'theta', position(4, j))
            if (section_default(fields, 2)) then
               call section_value(source, deck, line, fields, 2, elements(j), .false., alpha, error)
            else
               call field_real(source, table, line, fields(2), 'a coefficient of thermal expansion', alpha, error, &
                              where_evaluated(deck, elements(j), position(:, j)))
            end if
            if (allocated(error)) return
            call field_real(source, table, line, fields(3), 'a temperature change', delta_t, error, &
                           where_evaluated(deck, elements(j), position(:, j)))
            if (allocated(error)) return
            call check_magnitude(source, line, fields(3), delta_t, error, &
                                 where_evaluated(deck, elements(j), position(:, j)))
            if (allocated(error)) return
            difference = 0.0_dp
            depth = 0.0_dp
            if (size(fields) == 5) then
               call field_real(source, table, line, fields(4), 'a temperature difference', difference, error, &
                              where_evaluated(deck, elements(j), position(:, j)))
               if (allocated(error)) return
               call field_real(source, table, line, fields(5), 'a depth', depth, error, &
                              where_evaluated(deck, elements(j), position(:, j)))
               if (allocated(error)) return
               if (.not. depth > 0.0_dp) then
                  call raise(source, line, fields(5)%column, 'expected a depth h > 0, found '''// &
                             clip(fields(5)%text)//''' = '//real_to_string(depth)// &
                             where_evaluated(deck, elements(j), position(:, j)), error)
                  return
               end if
               if (difference /= 0.0_dp .and. element_kind(deck%model, elements(j)) == element_truss) then
                  call raise(source, line, fields(4)%column, 'expected no temperature difference on truss element '// &
                             integer_to_string(deck%model%element_label(elements(j)))// &
                             ' (a truss has no bending)', error)
                  return
               end if
            end if
            ! A deformation beyond the element's (docs/theory.md §1.9) refused at the value that makes it.
            nodes = deck%model%connectivity(1:2, elements(j))
            length = norm2(deck%model%coordinates(:, nodes(2)) - deck%model%coordinates(:, nodes(1)))
            call thermal_excess(alpha, delta_t, difference, depth, length, what, axial)
            if (len(what) > 0) then
               call raise(source, line, fields(merge(3, 4, axial))%column, 'expected a thermal deformation '// &
                          'the element can take (a small strain, a rotation against its chord): element '// &
                          integer_to_string(deck%model%element_label(elements(j)))//' would have '//what// &
                          '; check the units of alpha, dT, dT_d and h', error)
               return
            end if
            call add_thermal_load(deck%model, elements(j), alpha, delta_t, difference, depth, status)
            call allocation_failure(status, 'the list of temperature changes', 80.0_dp*deck%model%n_thermal, &
                                    error_input, error)
            if (allocated(error)) return
         end do
      end do
   end subroutine read_temperature

   !> Field k of a data line is absent or empty: its value is the section's (*SECTION, WEIGHT= or ALPHA=).
   pure logical function section_default(fields, k)
      type(field_t), intent(in) :: fields(:)
      integer, intent(in) :: k
      section_default = size(fields) < k
      if (.not. section_default) section_default = len(fields(k)%text) == 0
   end function section_default

   !> The weight per unit length (`weight`) or the coefficient of thermal expansion of element
   !> `element`'s section, for a load line whose field k is absent or empty; an error at that field (or
   !> after the line) when the section gives none.
   subroutine section_value(source, deck, line, fields, k, element, weight, value, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: line, k, element
      type(field_t), intent(in) :: fields(:)
      logical, intent(in) :: weight
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer :: column, s
      logical :: given
      s = deck%model%element_section(element)
      if (weight) then
         given = deck%model%sections(s)%has_weight
         value = deck%model%sections(s)%weight
      else
         given = deck%model%sections(s)%has_alpha
         value = deck%model%sections(s)%alpha
      end if
      if (given) return
      if (size(fields) >= k) then
         column = fields(k)%column
      else
         column = len_trim(source%lines(line)%text) + 1
      end if
      call raise(source, line, column, 'expected '//trim(merge('a weight per unit length          ', &
                 'a coefficient of thermal expansion', weight))//' here or on the section of element '// &
                 integer_to_string(deck%model%element_label(element))//' (*SECTION, NAME='// &
                 deck%model%sections(s)%name//', '//trim(merge('WEIGHT=', 'ALPHA= ', weight))//'), found none', error)
   end subroutine section_value

   !> At the end of the deck: a node with a prescribed displacement may not be a contact candidate (its
   !> gap is evaluated on the displacements the analysis solves for, which do not include the
   !> prescribed ones): refused at the value's field.
   subroutine check_prescribed_nodes(source, deck, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(in) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, c
      do i = 1, deck%n_prescribed
         do c = 1, deck%model%n_contacts
            if (deck%model%contacts(c)%node /= deck%prescribed_node(i)) cycle
            call raise(source, deck%prescribed_line(i), deck%prescribed_column(i), 'expected no prescribed '// &
                       'displacement at node '//integer_to_string(deck%model%node_label(deck%prescribed_node(i)))// &
                       ', a contact candidate (its gap would not see the motion): prescribe the displacement '// &
                       'of a node next to it', error)
            return
         end do
      end do
   end subroutine check_prescribed_nodes

   !> A load, temperature change or prescribed displacement beyond 1e100 in magnitude is refused at its
   !> field (file:line:col, exit code 2), as stiffnesses beyond 1e100 are (uniarc_deck_mesh): the
   !> displacements it drives would overflow double precision in the equations.
   subroutine check_magnitude(source, line, field, value, error, context)
      type(source_t), intent(in) :: source
      integer, intent(in) :: line
      type(field_t), intent(in) :: field
      real(dp), intent(in) :: value
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: context   !< where it was evaluated, ends the message
      character(len=:), allocatable :: message
      if (abs(value) <= 1.0e100_dp) return
      message = 'expected a value at most 1e100 in magnitude (larger loads overflow the equations in '// &
                'double precision: rescale the units), found '//real_to_string(value)
      if (present(context)) message = message//context
      call raise(source, line, field%column, message, error)
   end subroutine check_magnitude

   !> Where an expression of position was evaluated, for a message: ' at element L (x = .., y = ..,
   !> s = .., theta = ..)', `position` the element's (x, y, s, theta) of `element_positions`.
   function where_evaluated(deck, element, position) result(text)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: element
      real(dp), intent(in) :: position(4)
      character(len=:), allocatable :: text
      text = ' at element '//integer_to_string(deck%model%element_label(element))//' (x = '// &
             real_to_string(position(1))//', y = '//real_to_string(position(2))//', s = '// &
             real_to_string(position(3))//', theta = '//real_to_string(position(4))//')'
   end function where_evaluated

end module uniarc_deck_loads
