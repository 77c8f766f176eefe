!> uniarc: the thin main program. Reads the command line and the deck, runs the analysis, and maps
!> errors to exit codes (docs/contracts.md: 0 success, 1 analysis failed, 2 bad input or usage,
!> 128 + N interrupted by signal N: 130 SIGINT, 143 SIGTERM).
program main
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use uniarc_error, only: error_t, error_input, error_analysis
   use uniarc_foreign, only: exit_program, ignore_file_size_signal, catch_interrupts, interrupt_signal, signal_name
   use uniarc_model, only: model_t
   use uniarc_deck, only: read_deck
   use uniarc_cli, only: cli_options_t, parse_command_line, usage_text, version_text, deck_stem
   use uniarc_run, only: run_options_t, run_model
   use uniarc_run_checks, only: check_deck
   use uniarc_provenance, only: make_provenance
   implicit none
   type(cli_options_t) :: cli
   type(model_t) :: model
   type(run_options_t) :: run_options
   type(error_t), allocatable :: error
   integer :: signal

   ! A file size limit (ulimit -f) makes writes fail with EFBIG, reported like a full file system.
   call ignore_file_size_signal()
   ! SIGINT and SIGTERM end a path after its current step, with the files of the steps traced
   ! (docs/contracts.md, "Interrupts"); the exit code is then 128 + the signal's number.
   call catch_interrupts()
   call parse_command_line(cli, error)
   if (allocated(error)) call fail(error)
   if (cli%help) then
      write (output_unit, '(a)') usage_text()
      call exit_program(0)
   end if
   if (cli%version) then
      write (output_unit, '(a)') version_text
      call exit_program(0)
   end if

   call read_deck(cli%deck, cli%overrides, model, error)
   ! the reading stops at an interrupt (uniarc_deck): said as one, exit 128 + its number
   if (allocated(error)) call check_interrupt('the reading of the deck')
   if (allocated(error)) call fail(error)

   if (cli%check) then
      ! --check stops at an interrupt too (after the deck is read, and after the check's own work).
      call check_interrupt('the check of the deck')
      call check_deck(model, error)
      call check_interrupt('the check of the deck')
      if (allocated(error)) call fail(error)
      call exit_program(0)
   end if

   run_options%output_directory = cli%output_directory
   run_options%stem = deck_stem(cli%deck)
   run_options%quiet = cli%quiet
   run_options%verbose = cli%verbose
   run_options%csv = cli%csv
   run_options%provenance = make_provenance(version_text, cli%deck, cli%overrides)
   call run_model(model, run_options, error, signal)
   if (allocated(error)) call fail(error)
   ! 128 + the signal the run said it was interrupted by; one that came after that, once the files were
   ! committed, does not change a complete run's exit code.
   if (signal /= 0) call exit_program(128 + signal)

contains

   !> With an interrupt received: say it, with what it stopped (`what`), and exit 128 + its number.
   subroutine check_interrupt(what)
      character(len=*), intent(in) :: what
      if (interrupt_signal() == 0) return
      write (error_unit, '(a)') 'interrupted by '//signal_name(interrupt_signal())//' during '//what// &
         '; no result file written'
      call exit_program(128 + interrupt_signal())
   end subroutine check_interrupt

   subroutine fail(error)
      type(error_t), intent(in) :: error
      write (error_unit, '(a)') 'error: '//error%message
      select case (error%category)
      case (error_input)
         call exit_program(2)
      case (error_analysis)
         call exit_program(1)
      case default
         call exit_program(3)
      end select
   end subroutine fail

end program main
