!> Runs the analysis a model asks for and writes its result files; what the program prints on stdout.
module uniarc_run
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit, int64
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_internal
   use uniarc_model, only: model_t, analysis_linear, analysis_nonlinear, tracked_values
   use uniarc_linear_static, only: solve_linear_static
   use uniarc_path_following, only: candidate_reactions
   use uniarc_path_driver, only: path_driver_t, step_outcome_t, driver_start, driver_step, stop_none, &
                                 stop_load_limit, stop_track_limit, stop_step_limit
   use uniarc_contact_summary, only: contact_summary_t, summarize_contact, summarize_groups
   use uniarc_output, only: output_files_t, step_record_t, open_outputs, write_path_row, write_shape, &
                            write_crit_row, close_outputs, discard_outputs, format_number, forces_due, write_forces
   use uniarc_vtk, only: vtk_series_t, open_vtk_series, vtk_snapshot_due, write_vtk_snapshot, &
                         finish_vtk_series
   use uniarc_result_directory, only: result_directory_t, claim_result_directory, commit_results, &
                                      abandon_results
   use uniarc_provenance, only: provenance_t
   use uniarc_modes_output, only: modes_table_t, add_mode, write_modes_file
   use uniarc_path_branch, only: nodal_mode
   use uniarc_path_imperfection, only: computed_imperfection
   use uniarc_critical_points, only: critical_event_t
   implicit none
   private
   public :: run_options_t, run_model

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
   !> converged step). An I/O error stops the run and removes its unfinished files.
   subroutine run_model(model, options, error)
      type(model_t), intent(in) :: model
      type(run_options_t), intent(in) :: options
      type(error_t), allocatable, intent(out) :: error
      type(result_directory_t) :: results
      type(model_t) :: imperfect
      call claim_result_directory(options%output_directory, options%stem, results, error)
      if (allocated(error)) return
      select case (model%analysis%kind)
      case (analysis_linear)
         call run_linear(model, options, results, error)
      case (analysis_nonlinear)
         if (model%analysis%imperfection_bifurcation > 0) then
            ! *IMPERFECTION without FILE=: the mode of the perfect structure's path first.
            call computed_imperfection(model, imperfect, error)
            if (.not. allocated(error)) call run_path(imperfect, options, results, error)
         else
            call run_path(model, options, results, error)
         end if
      case default
         call make_error(error, 'unknown analysis kind', error_internal)
      end select
      ! The lock and the work directory go on every way out (nothing left once the files are committed).
      call abandon_results(results)
   end subroutine run_model

   subroutine run_linear(model, options, results, error)
      type(model_t), intent(in) :: model
      type(run_options_t), intent(in) :: options
      type(result_directory_t), intent(inout) :: results
      type(error_t), allocatable, intent(out) :: error
      type(output_files_t) :: files
      type(vtk_series_t) :: vtk
      type(step_record_t) :: record
      type(error_t), allocatable :: io_error
      type(contact_summary_t) :: summary
      logical, allocatable :: active(:)
      call solve_linear_static(model, record%displacement, record%neg_pivots, error, record%reactions, active, &
                               record%lcp_pivots, record%lcp_residual)
      if (allocated(error)) return
      summary = summarize_contact(model, record%reactions, active)
      record%groups = summarize_groups(model, record%reactions, active)
      record%n_contact = summary%n_contact
      record%contact_regions = summary%regions
      record%s_contact = summary%s_contact
      record%reaction_max = summary%reaction_max
      record%reaction_sum = summary%reaction_sum
      record%step = 1
      record%lambda = 1.0_dp
      record%iterations = 1
      call open_outputs(model, results, options%provenance, options%csv, files, io_error)
      call open_vtk_series(model, options%stem, vtk)
      if (.not. allocated(io_error)) call write_path_row(files, model, record, io_error)
      if (.not. allocated(io_error)) call write_shape(files, model, record, io_error)
      if (.not. allocated(io_error)) call write_forces(files, model, record, io_error)
      if (.not. allocated(io_error)) call finish_vtk_series(vtk, results, model, record, io_error)
      call conclude_outputs(files, results, io_error, error)
      if (allocated(error)) return
      if (.not. options%quiet) call print_tracks(model, record)
   end subroutine run_linear

   !> Follow the equilibrium path with the path driver (uniarc_path_driver: the steps, the stop rules,
   !> the critical points between steps), writing each converged step, its critical points and the
   !> progress messages. An error of the analysis ends the path with the files of the steps so far; an
   !> error of the result files ends it at once.
   subroutine run_path(model, options, results, error)
      type(model_t), intent(in) :: model
      type(run_options_t), intent(in) :: options
      type(result_directory_t), intent(inout) :: results
      type(error_t), allocatable, intent(out) :: error
      type(output_files_t) :: files
      type(vtk_series_t) :: vtk
      type(path_driver_t) :: driver
      type(step_outcome_t) :: outcome
      type(step_record_t) :: record
      type(modes_table_t) :: modes
      type(error_t), allocatable :: io_error
      integer(int64) :: clock_start, clock_now, clock_rate, clock_last
      integer :: k, n_events
      logical :: done
      call system_clock(clock_start, clock_rate)
      clock_last = clock_start
      call driver_start(model, driver, error)
      if (allocated(error)) return
      call open_outputs(model, results, options%provenance, options%csv, files, io_error)
      call open_vtk_series(model, options%stem, vtk)
      call record_state(model, driver, record)
      if (.not. allocated(io_error)) call write_path_row(files, model, record, io_error)
      if (.not. allocated(io_error)) call write_shape(files, model, record, io_error)
      if (.not. allocated(io_error)) call write_vtk_snapshot(vtk, results, model, record, io_error)
      if (.not. allocated(io_error) .and. forces_due(model, record%step)) call write_forces(files, model, record, io_error)
      n_events = 0
      done = allocated(io_error)
      do while (.not. done)
         call driver_step(model, driver, outcome, error)
         if (allocated(error)) exit
         call record_state(model, driver, record)
         call write_path_row(files, model, record, io_error)
         if (allocated(io_error)) exit
         do k = 1, size(outcome%events)
            call write_crit_row(files, outcome%events(k)%kind, outcome%events(k)%position, &
                                outcome%events(k)%lambda, outcome%event_tracked(:, k), io_error)
            if (allocated(io_error)) exit
            n_events = n_events + 1
            if (.not. options%quiet) write (output_unit, '(a,a,a,a,a,a)') '  ', outcome%events(k)%kind, &
               ' at step ', trim(format_number(outcome%events(k)%position)), ': lambda = ', &
               trim(format_number(outcome%events(k)%lambda))
         end do
         if (allocated(io_error)) exit
         if (model%output%modes) call keep_mode(model, driver, outcome%events, modes)
         if (mod(record%step, model%analysis%shape_every) == 0) then
            call write_shape(files, model, record, io_error)
            if (allocated(io_error)) exit
         end if
         if (vtk_snapshot_due(vtk, record%step)) then
            call write_vtk_snapshot(vtk, results, model, record, io_error)
            if (allocated(io_error)) exit
         end if
         if (forces_due(model, record%step)) call write_forces(files, model, record, io_error)
         if (allocated(io_error)) exit
         done = driver%stop /= stop_none
         call system_clock(clock_now)
         if (.not. options%quiet .and. (options%verbose .or. &
             (clock_now - clock_start > clock_rate .and. clock_now - clock_last > clock_rate/4))) then
            write (error_unit, '(a,i0,a,a,a,i0,a,i0,a,i0,a,f0.1,a)') 'step ', record%step, '  lambda ', &
               trim(format_number(record%lambda)), '  iterations ', record%iterations, &
               '  contacts ', record%n_contact, '  neg_pivots ', record%neg_pivots, '  (', &
               real(record%step, dp)/max(real(clock_now - clock_start, dp)/real(clock_rate, dp), 1.0e-3_dp), ' steps/s)'
            ! stderr redirected to a file is buffered: the progress of a long run must show as it goes.
            flush (error_unit)
            clock_last = clock_now
         end if
      end do
      if (.not. allocated(io_error) .and. mod(record%step, model%analysis%shape_every) /= 0) &
         call write_shape(files, model, record, io_error)
      ! The last converged step closes the VTK series and the forces tables, also when the path failed after it.
      if (.not. allocated(io_error)) call write_forces(files, model, record, io_error)
      if (.not. allocated(io_error)) call finish_vtk_series(vtk, results, model, record, io_error)
      if (.not. allocated(io_error) .and. model%output%modes) &
         call write_modes_file(modes, results, options%stem, options%provenance, model, model%output%vtk, io_error)
      call conclude_outputs(files, results, io_error, error)
      if (allocated(error)) return
      if (.not. options%quiet) then
         write (output_unit, '(a,i0,a,a,a,a)') 'path traced: ', record%step, ' steps, lambda = ', &
            trim(format_number(record%lambda)), '; stopped by ', stop_message(model, driver)
         write (output_unit, '(a,i0,a)') '  ', n_events, ' critical points in '//options%stem//'.crit'
      end if
   end subroutine run_path

   !> The buckling mode of the bifurcation the last step located (driver%state%bifurcation), if any,
   !> into the modes table (*OUTPUT, MODES), with the kind and position of its event in STEM.crit.
   subroutine keep_mode(model, driver, events, modes)
      type(model_t), intent(in) :: model
      type(path_driver_t), intent(in) :: driver
      type(critical_event_t), intent(in) :: events(:)
      type(modes_table_t), intent(inout) :: modes
      integer :: k
      if (.not. allocated(driver%state%bifurcation) .or. driver%state%point%switched) return
      do k = size(events), 1, -1
         if (index(events(k)%kind, 'bifurcation') == 0) cycle
         call add_mode(modes, events(k)%kind, events(k)%position, events(k)%lambda, &
                       nodal_mode(model, driver%state%map, driver%state%bifurcation%mode))
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

   !> The committed state of the path as a row of the result files.
   subroutine record_state(model, driver, record)
      type(model_t), intent(in) :: model
      type(path_driver_t), intent(in) :: driver
      type(step_record_t), intent(inout) :: record
      type(contact_summary_t) :: summary
      associate (state => driver%state)
         record%displacement = driver%displacement
         record%step = state%point%step
         record%lambda = state%lambda
         record%iterations = state%point%iterations
         record%neg_pivots = state%point%neg_pivots
         record%lcp_pivots = state%point%lcp_pivots
         record%lcp_residual = state%point%lcp_residual
         record%reactions = candidate_reactions(state)
         summary = summarize_contact(model, record%reactions, state%active)
         record%groups = summarize_groups(model, record%reactions, state%active)
      end associate
      record%n_contact = summary%n_contact
      record%contact_regions = summary%regions
      record%s_contact = summary%s_contact
      record%reaction_max = summary%reaction_max
      record%reaction_sum = summary%reaction_sum
   end subroutine record_state

   !> Which stop rule ended the path, for the closing message.
   function stop_message(model, driver) result(message)
      type(model_t), intent(in) :: model
      type(path_driver_t), intent(in) :: driver
      character(len=:), allocatable :: message
      select case (driver%stop)
      case (stop_load_limit)
         message = 'the load limit'
      case (stop_track_limit)
         message = 'the limit on '//model%tracks(driver%rules%track)%name
      case (stop_step_limit)
         message = 'the maximum number of steps'
      case default
         message = 'an error'
      end select
   end function stop_message

   subroutine print_tracks(model, record)
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      real(dp), allocatable :: values(:)
      integer :: i
      write (output_unit, '(a,i0,a,i0,a)') 'linear static analysis: ', model%n_nodes, ' nodes, ', &
         model%n_elements, ' elements'
      values = tracked_values(model, record%displacement)
      do i = 1, size(values)
         write (output_unit, '(2x,a,a,a)') model%tracks(i)%name, ' = ', trim(format_number(values(i)))
      end do
   end subroutine print_tracks

end module uniarc_run
