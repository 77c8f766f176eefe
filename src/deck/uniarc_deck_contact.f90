!> The contact cards of the deck: *FOUNDATION, *SPRING and *OBSTACLE (docs/input.md, "Foundations and
!> obstacles"). Each reads its options and data into a description (a `foundation_t`, springs, an
!> obstacle's shape), which the model builder turns into contact candidates through the contact law
!> (uniarc_contact_law); the checks that need the geometry (nodal normals, a straight set, a node inside
!> an obstacle) come back from there as codes that become positioned messages here.
module uniarc_deck_contact
   use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_input
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: field_t, to_upper, is_name, integer_to_string, real_to_string
   use uniarc_growth, only: append_integers, grow_reals_2
   use uniarc_expression, only: sin_degrees, cos_degrees
   use uniarc_deck_source, only: source_t, card_t, raise, clip, check_options, option_index, require_option, &
                                 data_fields, require_field_count, field_real
   use uniarc_model, only: foundation_t, foundation_winkler, foundation_pasternak, side_left, side_right, &
                           side_inner, side_outer, &
                           side_direction, gap_fixed_direction, gap_circle_inside, gap_circle_outside, &
                           gap_ellipse_inside, gap_ellipse_outside, gap_polyline, tangential_contact, &
                           tangential_bonded
   use uniarc_model_contacts, only: add_foundation, add_springs, add_obstacle
   use uniarc_model_builder, only: contact_group_index
   use uniarc_contact_law, only: foundation_straight, foundation_problem, foundation_not_open_chain
   use uniarc_deck_move, only: record_obstacle
   use uniarc_deck_state, only: deck_t, option_field, option_real, require_one_data_line, resolve_nodes, &
                                resolve_elements
   implicit none
   private
   public :: read_foundation, read_spring, read_obstacle

   !> Length of the sum of two consecutive unit directions of a polyline under which they are taken as
   !> opposite (the second segment folds back on the first).
   real(dp), parameter :: fold_tolerance = 1.0e-9_dp

contains

   !> *FOUNDATION, ELSET=set, MODULUS=K, SIDE=INNER|OUTER|LEFT|RIGHT or DIRECTION=angle [, BILATERAL]
   !> [, NAME=name] [, SCALE=s] [, KT=K_t [, TANGENTIAL=CONTACT|BONDED]] [, QU=q_u] [, TYPE=WINKLER|PASTERNAK
   !> [, GP=G_p [, CONTINUES=BOTH|NONE|START|END]]] [, GAP=g0] [, TU=t_u [, KU=k_u]]: a Winkler foundation
   !> along an element set, lumped to its nodes, with tangential springs of modulus K_t if asked
   !> (`tangential_springs`), a bearing limit q_u if asked (`bearing_limit`) and an uplift limit t_u with
   !> it (`uplift_limit`, its own modulus KU=); or a Pasternak bed, Winkler's under a shear layer G_p
   !> (`foundation_law`; uniarc_contact_law, pasternak_bed); an initial gap g0.
   !>
   !> Node stiffness k = K × (half the initial length of the node's adjacent elements in the set): a
   !> Winkler bed (Kerr 1964) lumped onto the nodes by the trapezoidal rule for ∫ K w δw ds, i.e. a
   !> diagonal foundation matrix C_b in the paper's Eq. (7), Δr_b = C_b Δu_b; flexibility 1/k.
   !> The reaction direction n (the direction in which the foundation pushes, toward the free side) is
   !> fixed (DIRECTION) or the nodal normal of the set on the side away from the foundation (SIDE; the
   !> concave side of INNER/OUTER from the sign of the set's total turning). Gap g = g0 + n·u.
   subroutine read_foundation(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: set_option, modulus_option, side_option, direction_option, status, bad_node
      real(dp) :: angle, uplift_stiffness
      type(field_t) :: field
      type(foundation_t) :: foundation
      character(len=:), allocatable :: side

      call check_options(source, card, [character(len=11) :: 'ELSET=', 'MODULUS=', 'SIDE=', 'DIRECTION=', &
                                        'BILATERAL', 'NAME=', 'SCALE=', 'KT=', 'TANGENTIAL=', 'QU=', 'TYPE=', &
                                        'GP=', 'GAP=', 'TU=', 'KU=', 'CONTINUES='], error)
      if (allocated(error)) return
      call contact_group_name(source, card, deck, 'foundation', foundation%name, error)
      if (allocated(error)) return
      call require_option(source, card, 'ELSET', set_option, error)
      if (allocated(error)) return
      field = option_field(card, set_option)
      foundation%element_set = field%text
      call resolve_elements(source, deck, card%line, field, foundation%elements, error)
      if (allocated(error)) return
      if (size(foundation%elements) == 0) then
         call raise(source, card%line, field%column, 'expected an element set with elements, found '''// &
                    field%text//''' empty', error)
         return
      end if
      call require_option(source, card, 'MODULUS', modulus_option, error)
      if (allocated(error)) return
      call option_real(source, card, deck, modulus_option, 'a modulus', foundation%modulus, error)
      if (allocated(error)) return
      ! MODULUS = 0 is no foundation (a group without candidates), so that a sweep over k can start at 0.
      ! Otherwise from 1e-100 to 1e100, as EA and EI (uniarc_deck_mesh): with tributary lengths L from
      ! 1e-100 to 1e100 (uniarc_check) the node spring k·L stays within 1e-200..1e200, so that its
      ! flexibility 1/(k·L) and the spring's force and energy terms stay finite (k = 1e-300 overflowed
      ! 1/(k·L): a NaN complementarity residual in Release, SIGFPE in Debug).
      if (.not. stiffness_in_range(foundation%modulus, zero_allowed=.true.)) then
         call raise(source, card%line, card%options(modulus_option)%value_column, &
                    'expected a MODULUS of 0 (no foundation) or from 1e-100 to 1e100 (beyond, the node springs '// &
                    'overflow double precision: rescale the units), found '//real_to_string(foundation%modulus), error)
         return
      end if
      call tangential_springs(source, card, deck, foundation, error)
      if (allocated(error)) return
      call uplift_limit(source, card, deck, foundation%uplift_limit, uplift_stiffness, error)
      if (allocated(error)) return
      foundation%uplift_modulus = uplift_stiffness   ! k_u (0: the bearing modulus)
      call bearing_limit(source, card, deck, foundation%bearing_limit, error)
      if (allocated(error)) return
      call contact_scale(source, card, deck, foundation%scale, error)
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

      call foundation_law(source, card, deck, foundation, error)
      if (allocated(error)) return
      if (foundation%uplift_limit > 0.0_dp .and. foundation%gap /= 0.0_dp) then
         ! bonded while elastic: an initial gap would be a tension at the start
         call raise(source, card%line, card%options(option_index(card, 'GAP'))%column, 'expected no GAP= ' // &
                    'with TU= (a spring with an uplift limit is bonded to the node at the start), found GAP='// &
                    real_to_string(foundation%gap), error)
         return
      end if
      foundation%bilateral = option_index(card, 'BILATERAL') > 0
      if (foundation%bilateral .and. foundation%gap /= 0.0_dp) then
         ! bonded: the bed holds the node where it starts, so an initial gap would pull it down by g0
         ! at the start (as with TU= above)
         call raise(source, card%line, card%options(option_index(card, 'GAP'))%column, 'expected no GAP= ' // &
                    'with BILATERAL (a bonded bed is attached to the nodes at the start), found GAP='// &
                    real_to_string(foundation%gap), error)
         return
      end if
      if (direction_option > 0) then
         call option_real(source, card, deck, direction_option, 'an angle in degrees', angle, error)
         if (allocated(error)) return
         foundation%side = side_direction
         foundation%direction = [cos_degrees(angle), sin_degrees(angle)]
      else
         side = to_upper(card%options(side_option)%value)
         select case (side)
         case ('LEFT')
            foundation%side = side_left
         case ('RIGHT')
            foundation%side = side_right
         case ('INNER')
            foundation%side = side_inner
         case ('OUTER')
            foundation%side = side_outer
         case default
            call raise(source, card%line, card%options(side_option)%value_column, 'expected SIDE=INNER, ' // &
                       'OUTER, LEFT or RIGHT, found '''//clip(card%options(side_option)%value)//'''', error)
            return
         end select
      end if

      ! The builder derives the candidates (uniarc_contact_law); its error is said here with the position.
      call add_foundation(deck%model, foundation, error, status, bad_node)
      if (.not. allocated(error)) return
      if (error%out_of_memory) return   ! the model does not fit: said at the card (uniarc_deck)
      if (status == foundation_not_open_chain) then
         call raise(source, card%line, card%options(set_option)%value_column, 'expected one open chain of ' // &
                    'elements for TYPE=PASTERNAK (its shear layer couples consecutive nodes along one line: ' // &
                    'no ring, branch or second chain), found '''//field%text//'''', error)
      else if (status == foundation_straight) then
         call raise(source, card%line, card%options(side_option)%value_column, 'expected a curved ' // &
                    'element set for SIDE='//side//' (no concave side on a straight one: use ' // &
                    'SIDE=LEFT|RIGHT or DIRECTION=angle), found '''//field%text//''' straight', error)
      else
         call raise(source, card%line, card%options(set_option)%value_column, 'expected a chain of ' // &
                    'elements running one way for SIDE= (use DIRECTION= otherwise), found at node '// &
                    integer_to_string(deck%model%node_label(bad_node))//' '//foundation_problem(status), error)
      end if
   end subroutine read_foundation

   !> *SPRING [, BILATERAL] [, NAME=name] [, QU=q_u [, TU=t_u [, KU=k_u]]]: lines `target, angle_deg, k`, a
   !> discrete spring of stiffness k at each node of the target pushing the node along the direction
   !> `angle` (gap g = n·u, offset 0); with TU= also an uplift limit (`uplift_limit`), KU= the stiffness
   !> of every spring's uplift branch (default: its k).
   subroutine read_spring(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, line, count, k, status
      real(dp) :: angle, stiffness
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: nodes(:), spring_nodes(:)
      real(dp), allocatable :: directions(:, :), stiffnesses(:, :)
      character(len=:), allocatable :: name
      real(dp) :: limit, uplift, uplift_stiffness

      call check_options(source, card, [character(len=9) :: 'BILATERAL', 'NAME=', 'QU=', 'TU=', 'KU='], error)
      if (allocated(error)) return
      call uplift_limit(source, card, deck, uplift, uplift_stiffness, error)
      if (allocated(error)) return
      call bearing_limit(source, card, deck, limit, error)
      if (allocated(error)) return
      call contact_group_name(source, card, deck, 'spring', name, error)
      if (allocated(error)) return
      if (card%n_data == 0) then
         call raise(source, card%line, len_trim(source%lines(card%line)%text) + 1, 'expected data lines ' // &
                    '`target, angle, k` after *SPRING, found none', error)
         return
      end if
      ! one column per spring: its node, its direction, its stiffness (a 1-row array, to grow like the others)
      allocate (spring_nodes(8), directions(2, 8), stiffnesses(1, 8))
      count = 0
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 3, 3, 'target, angle, k', error)
         if (allocated(error)) return
         call resolve_nodes(source, deck, line, fields(1), nodes, error)
         if (allocated(error)) return
         call field_real(source, deck%parameters, line, fields(2), 'an angle in degrees', angle, error)
         if (allocated(error)) return
         call field_real(source, deck%parameters, line, fields(3), 'a stiffness k', stiffness, error)
         if (allocated(error)) return
         ! from 1e-100 to 1e100, as a foundation's MODULUS: its flexibility 1/k and k times the
         ! structure's displacements (up to coordinates of 1e100) stay finite
         if (.not. stiffness_in_range(stiffness, zero_allowed=.false.)) then
            call raise(source, line, fields(3)%column, 'expected a stiffness k from 1e-100 to 1e100 (beyond, '// &
                       'the springs overflow double precision: rescale the units), found '// &
                       real_to_string(stiffness), error)
            return
         end if
         ! the springs' arrays grow with stat= (a spring at every node of a large set)
         status = 0
         if (count + size(nodes) > size(spring_nodes)) then
            call grow_reals_2(directions, max(2*size(spring_nodes), count + size(nodes)), status)
            if (status == 0) call grow_reals_2(stiffnesses, max(2*size(spring_nodes), count + size(nodes)), status)
         end if
         if (status == 0) call append_integers(spring_nodes, count, nodes, status)
         call allocation_failure(status, 'the springs of group '''//name//'''', &
                                 28.0_dp*max(2*size(spring_nodes), count + size(nodes)), error_input, error)
         if (allocated(error)) return
         do k = count - size(nodes) + 1, count
            directions(:, k) = [cos_degrees(angle), sin_degrees(angle)]
         end do
         stiffnesses(1, count - size(nodes) + 1:count) = stiffness
      end do
      if (uplift > 0.0_dp .and. uplift_stiffness > 0.0_dp) then
         call add_springs(deck%model, name, spring_nodes(1:count), directions(:, 1:count), stiffnesses(1, 1:count), &
                          .false., error, limit, uplift, uplift_stiffness)
      else if (uplift > 0.0_dp) then
         call add_springs(deck%model, name, spring_nodes(1:count), directions(:, 1:count), stiffnesses(1, 1:count), &
                          .false., error, limit, uplift)
      else if (limit > 0.0_dp) then
         call add_springs(deck%model, name, spring_nodes(1:count), directions(:, 1:count), stiffnesses(1, 1:count), &
                          option_index(card, 'BILATERAL') > 0, error, limit)
      else
         call add_springs(deck%model, name, spring_nodes(1:count), directions(:, 1:count), stiffnesses(1, 1:count), &
                          option_index(card, 'BILATERAL') > 0, error)
      end if
   end subroutine read_spring


   !> *OBSTACLE, TYPE=PLANE|CIRCLE|ELLIPSE|POLYLINE, NSET=set [, SIDE=...] [, STIFFNESS=k] [, END_FACTOR=f]
   !> [, NAME=name] [, SCALE=s]: a rigid (or, with STIFFNESS, elastic) obstacle for every node of the set.
   !>
   !> PLANE `px, py, angle`: the line through p whose normal n = (cos, sin) points to the free side;
   !> g = n·(x0 − p) + n·u. CIRCLE `xc, yc, R`: g = R − |x − c| (SIDE=INSIDE a cavity, the default) or
   !> |x − c| − R (SIDE=OUTSIDE a cylinder). ELLIPSE `xc, yc, a, b [, angle]`: the ellipse of semi-axis a
   !> along the direction `angle` (degrees, default 0) and b across, SIDE=INSIDE (default) or OUTSIDE.
   !> POLYLINE: data lines `x, y`, at least two vertices, the first and last segments going on as rays;
   !> SIDE=LEFT (default) or RIGHT of the direction first → last vertex is free. Ellipse and polyline gaps:
   !> the signed distance (uniarc_obstacle_shapes). A node that starts inside the obstacle is an error.
   subroutine read_obstacle(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: type_option, set_option, side_option, stiffness_option, factor_option, line, i, gap_kind, bad
      real(dp) :: values(5), scale, stiffness, end_factor, normal(2), depth, angle
      type(field_t) :: field
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: nodes(:)
      real(dp), allocatable :: vertices(:, :)
      character(len=:), allocatable :: name, kind, layout, surface, side
      character(len=5), parameter :: plane_names(3) = ['px   ', 'py   ', 'angle']
      character(len=5), parameter :: circle_names(3) = ['xc   ', 'yc   ', 'R    ']
      character(len=5), parameter :: ellipse_names(5) = ['xc   ', 'yc   ', 'a    ', 'b    ', 'angle']

      call check_options(source, card, [character(len=11) :: 'TYPE=', 'NSET=', 'SIDE=', 'STIFFNESS=', &
                                        'END_FACTOR=', 'NAME=', 'SCALE='], error)
      if (allocated(error)) return
      call contact_group_name(source, card, deck, 'obstacle', name, error)
      if (allocated(error)) return
      call require_option(source, card, 'TYPE', type_option, error)
      if (allocated(error)) return
      kind = to_upper(card%options(type_option)%value)
      if (kind /= 'PLANE' .and. kind /= 'CIRCLE' .and. kind /= 'ELLIPSE' .and. kind /= 'POLYLINE') then
         call raise(source, card%line, card%options(type_option)%value_column, 'expected TYPE=PLANE, ' // &
                    'CIRCLE, ELLIPSE or POLYLINE, found '''//clip(card%options(type_option)%value)//'''', error)
         return
      end if
      call require_option(source, card, 'NSET', set_option, error)
      if (allocated(error)) return
      field = option_field(card, set_option)
      call resolve_nodes(source, deck, card%line, field, nodes, error)
      if (allocated(error)) return
      if (size(nodes) == 0) then
         call raise(source, card%line, field%column, 'expected a node set with nodes, found '''// &
                    field%text//''' empty', error)
         return
      end if

      select case (kind)
      case ('CIRCLE')
         gap_kind = gap_circle_inside
      case ('ELLIPSE')
         gap_kind = gap_ellipse_inside
      case ('POLYLINE')
         gap_kind = gap_polyline
      case default
         gap_kind = gap_fixed_direction
      end select
      side = ''
      side_option = option_index(card, 'SIDE')
      if (side_option > 0) then
         side = to_upper(card%options(side_option)%value)
         select case (kind)
         case ('PLANE')
            call raise(source, card%line, card%options(side_option)%column, 'expected SIDE= only with ' // &
                       'TYPE=CIRCLE, ELLIPSE or POLYLINE (a plane''s free side is its normal''s), found it ' // &
                       'with TYPE=PLANE', error)
            return
         case ('POLYLINE')
            if (side /= 'LEFT' .and. side /= 'RIGHT') then
               call raise(source, card%line, card%options(side_option)%value_column, 'expected SIDE=LEFT ' // &
                          'or SIDE=RIGHT with TYPE=POLYLINE, found '''//clip(card%options(side_option)%value)// &
                          '''', error)
               return
            end if
         case default
            if (side /= 'INSIDE' .and. side /= 'OUTSIDE') then
               call raise(source, card%line, card%options(side_option)%value_column, 'expected SIDE=INSIDE ' // &
                          'or SIDE=OUTSIDE, found '''//clip(card%options(side_option)%value)//'''', error)
               return
            end if
            if (side == 'OUTSIDE') then
               gap_kind = merge(gap_circle_outside, gap_ellipse_outside, kind == 'CIRCLE')
            end if
         end select
      end if

      stiffness = 0.0_dp
      stiffness_option = option_index(card, 'STIFFNESS')
      if (stiffness_option > 0) then
         call option_real(source, card, deck, stiffness_option, 'a stiffness', stiffness, error)
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
         call option_real(source, card, deck, factor_option, 'a factor', end_factor, error)
         if (allocated(error)) return
         if (.not. end_factor > 0.0_dp) then
            call raise(source, card%line, card%options(factor_option)%value_column, 'expected a positive ' // &
                       'END_FACTOR, found '//real_to_string(end_factor), error)
            return
         end if
      end if
      call contact_scale(source, card, deck, scale, error)
      if (allocated(error)) return

      if (kind == 'POLYLINE') then
         call read_polyline(source, card, deck, side == 'RIGHT', vertices, error)
         if (allocated(error)) return
         line = card%data_lines(1)
         call data_fields(source, line, fields)
         call add_obstacle(deck%model, name, gap_kind, [0.0_dp, 0.0_dp], [1.0_dp, 0.0_dp], 0.0_dp, nodes, &
                           stiffness, end_factor, scale, error, bad, depth, vertices=vertices)
      else
         call require_one_data_line(source, card, error)
         if (allocated(error)) return
         line = card%data_lines(1)
         call data_fields(source, line, fields)
         select case (kind)
         case ('PLANE')
            layout = 'px, py, angle'
            call require_field_count(source, line, fields, 3, 3, layout, error)
         case ('CIRCLE')
            layout = 'xc, yc, R'
            call require_field_count(source, line, fields, 3, 3, layout, error)
         case default
            layout = 'xc, yc, a, b [, angle]'
            call require_field_count(source, line, fields, 4, 5, layout, error)
         end select
         if (allocated(error)) return
         values = 0.0_dp
         do i = 1, size(fields)
            select case (kind)
            case ('PLANE')
               call field_real(source, deck%parameters, line, fields(i), trim(plane_names(i)), values(i), error)
            case ('CIRCLE')
               call field_real(source, deck%parameters, line, fields(i), trim(circle_names(i)), values(i), error)
            case default
               call field_real(source, deck%parameters, line, fields(i), trim(ellipse_names(i)), values(i), error)
            end select
            if (allocated(error)) return
            ! the centre or point within ±1e50, as the elements' coordinates (uniarc_check): the gaps
            ! are differences and squares of coordinates (g0 = 1e150 overflowed them: SIGFPE in Debug)
            if (i <= 2 .and. .not. abs(values(i)) <= 1.0e50_dp) then
               call raise(source, line, fields(i)%column, 'expected a coordinate at most 1e50 in magnitude '// &
                          '(beyond, the gaps overflow double precision: rescale the units), found '// &
                          real_to_string(values(i)), error)
               return
            end if
         end do
         ! lengths within 1e-100..1e50 as an element's and its coordinates (uniarc_check): the gap
         ! functions form a/b, b²/a and squares of coordinates over the axes, which overflow beyond
         if (kind == 'CIRCLE' .and. .not. (values(3) >= 1.0e-100_dp .and. values(3) <= 1.0e50_dp)) then
            call raise(source, line, fields(3)%column, 'expected a radius R from 1e-100 to 1e50 (beyond, the '// &
                       'gaps overflow double precision: rescale the units), found '// &
                       real_to_string(values(3)), error)
            return
         end if
         if (kind == 'ELLIPSE') then
            do i = 3, 4
               if (.not. (values(i) >= 1.0e-100_dp .and. values(i) <= 1.0e50_dp)) then
                  call raise(source, line, fields(i)%column, 'expected a semi-axis '// &
                             trim(ellipse_names(i))//' from 1e-100 to 1e50 (beyond, the gaps overflow double '// &
                             'precision: rescale the units), found '//real_to_string(values(i)), error)
                  return
               end if
            end do
         end if

         ! The angle of a plane's normal or an ellipse's axis: at most one turn either way. The normal
         ! comes from sin and cos of the angle reduced modulo 360 (sin_degrees), whose reduction of a
         ! huge number is round-off (1e300: a direction that no angle of the deck gave, and a false
         ! mechanism refusal); a turn and more says nothing a smaller angle does not.
         if (kind == 'PLANE' .or. (kind == 'ELLIPSE' .and. size(fields) == 5)) then
            i = merge(3, 5, kind == 'PLANE')
            if (.not. abs(values(i)) <= 360.0_dp) then
               call raise(source, line, fields(i)%column, 'expected an angle from -360 to 360 degrees, found '// &
                          real_to_string(values(i)), error)
               return
            end if
         end if
         ! The builder makes the candidates (uniarc_contact_law) and finds a node that starts inside; the
         ! message says it here with the position.
         angle = values(3)
         if (kind == 'ELLIPSE') angle = values(5)
         normal = [cos_degrees(angle), sin_degrees(angle)]
         call add_obstacle(deck%model, name, gap_kind, values(1:2), normal, values(3), nodes, stiffness, &
                           end_factor, scale, error, bad, depth, semi_axes=values(3:4))
      end if
      if (.not. allocated(error)) then
         call record_obstacle(deck, deck%model%n_contact_groups, gap_kind)
         return
      end if
      if (error%out_of_memory) return   ! the model does not fit: said at the card (uniarc_deck)
      select case (gap_kind)
      case (gap_fixed_direction)
         surface = 'the plane'
      case (gap_circle_inside)
         surface = 'the circular cavity'
      case (gap_ellipse_inside)
         surface = 'the elliptical cavity'
      case (gap_ellipse_outside)
         surface = 'the elliptical cylinder'
      case (gap_polyline)
         surface = 'the polyline'
      case default
         surface = 'the cylinder'
      end select
      call raise(source, line, fields(1)%column, 'expected every node of '''//field%text// &
                 ''' clear of '//surface//', found node '//integer_to_string(deck%model%node_label(nodes(bad)))// &
                 ' inside it by '//real_to_string(depth), error)
   end subroutine read_obstacle

   !> The vertices (2, n ≥ 2) of a TYPE=POLYLINE obstacle, one `x, y` data line each, in the order read
   !> (free side on the left) or reversed when `reverse` (SIDE=RIGHT), so that the free side is always
   !> on the left of the stored order. Two equal consecutive vertices (a segment of zero length) and a
   !> segment that turns back along the previous one (no side there) are errors at the vertex's line.
   subroutine read_polyline(source, card, deck, reverse, vertices, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(in) :: deck
      logical, intent(in) :: reverse
      real(dp), allocatable, intent(out) :: vertices(:, :)
      type(error_t), allocatable, intent(out) :: error
      type(field_t), allocatable :: fields(:)
      real(dp) :: before(2), after(2)
      integer :: i, line

      if (card%n_data < 2) then
         call raise(source, card%line, len_trim(source%lines(card%line)%text) + 1, 'expected at least two ' // &
                    'data lines `x, y` (the vertices) after *OBSTACLE, TYPE=POLYLINE, found '// &
                    integer_to_string(card%n_data), error)
         return
      end if
      allocate (vertices(2, card%n_data))
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 2, 2, 'x, y', error)
         if (allocated(error)) return
         call field_real(source, deck%parameters, line, fields(1), 'x', vertices(1, i), error)
         if (allocated(error)) return
         call field_real(source, deck%parameters, line, fields(2), 'y', vertices(2, i), error)
         if (allocated(error)) return
         if (i == 1) cycle
         after = vertices(:, i) - vertices(:, i - 1)
         if (.not. norm2(after) > 0.0_dp) then
            call raise(source, line, fields(1)%column, 'expected a vertex different from the previous one, ' // &
                       'found the same point', error)
            return
         end if
         if (i == 2) cycle
         before = vertices(:, i - 1) - vertices(:, i - 2)
         ! the two unit directions opposite (to round-off): the segment runs back over the previous one
         if (norm2(after/norm2(after) + before/norm2(before)) < fold_tolerance) then
            call raise(source, line, fields(1)%column, 'expected a segment that does not run back along ' // &
                       'the previous one, found a fold at the previous vertex', error)
            return
         end if
      end do
      if (reverse) vertices = vertices(:, card%n_data:1:-1)
   end subroutine read_polyline


   !> The SCALE= option of a contact card (default 1): the factor from arc length to the coordinate of
   !> the contact-region output. Zero would make every coordinate 0, so it must not be.
   subroutine contact_scale(source, card, deck, scale, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(in) :: deck
      real(dp), intent(out) :: scale
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      scale = 1.0_dp
      k = option_index(card, 'SCALE')
      if (k == 0) return
      call option_real(source, card, deck, k, 'a scale', scale, error)
      if (allocated(error)) return
      if (.not. abs(scale) > 0.0_dp) then
         call raise(source, card%line, card%options(k)%value_column, 'expected a non-zero SCALE, found '// &
                    real_to_string(scale), error)
      end if
   end subroutine contact_scale

   !> The name of the contact group a card makes: its NAME= option, or `default_stem_<index>` with the
   !> group's index. Either must be new among the contact groups (case-insensitive).
   subroutine contact_group_name(source, card, deck, default_stem, name, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(in) :: deck
      character(len=*), intent(in) :: default_stem
      character(len=:), allocatable, intent(out) :: name
      type(error_t), allocatable, intent(out) :: error
      integer :: k, column
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
         name = default_stem//'_'//integer_to_string(deck%model%n_contact_groups + 1)
         column = card%column
      end if
      if (contact_group_index(deck%model, name) > 0) then
         if (k > 0) then
            call raise(source, card%line, column, 'expected a new contact group name, found '''// &
                       name//''' again', error)
         else
            call raise(source, card%line, column, 'expected a new contact group name, found the ' // &
                       'default name '''//name//''' already taken (give this card a NAME=)', error)
         end if
         return
      end if
   end subroutine contact_group_name

   !> KT=K_t [, TANGENTIAL=CONTACT|BONDED] of *FOUNDATION: the modulus K_t ≥ 0 of tangential springs
   !> (force per unit length per unit tangential displacement; 0 when absent: frictionless) and their
   !> law: acting where the node's radial contact is closed (CONTACT, the default), or always (BONDED).
   !> TANGENTIAL= needs KT=; K_t > 0 needs a radial MODULUS > 0 (the springs sit on the bed's nodes).
   subroutine tangential_springs(source, card, deck, foundation, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(in) :: deck
      type(foundation_t), intent(inout) :: foundation  !< its MODULUS already read
      type(error_t), allocatable, intent(out) :: error
      integer :: kt_option, law_option
      foundation%tangential_modulus = 0.0_dp
      foundation%tangential_law = tangential_contact
      kt_option = option_index(card, 'KT')
      law_option = option_index(card, 'TANGENTIAL')
      if (law_option > 0) then
         if (kt_option == 0) then
            call raise(source, card%line, card%options(law_option)%column, 'expected KT=modulus with ' // &
                       'TANGENTIAL= on *FOUNDATION, found TANGENTIAL= alone', error)
            return
         end if
         select case (to_upper(card%options(law_option)%value))
         case ('CONTACT')
            foundation%tangential_law = tangential_contact
         case ('BONDED')
            foundation%tangential_law = tangential_bonded
         case default
            call raise(source, card%line, card%options(law_option)%value_column, 'expected TANGENTIAL=' // &
                       'CONTACT or BONDED, found '''//clip(card%options(law_option)%value)//'''', error)
            return
         end select
      end if
      if (kt_option == 0) return
      call option_real(source, card, deck, kt_option, 'a tangential modulus', foundation%tangential_modulus, error)
      if (allocated(error)) return
      ! from 1e-100 to 1e100 as MODULUS= (k_t·L and 1/(k_t·L) finite)
      if (.not. stiffness_in_range(foundation%tangential_modulus, zero_allowed=.true.)) then
         call raise(source, card%line, card%options(kt_option)%value_column, &
                    'expected KT of 0 (frictionless) or from 1e-100 to 1e100 (beyond, the springs overflow '// &
                    'double precision: rescale the units), found '//real_to_string(foundation%tangential_modulus), error)
      else if (foundation%tangential_modulus > 0.0_dp .and. .not. foundation%modulus > 0.0_dp) then
         call raise(source, card%line, card%options(kt_option)%value_column, 'expected KT=0 with MODULUS=0 ' // &
                    '(the tangential springs sit on the nodes of the bed), found KT='// &
                    real_to_string(foundation%tangential_modulus), error)
      end if
   end subroutine tangential_springs

   !> QU=q_u of *FOUNDATION (force per unit length) and *SPRING (force): the bearing limit of an
   !> elastic–perfectly plastic medium in compression (docs/theory.md §3.9); 0 when absent (elastic).
   !> Errors: q_u not positive and finite; QU= with BILATERAL (the plastic law is that of a
   !> compression-only medium).
   subroutine bearing_limit(source, card, deck, limit, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      real(dp), intent(out) :: limit
      type(error_t), allocatable, intent(out) :: error
      integer :: k, t
      limit = 0.0_dp
      k = option_index(card, 'QU')
      if (k == 0) return
      if (option_index(card, 'BILATERAL') > 0) then
         call raise(source, card%line, card%options(k)%column, 'expected QU= without BILATERAL (the ' // &
                    'bearing limit is that of a compression-only medium), found both', error)
         return
      end if
      t = option_index(card, 'TYPE')
      if (t > 0) then
         if (to_upper(card%options(t)%value) == 'PASTERNAK') then
            ! the plastic law is that of a spring's own flexibility; a Pasternak bed's points touch its
            ! surface rigidly (docs/theory.md §3.9, §3.10)
            call raise(source, card%line, card%options(k)%column, 'expected QU= on a Winkler foundation ' // &
                       '(TYPE=WINKLER), found it with TYPE=PASTERNAK', error)
            return
         end if
      end if
      call option_real(source, card, deck, k, 'a bearing limit', limit, error)
      if (allocated(error)) return
      if (.not. (limit > 0.0_dp .and. limit < huge(1.0_dp))) then
         call raise(source, card%line, card%options(k)%value_column, 'expected a positive finite bearing ' // &
                    'limit QU, found '//real_to_string(limit), error)
         return
      end if
      if (deck%plastic_line == 0) then
         deck%plastic_line = card%line
         deck%plastic_column = card%options(k)%column
      end if
   end subroutine bearing_limit

   !> TU=t_u [, KU=k_u] of *FOUNDATION (force per unit length; stiffness per unit length) and *SPRING
   !> (force; stiffness): the uplift (tension) limit of a bearing-limited medium, the spring then bonded
   !> while elastic and elastic–perfectly plastic on both sides with one slip (docs/theory.md §3.9).
   !> `uplift` is 0 when TU= is absent; `uplift_stiffness` is KU (0 when absent: the bearing modulus),
   !> the stiffness of the uplift branch (δ < 0) of the bilinear elastic law (docs/theory.md §3.9).
   !> Errors: KU= without TU=; TU= on TYPE=PASTERNAK, with BILATERAL or without QU=; t_u or k_u not
   !> positive and finite.
   subroutine uplift_limit(source, card, deck, uplift, uplift_stiffness, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      real(dp), intent(out) :: uplift, uplift_stiffness
      type(error_t), allocatable, intent(out) :: error
      integer :: tu, ku, t
      uplift = 0.0_dp
      uplift_stiffness = 0.0_dp
      tu = option_index(card, 'TU')
      ku = option_index(card, 'KU')
      if (ku > 0 .and. tu == 0) then
         call raise(source, card%line, card%options(ku)%column, 'expected KU= with an uplift limit TU= ' // &
                    '(KU is its stiffness), found KU= without TU=', error)
         return
      end if
      if (tu == 0) return
      t = option_index(card, 'TYPE')
      if (t > 0) then
         if (to_upper(card%options(t)%value) == 'PASTERNAK') then
            call raise(source, card%line, card%options(tu)%column, 'expected TU= on a Winkler foundation ' // &
                       '(TYPE=WINKLER), found it with TYPE=PASTERNAK', error)
            return
         end if
      end if
      if (option_index(card, 'BILATERAL') > 0) then
         call raise(source, card%line, card%options(tu)%column, 'expected TU= without BILATERAL (a medium ' // &
                    'with an uplift limit is bonded while elastic already), found both', error)
         return
      end if
      if (option_index(card, 'QU') == 0) then
         call raise(source, card%line, card%options(tu)%column, 'expected TU= with a bearing limit QU= ' // &
                    '(both limits share one plastic slip), found TU= without QU=', error)
         return
      end if
      call option_real(source, card, deck, tu, 'an uplift limit', uplift, error)
      if (allocated(error)) return
      if (.not. (uplift > 0.0_dp .and. uplift < huge(1.0_dp))) then
         call raise(source, card%line, card%options(tu)%value_column, 'expected a positive finite uplift ' // &
                    'limit TU, found '//real_to_string(uplift), error)
         return
      end if
      if (ku == 0) return
      call option_real(source, card, deck, ku, 'an uplift stiffness', uplift_stiffness, error)
      if (allocated(error)) return
      ! from 1e-100 to 1e100, as MODULUS and k: its flexibility 1/k_u stays finite (uniarc_check)
      if (.not. stiffness_in_range(uplift_stiffness, zero_allowed=.false.)) then
         call raise(source, card%line, card%options(ku)%value_column, 'expected an uplift stiffness KU ' // &
                    'from 1e-100 to 1e100 (beyond, the springs overflow double precision: rescale the units), '// &
                    'found '//real_to_string(uplift_stiffness), error)
      end if
   end subroutine uplift_limit
   !> TYPE=WINKLER|PASTERNAK, GP=G_p and GAP=g0 of *FOUNDATION: the law of the bed and its initial gap.
   !> TYPE=PASTERNAK needs GP (≥ 0, force: the shear layer's stiffness per unit width; 0 is Winkler's
   !> bed, the same candidates); GP is refused with Winkler's law. GAP (≥ 0, length; default 0) is the
   !> gap g0 between the structure and the bed's surface at the start, at every node. CONTINUES= (with
   !> TYPE=PASTERNAK only) names the ends of the set, in its chain order, beyond which the bed goes on
   !> (an end spring √(K G_p) there, docs/theory.md §3.10): BOTH (the default), NONE, START or END.
   subroutine foundation_law(source, card, deck, foundation, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(in) :: deck
      type(foundation_t), intent(inout) :: foundation
      type(error_t), allocatable, intent(out) :: error
      integer :: type_option, gp_option, gap_option, continues_option
      foundation%law = foundation_winkler
      foundation%shear_modulus = 0.0_dp
      foundation%gap = 0.0_dp
      type_option = option_index(card, 'TYPE')
      gp_option = option_index(card, 'GP')
      gap_option = option_index(card, 'GAP')
      continues_option = option_index(card, 'CONTINUES')
      if (type_option > 0) then
         select case (to_upper(card%options(type_option)%value))
         case ('WINKLER')
            foundation%law = foundation_winkler
         case ('PASTERNAK')
            foundation%law = foundation_pasternak
         case default
            call raise(source, card%line, card%options(type_option)%value_column, 'expected TYPE=WINKLER ' // &
                       'or PASTERNAK, found '''//clip(card%options(type_option)%value)//'''', error)
            return
         end select
      end if
      if (foundation%law == foundation_pasternak) then
         if (gp_option == 0) then
            call raise(source, card%line, card%options(type_option)%column, 'expected GP=G_p (the shear ' // &
                       'layer''s stiffness, a force) with TYPE=PASTERNAK, found none', error)
            return
         end if
         call option_real(source, card, deck, gp_option, 'a shear-layer stiffness', foundation%shear_modulus, error)
         if (allocated(error)) return
         ! At most 1e100, as EA and EI (uniarc_deck_mesh): K_b's entries G_p/h and their products in the
         ! solves must stay finite in double precision (GP=1e200 ended Lemke on a ray instead).
         if (foundation%shear_modulus < 0.0_dp .or. .not. foundation%shear_modulus <= 1.0e100_dp) then
            call raise(source, card%line, card%options(gp_option)%value_column, &
                       'expected 0 <= GP <= 1e100 (0: Winkler''s bed; larger overflow the equations in double '// &
                       'precision: rescale the units), found '//real_to_string(foundation%shear_modulus), error)
            return
         end if
      else if (gp_option > 0) then
         call raise(source, card%line, card%options(gp_option)%column, 'expected GP= only with ' // &
                    'TYPE=PASTERNAK on *FOUNDATION, found it on a Winkler foundation', error)
         return
      end if
      if (continues_option > 0) then
         if (foundation%law /= foundation_pasternak) then
            call raise(source, card%line, card%options(continues_option)%column, 'expected CONTINUES= only ' // &
                       'with TYPE=PASTERNAK on *FOUNDATION, found it on a Winkler foundation', error)
            return
         end if
         select case (to_upper(card%options(continues_option)%value))
         case ('BOTH')
            foundation%continues = [.true., .true.]
         case ('NONE')
            foundation%continues = [.false., .false.]
         case ('START')
            foundation%continues = [.true., .false.]
         case ('END')
            foundation%continues = [.false., .true.]
         case default
            call raise(source, card%line, card%options(continues_option)%value_column, 'expected ' // &
                       'CONTINUES=BOTH|NONE|START|END (the ends the bed goes on beyond), found '''// &
                       clip(card%options(continues_option)%value)//'''', error)
            return
         end select
      end if
      if (gap_option == 0) return
      call option_real(source, card, deck, gap_option, 'an initial gap', foundation%gap, error)
      if (allocated(error)) return
      ! at most 1e100 in magnitude, as coordinates (uniarc_check: coordinate_bound)
      if (foundation%gap < 0.0_dp .or. .not. foundation%gap <= 1.0e100_dp) then
         call raise(source, card%line, card%options(gap_option)%value_column, &
                    'expected 0 <= GAP <= 1e100 (the gap between the structure and the bed at the start), found '// &
                    real_to_string(foundation%gap), error)
      end if
   end subroutine foundation_law

   !> Whether a stiffness-like input (a bed's modulus, a spring's stiffness; force per length per
   !> length or force per length) lies from 1e-100 to 1e100, or is 0 where `zero_allowed` (no
   !> springs). The products the analysis forms with lengths from 1e-100 to 1e100 (uniarc_check) then
   !> lie within 1e-200..1e200 and their reciprocals (flexibilities) stay finite. A NaN is refused
   !> without an ordered comparison with it (which would raise the invalid-operation trap).
   pure logical function stiffness_in_range(value, zero_allowed) result(ok)
      real(dp), intent(in) :: value
      logical, intent(in) :: zero_allowed
      if (ieee_is_nan(value)) then
         ok = .false.
      else
         ok = (value >= 1.0e-100_dp .and. value <= 1.0e100_dp) .or. (zero_allowed .and. value == 0.0_dp)
      end if
   end function stiffness_in_range

end module uniarc_deck_contact
