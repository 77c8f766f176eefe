!> Runs the analysis a model asks for: the checks that can refuse the deck, the result directory
!> claimed, then the linear run (uniarc_run_linear) or the path (uniarc_run_path), and the lock released.
module uniarc_run
   use, intrinsic :: iso_fortran_env, only: error_unit
   use uniarc_error, only: error_t, make_error, error_internal, error_analysis, error_input, add_context
   use uniarc_model, only: model_t, analysis_linear, analysis_nonlinear
   use uniarc_model_steps, only: step_model
   use uniarc_result_directory, only: result_directory_t, claim_result_directory, abandon_results
   use uniarc_foreign, only: interrupt_signal, signal_name
   use uniarc_dof_map, only: dof_map_t, build_dof_map
   use uniarc_check, only: check_model, check_element_scales, check_bed_ends, nearly_mechanism_warning, &
                           held_contact_warning
   use uniarc_path_imperfection, only: computed_imperfection
   use uniarc_run_common, only: run_options_t, release_warning
   use uniarc_run_checks, only: check_step_supports, print_memory_line, refuse_deck_among_results
   use uniarc_run_linear, only: run_linear
   use uniarc_run_path, only: run_path
   implicit none
   private
   public :: run_options_t, run_model

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

end module uniarc_run
