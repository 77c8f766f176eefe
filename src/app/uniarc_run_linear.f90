!> The linear static analysis of a model (with contact: one LCP per analysis step) and its result files.
module uniarc_run_linear
   use, intrinsic :: iso_fortran_env, only: error_unit
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_model, only: model_t
   use uniarc_linear_static, only: solve_linear_static, explain_static_imbalance
   use uniarc_model_steps, only: n_analysis_steps, step_model, has_prescribed
   use uniarc_support_reactions, only: support_reactions, prescribed_force
   use uniarc_static_balance, only: check_static_balance
   use uniarc_contact_summary, only: contact_summary_t, summarize_contacts
   use uniarc_output, only: output_files_t, step_record_t, open_outputs, write_path_row, write_shape, write_forces
   use uniarc_vtk, only: vtk_series_t, open_vtk_series, write_vtk_snapshot, finish_vtk_series
   use uniarc_result_directory, only: result_directory_t
   use uniarc_foreign, only: interrupt_signal, signal_name
   use uniarc_console, only: print_tracks
   use uniarc_run_common, only: run_options_t, release_warning, name_analysis_step, conclude_outputs, finite_record
   implicit none
   private
   public :: run_linear

contains

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

end module uniarc_run_linear
