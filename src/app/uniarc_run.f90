!> Runs the analysis a model asks for and writes its result files; what the program prints on stdout.
module uniarc_run
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit, int64
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_internal, error_analysis, error_input, add_context
   use uniarc_model, only: model_t, analysis_linear, analysis_nonlinear, tracked_values, analysis_step_t
   use uniarc_deck_source, only: echo_window
   use uniarc_linear_static, only: solve_linear_static, explain_static_imbalance
   use uniarc_copy, only: copy_array, reserve
   use uniarc_path_driver, only: path_driver_t, step_outcome_t, driver_start, driver_step, stop_none, &
                                 stop_load_limit, stop_track_limit, stop_step_limit, stop_failure, stop_collapse, stop_closed_loop, &
                                 driver_next_analysis_step
   use uniarc_model_steps, only: n_analysis_steps, step_model, has_prescribed
   use uniarc_support_reactions, only: support_reactions, prescribed_force
   use uniarc_static_balance, only: check_static_balance
   use uniarc_contact_summary, only: contact_summary_t, summarize_contacts
   use uniarc_contact_plastic, only: has_plastic
   use uniarc_output, only: output_files_t, step_record_t, move_record, open_outputs, write_path_row, write_shape, &
                            write_crit_row, close_outputs, discard_outputs, format_number, forces_due, write_forces
   use uniarc_vtk, only: vtk_series_t, open_vtk_series, vtk_snapshot_due, write_vtk_snapshot, &
                         finish_vtk_series
   use uniarc_result_directory, only: result_directory_t, claim_result_directory, commit_results, &
                                      abandon_results, stem_file
   use uniarc_foreign, only: interrupt_signal, signal_name, same_file, directory_entries, entry_name_t
   use uniarc_dof_map, only: dof_map_t, build_dof_map, bed_deflection
   use uniarc_path_mechanism, only: check_model_mechanism
   use uniarc_check, only: check_model, check_element_scales, check_bed_ends, print_model_summary, model_memory_estimate, &
                           nearly_mechanism_warning, held_contact_warning
   use uniarc_memory, only: available_memory, memory_text, allocation_failure
   use uniarc_strings, only: integer_to_string, counted
   use uniarc_provenance, only: provenance_t
   use uniarc_console, only: progress_line, short_number, print_tracks, step_limit_notes
   use uniarc_modes_output, only: modes_table_t, add_mode, write_modes_file
   use uniarc_path_branch, only: nodal_mode
   use uniarc_path_imperfection, only: computed_imperfection
   use uniarc_critical_points, only: critical_event_t
   implicit none
   private
   public :: run_options_t, run_model, check_deck

   !> How to run: where the files go and how much to say.
   type :: run_options_t
      character(len=:), allocatable :: output_directory
      character(len=:), allocatable :: stem
      logical :: quiet = .false.
      logical :: verbose = .false.
      type(provenance_t) :: provenance   !< under the header of every table (uniarc_provenance)
      logical :: csv = .false.           !< also write the tables as STEM.*.csv (--csv)
   end type run_options_t

contains

   !> Run the model's analysis and write its result files into OUTDIR (uniarc_result_directory):
   !> claimed first (an unusable or locked OUTDIR is bad input, and nothing is computed), then written
   !> in the run's work directory and moved to their final names together when every file is complete
   !> — when the analysis succeeds and when it fails part-way (docs/contracts.md: exit code 1, every
   !> converged step). An I/O error stops the run and removes its unfinished files. A SIGINT or SIGTERM
   !> (uniarc_foreign: catch_interrupts) abandons the step in progress (its Lemke pivots, Newton
   !> iterations, cut-backs and critical-point search poll it) and ends the path with the files of the
   !> steps traced. `signal` is the number of the signal the run said ("interrupted by ...") it was
   !> interrupted by, 0 when none: the caller's exit code is 128 + it (docs/contracts.md, "Interrupts").
   !> A signal that arrives after that message was due (the run complete) is not reported: exit 0.
   !> Errors: those of check_model (error_input: memory, stiffness), of the result directory, of the
   !> analysis; a non-finite displacement, λ or reaction ends the run (error_analysis) before it is
   !> written. `model` is unchanged on return (intent(inout) for uniarc_model_steps: step_model, which
   !> moves its steps out for a copy of it and back).
   subroutine run_model(model, options, error, signal)
      type(model_t), intent(inout) :: model
      type(run_options_t), intent(in) :: options
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: signal
      type(result_directory_t) :: results
      type(model_t) :: imperfect
      type(dof_map_t) :: map
      character(len=:), allocatable :: warning, held
      ! An interrupt while the deck was read: nothing computed, nothing written (main's exit code).
      signal = interrupt_signal()
      if (signal /= 0) then
         write (error_unit, '(a)') 'interrupted by '//signal_name(interrupt_signal())// &
            ' before the analysis started; no result file written'
         return
      end if
      ! Memory and stiffness checks (uniarc_check) before any large array or result file.
      call check_element_scales(model, error)
      if (allocated(error)) return
      call check_bed_ends(model, error)
      if (.not. allocated(error)) call build_dof_map(model, map, error)
      if (.not. allocated(error)) call check_model(model, map, error)
      if (.not. allocated(error)) call check_step_supports(model, error)
      if (allocated(error)) then
         ! memory refused by the checks: the model does not fit, said of the deck (`DECK: the model ...`)
         if (error%out_of_memory .and. error%category == error_input .and. allocated(model%deck_path)) &
            call add_context(error, model%deck_path)
         return
      end if
      ! The nearly singular model's warning is measured here and said once the checks that can still
      ! refuse the deck (exit code 2: the result directory, a mechanism under its loads at the start of
      ! the analysis, the perfect structure's first run of *IMPERFECTION) are passed: a refused deck's
      ! stderr starts with its error (docs/contracts.md, "Nearly singular models").
      call nearly_mechanism_warning(model, map, warning)
      call held_contact_warning(model, held)
      if (allocated(held)) then
         ! said with the nearly singular model's warning, as one more line of it
         if (allocated(warning)) then
            warning = held//new_line('a')//'warning: '//warning
         else
            call move_alloc(held, warning)
         end if
      end if
      if (options%verbose .and. .not. options%quiet) call print_memory_line(model, map)
      call refuse_deck_among_results(model, options, error)
      if (allocated(error)) return
      call claim_result_directory(options%output_directory, options%stem, results, error)
      if (allocated(error)) return
      ! a stale lock taken over (its run killed): said, as it may have left an incomplete set
      if (allocated(results%note)) write (error_unit, '(a)') 'note: '//results%note
      select case (model%analysis%kind)
      case (analysis_linear)
         call run_linear(model, options, results, error, warning, signal)
      case (analysis_nonlinear)
         if (model%analysis%imperfection_bifurcation > 0) then
            ! *IMPERFECTION without FILE=: the mode of the perfect structure's path first.
            call computed_imperfection(model, imperfect, error)
            if (.not. allocated(error)) then
               ! The deck's analysis steps moved, not copied, into the imperfect model and back.
               if (allocated(model%steps)) call move_alloc(model%steps, imperfect%steps)
               call run_path(imperfect, options, results, error, warning, signal)
               if (allocated(imperfect%steps)) call move_alloc(imperfect%steps, model%steps)
            end if
         else
            call run_path(model, options, results, error, warning, signal)
         end if
      case default
         call make_error(error, 'unknown analysis kind', error_internal)
      end select
      ! An analysis that failed with an interrupt received: its solve was abandoned for the signal
      ! (the solvers poll it) before there was a converged state to write (the start of the path, the
      ! linear solve, the perfect structure's run of *IMPERFECTION); said as an interrupt, not as a
      ! failure, and nothing is committed (abandon_results below). Not once files were committed or
      ! removed (results%claimed false: a failure reported with its rows, or an I/O error).
      if (allocated(error) .and. signal == 0 .and. interrupt_signal() /= 0 .and. results%claimed) then
         if (error%category == error_analysis .and. .not. error%out_of_memory) then
            signal = interrupt_signal()
            deallocate (error)
            write (error_unit, '(a)') 'interrupted by '//signal_name(signal)// &
               ' before the analysis had a converged state to write; no result file written'
         end if
      end if
      ! Not said yet (the first run of *IMPERFECTION failed): said unless the deck is refused.
      call release_warning(warning, error)
      ! The lock and the work directory go on every way out (nothing left once the files are committed).
      call abandon_results(results)
   end subroutine run_model

   !> Write the nearly singular model's warning `warning` (uniarc_check: nearly_mechanism_warning; also
   !> with -q, as errors are) on stderr unless `error` refuses the deck (error_input: exit code 2, whose
   !> stderr is the error alone), and deallocate it: said at most once. Nothing if it is not allocated.
   subroutine release_warning(warning, error)
      character(len=:), allocatable, intent(inout) :: warning
      type(error_t), allocatable, intent(in) :: error
      if (.not. allocated(warning)) return
      if (.not. allocated(error)) then
         write (error_unit, '(a)') 'warning: '//warning
      else if (error%category /= error_input) then
         write (error_unit, '(a)') 'warning: '//warning
      end if
      deallocate (warning)
   end subroutine release_warning

   !> A deck whose analysis steps release supports (*BOUNDARY, REMOVE): the structure of each such
   !> step — its supports, every contact closed, the model's own check (check_model_mechanism) — must
   !> not be a mechanism, checked before the analysis (exit code 2, no result file), the message naming
   !> the step, the free motion and the node and DOF it moves most. `model` is unchanged on return
   !> (intent(inout) for step_model).
   subroutine check_step_supports(model, error)
      type(model_t), intent(inout) :: model
      type(error_t), allocatable, intent(out) :: error
      type(model_t) :: stepped
      type(dof_map_t) :: map
      real(dp), allocatable :: end_lambda(:)
      logical, allocatable :: before(:, :)
      integer :: k
      if (.not. allocated(model%steps)) return
      allocate (end_lambda(size(model%steps)), source=0.0_dp)
      before = model%fixed
      do k = 1, size(model%steps)
         if (.not. allocated(model%steps(k)%fixed)) cycle
         if (.not. any(before .and. .not. model%steps(k)%fixed)) then
            before = model%steps(k)%fixed
            cycle
         end if
         before = model%steps(k)%fixed
         call step_model(model, k, end_lambda, stepped, error)
         if (.not. allocated(error)) call build_dof_map(stepped, map, error)
         if (.not. allocated(error)) call check_model_mechanism(stepped, map, error)
         if (allocated(error)) then
            call name_analysis_step(model, k, error)
            error%message = error%message//' (the supports of this step are those left after its *BOUNDARY, REMOVE)'
            call point_at_remove(model%deck_path, model%steps(k), error)
            return
         end if
      end do
   end subroutine check_step_supports

   !> The message of a step that its *BOUNDARY, REMOVE leaves a mechanism, as an input error's:
   !> `DECK:LINE:COL: ...` at the step's first REMOVE, with that line and a caret under REMOVE
   !> (docs/contracts.md, exit code 2). Unchanged when the step has no REMOVE or the message does
   !> not start with the deck's name.
   subroutine point_at_remove(deck_path, step, error)
      character(len=*), intent(in) :: deck_path
      type(analysis_step_t), intent(in) :: step
      type(error_t), intent(inout) :: error
      character(len=:), allocatable :: shown
      integer :: n, caret
      n = len(deck_path)
      if (step%remove_line == 0 .or. .not. allocated(step%remove_text) .or. n == 0) return
      if (len(error%message) <= n + 1) return
      if (error%message(1:n + 1) /= deck_path//':') return
      call echo_window(step%remove_text, step%remove_column, shown, caret)
      error%message = deck_path//':'//integer_to_string(step%remove_line)//':'// &
                      integer_to_string(step%remove_column)//':'//error%message(n + 2:)// &
                      new_line('a')//shown//new_line('a')//repeat(' ', max(caret - 1, 0))//'^'
   end subroutine point_at_remove

   !> A nearly singular model's warning on stderr (uniarc_check, nearly_mechanism_warning; also with
   !> -q, as errors are): the analysis goes on (docs/contracts.md, "Nearly singular models").
   subroutine warn_nearly_mechanism(model, map)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      character(len=:), allocatable :: message
      call nearly_mechanism_warning(model, map, message)
      if (allocated(message)) write (error_unit, '(a)') 'warning: '//message
   end subroutine warn_nearly_mechanism

   !> The warning of rigid contacts left out because their node's DOF along the normal is held
   !> (uniarc_check: held_contact_warning) on stderr, also with -q; the analysis goes on.
   subroutine warn_held_contacts(model)
      type(model_t), intent(in) :: model
      character(len=:), allocatable :: message
      call held_contact_warning(model, message)
      if (allocated(message)) write (error_unit, '(a)') 'warning: '//message
   end subroutine warn_held_contacts

   !> The memory line of `-v` on stderr before the analysis (docs/contracts.md, "Progress and
   !> messages"): the estimate of uniarc_check (model_memory_estimate) and what is available
   !> (uniarc_memory: available_memory), e.g. `memory: about 1.23 MB estimated; 3.40 GB available
   !> (MemAvailable in /proc/meminfo)`; without the second part when the available memory is unknown.
   subroutine print_memory_line(model, map)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp) :: available
      character(len=:), allocatable :: origin, text
      text = 'memory: about '//memory_text(model_memory_estimate(model, map))//' estimated'
      call available_memory(available, origin)
      if (available >= 0.0_dp) text = text//'; '//memory_text(available)//' available ('//origin//')'
      write (error_unit, '(a)') text
      ! said before the analysis starts, not held in the buffer until the first progress line
      flush (error_unit)
   end subroutine print_memory_line

   !> `uniarc --check`: the checks of run_model (uniarc_check: memory, stiffness) and the model's
   !> summary on stdout, without an analysis and without any file. Errors: those of check_model.
   subroutine check_deck(model, error)
      type(model_t), intent(inout) :: model   !< unchanged on return (check_step_supports)
      type(error_t), allocatable, intent(out) :: error
      type(dof_map_t) :: map
      integer :: k
      call check_element_scales(model, error)
      if (allocated(error)) return
      call check_bed_ends(model, error)
      if (allocated(error)) return
      call build_dof_map(model, map, error)
      if (allocated(error)) return
      call print_model_summary(model, map)
      ! A deck with *STEP: the loads and analysis above are empty; each step's own, in order.
      if (allocated(model%steps)) then
         do k = 1, size(model%steps)
            associate (step => model%steps(k))
               write (output_unit, '(a)') '  analysis step '//integer_to_string(k)//' ('//step%name//'): '// &
                  trim(merge('*STATIC', '*PATH  ', step%analysis%kind == analysis_linear))//', loads on '// &
                  integer_to_string(count(any(step%loads%nodal_load /= 0.0_dp, dim=1)))//' nodes, '// &
                  integer_to_string(size(step%loads%distributed_loads))//' element loads, '// &
                  integer_to_string(size(step%loads%thermal_loads))//' temperature changes'// &
                  trim(support_changes(model, k))
            end associate
         end do
      end if
      call check_model(model, map, error)
      if (.not. allocated(error)) call check_model_mechanism(model, map, error)
      if (.not. allocated(error)) call check_step_supports(model, error)
      if (.not. allocated(error)) call warn_held_contacts(model)
      if (.not. allocated(error)) call warn_nearly_mechanism(model, map)
      if (.not. allocated(error)) write (output_unit, '(a)') 'check passed: the model can be analysed'
   end subroutine check_deck

   !> The linear static analysis (with contact: one LCP, uniarc_linear_static); one row per analysis
   !> step (*STEP), each solved under the loads of every step so far (uniarc_model_steps). `warning`
   !> (a nearly singular model's, if allocated) is said once the first solution has passed the checks
   !> that refuse a deck (release_warning).
   subroutine run_linear(model, options, results, error, warning, signal)
      type(model_t), intent(inout) :: model
      type(run_options_t), intent(in) :: options
      type(result_directory_t), intent(inout) :: results
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable, intent(inout) :: warning
      integer, intent(inout) :: signal   !< the signal said to have interrupted the run (run_model)
      type(output_files_t) :: files
      type(vtk_series_t) :: vtk
      type(step_record_t), allocatable :: records(:)
      type(error_t), allocatable :: io_error
      type(contact_summary_t) :: summary
      type(model_t) :: stepped
      logical, allocatable :: active(:)
      real(dp), allocatable :: end_lambda(:), reactions(:, :)
      integer :: k, n_steps
      n_steps = n_analysis_steps(model)
      allocate (records(n_steps))
      allocate (end_lambda(n_steps), source=1.0_dp)
      do k = 1, n_steps
         call step_model(model, k, end_lambda, stepped, error)
         if (allocated(error)) then
            call name_analysis_step(model, k, error)
            return
         end if
         associate (record => records(k))
            call solve_linear_static(stepped, record%displacement, record%neg_pivots, &
                                     error, record%reactions, active, record%lcp_pivots, record%lcp_residual, &
                                     record%bed_deflections)
            call release_warning(warning, error)
            if (allocated(error)) then
               call name_analysis_step(model, k, error)
               return
            end if
            call summarize_contacts(model, record%reactions, active, summary, record%groups, error)
            if (allocated(error)) then
               call name_analysis_step(model, k, error)
               return
            end if
            record%n_contact = summary%n_contact
            record%contact_regions = summary%regions
            record%s_contact = summary%s_contact
            record%reaction_max = summary%reaction_max
            record%reaction_sum = summary%reaction_sum
            if (has_prescribed(model)) then
               call support_reactions(stepped, record%displacement, 1.0_dp, .true., &
                                      reactions, error=error)
               if (allocated(error)) return
               record%prescribed_force = prescribed_force(stepped, reactions)
            end if
            if (finite_record(record)) then
               ! Nothing is written unless the structure is in equilibrium as a whole (uniarc_static_balance).
               call check_static_balance(stepped, record%displacement, record%reactions, active, error)
               ! an imbalance left by a load that lifts the structure off its media is said so
               call explain_static_imbalance(stepped, error)
               if (allocated(error)) then
                  call name_analysis_step(model, k, error)
                  return
               end if
            end if
            if (.not. finite_record(record)) then
               call make_error(error, 'the linear solution is not finite (NaN or overflow): the loads are too large '// &
                               'for the stiffnesses, or the stiffness matrix is singular or badly scaled; no result '// &
                               'file written', error_analysis)
               call name_analysis_step(model, k, error)
               return
            end if
            record%step = k
            record%lambda = 1.0_dp
            record%iterations = 1
            record%analysis_step = k
         end associate
      end do
      call open_outputs(model, results, options%provenance, options%csv, files, io_error)
      call open_vtk_series(model, options%stem, vtk)
      do k = 1, n_steps
         if (.not. allocated(io_error)) call write_path_row(files, model, records(k), io_error)
         if (.not. allocated(io_error)) call write_shape(files, model, records(k), io_error)
         if (.not. allocated(io_error)) call step_model(model, k, end_lambda, stepped, io_error)
         if (.not. allocated(io_error)) call write_forces(files, stepped, records(k), io_error)
         if (k < n_steps .and. .not. allocated(io_error)) &
            call write_vtk_snapshot(vtk, results, stepped, records(k), io_error)
      end do
      ! `stepped` is the model of the last step here
      if (.not. allocated(io_error)) call finish_vtk_series(vtk, results, stepped, records(n_steps), io_error)
      call conclude_outputs(files, results, io_error, error)
      if (allocated(error)) return
      signal = interrupt_signal()
      if (signal /= 0) write (error_unit, '(a)') 'interrupted by '//signal_name(signal)// &
         ' during the linear analysis, which ended all the same: its result files are complete'
      if (.not. options%quiet) call print_tracks(model, records(n_steps))
   end subroutine run_linear

   !> Follow the equilibrium path with the path driver (uniarc_path_driver: the steps, the stop rules,
   !> the critical points between steps), writing each converged step, its critical points and the
   !> progress messages. A deck with analysis steps (*STEP) traces them in turn, each from the state
   !> where the previous one stopped (driver_next_analysis_step) on the model of the step
   !> (uniarc_model_steps: the earlier steps' loads held at their final λ); each later step starts with
   !> a row of that state at its λ = 0. An error of the analysis ends the path with the files of the
   !> steps so far; an error of the result files ends it at once. A step whose λ, displacements or
   !> reactions are not finite is not written: it ends the path as an analysis error. An interrupt
   !> (SIGINT, SIGTERM) is polled after every written step and inside the step (driver_step: the step
   !> in progress is abandoned, not written): the path ends at the last written step, and its files
   !> are completed and committed. One that arrives after the path ended by its stop rule is said too
   !> (the files are then complete); `signal` returns the one said (run_model). `warning` (a nearly singular model's, if allocated) is said once the
   !> path's start has passed the checks that refuse a deck (release_warning).
   subroutine run_path(model, options, results, error, warning, signal)
      type(model_t), intent(inout) :: model
      type(run_options_t), intent(in) :: options
      type(result_directory_t), intent(inout) :: results
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable, intent(inout) :: warning
      integer, intent(inout) :: signal   !< the signal said to have interrupted the run (run_model)
      type(output_files_t) :: files
      type(vtk_series_t) :: vtk
      type(path_driver_t) :: driver
      type(step_outcome_t) :: outcome
      type(step_record_t) :: record, next
      type(modes_table_t) :: modes
      type(error_t), allocatable :: io_error
      type(model_t) :: stepped
      real(dp), allocatable :: end_lambda(:), reactions(:, :)
      integer(int64) :: clock_start, clock_now, clock_rate, clock_last
      integer :: k, n_critical, n_contact_events, k_step, n_steps
      logical :: done
      call system_clock(clock_start, clock_rate)
      clock_last = clock_start
      n_steps = n_analysis_steps(model)
      allocate (end_lambda(n_steps), source=0.0_dp)
      k_step = 1
      call step_model(model, k_step, end_lambda, stepped, error)
      if (.not. allocated(error)) call driver_start(stepped, driver, error)
      call release_warning(warning, error)
      if (allocated(error)) then
         call name_analysis_step(model, k_step, error)
         return
      end if
      call open_outputs(model, results, options%provenance, options%csv, files, io_error)
      call open_vtk_series(model, options%stem, vtk)
      call record_state(model, stepped, driver, record, error)
      if (allocated(error)) return
      ! the starting state is written as row 0 only when every column is finite, as every step is
      if (.not. finite_record(record)) then
         call make_error(error, 'the starting state (step 0) is not finite (NaN or overflow in the '// &
                         'displacements, the reactions or the complementarity residual); it is not written', &
                         error_analysis)
         return
      end if
      record%analysis_step = k_step
      if (.not. allocated(io_error)) call write_path_row(files, model, record, io_error)
      if (.not. allocated(io_error)) call write_shape(files, model, record, io_error)
      if (.not. allocated(io_error)) call write_vtk_snapshot(vtk, results, stepped, record, io_error)
      if (.not. allocated(io_error) .and. forces_due(stepped, record%step)) &
         call write_forces(files, stepped, record, io_error)
      n_critical = 0
      n_contact_events = 0
      do
         done = allocated(io_error) .or. interrupt_signal() /= 0
         do while (.not. done)
            call driver_step(stepped, driver, outcome, error)
            if (allocated(error)) exit
            ! A bearing collapse (stop_collapse) takes no new step: its event is at the last row written.
            if (outcome%advanced) then
               ! The new row in a record of its own, moved into `record` (the last written) once it is
               ! known to be whole and finite: no copy of a record (docs/contracts.md, "Memory").
               call record_state(model, stepped, driver, next, error)
               if (allocated(error)) exit
               next%analysis_step = k_step
               if (.not. finite_record(next)) then
                  call make_error(error, 'step '//integer_to_string(next%step)//' from lambda = '// &
                                  trim(format_number(outcome%lambda))//': the converged state is not finite (NaN or '// &
                                  'overflow in lambda, the displacements or the reactions); it is not written, '// &
                                  'the path ends at step '//integer_to_string(record%step), error_analysis)
                  exit
               end if
               call move_record(next, record)
               call write_path_row(files, model, record, io_error)
               if (allocated(io_error)) exit
            end if
            do k = 1, size(outcome%events)
               if (allocated(model%steps)) then
                  call write_crit_row(files, outcome%events(k)%kind, outcome%events(k)%position, &
                                      outcome%events(k)%lambda, outcome%event_tracked(:, k), io_error, &
                                      analysis_step=k_step, step_name=model%steps(k_step)%name)
               else
                  call write_crit_row(files, outcome%events(k)%kind, outcome%events(k)%position, &
                                      outcome%events(k)%lambda, outcome%event_tracked(:, k), io_error)
               end if
               if (allocated(io_error)) exit
               if (is_contact_event(outcome%events(k)%kind)) then
                  n_contact_events = n_contact_events + 1
               else
                  n_critical = n_critical + 1
               end if
               if (.not. options%quiet) write (output_unit, '(a)') '  '//outcome%events(k)%kind//' '// &
                  event_place(outcome%events(k)%position, record%step)//', lambda = '// &
                  short_number(outcome%events(k)%lambda)//multiplicity_note(outcome%events(k)%multiplicity)// &
                  step_label(model, k_step)
            end do
            if (allocated(io_error)) exit
            if (.not. outcome%advanced) exit
            if (model%output%modes) call keep_mode(model, driver, outcome%events, modes, error)
            if (allocated(error)) exit
            if (mod(record%step, stepped%analysis%shape_every) == 0) then
               call write_shape(files, model, record, io_error)
               if (allocated(io_error)) exit
            end if
            if (vtk_snapshot_due(vtk, record%step)) then
               call write_vtk_snapshot(vtk, results, stepped, record, io_error)
               if (allocated(io_error)) exit
            end if
            if (forces_due(stepped, record%step)) call write_forces(files, stepped, record, io_error)
            if (allocated(io_error)) exit
            done = driver%stop /= stop_none .or. interrupt_signal() /= 0
            call system_clock(clock_now)
            if (.not. options%quiet .and. (options%verbose .or. &
                (clock_now - clock_start > clock_rate .and. clock_now - clock_last > clock_rate/4))) then
               write (error_unit, '(a)') progress_line(driver, record, &
                                                       real(clock_now - clock_start, dp)/real(clock_rate, dp))
               ! stderr redirected to a file is buffered: the progress of a long run must show as it goes.
               flush (error_unit)
               clock_last = clock_now
            end if
         end do
         if (allocated(error) .and. interrupt_signal() /= 0) then
            ! The step in progress was abandoned for the interrupt (driver_step): not an analysis
            ! error; the path ends at the last written step, as between steps.
            deallocate (error)
            driver%stop = stop_none
         end if
         if (allocated(error)) call name_analysis_step(model, k_step, error)
         if (allocated(error) .or. allocated(io_error) .or. k_step == n_steps .or. driver%stop == stop_none .or. &
             interrupt_signal() /= 0) exit
         ! The next analysis step, from the state where this one stopped (its shape and, with *OUTPUT,
         ! FORCES, its forces written first: the end of every analysis step is in STEM.forces).
         call write_forces(files, stepped, record, io_error)
         if (allocated(io_error)) exit
         end_lambda(k_step) = driver%state%lambda
         if (.not. options%quiet) write (output_unit, '(a)') 'analysis step '//integer_to_string(k_step)//' ('// &
            model%steps(k_step)%name//') ended at step '//integer_to_string(record%step)//', lambda = '// &
            trim(format_number(record%lambda))//'; '//stop_message(model, driver)
         if (mod(record%step, stepped%analysis%shape_every) /= 0) then
            call write_shape(files, model, record, io_error)
            if (allocated(io_error)) exit
         end if
         k_step = k_step + 1
         if (allocated(model%steps(k_step)%fixed)) then
            ! The forces of the supports where the step begins, for those it removes (step_model).
            if (allocated(driver%state%joint_plastic)) then
               call support_reactions(stepped, driver%displacement, driver%state%lambda, .false., reactions, &
                                      driver%state%joint_plastic, error)
            else
               call support_reactions(stepped, driver%displacement, driver%state%lambda, .false., reactions, &
                                      error=error)
            end if
            if (allocated(error)) then
               call name_analysis_step(model, k_step, error)
               exit
            end if
            call step_model(model, k_step, end_lambda, stepped, error, driver%displacement, reactions)
         else
            call step_model(model, k_step, end_lambda, stepped, error)
         end if
         if (.not. allocated(error)) call driver_next_analysis_step(stepped, driver, error)
         if (allocated(error)) then
            call name_analysis_step(model, k_step, error)
            exit
         end if
         call record_state(model, stepped, driver, next, error)
         if (.not. allocated(error) .and. .not. finite_record(next)) &
            call make_error(error, 'the starting state of the analysis step is not finite (NaN or overflow); '// &
                            'it is not written, the path ends at step '//integer_to_string(record%step), &
                            error_analysis)
         if (allocated(error)) then
            call name_analysis_step(model, k_step, error)
            exit
         end if
         next%analysis_step = k_step
         call move_record(next, record)
         call write_path_row(files, model, record, io_error)
      end do
      if (.not. allocated(io_error) .and. mod(record%step, stepped%analysis%shape_every) /= 0) &
         call write_shape(files, model, record, io_error)
      ! The last converged step closes the VTK series and the forces tables, also when the path failed after it.
      if (.not. allocated(io_error)) call write_forces(files, stepped, record, io_error)
      if (.not. allocated(io_error)) call finish_vtk_series(vtk, results, stepped, record, io_error)
      if (.not. allocated(io_error) .and. model%output%modes) &
         call write_modes_file(modes, results, options%stem, options%provenance, model, model%output%vtk, io_error)
      call conclude_outputs(files, results, io_error, error)
      if (allocated(error)) return
      signal = interrupt_signal()
      if (signal /= 0 .and. driver%stop == stop_none) then
         write (error_unit, '(a)') 'interrupted by '//signal_name(signal)//' after step '// &
            integer_to_string(record%step)//' (lambda = '//short_number(record%lambda)//'): the '// &
            counted(record%step, 'step')//' traced '//trim(merge('is in ', 'are in', record%step == 1))//' '// &
            results%directory//'/'//options%stem//'.path'
      else if (signal /= 0) then
         ! The path had ended by its stop rule (or an error) when the signal came: said all the same,
         ! never a silent exit code 130/143 (docs/contracts.md, "Interrupts").
         write (error_unit, '(a)') 'interrupted by '//signal_name(signal)//' after the path had ended ('// &
            stop_message(model, driver)//'): its result files are complete'
      end if
      ! *PATH, SWITCH=n on a path that met fewer bifurcations: said, not left to be guessed from .crit.
      if (stepped%analysis%switch_bifurcation > driver%state%bifurcations .and. .not. allocated(error)) &
         write (error_unit, '(a)') 'warning: *PATH, SWITCH='//integer_to_string(stepped%analysis%switch_bifurcation)// &
         ': the path located '//counted(driver%state%bifurcations, 'bifurcation')//', so it did not switch branches'
      if (.not. options%quiet) then
         if (allocated(model%steps)) write (output_unit, '(a)') 'analysis step '//integer_to_string(k_step)// &
            ' ('//model%steps(k_step)%name//') ended at lambda = '//trim(format_number(record%lambda))//'; '// &
            stop_message(model, driver)
         write (output_unit, '(a)') 'path traced: '//counted(record%step, 'step')//', lambda = '// &
            trim(format_number(record%lambda))//'; '//stop_message(model, driver)
         if (driver%stop == stop_step_limit) write (output_unit, '(a)', advance='no') step_limit_notes(driver)
         write (output_unit, '(a)') '  '//counted(n_critical, 'critical point')//' and '// &
            counted(n_contact_events, 'contact event')//' in '//options%stem//'.crit'
      end if
   end subroutine run_path

   !> ' (analysis step K NAME)' for the messages of a deck with steps; '' without.
   function step_label(model, k) result(label)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      character(len=:), allocatable :: label
      label = ''
      if (allocated(model%steps)) label = ' (analysis step '//integer_to_string(k)//' '//model%steps(k)%name//')'
   end function step_label

   !> Prefix an error of the analysis with the analysis step it happened in (decks with steps); an
   !> input error (exit code 2) keeps its `file:` first (docs/contracts.md) and names the step after it.
   subroutine name_analysis_step(model, k, error)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      type(error_t), intent(inout) :: error
      character(len=:), allocatable :: label
      integer :: n
      if (.not. allocated(model%steps)) return
      label = 'analysis step '//integer_to_string(k)//' ('//model%steps(k)%name//')'
      n = len(model%deck_path)
      if (error%category == error_input .and. n > 0 .and. len(error%message) > n + 1) then
         if (error%message(1:n + 1) == model%deck_path//':') then
            error%message = error%message(1:n + 1)//' '//label//':'//error%message(n + 2:)
            return
         end if
      end if
      error%message = label//': '//error%message
   end subroutine name_analysis_step

   !> The buckling mode of the bifurcation the last step located (driver%state%bifurcation), if any,
   !> into the modes table (*OUTPUT, MODES), with the kind and position of its event in STEM.crit.
   !> Errors: the mode or the grown table refused by the system (error_analysis, out of memory).
   subroutine keep_mode(model, driver, events, modes, error)
      type(model_t), intent(in) :: model
      type(path_driver_t), intent(in) :: driver
      type(critical_event_t), intent(in) :: events(:)
      type(modes_table_t), intent(inout) :: modes
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: mode(:, :)
      integer :: k
      if (.not. allocated(driver%state%bifurcation) .or. driver%state%point%switched) return
      do k = size(events), 1, -1
         if (index(events(k)%kind, 'bifurcation') == 0) cycle
         call nodal_mode(model, driver%state%map, driver%state%bifurcation%mode, mode, error, &
                         keep_sign=driver%state%bifurcation%liftoff)
         if (allocated(error)) return
         call add_mode(modes, events(k)%kind, events(k)%position, events(k)%lambda, mode, error)
         return
      end do
   end subroutine keep_mode

   !> End the result files of a run. Without an I/O error (`io_error`) they are closed and moved to
   !> their final names together, and `error` (the analysis' error, if any) is left as it is. After an
   !> I/O error — of a write, a flush, a close or the commit — the files not moved are removed, and
   !> `error` becomes the I/O error (analysis category, exit code 1), which says so and names any
   !> analysis error before it.
   subroutine conclude_outputs(files, results, io_error, error)
      type(output_files_t), intent(inout) :: files
      type(result_directory_t), intent(inout) :: results
      type(error_t), allocatable, intent(inout) :: io_error
      type(error_t), allocatable, intent(inout) :: error
      ! An array of a table the system refused (uniarc_output, uniarc_vtk: out of memory) is no I/O
      ! error: the rows written so far are complete, the files are kept, the run ends with it
      ! (docs/contracts.md, "Memory"), unless the analysis failed first.
      if (allocated(io_error)) then
         if (io_error%out_of_memory) then
            if (.not. allocated(error)) then
               call move_alloc(io_error, error)
            else
               deallocate (io_error)
            end if
         end if
      end if
      if (.not. allocated(io_error)) call close_outputs(files, io_error)
      if (.not. allocated(io_error)) then
         call commit_results(results, io_error)
      else
         call discard_outputs(files)
         call abandon_results(results)
         io_error%message = io_error%message//'; the run stopped and removed its unfinished result files '// &
                            '(no file of this run is in '//results%directory//')'
      end if
      if (.not. allocated(io_error)) return
      if (allocated(error)) io_error%message = io_error%message//'; before that: '//error%message
      call move_alloc(io_error, error)
   end subroutine conclude_outputs

   !> What analysis step k changes of the supports, for the --check summary: ', N DOFs held from
   !> here, N released, N moved' (the counts that are not zero), or ''.
   pure function support_changes(model, k) result(text)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      character(len=:), allocatable :: text
      integer :: added, released, moved
      text = ''
      added = 0
      released = 0
      moved = 0
      if (allocated(model%steps(k)%fixed) .and. k > 1) then
         if (allocated(model%steps(k - 1)%fixed)) then
            added = count(model%steps(k)%fixed .and. .not. model%steps(k - 1)%fixed)
            released = count(model%steps(k - 1)%fixed .and. .not. model%steps(k)%fixed)
         end if
      end if
      if (allocated(model%steps(k)%loads%prescribed)) moved = count(model%steps(k)%loads%prescribed /= 0.0_dp)
      if (added > 0) text = text//', '//counted(added, 'DOF')//' held from here'
      if (released > 0) text = text//', '//counted(released, 'DOF')//' released'
      if (moved > 0) text = text//', '//counted(moved, 'DOF')//' moved'
   end function support_changes

   !> The committed state of the path as a row of the result files (`stepped`: the model of the
   !> analysis step traced, uniarc_model_steps; it has the prescribed displacements of the step).
   subroutine record_state(model, stepped, driver, record, error)
      type(model_t), intent(in) :: model
      type(model_t), intent(inout) :: stepped   !< unchanged (inout for support_reactions' copy_model)
      type(path_driver_t), intent(in) :: driver
      type(step_record_t), intent(inout) :: record
      !> an array of the record or the support reactions' numbering refused by the system (out of
      !> memory, error_analysis); `record` is then to be discarded
      type(error_t), allocatable, intent(out) :: error
      type(contact_summary_t) :: summary
      real(dp), allocatable :: reactions(:, :)
      real(dp) :: bytes
      integer :: c, m, status
      associate (state => driver%state)
         ! The record's arrays allocated with stat= (an assignment would allocate them unchecked).
         m = size(state%map%candidate_equation)
         bytes = 0.0_dp
         call copy_array(driver%displacement, record%displacement, status, bytes)
         if (status == 0) call reserve(record%reactions, m, status, bytes)
         if (status == 0) call reserve(record%bed_deflections, m, status, bytes)
         if (status == 0 .and. has_plastic(model)) then
            call copy_array(state%slip, record%slip, status, bytes)
            if (status == 0) call reserve(record%yielding, size(state%yielding), status, bytes)
         end if
         if (status == 0 .and. allocated(state%joint_plastic)) &
            call copy_array(state%joint_plastic, record%joint_plastic, status, bytes)
         call allocation_failure(status, 'an array of the row of step '//integer_to_string(state%point%step), &
                                 bytes, error_analysis, error)
         if (allocated(error)) return
         record%step = state%point%step
         record%lambda = state%lambda
         record%iterations = state%point%iterations
         record%neg_pivots = state%point%neg_pivots
         record%lcp_pivots = state%point%lcp_pivots
         record%lcp_residual = state%point%lcp_residual
         ! candidate_reactions and the bed deflections (uniarc_path_state, bed_deflection) into the record
         record%reactions = 0.0_dp
         if (allocated(state%reactions)) then
            ! Out of the working set a reaction is zero by definition; its unknown holds round-off only.
            do c = 1, m
               if (state%active(c)) record%reactions(c) = state%reactions(c)
            end do
         end if
         if (has_plastic(model)) record%yielding(:) = state%yielding .and. state%active
         do c = 1, m
            record%bed_deflections(c) = bed_deflection(state%map, c, state%u)
         end do
         call summarize_contacts(model, record%reactions, state%active, summary, record%groups, error)
      end associate
      if (allocated(error)) return
      record%n_contact = summary%n_contact
      record%contact_regions = summary%regions
      record%s_contact = summary%s_contact
      record%reaction_max = summary%reaction_max
      record%reaction_sum = summary%reaction_sum
      if (has_prescribed(model)) then
         if (allocated(driver%state%joint_plastic)) then
            call support_reactions(stepped, record%displacement, record%lambda, .false., reactions, &
                                   driver%state%joint_plastic, error)
         else
            call support_reactions(stepped, record%displacement, record%lambda, .false., reactions, error=error)
         end if
         if (allocated(error)) return
         record%prescribed_force = prescribed_force(stepped, reactions)
      end if
   end subroutine record_state

   !> error_input when the deck itself is in OUTDIR under the name of one of its own result files or
   !> of its lock (a deck walker.path, whose stem is walker; or a link of that name to the deck, or the
   !> deck a link to such a file): the run would overwrite it with its path table, or remove it as an
   !> earlier run's file (docs/contracts.md, "Result files"). Every such name in OUTDIR is compared
   !> with the deck as a file (same_file: device and inode, links followed).
   subroutine refuse_deck_among_results(model, options, error)
      type(model_t), intent(in) :: model
      type(run_options_t), intent(in) :: options
      type(error_t), allocatable, intent(out) :: error
      type(entry_name_t), allocatable :: names(:)
      logical :: ok
      integer :: i
      if (.not. allocated(model%deck_path)) return
      call directory_entries(options%output_directory, names, ok)
      if (.not. ok) then
         ! OUTDIR cannot be listed (searchable, not readable) or does not exist yet: the deck's own
         ! name at least
         if (allocated(names)) deallocate (names)
         allocate (names(1))
         names(1)%name = model%deck_path(index(model%deck_path, '/', back=.true.) + 1:)
      end if
      do i = 1, size(names)
         associate (name => names(i)%name)
            if (.not. (stem_file(options%stem, name) .or. name == options%stem//'.lock')) cycle
            if (.not. same_file(model%deck_path, options%output_directory//'/'//name)) cycle
            call make_error(error, model%deck_path//': expected a deck whose file is not one of its own result '// &
                            'files: the results of '//options%stem//' in '//options%output_directory// &
                            ' include '//name//', which is the deck and would overwrite or remove it; rename '// &
                            'the deck (e.g. '//options%stem//'.inp) or write the results elsewhere (-o DIR)', &
                            error_input)
            return
         end associate
      end do
   end subroutine refuse_deck_among_results

   !> Which stop rule ended the path, with the limit that was met, for the closing message.
   function stop_message(model, driver) result(message)
      type(model_t), intent(in) :: model
      type(path_driver_t), intent(in) :: driver
      character(len=:), allocatable :: message
      select case (driver%stop)
      case (stop_load_limit)
         message = 'stopped by the load limit: |lambda| = '//short_number(abs(driver%state%lambda))// &
                   ' reached lambda_max = '//short_number(driver%rules%lambda_max)
      case (stop_track_limit)
         associate (name => model%tracks(driver%rules%track)%name)
            message = 'stopped by the limit on '//name//': |'//name//'| = '// &
                      short_number(abs(driver%tracked(driver%rules%track)))//' reached stop_value = '// &
                      short_number(driver%rules%track_limit)
         end associate
      case (stop_step_limit)
         message = 'stopped by the step limit: max_steps = '//integer_to_string(driver%rules%max_steps)//' reached'
      case (stop_failure)
         message = 'stopped by an error'
      case (stop_closed_loop)
         message = 'stopped where the path closes on itself: its last step passes through the state of step '// &
                   integer_to_string(driver%loop_origin_step)//' (lambda = '// &
                   short_number(driver%loop_origin_lambda)//') where this branch began; followed on, it '// &
                   'would go round the same loop again'
      case (stop_collapse)
         message = 'stopped by a bearing collapse: '//integer_to_string(driver%collapse_points)// &
                   ' contact point(s) of beds or springs at their limit QU or TU (nodes '//driver%collapse_nodes// &
                   ') and nothing else holding the motion the load drives; no higher load may be carried '// &
                   '(collapse load between lambda = '//short_number(driver%state%lambda)//' and '// &
                   short_number(driver%collapse_upper)//')'
      case default
         message = 'stopped by an interrupt'
      end select
   end function stop_message

   !> Where a critical point lies: "at step N" on a converged step, else "between steps N and N+1".
   function event_place(position, step) result(text)
      real(dp), intent(in) :: position
      integer, intent(in) :: step
      character(len=:), allocatable :: text
      if (position >= real(step, dp)) then
         text = 'at step '//integer_to_string(step)
      else
         text = 'between steps '//integer_to_string(step - 1)//' and '//integer_to_string(step)
      end if
   end function event_place

   !> The note on a bifurcation at which several eigenvalues of the tangent vanish together (a double
   !> eigenvalue of a symmetric structure, docs/theory.md §2.3); empty for a simple one.
   function multiplicity_note(multiplicity) result(text)
      integer, intent(in) :: multiplicity
      character(len=:), allocatable :: text
      text = ''
      if (multiplicity > 1) text = ' (multiplicity '//integer_to_string(multiplicity)//': '// &
                                   integer_to_string(multiplicity)//' eigenvalues of the tangent vanish together)'
   end function multiplicity_note

   !> Contact events (contact_start, contact_lost, contact_stability) as opposed to critical points of
   !> the path.
   pure logical function is_contact_event(kind)
      character(len=*), intent(in) :: kind
      is_contact_event = kind == 'contact_start' .or. kind == 'contact_lost' .or. kind == 'contact_stability'
   end function is_contact_event

   !> Every number of a step's row is finite (λ, displacements, reactions, contact summaries).
   pure logical function finite_record(record)
      type(step_record_t), intent(in) :: record
      integer :: g
      ! every real column of the path row (the tracked values are formed from the displacements; the
      ! group columns are the groups' own), the reactions of STEM.contact and the joints' plastic
      ! rotations, tested with ieee_is_finite: an ordered comparison with a NaN would itself raise the
      ! invalid-operation trap of the Debug build
      finite_record = ieee_is_finite(record%lambda) .and. all(ieee_is_finite(record%displacement)) .and. &
                      ieee_is_finite(record%reaction_max) .and. ieee_is_finite(record%reaction_sum) .and. &
                      ieee_is_finite(record%prescribed_force) .and. all(ieee_is_finite(record%s_contact)) .and. &
                      ieee_is_finite(record%lcp_residual)
      if (allocated(record%reactions)) finite_record = finite_record .and. all(ieee_is_finite(record%reactions))
      if (allocated(record%bed_deflections)) &
         finite_record = finite_record .and. all(ieee_is_finite(record%bed_deflections))
      if (allocated(record%joint_plastic)) finite_record = finite_record .and. all(ieee_is_finite(record%joint_plastic))
      if (allocated(record%slip)) finite_record = finite_record .and. all(ieee_is_finite(record%slip))
      if (allocated(record%groups)) then
         do g = 1, size(record%groups)
            finite_record = finite_record .and. all(ieee_is_finite(record%groups(g)%s_contact)) .and. &
                            ieee_is_finite(record%groups(g)%reaction_max) .and. &
                            ieee_is_finite(record%groups(g)%reaction_sum)
         end do
      end if
   end function finite_record

end module uniarc_run
