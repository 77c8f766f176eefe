!> The path of a model traced step by step with the path driver, its result files and its messages.
module uniarc_run_path
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit, int64
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_model, only: model_t
   use uniarc_copy, only: copy_array, reserve
   use uniarc_path_driver, only: path_driver_t, step_outcome_t, driver_start, driver_step, stop_none, &
                                 stop_load_limit, stop_track_limit, stop_step_limit, stop_failure, stop_collapse, &
                                 stop_closed_loop, driver_next_analysis_step
   use uniarc_model_steps, only: n_analysis_steps, step_model, has_prescribed
   use uniarc_support_reactions, only: support_reactions, prescribed_force
   use uniarc_contact_summary, only: contact_summary_t, summarize_contacts
   use uniarc_contact_plastic, only: has_plastic
   use uniarc_output, only: output_files_t, step_record_t, move_record, open_outputs, write_path_row, write_shape, &
                            write_crit_row, format_number, forces_due, write_forces
   use uniarc_vtk, only: vtk_series_t, open_vtk_series, vtk_snapshot_due, write_vtk_snapshot, finish_vtk_series
   use uniarc_result_directory, only: result_directory_t
   use uniarc_foreign, only: interrupt_signal, signal_name
   use uniarc_dof_map, only: bed_deflection
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: integer_to_string, counted
   use uniarc_console, only: progress_line, short_number, step_limit_notes
   use uniarc_modes_output, only: modes_table_t, add_mode, write_modes_file
   use uniarc_path_branch, only: nodal_mode
   use uniarc_critical_points, only: critical_event_t
   use uniarc_run_common, only: run_options_t, release_warning, name_analysis_step, step_label, conclude_outputs, &
                                finite_record
   implicit none
   private
   public :: run_path

contains

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
                  placement_note(outcome%events(k)%located)//step_label(model, k_step)
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
         if (allocated(error) .and. .not. allocated(io_error)) then
            ! Under load control the path cannot pass a limit point: the step past the last row failed
            ! from a stable state down to the least increment (uniarc_path_following). That row, the
            ! highest λ load control reaches, is the limit_max row (docs/contracts.md, STEM.crit).
            if (driver%state%limit_under_load) then
               if (allocated(model%steps)) then
                  call write_crit_row(files, 'limit_max', real(record%step, dp), record%lambda, driver%tracked, &
                                      io_error, analysis_step=k_step, step_name=model%steps(k_step)%name)
               else
                  call write_crit_row(files, 'limit_max', real(record%step, dp), record%lambda, driver%tracked, &
                                      io_error)
               end if
               n_critical = n_critical + 1
               if (.not. options%quiet) write (output_unit, '(a)') '  limit_max at step '// &
                  integer_to_string(record%step)//', lambda = '//short_number(record%lambda)// &
                  ' (under load control: the last converged state, no equilibrium found past it)'// &
                  step_label(model, k_step)
            end if
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

   !> Which stop rule ended the path, with the limit that was met, for the closing message.
   function stop_message(model, driver) result(message)
      type(model_t), intent(in) :: model
      type(path_driver_t), intent(in) :: driver
      character(len=:), allocatable :: message
      character(len=:), allocatable :: hinges
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
         if (driver%loop_repeated) then
            message = 'stopped where the path repeats itself: its last step, past a critical point or a '// &
                      'corner, ends on the state of step '//integer_to_string(driver%loop_origin_step)// &
                      ' (lambda = '//short_number(driver%loop_origin_lambda)//'), reached past one too; the '// &
                      'steps between are a loop, and followed on it would go round it again'
         else
            message = 'stopped where the path closes on itself: its last step passes through the state of step '// &
                      integer_to_string(driver%loop_origin_step)//' (lambda = '// &
                      short_number(driver%loop_origin_lambda)//') where this branch began; followed on, it '// &
                      'would go round the same loop again'
         end if
      case (stop_collapse)
         hinges = ''
         if (allocated(driver%collapse_joints)) then
            if (len(driver%collapse_joints) > 0) hinges = ' and joint(s) at their moment limit MY as hinges ('// &
                                                          driver%collapse_joints//')'
         end if
         message = 'stopped by a bearing collapse: '//integer_to_string(driver%collapse_points)// &
                   ' contact point(s) of beds or springs at their limit QU or TU (nodes '//driver%collapse_nodes// &
                   ')'//hinges//' and nothing else holding the motion the load drives; no higher load may be '// &
                   'carried '// &
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

   !> The note on a bifurcation that could not be bracketed by re-solving the step: it is placed at a
   !> converged state beside the change of the count of negative pivots (docs/contracts.md, STEM.crit).
   function placement_note(located) result(text)
      logical, intent(in) :: located
      character(len=:), allocatable :: text
      text = ''
      if (.not. located) text = ' (not bracketed by re-solving the step: placed at a converged state '// &
                                'beside the change of the count of negative pivots)'
   end function placement_note

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

end module uniarc_run_path
