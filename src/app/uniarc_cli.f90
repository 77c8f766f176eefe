!> The command line of docs/contracts.md:
!>   uniarc DECK [-o OUTDIR] [-D NAME=VALUE]... [-q|--quiet] [-v|--verbose] [--csv] [--check]
!>   uniarc --help | --version
module uniarc_cli
   use uniarc_error, only: error_t, make_error, error_input
   use uniarc_deck, only: parameter_override_t
   implicit none
   private
   public :: cli_options_t, parse_command_line, usage_text, version_text, deck_stem

   !> Version of uniarc.
   character(len=*), parameter :: version_text = 'uniarc 0.1.0'

   !> What the command line asks for.
   type :: cli_options_t
      character(len=:), allocatable :: deck
      character(len=:), allocatable :: output_directory
      type(parameter_override_t), allocatable :: overrides(:)
      logical :: help = .false.
      logical :: version = .false.
      logical :: quiet = .false.
      logical :: verbose = .false.
      logical :: csv = .false.       !< --csv: the tables also as comma-separated STEM.*.csv
      logical :: check = .false.   !< --check: read, build and summarise the model; no analysis
   end type cli_options_t

contains

   !> Read the arguments of the program; a usage error is an error of category input (exit code 2).
   subroutine parse_command_line(options, error)
      type(cli_options_t), intent(out) :: options
      type(error_t), allocatable, intent(out) :: error
      integer :: i, n
      character(len=:), allocatable :: argument
      n = command_argument_count()
      options%output_directory = '.'
      allocate (options%overrides(0))
      i = 0
      do while (i < n)
         i = i + 1
         argument = get_argument(i)
         select case (argument)
         case ('-h', '--help')
            options%help = .true.
         case ('--version')
            options%version = .true.
         case ('-q', '--quiet')
            options%quiet = .true.
         case ('-v', '--verbose')
            options%verbose = .true.
         case ('--csv')
            options%csv = .true.
         case ('--check')
            options%check = .true.
         case ('-o', '--output')
            if (i == n) then
               call make_error(error, 'option '//argument//' needs a directory', error_input)
               return
            end if
            i = i + 1
            options%output_directory = get_argument(i)
            ! an empty OUTDIR would make the result files '/STEM.path': refused, not taken as the root
            if (len(options%output_directory) == 0) then
               call make_error(error, 'option '//argument//' needs a directory, found an empty argument', &
                               error_input)
               return
            end if
         case ('-D')
            if (i == n) then
               call make_error(error, 'option -D needs NAME=VALUE', error_input)
               return
            end if
            i = i + 1
            call add_override(get_argument(i), options, error)
            if (allocated(error)) return
         case default
            if (len(argument) > 2 .and. argument(1:min(2, len(argument))) == '-D') then
               call add_override(argument(3:), options, error)
               if (allocated(error)) return
            else if (argument(1:1) == '-' .and. len(argument) > 1) then
               call make_error(error, 'unknown option '//argument//' (see uniarc --help)', error_input)
               return
            else if (allocated(options%deck)) then
               call make_error(error, 'more than one deck given: '//options%deck//' and '//argument, &
                               error_input)
               return
            else
               options%deck = argument
            end if
         end select
      end do
      if (.not. (options%help .or. options%version) .and. .not. allocated(options%deck)) then
         call make_error(error, 'no input deck given (usage: uniarc DECK [options]; see uniarc --help)', &
                         error_input)
      end if
   end subroutine parse_command_line

   !> The file name of the deck without folder and extension: the stem of the output files.
   pure function deck_stem(path) result(stem)
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: stem
      integer :: slash, dot
      slash = index(path, '/', back=.true.)
      stem = path(slash + 1:)
      dot = index(stem, '.', back=.true.)
      if (dot > 1) stem = stem(:dot - 1)
   end function deck_stem

   !> The text of `uniarc --help`.
   pure function usage_text() result(text)
      character(len=:), allocatable :: text
      character(len=*), parameter :: nl = new_line('a')
      text = 'usage: uniarc DECK [-o OUTDIR] [-D NAME=VALUE]... [-q|--quiet] [-v|--verbose] [--csv] [--check]'//nl// &
             '       uniarc --help | --version'//nl//nl// &
             'Traces the equilibrium path of the structure described by the input deck DECK'//nl// &
             '(keyword cards, see docs/input.md) and writes, named after the deck''s stem:'//nl// &
             '  STEM.path   one row per converged step: step, lambda, tracked values, contact, solver'//nl// &
             '  STEM.crit   critical points and contact events along the path'//nl// &
             '  STEM.shape  node coordinates and displacements per snapshot'//nl// &
             '  STEM.surface  where each contact candidate meets its foundation or obstacle'//nl// &
             '  STEM_NNNN.vtp, STEM_NNNN.vtk, STEM.pvd  ParaView snapshots (with *OUTPUT, VTK)'//nl//nl// &
             'options:'//nl// &
             '  -o OUTDIR        write the result files to OUTDIR (created; default: .)'//nl// &
             '  -D NAME=VALUE    override the deck''s *PARAMETER NAME (repeatable; VALUE may be'//nl// &
             '                   an expression)'//nl// &
             '  -q, --quiet      no progress on stderr'//nl// &
             '  -v, --verbose    more progress on stderr (every step)'//nl// &
             '      --csv        also write the tables comma-separated: STEM.path.csv, ...'//nl// &
             '      --check      read the deck, build the model and print its summary (counts,'//nl// &
             '                   supports, loads, contact groups, analysis, estimated memory);'//nl// &
             '                   no analysis, no file; exit status 0 or 2 (130/143 if interrupted)'//nl// &
             '  -h, --help       this text'//nl// &
             '      --version    the version'//nl//nl// &
             'exit status: 0 success; 1 analysis failed (steps traced so far are kept);'//nl// &
             '             2 bad input or usage, or a model too large for the memory (no output'//nl// &
             '             file is written); 130/143 interrupted by SIGINT/SIGTERM (the steps'//nl// &
             '             traced so far are written, as for 1)'
   end function usage_text

   !> Add `-D NAME=VALUE` to the overrides, in the order given (the provenance lists them so); of
   !> several -D of one NAME the deck applies the last (uniarc_deck: find_override).
   subroutine add_override(text, options, error)
      character(len=*), intent(in) :: text
      type(cli_options_t), intent(inout) :: options
      type(error_t), allocatable, intent(out) :: error
      type(parameter_override_t) :: override
      integer :: equals
      equals = index(text, '=')
      if (equals <= 1 .or. equals == len(text)) then
         call make_error(error, '-D '//text//': expected NAME=VALUE', error_input)
         return
      end if
      override%name = trim(adjustl(text(:equals - 1)))
      override%value = trim(adjustl(text(equals + 1:)))
      options%overrides = [options%overrides, override]
   end subroutine add_override

   function get_argument(i) result(argument)
      integer, intent(in) :: i
      character(len=:), allocatable :: argument
      integer :: length
      call get_command_argument(i, length=length)
      allocate (character(len=length) :: argument)
      if (length > 0) call get_command_argument(i, argument)
   end function get_argument

end module uniarc_cli
