!> The checks of a deck before its analysis (supports left by analysis steps, the deck among its own
!> result files, the memory line of -v) and `uniarc --check`.
module uniarc_run_checks
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input
   use uniarc_model, only: model_t, analysis_linear, analysis_step_t
   use uniarc_deck_source, only: echo_window
   use uniarc_model_steps, only: step_model
   use uniarc_result_directory, only: stem_file
   use uniarc_foreign, only: same_file, directory_entries, entry_name_t
   use uniarc_dof_map, only: dof_map_t, build_dof_map
   use uniarc_path_mechanism, only: check_model_mechanism
   use uniarc_check, only: check_model, check_element_scales, check_bed_ends, print_model_summary, &
                           model_memory_estimate, nearly_mechanism_warning, held_contact_warning, analysis_summary
   use uniarc_memory, only: available_memory, memory_text
   use uniarc_strings, only: integer_to_string, counted
   use uniarc_run_common, only: run_options_t, name_analysis_step
   implicit none
   private
   public :: check_deck, check_step_supports, print_memory_line, refuse_deck_among_results

contains

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
                  analysis_summary(step%analysis, model%tracks)//'; loads on '// &
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

   !> What analysis step k changes of the supports and obstacles, for the --check summary: ', N DOFs
   !> held from here, N released, N moved, N obstacles moved (*MOVE)' (the counts that are not zero), or ''.
   pure function support_changes(model, k) result(text)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      character(len=:), allocatable :: text
      integer :: added, released, moved, obstacles
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
      obstacles = 0
      if (allocated(model%steps(k)%loads%moves)) obstacles = count(any(model%steps(k)%loads%moves /= 0.0_dp, dim=1))
      if (added > 0) text = text//', '//counted(added, 'DOF')//' held from here'
      if (released > 0) text = text//', '//counted(released, 'DOF')//' released'
      if (moved > 0) text = text//', '//counted(moved, 'DOF')//' moved'
      if (obstacles > 0) text = text//', '//counted(obstacles, 'obstacle')//' moved (*MOVE)'
   end function support_changes

end module uniarc_run_checks
