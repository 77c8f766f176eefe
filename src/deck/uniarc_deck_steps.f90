!> The analysis steps of a deck: *STEP [, NAME=name] ... *END STEP (docs/input.md, *STEP).
!>
!> The model (mesh, sections, supports, contact media, tracks, output) comes first; then one or more
!> steps, each with its loads (*CLOAD, *DLOAD, *TEMPERATURE) and its analysis card (*STATIC or *PATH,
!> none: *STATIC). At *END STEP the loads read since *STEP are taken out of the model builder into the
!> step (take_loads), so that the next step starts without loads of its own; uniarc_model_steps then
!> holds the earlier ones. The placement rules are checked card by card (`check_step_placement`), so
!> that each message points at the card that breaks them:
!> - inside a step only loads, *BOUNDARY (supports added, removed with REMOVE, or moved: nonlinear
!>   steps only) and one analysis card; no *STEP inside a step;
!> - in a deck with steps, no load or analysis card outside them, and nothing after the last
!>   *END STEP but further steps;
!> - every step has a load, and the steps are all *STATIC or all *PATH.
module uniarc_deck_steps
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_input
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: integer_to_string, same_text
   use uniarc_deck_source, only: source_t, card_t, raise, clip, check_options, option_index
   use uniarc_model, only: analysis_step_t, analysis_options_t, analysis_linear
   use uniarc_model_builder, only: take_loads, copy_supports
   use uniarc_deck_state, only: deck_t
   use uniarc_name_table, only: add_name, find_name
   implicit none
   private
   public :: check_step_placement, read_step, read_end_step, finish_steps, take_steps

contains

   !> The rules of where a card may be with respect to the steps (module header); records the first
   !> load and analysis card outside every step, refused when a *STEP follows.
   subroutine check_step_placement(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      logical :: load, analysis
      if (card%keyword == 'STEP' .or. card%keyword == 'END STEP') return
      load = card%keyword == 'CLOAD' .or. card%keyword == 'DLOAD' .or. card%keyword == 'TEMPERATURE' .or. &
             card%keyword == 'MOVE'
      analysis = card%keyword == 'STATIC' .or. card%keyword == 'PATH'
      if (deck%in_step) then
         if (analysis .and. deck%analysis_line == 0) deck%analysis_column = card%column
         if (load .or. analysis) return
         if (card%keyword == 'BOUNDARY') then
            if (deck%step_boundary_line == 0) then
               deck%step_boundary_line = card%line
               deck%step_boundary_column = card%column
            end if
            return
         end if
         call raise(source, card%line, card%column, 'expected a load (*CLOAD, *DLOAD, *TEMPERATURE, *MOVE), '// &
                    '*BOUNDARY, *STATIC, *PATH or *END STEP in the step opened at line '// &
                    integer_to_string(deck%step_line)// &
                    ', found *'//card%keyword//' (the model comes before the first *STEP)', error)
      else if (deck%n_steps > 0) then
         if (load .or. analysis) then
            call raise(source, card%line, card%column, 'expected *STEP before *'//card%keyword//': in a deck '// &
                       'with steps every load and analysis card belongs to a step', error)
         else
            call raise(source, card%line, card%column, 'expected *STEP after *END STEP, found *'// &
                       card%keyword//' (the model comes before the first *STEP)', error)
         end if
      else if (load .and. deck%loose_load_line == 0) then
         deck%loose_load_line = card%line
         deck%loose_load_column = card%column
      else if (analysis .and. deck%loose_analysis_line == 0) then
         deck%loose_analysis_line = card%line
         deck%loose_analysis_column = card%column
      end if
   end subroutine check_step_placement

   !> *STEP [, NAME=name]: opens an analysis step (no data lines). Its name (default Step-k, k its
   !> number) is used in the messages.
   subroutine read_step(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: k, j, status
      call check_options(source, card, [character(len=5) :: 'NAME='], error)
      if (allocated(error)) return
      if (deck%in_step) then
         call raise(source, card%line, card%column, 'expected *END STEP before another *STEP (the step '// &
                    'opened at line '//integer_to_string(deck%step_line)//' is not closed; steps do not nest)', error)
         return
      end if
      if (deck%loose_load_line > 0) then
         call raise(source, deck%loose_load_line, deck%loose_load_column, 'expected this load inside '// &
                    '*STEP ... *END STEP: the deck has steps (*STEP at line '//integer_to_string(card%line)// &
                    ') and every load belongs to one', error)
         return
      end if
      if (deck%loose_analysis_line > 0) then
         call raise(source, deck%loose_analysis_line, deck%loose_analysis_column, 'expected this analysis '// &
                    'card inside *STEP ... *END STEP: the deck has steps (*STEP at line '// &
                    integer_to_string(card%line)//') and each step has its own', error)
         return
      end if
      if (card%n_data > 0) then
         call raise(source, card%data_lines(1), verify(source%lines(card%data_lines(1))%text, ' '), &
                    'expected a card after *STEP (it takes no data line), found a data line', error)
         return
      end if
      if (.not. allocated(deck%steps)) allocate (deck%steps(4))
      if (deck%n_steps == size(deck%steps)) then
         call grow_steps(deck, error)
         if (allocated(error)) return
      end if
      deck%steps(deck%n_steps + 1)%name = 'Step-'//integer_to_string(deck%n_steps + 1)
      k = option_index(card, 'NAME')
      if (k > 0) then
         if (len_trim(card%options(k)%value) == 0) then
            call raise(source, card%line, card%options(k)%value_column, 'expected a step name after NAME=, '// &
                       'found none', error)
            return
         end if
         if (.not. is_step_name(trim(card%options(k)%value))) then
            call raise(source, card%line, card%options(k)%value_column, 'expected a step name (a letter, '// &
                       'then letters, digits, _ or -), found '''//clip(trim(card%options(k)%value))//'''', error)
            return
         end if
         deck%steps(deck%n_steps + 1)%name = trim(card%options(k)%value)
      end if
      ! Names are unique regardless of case (a step's name is a field of the crit file's rows).
      ! (a hash lookup: O(1) a step, not a comparison with every earlier step; issue 14)
      j = find_name(deck%step_names, deck%steps(deck%n_steps + 1)%name)
      if (j > 0) then
         if (k > 0) then
            call raise(source, card%line, card%options(k)%value_column, 'expected a new step name, found '''// &
                       deck%steps(deck%n_steps + 1)%name//''', the name of step '//integer_to_string(j), error)
         else
            call raise(source, card%line, card%column, 'expected a new step name, found the default name '''// &
                       deck%steps(deck%n_steps + 1)%name//''' already taken by step '//integer_to_string(j)// &
                       ' (give this *STEP a NAME=)', error)
         end if
         return
      end if
      call add_name(deck%step_names, deck%steps(deck%n_steps + 1)%name, j, status)
      call allocation_failure(status, 'the table of step names', 32.0_dp*(deck%n_steps + 1), error_input, error)
      if (allocated(error)) return
      deck%in_step = .true.
      deck%step_line = card%line
      deck%step_column = card%column
      call copy_supports(deck%model, deck%step_start_fixed, status)
      call allocation_failure(status, 'the supports at the start of analysis step '// &
                              integer_to_string(deck%n_steps + 1), 12.0_dp*deck%model%n_nodes, error_input, error)
      if (allocated(error)) return
      deck%step_boundary_line = 0
      deck%step_boundary_column = 0
      ! Each step has its own analysis card (none: linear static) and stop track.
      deck%analysis_line = 0
      deck%analysis_column = 0
      deck%model%analysis = analysis_options_t()
      if (allocated(deck%stop_track)) deallocate (deck%stop_track)
   end subroutine read_step

   !> *END STEP: closes the open step, whose loads and analysis it takes from the builder.
   subroutine read_end_step(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, line, column, status
      logical :: released, moved
      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      if (.not. deck%in_step) then
         call raise(source, card%line, card%column, 'expected *STEP before *END STEP, found no open step', error)
         return
      end if
      if (card%n_data > 0) then
         call raise(source, card%data_lines(1), verify(source%lines(card%data_lines(1))%text, ' '), &
                    'expected a card after *END STEP (it takes no data line), found a data line', error)
         return
      end if
      associate (step => deck%steps(deck%n_steps + 1))
         call take_loads(deck%model, step%loads, status)
         call allocation_failure(status, 'the load pattern of analysis step '//integer_to_string(deck%n_steps + 1), &
                                 24.0_dp*deck%model%n_nodes, error_input, error)
         if (allocated(error)) return
         call copy_supports(deck%model, step%fixed, status)
         call allocation_failure(status, 'the supports of analysis step '//integer_to_string(deck%n_steps + 1), &
                                 12.0_dp*deck%model%n_nodes, error_input, error)
         if (allocated(error)) return
         released = any(deck%step_start_fixed .and. .not. step%fixed)
         ! A move or a prescribed displacement of zero drives nothing (λ would scale nothing): no load.
         moved = .false.
         if (allocated(step%loads%moves)) moved = any(step%loads%moves /= 0.0_dp)
         if (allocated(step%loads%prescribed)) moved = moved .or. any(step%loads%prescribed /= 0.0_dp)
         ! (a force on a DOF the step holds is a load: it acts once a later step releases the DOF)
         if (all(step%loads%nodal_load == 0.0_dp) .and. size(step%loads%distributed_loads) == 0 .and. &
             size(step%loads%thermal_loads) == 0 .and. .not. moved .and. .not. released) then
            call raise(source, card%line, card%column, 'expected a load (*CLOAD, *DLOAD, *TEMPERATURE, a '// &
                       'prescribed displacement, an obstacle moved or a support removed, not all zero) in the '// &
                       'step opened at line '//integer_to_string(deck%step_line)//', found none', error)
            return
         end if
         if (allocated(deck%stop_track)) then
            do i = 1, deck%model%n_tracks
               if (same_text(deck%model%tracks(i)%name, deck%stop_track)) deck%model%analysis%stop_track = i
            end do
            if (deck%model%analysis%stop_track == 0) then
               call raise(source, deck%stop_track_line, deck%stop_track_column, 'expected the name of a '// &
                          '*TRACK defined before the step, found '''//deck%stop_track//'''', error)
               return
            end if
            deallocate (deck%stop_track)
         end if
         step%analysis = deck%model%analysis
         ! A *PATH step that removes a support ramps the support's force down to zero at λ = 1; past it
         ! the force would come back reversed, which no construction stage means: lambda_max = 1 unless
         ! the step gives its own (docs/input.md, *STEP).
         if (released .and. step%analysis%kind /= analysis_linear .and. &
             .not. (step%analysis%lambda_max < huge(1.0_dp))) step%analysis%lambda_max = 1.0_dp
         ! Supports change between nonlinear steps only: a linear static step solves all the loads so far
         ! on one structure (superposition), which a support added or removed on the way would break.
         if (step%analysis%kind == analysis_linear .and. any(deck%step_start_fixed .neqv. step%fixed)) then
            call raise(source, deck%step_boundary_line, deck%step_boundary_column, 'expected supports '// &
                       'changed in *PATH steps only: a *STATIC step solves the loads of every step so far '// &
                       'on one structure (add the support before the first *STEP, or trace the steps '// &
                       'with *PATH)', error)
            return
         end if
         if (deck%n_steps > 0) then
            if ((step%analysis%kind == analysis_linear) .neqv. (deck%steps(1)%analysis%kind == analysis_linear)) then
               line = deck%analysis_line
               column = deck%analysis_column
               if (line == 0) then
                  line = deck%step_line
                  column = deck%step_column
               end if
               call raise(source, line, column, 'expected the analysis of the first step ('// &
                          trim(merge('*STATIC', '*PATH  ', deck%steps(1)%analysis%kind == analysis_linear))// &
                          ') in every step: a linear static step cannot go before or after a path (use *PATH, '// &
                          'CONTROL=LOAD with lambda_max = 1 for a load to apply before a path)', error)
               return
            end if
         end if
      end associate
      deck%n_steps = deck%n_steps + 1
      deck%in_step = .false.
      deck%model%analysis = analysis_options_t()
      deck%analysis_line = 0
   end subroutine read_end_step

   !> The list of steps doubled: the steps read so far moved into a list twice as long, their arrays
   !> not copied (an array constructor [steps, steps] copied every step's load patterns three times, and
   !> a copy that the system refuses crashes inside gfortran's copy of a derived type). Errors: the
   !> system refuses the longer list (error_input, exit code 2: the deck does not fit in memory).
   subroutine grow_steps(deck, error)
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      type(analysis_step_t), allocatable :: grown(:)
      integer :: status, j
      allocate (grown(2*size(deck%steps)), stat=status)
      call allocation_failure(status, 'the list of '//integer_to_string(2*size(deck%steps))//' analysis steps', &
                              real(storage_size(grown)/8, dp)*2*size(deck%steps), error_input, error)
      if (allocated(error)) return
      do j = 1, deck%n_steps
         call move_step(deck%steps(j), grown(j))
      end do
      call move_alloc(grown, deck%steps)
   end subroutine grow_steps

   !> The deck's `n_steps` analysis steps moved into `steps` (the model's), the deck's list left empty:
   !> no copy of their load patterns. Errors: the system refuses the list (error_input, exit code 2).
   subroutine take_steps(deck, steps, error)
      type(deck_t), intent(inout) :: deck
      type(analysis_step_t), allocatable, intent(out) :: steps(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: status, j
      allocate (steps(deck%n_steps), stat=status)
      call allocation_failure(status, 'the list of '//integer_to_string(deck%n_steps)//' analysis steps', &
                              real(storage_size(steps)/8, dp)*deck%n_steps, error_input, error)
      if (allocated(error)) return
      do j = 1, deck%n_steps
         call move_step(deck%steps(j), steps(j))
      end do
   end subroutine take_steps

   !> Step `from` moved into `to` (`from` left empty): its allocatable components handed over with
   !> move_alloc, its scalars and small records copied. Every allocatable component of analysis_step_t
   !> and load_pattern_t (uniarc_model) must be moved here.
   subroutine move_step(from, to)
      type(analysis_step_t), intent(inout) :: from
      type(analysis_step_t), intent(inout) :: to
      if (allocated(from%name)) call move_alloc(from%name, to%name)
      to%analysis = from%analysis
      if (allocated(from%fixed)) call move_alloc(from%fixed, to%fixed)
      to%remove_line = from%remove_line
      to%remove_column = from%remove_column
      if (allocated(from%remove_text)) call move_alloc(from%remove_text, to%remove_text)
      to%loads%factor = from%loads%factor
      if (allocated(from%loads%nodal_load)) call move_alloc(from%loads%nodal_load, to%loads%nodal_load)
      if (allocated(from%loads%distributed_loads)) &
         call move_alloc(from%loads%distributed_loads, to%loads%distributed_loads)
      if (allocated(from%loads%thermal_loads)) call move_alloc(from%loads%thermal_loads, to%loads%thermal_loads)
      if (allocated(from%loads%prescribed)) call move_alloc(from%loads%prescribed, to%loads%prescribed)
      if (allocated(from%loads%moves)) call move_alloc(from%loads%moves, to%loads%moves)
   end subroutine move_step

   !> At the end of the deck: a step left open is an error (at its *STEP).
   subroutine finish_steps(source, deck, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(in) :: deck
      type(error_t), allocatable, intent(out) :: error
      if (deck%in_step) call raise(source, deck%step_line, deck%step_column, 'expected *END STEP to close '// &
                                   'this *STEP, found the end of the deck', error)
   end subroutine finish_steps

   !> A step name: a letter, then letters, digits, `_` or `-` (the default names are Step-1, Step-2, ...).
   pure logical function is_step_name(text)
      character(len=*), intent(in) :: text
      character(len=*), parameter :: letters = 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ'
      is_step_name = .false.
      if (len(text) == 0) return
      if (index(letters, text(1:1)) == 0) return
      is_step_name = verify(text, letters//'0123456789_-') == 0
   end function is_step_name

end module uniarc_deck_steps
