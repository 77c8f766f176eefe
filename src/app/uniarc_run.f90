!> Runs the analysis a model asks for and writes its result files; what the program prints on stdout.
module uniarc_run
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit, int64
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_internal
   use uniarc_model, only: model_t, analysis_linear, analysis_nonlinear
   use uniarc_linear_static, only: solve_linear_static
   use uniarc_path_following, only: path_state_t, path_point_t, path_initialize, path_advance, &
                                    nodal_displacements, candidate_reactions
   use uniarc_contact, only: contact_summary_t, summarize_contact
   use uniarc_critical_points, only: critical_event_t, find_critical_events, find_contact_events
   use uniarc_output, only: output_files_t, step_record_t, open_outputs, write_path_row, write_shape, &
                            write_crit_row, commit_outputs, tracked_values, format_number
   use uniarc_vtk, only: vtk_series_t, open_vtk_series, vtk_snapshot_due, write_vtk_snapshot, &
                         finish_vtk_series
   implicit none
   private
   public :: run_options_t, run_model

   !> How to run: where the files go and how much to say.
   type :: run_options_t
      character(len=:), allocatable :: output_directory
      character(len=:), allocatable :: stem
      logical :: quiet = .false.
      logical :: verbose = .false.
   end type run_options_t

contains

   !> Run the model's analysis; the result files are complete (renamed) whether it succeeds or fails.
   subroutine run_model(model, options, error)
      type(model_t), intent(in) :: model
      type(run_options_t), intent(in) :: options
      type(error_t), allocatable, intent(out) :: error
      select case (model%analysis%kind)
      case (analysis_linear)
         call run_linear(model, options, error)
      case (analysis_nonlinear)
         call run_path(model, options, error)
      case default
         call make_error(error, 'unknown analysis kind', error_internal)
      end select
   end subroutine run_model

   subroutine run_linear(model, options, error)
      type(model_t), intent(in) :: model
      type(run_options_t), intent(in) :: options
      type(error_t), allocatable, intent(out) :: error
      type(output_files_t) :: files
      type(vtk_series_t) :: vtk
      type(step_record_t) :: record
      type(error_t), allocatable :: commit_error
      call solve_linear_static(model, record%displacement, record%neg_pivots, error)
      if (allocated(error)) return
      record%step = 1
      record%lambda = 1.0_dp
      record%iterations = 1
      call open_outputs(model, options%output_directory, options%stem, files, error)
      if (allocated(error)) return
      call open_vtk_series(model, options%output_directory, options%stem, vtk)
      call write_path_row(files, model, record)
      call write_shape(files, model, record)
      call finish_vtk_series(vtk, model, record, error)
      call commit_outputs(files, commit_error)
      if (allocated(commit_error) .and. .not. allocated(error)) call move_alloc(commit_error, error)
      if (.not. options%quiet) call print_tracks(model, record)
   end subroutine run_linear

   !> Follow the equilibrium path step by step, writing each converged step and the critical points.
   subroutine run_path(model, options, error)
      type(model_t), intent(in) :: model
      type(run_options_t), intent(in) :: options
      type(error_t), allocatable, intent(out) :: error
      type(output_files_t) :: files
      type(vtk_series_t) :: vtk
      type(path_state_t) :: state
      type(path_point_t) :: previous
      type(step_record_t) :: record
      type(critical_event_t), allocatable :: events(:)
      type(error_t), allocatable :: commit_error
      real(dp), allocatable :: tracked_before(:), tracked_after(:)
      character(len=:), allocatable :: stop_reason
      integer(int64) :: clock_start, clock_now, clock_rate, clock_last
      integer :: k, n_events
      logical :: done
      call system_clock(clock_start, clock_rate)
      clock_last = clock_start
      call path_initialize(model, state, error)
      if (allocated(error)) return
      call open_outputs(model, options%output_directory, options%stem, files, error)
      if (allocated(error)) return
      call open_vtk_series(model, options%output_directory, options%stem, vtk)
      call record_state(model, state, record)
      call write_path_row(files, model, record)
      call write_shape(files, model, record)
      n_events = 0
      stop_reason = 'an error'
      call write_vtk_snapshot(vtk, model, record, error)
      done = allocated(error)
      do while (.not. done)
         previous = state%point
         tracked_before = tracked_values(model, record%displacement)
         call path_advance(model, state, error)
         if (allocated(error)) exit
         call record_state(model, state, record)
         call write_path_row(files, model, record)
         tracked_after = tracked_values(model, record%displacement)
         call find_critical_events(previous, state%point, events)
         call find_contact_events(previous, state%point, events)
         do k = 1, size(events)
            ! Tracked values at the event: linear between the steps (the event's λ is on the Hermite
            ! interpolant; the displacements vary slowly there).
            call write_crit_row(files, events(k)%kind, events(k)%position, events(k)%lambda, &
                                tracked_before + events(k)%fraction*(tracked_after - tracked_before))
            n_events = n_events + 1
            if (.not. options%quiet) write (output_unit, '(a,a,a,a,a,a)') '  ', events(k)%kind, &
               ' at step ', trim(format_number(events(k)%position)), ': lambda = ', &
               trim(format_number(events(k)%lambda))
         end do
         if (mod(record%step, model%analysis%shape_every) == 0) &
            call write_shape(files, model, record)
         if (vtk_snapshot_due(vtk, record%step)) then
            call write_vtk_snapshot(vtk, model, record, error)
            if (allocated(error)) exit
         end if
         call stop_criteria(model, record, tracked_after, done, stop_reason)
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
      if (mod(record%step, model%analysis%shape_every) /= 0) &
         call write_shape(files, model, record)
      ! The last converged step closes the VTK series, also when the path failed after it; an error
      ! of the analysis comes first in the report.
      call finish_vtk_series(vtk, model, record, commit_error)
      if (allocated(commit_error) .and. .not. allocated(error)) call move_alloc(commit_error, error)
      call commit_outputs(files, commit_error)
      if (allocated(error)) return
      if (allocated(commit_error)) then
         call move_alloc(commit_error, error)
         return
      end if
      if (.not. options%quiet) then
         write (output_unit, '(a,i0,a,a,a,a)') 'path traced: ', record%step, ' steps, lambda = ', &
            trim(format_number(record%lambda)), '; stopped by ', stop_reason
         write (output_unit, '(a,i0,a)') '  ', n_events, ' critical points in '//options%stem//'.crit'
      end if
   end subroutine run_path

   subroutine record_state(model, state, record)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(step_record_t), intent(inout) :: record
      type(contact_summary_t) :: summary
      call nodal_displacements(model, state, record%displacement)
      record%step = state%point%step
      record%lambda = state%lambda
      record%iterations = state%point%iterations
      record%neg_pivots = state%point%neg_pivots
      record%lcp_pivots = state%point%lcp_pivots
      record%lcp_residual = state%point%lcp_residual
      record%reactions = candidate_reactions(state)
      summary = summarize_contact(model, record%reactions, state%active)
      record%n_contact = summary%n_contact
      record%contact_regions = summary%regions
      record%s_contact = summary%s_contact
      record%reaction_max = summary%reaction_max
      record%reaction_sum = summary%reaction_sum
   end subroutine record_state

   pure subroutine stop_criteria(model, record, tracked, done, reason)
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      real(dp), intent(in) :: tracked(:)
      logical, intent(out) :: done
      character(len=:), allocatable, intent(inout) :: reason
      done = .true.
      if (abs(record%lambda) >= model%analysis%lambda_max) then
         reason = 'the load limit'
         return
      end if
      if (model%analysis%stop_track > 0) then
         if (abs(tracked(model%analysis%stop_track)) >= model%analysis%stop_value) then
            reason = 'the limit on '//model%tracks(model%analysis%stop_track)%name
            return
         end if
      end if
      if (record%step >= model%analysis%max_steps) then
         reason = 'the maximum number of steps'
         return
      end if
      done = .false.
   end subroutine stop_criteria

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
