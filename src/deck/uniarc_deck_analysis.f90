!> The analysis and output cards of the deck: *TRACK (the path file's displacement columns), *STATIC,
!> *PATH (path following, docs/theory.md §2) and *OUTPUT (extra result files), docs/input.md.
module uniarc_deck_analysis
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_input
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: field_t, to_upper, is_name, same_text, integer_to_string, real_to_string
   use uniarc_deck_source, only: source_t, card_t, raise, clip, check_options, option_index, require_option, &
                                 data_fields, require_field_count, field_real, field_integer
   use uniarc_model, only: analysis_options_t, dof_ux, dof_uy, dof_rz, analysis_nonlinear, control_load, &
                           control_displacement, control_arclength, iteration_chan, iteration_cylindrical, &
                           iteration_riks
   use uniarc_model_builder, only: add_track, track_index
   use uniarc_growth, only: grow_integers
   use uniarc_deck_state, only: deck_t, option_field, resolve_nodes
   implicit none
   private
   public :: read_track, read_static, read_path, read_output, check_track_names

   !> The path file's own columns (uniarc_output, path_header; docs/contracts.md), which a *TRACK name
   !> may not repeat (compared as track names are, regardless of case), and the columns each contact
   !> group gets under its name in a model with more than one group.
   character(len=*), parameter :: builtin_columns(14) = [character(len=16) :: 'step', 'lambda', 'n_contact', &
      'contact_regions', 's_contact_1', 's_contact_2', 'reaction_max', 'reaction_sum', 'prescribed_force', &
      'lcp_residual', 'lcp_pivots', 'iterations', 'neg_pivots', 'analysis_step']
   character(len=*), parameter :: group_columns(6) = [character(len=15) :: 'n_contact', 'contact_regions', &
      's_contact_1', 's_contact_2', 'reaction_max', 'reaction_sum']

contains

   !> *TRACK: lines `name, target, component [, scale]`; the target is one node, component UX|UY|RZ.
   subroutine read_track(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, dof, status
      real(dp) :: scale
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: nodes(:)

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
         do j = 1, size(builtin_columns)
            if (same_text(trim(builtin_columns(j)), fields(1)%text)) then
               call raise(source, line, fields(1)%column, 'expected a track name that is not a column of '// &
                          'the path file, found '''//fields(1)%text//''' (the path file''s own column '''// &
                          trim(builtin_columns(j))//''')', error)
               return
            end if
         end do
         if (track_index(deck%model, fields(1)%text) > 0) then
            call raise(source, line, fields(1)%column, 'expected a new track name, found '''// &
                       fields(1)%text//''' again', error)
            return
         end if
         call resolve_nodes(source, deck, line, fields(2), nodes, error)
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
            call field_real(source, deck%parameters, line, fields(4), 'a scale', scale, error)
            if (allocated(error)) return
         end if

         call add_track(deck%model, fields(1)%text, nodes(1), dof, scale, status)
         call allocation_failure(status, 'the list of tracks and its name table', 80.0_dp*(deck%model%n_tracks + 1), &
                                 error_input, error)
         if (allocated(error)) return
         ! grown by doubling (amortised O(1) a track; issue 14), entries 1..n_tracks in use
         call grow_integers(deck%track_line, deck%model%n_tracks, status)
         if (status == 0) call grow_integers(deck%track_column, deck%model%n_tracks, status)
         call allocation_failure(status, 'the deck positions of the tracks', 16.0_dp*deck%model%n_tracks, &
                                 error_input, error)
         if (allocated(error)) return
         deck%track_line(deck%model%n_tracks) = line
         deck%track_column(deck%model%n_tracks) = fields(1)%column
      end do
   end subroutine read_track

   !> At the end of the deck: no *TRACK name may be one of the path columns of a contact group, which a
   !> model with more than one group writes as `<column>_<group name>` (docs/contracts.md), the contact
   !> cards possibly after the *TRACK.
   subroutine check_track_names(source, deck, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(in) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, g, k, first, first_group
      if (deck%model%n_contact_groups < 2 .or. deck%model%n_tracks == 0) return
      ! Each group column looked up among the tracks (O(groups), not O(tracks × groups); issue 14); the
      ! first track in deck order that clashes is reported, with the first group it clashes with.
      first = huge(1)
      first_group = 0
      do g = 1, deck%model%n_contact_groups
         do k = 1, size(group_columns)
            i = track_index(deck%model, trim(group_columns(k))//'_'//deck%model%contact_groups(g)%name)
            if (i > 0 .and. i < first) then
               first = i
               first_group = g
            end if
         end do
      end do
      if (first_group > 0) then
         call raise(source, deck%track_line(first), deck%track_column(first), 'expected a track name that '// &
                    'is not a column of the path file, found '''//deck%model%tracks(first)%name// &
                    ''' (the path column of contact group '''//deck%model%contact_groups(first_group)%name// &
                    ''')', error)
      end if
   end subroutine check_track_names

   !> *STATIC: a linear static analysis (also what a deck without an analysis card gets).
   subroutine read_static(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      call require_analysis_once(source, card, deck, error)
      if (allocated(error)) return
      if (card%n_data > 0) then
         call raise(source, card%data_lines(1), verify(source%lines(card%data_lines(1))%text, ' '), &
                    'expected no data line after *STATIC, found one', error)
         return
      end if
   end subroutine read_static

   !> *PATH: a nonlinear analysis that follows the equilibrium path (docs/input.md, docs/theory.md §2).
   !> Options CONTROL=, ITERATION=, NODE= and DOF= (displacement control); data lines `key = value`.
   subroutine read_path(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, k, line, equals, first
      integer, allocatable :: nodes(:)
      character(len=:), allocatable :: text, key
      type(field_t) :: field
      real(dp) :: value

      call check_options(source, card, [character(len=10) :: 'CONTROL=', 'ITERATION=', 'NODE=', 'DOF=', 'SWITCH=', &
                                        'TIES='], error)
      if (allocated(error)) return
      call require_analysis_once(source, card, deck, error)
      if (allocated(error)) return
      deck%model%analysis%kind = analysis_nonlinear
      k = option_index(card, 'CONTROL')
      if (k > 0) then
         select case (to_upper(card%options(k)%value))
         case ('ARCLENGTH', 'ARC_LENGTH')
            deck%model%analysis%control = control_arclength
         case ('LOAD')
            deck%model%analysis%control = control_load
         case ('DISPLACEMENT')
            deck%model%analysis%control = control_displacement
         case default
            call raise(source, card%line, card%options(k)%value_column, 'expected CONTROL=ARCLENGTH, '// &
                       'LOAD or DISPLACEMENT, found '''//clip(card%options(k)%value)//'''', error)
            return
         end select
      end if
      k = option_index(card, 'TIES')
      if (k > 0) then
         select case (to_upper(card%options(k)%value))
         case ('KEEP')
            deck%model%analysis%keep_ties = .true.
         case ('SPLIT')
            deck%model%analysis%keep_ties = .false.
         case default
            call raise(source, card%line, card%options(k)%value_column, 'expected TIES=KEEP or SPLIT, found '''// &
                       clip(card%options(k)%value)//'''', error)
            return
         end select
      end if
      k = option_index(card, 'ITERATION')
      if (k > 0) then
         select case (to_upper(card%options(k)%value))
         case ('CHAN')
            deck%model%analysis%iteration = iteration_chan
         case ('CYLINDRICAL')
            deck%model%analysis%iteration = iteration_cylindrical
         case ('RIKS')
            deck%model%analysis%iteration = iteration_riks
         case default
            call raise(source, card%line, card%options(k)%value_column, 'expected ITERATION=CHAN, '// &
                       'CYLINDRICAL or RIKS, found '''//clip(card%options(k)%value)//'''', error)
            return
         end select
      end if
      call read_switch(source, card, deck, error)
      if (allocated(error)) return
      if (deck%model%analysis%control == control_displacement) then
         call require_option(source, card, 'NODE', k, error)
         if (allocated(error)) return
         field%text = card%options(k)%value
         field%column = card%options(k)%value_column
         call resolve_nodes(source, deck, card%line, field, nodes, error)
         if (allocated(error)) return
         if (size(nodes) /= 1) then
            call raise(source, card%line, field%column, 'expected a single node to control, found '// &
                       integer_to_string(size(nodes))//' nodes', error)
            return
         end if
         deck%model%analysis%control_node = nodes(1)
         call require_option(source, card, 'DOF', k, error)
         if (allocated(error)) return
         select case (to_upper(card%options(k)%value))
         case ('UX', '1')
            deck%model%analysis%control_dof = dof_ux
         case ('UY', '2')
            deck%model%analysis%control_dof = dof_uy
         case ('RZ', '3')
            deck%model%analysis%control_dof = dof_rz
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
            deck%stop_track = field%text
            deck%stop_track_line = line
            deck%stop_track_column = field%column
            cycle
         end if
         call field_real(source, deck%parameters, line, field, 'a value for '//key, value, error)
         if (allocated(error)) return
         call set_path_value(source, line, first, field%column, key, value, deck%model%analysis, error)
         if (allocated(error)) return
      end do
      if (.not. abs(deck%model%analysis%first_increment) > 0.0_dp) then
         call raise(source, card%line, card%column, 'expected a data line `increment = value` '// &
                    '(the first load increment, non-zero) after *PATH', error)
         return
      end if
      if (allocated(deck%stop_track) .and. .not. deck%model%analysis%stop_value > 0.0_dp) then
         call raise(source, deck%stop_track_line, deck%stop_track_column, 'expected a positive '// &
                    '`stop_value = ...` with stop_track', error)
         return
      end if
   end subroutine read_path

   !> *PATH, SWITCH=n: follow the secondary branch from the n-th located bifurcation (n >= 1), under
   !> arc-length control (docs/theory.md §2.6).
   subroutine read_switch(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: k, n
      k = option_index(card, 'SWITCH')
      if (k == 0) return
      call field_integer(source, deck%parameters, card%line, option_field(card, k), &
                         'the number of the bifurcation for SWITCH=', n, error)
      if (allocated(error)) return
      if (n < 1) then
         call raise(source, card%line, card%options(k)%value_column, 'expected SWITCH=n with n >= 1 (the '// &
                    'n-th bifurcation located on the path), found '//integer_to_string(n), error)
         return
      end if
      if (deck%model%analysis%control /= control_arclength) then
         call raise(source, card%line, card%options(k)%column, 'expected CONTROL=ARCLENGTH with SWITCH= '// &
                    '(a secondary branch is followed by its arc length), found another control', error)
         return
      end if
      deck%model%analysis%switch_bifurcation = n
   end subroutine read_switch

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
         ! As loads and stiffnesses are (uniarc_deck_loads, uniarc_deck_mesh): a first step beyond 1e100
         ! times the reference load overflows the corotational kinematics in double precision.
         if (.not. abs(value) <= 1.0e100_dp) then
            call raise(source, line, value_column, 'expected an increment at most 1e100 in magnitude '// &
                       '(larger steps overflow the equations in double precision: rescale the loads), found '// &
                       real_to_string(value), error)
            return
         end if
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
   !> one option without a value, so that further formats are further names here:
   !> - VTK: ParaView snapshots (uniarc_vtk), no data lines;
   !> - FORCES: the tables of internal forces and contact pressures (uniarc_output, STEM.forces and
   !>   STEM.contact); optional data lines list step numbers (whole numbers >= 0) at which to write them;
   !> - MODES: the buckling mode at every located bifurcation (uniarc_modes_output, STEM.modes), no data
   !>   lines, no EVERY=.
   !> EVERY= is the interval in steps; without it (and, for FORCES, without listed steps) the steps are
   !> those of the shape file (step 0 included). The last converged step is always written.
   subroutine read_output(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
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
         case ('VTK', 'FORCES', 'MODES')
            if (len(format_name) == 0) then
               format_name = card%options(i)%name
               format_column = card%options(i)%column
            else
               call raise(source, card%line, card%options(i)%column, 'expected one output format per '// &
                          '*OUTPUT card, found '''//clip(card%options(i)%name)//''' after '''//format_name// &
                          '''', error)
               return
            end if
         case default
            call raise(source, card%line, card%options(i)%column, 'expected an output format (VTK, FORCES, MODES) '// &
                       'on *OUTPUT, found '''//clip(card%options(i)%name)//'''', error)
            return
         end select
      end do
      call check_options(source, card, [character(len=6) :: 'VTK', 'FORCES', 'MODES', 'EVERY='], error)
      if (allocated(error)) return
      if (len(format_name) == 0) then
         call raise(source, card%line, card%column, 'expected an output format after *OUTPUT '// &
                    '(*OUTPUT, VTK or *OUTPUT, FORCES), found none', error)
         return
      end if
      every = 0
      k = option_index(card, 'EVERY')
      if (k > 0) then
         call field_integer(source, deck%parameters, card%line, option_field(card, k), &
                            'a number of steps for EVERY=', every, error)
         if (allocated(error)) return
         if (every <= 0) then
            call raise(source, card%line, card%options(k)%value_column, 'expected a positive number '// &
                       'of steps for EVERY=, found '//integer_to_string(every), error)
            return
         end if
      end if
      if (format_name == 'FORCES') then
         call read_output_forces(source, card, format_column, every, deck, error)
         return
      end if
      if (card%n_data > 0) then
         call raise(source, card%data_lines(1), verify(source%lines(card%data_lines(1))%text, ' '), &
                    'expected no data line after *OUTPUT, found one', error)
         return
      end if
      if (format_name == 'MODES') then
         if (k > 0) then
            call raise(source, card%line, card%options(k)%column, 'expected no EVERY= on *OUTPUT, MODES (a mode '// &
                       'is written at every located bifurcation)', error)
            return
         end if
         if (deck%model%output%modes) then
            call raise(source, card%line, format_column, 'expected one *OUTPUT, MODES card, found another', error)
            return
         end if
         deck%model%output%modes = .true.
         return
      end if
      if (deck%vtk_line > 0) then
         call raise(source, card%line, format_column, 'expected one *OUTPUT, VTK card, found another '// &
                    'after the one at line '//integer_to_string(deck%vtk_line), error)
         return
      end if
      deck%vtk_line = card%line
      deck%model%output%vtk = .true.
      deck%model%output%vtk_every = every
   end subroutine read_output

   !> The rest of *OUTPUT, FORCES [, EVERY=n] (read_output): once per deck; its data lines list the
   !> steps to write, whole numbers >= 0 separated by commas.
   subroutine read_output_forces(source, card, format_column, every, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      integer, intent(in) :: format_column, every
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: steps(:)
      integer :: i, j, line, step
      if (deck%forces_line > 0) then
         call raise(source, card%line, format_column, 'expected one *OUTPUT, FORCES card, found another '// &
                    'after the one at line '//integer_to_string(deck%forces_line), error)
         return
      end if
      allocate (steps(0))
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         do j = 1, size(fields)
            call field_integer(source, deck%parameters, line, fields(j), 'a step number', step, error)
            if (allocated(error)) return
            if (step < 0) then
               call raise(source, line, fields(j)%column, 'expected a step number (0 or more), found '// &
                          integer_to_string(step), error)
               return
            end if
            steps = [steps, step]
         end do
      end do
      deck%forces_line = card%line
      deck%model%output%forces = .true.
      deck%model%output%forces_every = every
      deck%model%output%forces_steps = steps
   end subroutine read_output_forces

   !> A deck describes one analysis: a second analysis card is an error.
   subroutine require_analysis_once(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      if (deck%analysis_line > 0) then
         call raise(source, card%line, card%column, 'expected one analysis card, found *'//card%keyword// &
                    ' after the one at line '//integer_to_string(deck%analysis_line), error)
         return
      end if
      deck%analysis_line = card%line
   end subroutine require_analysis_once

end module uniarc_deck_analysis
