!> The path driver: traces a model's equilibrium path step by step to one of its stop rules, for every
!> caller alike (the program, `src/app/uniarc_run_path.f90`; the benchmarks, `bench/bench_path.f90`; the
!> tests). One call of `driver_step` is one converged step of `path_advance` (which sizes the step,
!> cuts it back on failure and adapts the next length, uniarc_path_following) followed by what every
!> caller needs of it: the nodal displacements and tracked values at the new point, the critical points
!> and contact events between the previous point and the new one (uniarc_critical_points), the number
!> of cut-backs the step used, and the stop rules of docs/contracts.md (exit code 0: "the analysis ended
!> by one of its stop rules"). Writing files and messages is left to the caller.
!>
!>     call driver_start(model, driver, error)
!>     do while (driver%stop == stop_none)
!>        call driver_step(model, driver, outcome, error)
!>        if (allocated(error)) exit          ! driver%stop == stop_failure
!>        ... outcome%step, outcome%events, driver%state, driver%tracked ...
!>     end do
!>
!> The stop rules are checked after every converged step, in this order (the first that holds is the
!> reason): |λ| >= lambda_max; |tracked value| >= its limit; the step number reaches max_steps.
module uniarc_path_driver
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input, error_internal, error_analysis
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_foreign, only: interrupt_signal
   use uniarc_model, only: model_t, tracked_values
   use uniarc_path_following, only: path_state_t, path_point_t, path_trace_t, path_initialize, path_advance, &
                                    nodal_displacements, path_restart, path_change_working_set
   use uniarc_critical_points, only: critical_event_t, find_critical_events, find_contact_events, sort_events
   use uniarc_path_collapse, only: bearing_collapse, plastic_plateau
   use uniarc_path_contact_branch, only: find_contact_branching
   use uniarc_assembly, only: gather_nodal
   use uniarc_model_steps, only: has_prescribed
   use uniarc_dof_map, only: dof_map_t, build_dof_map
   use uniarc_band, only: band_allocate
   use uniarc_path_state_copy, only: copy_point_record, move_map, copy_state, move_state
   use uniarc_memory, only: allocation_failure
   use uniarc_path_pace, only: pace_t, pace_start, pace_record
   use uniarc_path_trace, only: trace_closed_loop, trace_event_revisited, trace_remember_event
   use uniarc_path_rest, only: rest_on_contacts
   implicit none
   private
   public :: path_driver_t, stop_rules_t, step_outcome_t, driver_start, driver_step
   public :: driver_next_analysis_step
   public :: stop_none, stop_load_limit, stop_track_limit, stop_step_limit, stop_failure, stop_collapse, &
             stop_closed_loop

   !> Why the path ended (`path_driver_t%stop`, `step_outcome_t%stop`).
   integer, parameter :: stop_none = 0         !< it has not: the next step may be taken
   integer, parameter :: stop_load_limit = 1   !< |λ| reached lambda_max
   integer, parameter :: stop_track_limit = 2  !< |tracked value| of the stop track reached its limit
   integer, parameter :: stop_step_limit = 3   !< the step number reached max_steps
   integer, parameter :: stop_failure = 4      !< a step failed after every cut-back (error returned)
   !> the next step failed at a bearing collapse of beds or springs at their limits (QU=, TU=), which
   !> the committed state certifies (uniarc_path_collapse): a result, the path's last point
   integer, parameter :: stop_collapse = 5
   !> the step passed through the state where the branch began (the unloaded state, the analysis
   !> step's start, the bifurcation of a branch switch), or a step past a critical point or a corner
   !> ended on the state of an earlier one: the path is a closed loop, traced once (uniarc_path_trace,
   !> trace_closed_loop, trace_event_revisited; docs/theory.md §2.3)
   integer, parameter :: stop_closed_loop = 6

   !> When the path stops (docs/input.md, *PATH); driver_start copies them from `model%analysis`.
   type :: stop_rules_t
      real(dp) :: lambda_max = huge(1.0_dp)  !< stop when |λ| >= lambda_max (λ dimensionless)
      integer :: track = 0                   !< index into model%tracks of the stop track (0: none)
      real(dp) :: track_limit = 0.0_dp       !< stop when |value of that track| >= track_limit (its units)
      integer :: max_steps = 200             !< stop when the step number reaches max_steps
   end type stop_rules_t

   !> A path being traced: the committed state of the path following, what callers read at it, and
   !> the stop rules. Components are read by callers; only driver_start and driver_step change them
   !> (a caller may change `rules` between steps).
   type :: path_driver_t
      type(path_state_t) :: state                  !< committed state (uniarc_path_following), point included
      !> the memory of the path traced (the last committed states and corners, uniarc_path_trace): path_advance's,
      !> kept here so that no copy of the state copies it
      type(path_trace_t) :: trace
      type(stop_rules_t) :: rules
      real(dp), allocatable :: displacement(:, :)  !< (dofs_per_node, n_nodes) nodal displacements at the committed state
      real(dp), allocatable :: tracked(:)          !< (size(model%tracks)) tracked values at the committed state
      integer :: stop = stop_none                  !< why the path ended; stop_none while it goes on
      !> at stop_collapse: the upper bound of the collapse load (λ of the state the lower bound), the
      !> contact points at their limits and their node labels (the first ones)
      real(dp) :: collapse_upper = 0.0_dp
      integer :: collapse_points = 0
      character(len=:), allocatable :: collapse_nodes
      !> the joints at their moment limit that are hinges of the collapse mechanism ('' for a rigid one)
      character(len=:), allocatable :: collapse_joints
      !> at stop_closed_loop: the step and λ of the state where the closed branch began, or (when
      !> loop_repeated) of the earlier step past an event whose state the last step repeated
      integer :: loop_origin_step = 0
      real(dp) :: loop_origin_lambda = 0.0_dp
      logical :: loop_repeated = .false.
      logical :: started = .false.                 !< driver_start succeeded
      !> Converged steps before the current analysis step (driver_next_analysis_step): the step
      !> numbers go on across analysis steps, and max_steps counts the steps of the current one.
      integer :: step_offset = 0
      !> The lengths of the steps of the current analysis step and λ's change with them (uniarc_path_pace):
      !> what a path that ends on its step limit says of its last steps.
      type(pace_t) :: pace
   end type path_driver_t

   !> What one call of driver_step did.
   type :: step_outcome_t
      integer :: step = 0               !< number of the converged step (that of the committed state on failure)
      real(dp) :: lambda = 0.0_dp       !< load factor at the converged step
      integer :: iterations = 0         !< Newton corrections of the converged attempt
      !> Halvings of the step length before the step converged (path_advance's count; on failure the
      !> halvings it made).
      integer :: cuts = 0
      !> Critical points and contact events between the previous converged point and this one, in path
      !> order (by position; at one position in the order of find_critical_events, find_contact_events).
      type(critical_event_t), allocatable :: events(:)
      !> (size(model%tracks), size(events)): the tracked values at each event: at a contact start
      !> located by re-solving the step (uniarc_path_contact_start) those of the state there; at a
      !> branch switch those of the bifurcation's state; at the others linear between the two steps at
      !> the event's fraction (the displacements vary slowly there).
      real(dp), allocatable :: event_tracked(:, :)
      integer :: stop = stop_none       !< the stop reason if the path ended with this step
      !> a new converged step was taken (.false. at a bearing collapse: its event is at the last step)
      logical :: advanced = .true.
   end type step_outcome_t

contains

   !> Start a path at the model's unloaded state (path_initialize: equations, first tangent, first
   !> step length) with the stop rules of `model%analysis`.
   !> Errors: those of path_initialize (error_analysis); a stop track that is not one of the model's
   !> tracks (error_input).
   subroutine driver_start(model, driver, error)
      type(model_t), intent(in) :: model
      type(path_driver_t), intent(out) :: driver
      type(error_t), allocatable, intent(out) :: error
      integer :: n_tracks
      driver%rules%lambda_max = model%analysis%lambda_max
      driver%rules%track = model%analysis%stop_track
      driver%rules%track_limit = model%analysis%stop_value
      driver%rules%max_steps = model%analysis%max_steps
      n_tracks = 0
      if (allocated(model%tracks)) n_tracks = size(model%tracks)
      if (driver%rules%track < 0 .or. driver%rules%track > n_tracks) then
         call make_error(error, 'the stop track '//integer_to_string(driver%rules%track)//' is not one of the '// &
                         integer_to_string(n_tracks)//' tracks of the model', error_input)
         return
      end if
      call path_initialize(model, driver%state, driver%trace, error)
      if (allocated(error)) return
      call nodal_displacements(model, driver%state, driver%displacement, error)
      if (allocated(error)) return
      call add_prescribed(model, driver%state%lambda, driver%displacement)
      driver%tracked = tracked_values(model, driver%displacement)
      call pace_start(driver%pace, driver%state%lambda, driver%rules%max_steps, driver%state%first_length, &
                      model%analysis%max_increment*driver%state%first_length)
      driver%stop = stop_none
      driver%started = .true.
   end subroutine driver_start

   !> Go on to the next analysis step (docs/theory.md §2.5) from the committed state of a path that
   !> ended by a stop rule: `model` is the new step's (uniarc_model_steps), whose stop rules replace
   !> the driver's; the state keeps its displacements, contacts and step number (path_restart), λ
   !> starts at 0, and max_steps counts the steps from here.
   !> Errors: path_restart's (error_analysis); a driver not started or whose path failed
   !> (error_internal); a stop track that is not one of the model's tracks (error_input).
   subroutine driver_next_analysis_step(model, driver, error)
      type(model_t), intent(in) :: model
      type(path_driver_t), intent(inout) :: driver
      type(error_t), allocatable, intent(out) :: error
      if (.not. driver%started .or. driver%stop == stop_failure) then
         call make_error(error, 'driver_next_analysis_step: no converged path to go on from', error_internal)
         return
      end if
      driver%rules%lambda_max = model%analysis%lambda_max
      driver%rules%track = model%analysis%stop_track
      driver%rules%track_limit = model%analysis%stop_value
      driver%rules%max_steps = model%analysis%max_steps
      if (driver%rules%track < 0 .or. driver%rules%track > size(driver%tracked)) then
         call make_error(error, 'the stop track '//integer_to_string(driver%rules%track)//' is not one of the '// &
                         integer_to_string(size(driver%tracked))//' tracks of the model', error_input)
         return
      end if
      if (any(model%fixed .neqv. driver%state%map%equation == 0)) then
         call renumber_supports(model, driver, error)
         if (allocated(error)) then
            driver%stop = stop_failure
            return
         end if
      end if
      call path_restart(model, driver%state, driver%trace, error)
      if (allocated(error)) then
         driver%stop = stop_failure
         return
      end if
      call nodal_displacements(model, driver%state, driver%displacement, error)
      if (allocated(error)) then
         driver%stop = stop_failure
         return
      end if
      call add_prescribed(model, driver%state%lambda, driver%displacement)
      driver%tracked = tracked_values(model, driver%displacement)
      driver%step_offset = driver%state%point%step
      call pace_start(driver%pace, driver%state%lambda, driver%rules%max_steps, driver%state%first_length, &
                      model%analysis%max_increment*driver%state%first_length)
      driver%stop = stop_none
   end subroutine driver_next_analysis_step

   !> Take one converged step (path_advance) and check the stop rules at the new point.
   !> On success the committed state, `displacement` and `tracked` are those of the new step and
   !> `driver%stop` (= `outcome%stop`) says whether the path has ended. If the step cannot be made
   !> converge, `error` is path_advance's (error_analysis: which step, from which λ, why), the committed
   !> state is the last converged one and `driver%stop` = stop_failure.
   !> Errors (error_internal): a driver not started, or whose path has already ended.
   subroutine driver_step(model, driver, outcome, error)
      type(model_t), intent(in) :: model
      type(path_driver_t), intent(inout) :: driver
      type(step_outcome_t), intent(out) :: outcome
      type(error_t), allocatable, intent(out) :: error
      type(path_point_t) :: previous
      real(dp), allocatable :: tracked_before(:), nodal_event(:, :)
      character(len=:), allocatable :: finding, nodes
      type(path_state_t), allocatable :: before
      real(dp) :: upper
      integer :: k, points, status, revisited
      logical :: collapsed, near_collapse, short, advanced, past_event
      real(dp), allocatable :: u_before(:)
      type(error_t), allocatable :: memory_error
      if (.not. driver%started) then
         call make_error(error, 'driver_step: the path was not started (driver_start)', error_internal)
         return
      end if
      if (driver%stop /= stop_none) then
         call make_error(error, 'driver_step: the path has ended at step '// &
                         integer_to_string(driver%state%point%step), error_internal)
         return
      end if
      ! the point before the step, copied with stat= (an assignment of the record is not checked)
      call copy_point_record(driver%state%point, previous, 'the point before the step', error)
      if (allocated(error)) then
         driver%stop = stop_failure
         outcome%stop = stop_failure
         return
      end if
      tracked_before = driver%tracked
      outcome%step = previous%step
      outcome%lambda = driver%state%lambda
      ! A committed state that the certificate (every point of the set counted as yielding, its slack
      ! in the bound: the upper-bound theorem) finds within the bracket of a bearing collapse: the
      ! collapse load is at most `upper` (docs/theory.md §3.9, "The step past the collapse"), so a step
      ! that converges above it has left the collapse (a large rotation of the mechanism) and is not
      ! taken; the state is kept to restore it (a copy made only near a collapse, component by component
      ! with stat=, copy_state; restored by moving it back, not copying).
      near_collapse = .false.
      if (allocated(driver%state%yielding) .and. allocated(driver%state%floating_motion) .and. &
          allocated(driver%state%active)) then
         if (any(driver%state%yielding .and. driver%state%active)) &
            call bearing_collapse(model, driver%state, .false., near_collapse, upper, points, nodes, error, &
                                  bound_only=.true.)
         if (allocated(error)) then
            driver%stop = stop_failure
            outcome%stop = stop_failure
            return
         end if
      end if
      if (near_collapse) then
         allocate (before, stat=status)
         call allocation_failure(status, 'the state before a step near a bearing collapse', 0.0_dp, error_analysis, &
                                 error)
         if (.not. allocated(error)) &
            call copy_state(driver%state, before, 'the state before a step near a bearing collapse', error)
         if (allocated(error)) then
            driver%stop = stop_failure
            outcome%stop = stop_failure
            return
         end if
      end if
      ! the displacements before the step: a structure whose working set lets go of it in the step is
      ! brought to rest on its contacts from there (rest_after_step)
      allocate (u_before(size(driver%state%u)), stat=status)
      call allocation_failure(status, 'the displacements before the step', 8.0_dp*size(driver%state%u), &
                              error_analysis, error)
      if (allocated(error)) then
         driver%stop = stop_failure
         outcome%stop = stop_failure
         return
      end if
      u_before(:) = driver%state%u
      call path_advance(model, driver%state, driver%trace, error, outcome%cuts)
      advanced = .not. allocated(error)
      ! A SIGINT or SIGTERM during the step (its critical-point search included): the step is
      ! abandoned, not returned as converged, and no collapse or plateau is sought after it; the caller
      ! ends the path at the step before (docs/contracts.md, "Interrupts").
      if (interrupt_signal() /= 0) then
         if (.not. allocated(error)) call make_error(error, 'step '//integer_to_string(previous%step + 1)// &
                                                     ' abandoned: interrupted by a signal', error_analysis)
         driver%stop = stop_failure
         outcome%stop = stop_failure
         return
      end if
      if (near_collapse .and. .not. allocated(error)) then
         ! (beyond the bound by more than the reactions' error: 100 times Newton's force tolerance,
         ! which the equilibrium on either side of the step meets)
         if (driver%state%lambda > upper + 100.0_dp*model%analysis%force_tolerance*abs(upper)) then
            ! (the step converged beyond the upper bound: the committed state is the collapse)
            ! (the trace keeps the step taken back: the path, or the analysis step, ends here, and
            ! path_restart forgets the kept states)
            call move_state(before, driver%state)
            driver%collapse_upper = upper
            driver%collapse_points = points
            driver%collapse_nodes = nodes
            call end_at_collapse(driver, previous, outcome)
            return
         end if
      end if
      if (allocated(error)) then
         ! A step that fails from a state at a bearing collapse (docs/theory.md §3.9, "Collapse"): the
         ! committed state is the collapse, a result and the end of the path (or of the analysis step).
         if (.not. error%out_of_memory) then
            call bearing_collapse(model, driver%state, .false., collapsed, driver%collapse_upper, &
                                  driver%collapse_points, driver%collapse_nodes, memory_error, finding, &
                                  joints=driver%collapse_joints)
            ! (an array of the certificate refused: the run ends out of memory, not as the failed step)
            if (allocated(memory_error)) call move_alloc(memory_error, error)
            ! No collapse, but perhaps a plateau: the yielded supports let the structure sink at constant
            ! load until an open contact closes (docs/theory.md §3.9, "Plateaus"); the step is then
            ! that motion, and the path goes on from the contact it closed (error deallocated).
            short = error%out_of_memory
            if (.not. collapsed .and. .not. short) call follow_plateau(model, driver, error, outcome%cuts)
            if (allocated(error)) short = error%out_of_memory
            if (short) collapsed = .false.
            if (allocated(error) .and. .not. collapsed .and. .not. short .and. allocated(driver%state%yielding) .and. &
                allocated(driver%state%active)) then
               ! Points at their bearing limit, but neither a certified collapse nor a plateau: say what
               ! the certificate found, and what the user can do, without claiming a collapse
               ! (docs/contracts.md, exit 1).
               if (any(driver%state%yielding .and. driver%state%active)) &
                  error%message = error%message//'; not certified a bearing collapse (docs/theory.md '// &
                                  '§3.9): '//finding//'; nor is the motion that failed a plateau at constant '// &
                                  'load that ends on an open contact (it may be a limit point of the path); the '// &
                                  'last converged state is statically admissible, so the collapse load is at '// &
                                  'least lambda = '//real_to_string(driver%state%lambda, '(es12.5)')// &
                                  '; try another CONTROL=, a smaller increment or a finer mesh'
            end if
            if (collapsed) then
               deallocate (error)
               call end_at_collapse(driver, previous, outcome)
               return
            end if
         end if
         if (allocated(error)) then
            driver%stop = stop_failure
            outcome%stop = stop_failure
            return
         end if
      end if
      if (advanced .and. .not. driver%state%point%switched) then
         call rest_after_step(model, driver%state, u_before, driver%state%lambda - outcome%lambda, error)
         if (allocated(error)) then
            driver%stop = stop_failure
            outcome%stop = stop_failure
            return
         end if
      end if
      call nodal_displacements(model, driver%state, driver%displacement, error)
      if (allocated(error)) then
         driver%stop = stop_failure
         outcome%stop = stop_failure
         return
      end if
      call add_prescribed(model, driver%state%lambda, driver%displacement)
      driver%tracked = tracked_values(model, driver%displacement)
      outcome%step = driver%state%point%step
      outcome%lambda = driver%state%lambda
      outcome%iterations = driver%state%point%iterations
      call pace_record(driver%pace, driver%state%lambda, driver%state%taken_length)
      if (driver%state%point%switched) then
         ! The first point of a secondary branch (*PATH, SWITCH=n): the interval joins two branches,
         ! and its one event is the switch, from the bifurcation's state (λ there) at its start.
         outcome%events = [critical_event_t('branch_switch', driver%state%bifurcation%position, &
                                            driver%state%point%switch_lambda, 0.0_dp)]
      else
         call find_critical_events(previous, driver%state%point, outcome%events)
         call find_contact_events(previous, driver%state%point, outcome%events)
         call find_contact_branching(previous, driver%state%point, outcome%events)
         ! STEM.crit rows in path order (a limit found before a contact event may lie after it)
         call sort_events(outcome%events)
      end if
      allocate (outcome%event_tracked(size(driver%tracked), size(outcome%events)))
      do k = 1, size(outcome%events)
         outcome%event_tracked(:, k) = tracked_before + outcome%events(k)%fraction*(driver%tracked - tracked_before)
      end do
      ! A contact start located by re-solving the step (uniarc_path_contact_start): its tracked values
      ! are those of the state there, not interpolated between the two steps.
      if (.not. driver%state%point%switched .and. driver%state%point%contact_start_fraction >= 0.0_dp .and. &
          allocated(driver%state%contact_start_u)) then
         do k = 1, size(outcome%events)
            ! (and a corner placed at that start, uniarc_critical_points)
            if (.not. (outcome%events(k)%kind == 'contact_start' .or. (outcome%events(k)%kind == &
                       'contact_corner' .and. outcome%events(k)%fraction == &
                       driver%state%point%contact_start_fraction))) cycle
            if (.not. allocated(nodal_event)) then
               allocate (nodal_event(size(driver%displacement, 1), size(driver%displacement, 2)), stat=status)
               call allocation_failure(status, 'the nodal displacements at the contact start', &
                                       8.0_dp*size(driver%displacement), error_analysis, error)
               if (allocated(error)) then
                  driver%stop = stop_failure
                  outcome%stop = stop_failure
                  return
               end if
            end if
            call gather_nodal(driver%state%map, driver%state%contact_start_u, nodal_event)
            call add_prescribed(model, driver%state%point%contact_start_lambda, nodal_event)
            outcome%event_tracked(:, k) = tracked_values(model, nodal_event)
         end do
      end if
      if (driver%state%point%switched) then
         ! The switch's tracked values: those of the state at the bifurcation it left from.
         allocate (nodal_event(size(driver%displacement, 1), size(driver%displacement, 2)), stat=status)
         call allocation_failure(status, 'the nodal displacements of the branch switch''s tracked values', &
                                 8.0_dp*size(driver%displacement), error_analysis, error)
         if (allocated(error)) then
            driver%stop = stop_failure
            outcome%stop = stop_failure
            return
         end if
         call gather_nodal(driver%state%map, driver%state%bifurcation%u, nodal_event)
         call add_prescribed(model, driver%state%point%switch_lambda, nodal_event)
         outcome%event_tracked(:, 1) = tracked_values(model, nodal_event)
      end if
      driver%stop = stop_reason(driver%rules, outcome%step - driver%step_offset, outcome%lambda, driver%tracked)
      ! A step through the state where its branch began: the path has closed on itself and would go round
      ! the same loop again (a secondary branch that is a closed curve through its bifurcation).
      if (.not. driver%state%point%switched) then
         call trace_closed_loop(driver%trace, driver%state%map, driver%state%lambda_scale, driver%loop_origin_step, &
                                driver%loop_origin_lambda)
         if (driver%loop_origin_step >= 0 .and. driver%stop == stop_none) driver%stop = stop_closed_loop
         ! A step past a critical point or a corner that ends on the state of an earlier one: the
         ! path came round to a state it passed (by a loop that does not go through its branch's
         ! origin, or one that a jump closed) and, taking the same steps again, would go round it
         ! for ever (the circular liner in its host at eps = 1e-5: limit_min 17.8833 every 19 steps
         ! until max_steps; docs/theory.md §2.3, "closed loops").
         past_event = .false.
         do k = 1, size(outcome%events)
            select case (outcome%events(k)%kind)
            case ('limit_max', 'limit_min', 'contact_corner', 'bifurcation')
               past_event = .true.
            end select
         end do
         if (driver%stop == stop_none .and. past_event) then
            revisited = trace_event_revisited(driver%trace, driver%state%u, driver%state%lambda)
            if (revisited > 0) then
               driver%stop = stop_closed_loop
               driver%loop_origin_step = revisited
               driver%loop_origin_lambda = driver%state%lambda
               driver%loop_repeated = .true.
            else
               call trace_remember_event(driver%trace, driver%state%u, driver%state%lambda, driver%state%point%step)
            end if
         end if
      end if
      ! A commit that switched tangential springs off is followed by its release step (Δλ = 0) before
      ! the path stops at a load or track limit: the last row is in equilibrium without their forces
      ! (docs/theory.md §3.8).
      if (driver%state%release_due .and. driver%stop /= stop_step_limit) driver%stop = stop_none
      ! A converged state at a bearing collapse (every motion the load drives held only by media at their
      ! limits, docs/theory.md §3.9): the path ends there, whatever else it reached.
      if (allocated(driver%state%yielding) .and. allocated(driver%state%floating_motion)) then
         call bearing_collapse(model, driver%state, .true., collapsed, driver%collapse_upper, &
                               driver%collapse_points, driver%collapse_nodes, error, joints=driver%collapse_joints)
         if (allocated(error)) then
            driver%stop = stop_failure
            outcome%stop = stop_failure
            return
         end if
         if (collapsed) then
            driver%stop = stop_collapse
            outcome%events = [outcome%events, critical_event_t('bearing_collapse', real(outcome%step, dp), &
                                                               outcome%lambda, 1.0_dp)]
            outcome%event_tracked = reshape([outcome%event_tracked, driver%tracked], &
                                            [size(driver%tracked), size(outcome%events)])
         end if
      end if
      outcome%stop = driver%stop
   end subroutine driver_step

   !> The plateau step (docs/theory.md §3.9, "Plateaus"): from the committed state, from which the
   !> step failed with its supports at their limits, the rigid mechanism of the yielded supports that
   !> the load drives and that closes an open contact (uniarc_path_collapse, plastic_plateau) moves the
   !> structure at constant load to that contact, the yielded supports flowing; a load step of the
   !> limits' slack (Δλ ≥ 0, at most 1e-3 of λ) from there restores equilibrium, and is the step taken;
   !> the contacts that touch already without being in the working set, and that the motion keeps
   !> touching, start that step in the set with the contact that closes (alone, a touching one would
   !> leave the turn about it free). Without a plateau, contacts that touch out of the set start the
   !> normal step again in the set (a step of the load then presses them: docs/theory.md §3.9,
   !> "Plateau of no length"). A plateau of no length (the motion within round-off, 1e-12, of the
   !> displacements: no progress) is not taken: no row would differ from the last.
   !> On success `error` is deallocated and the committed state is the step's end (a converged step,
   !> `cuts` its cut-backs); otherwise (no plateau, or its step does not converge) the committed state
   !> is restored and `error` (the failed step's) is kept, with a note when a plateau was tried; an
   !> array of plastic_plateau refused by the system replaces it (out of memory: the run ends).
   subroutine follow_plateau(model, driver, error, cuts)
      type(model_t), intent(in) :: model
      type(path_driver_t), intent(inout) :: driver
      type(error_t), allocatable, intent(inout) :: error
      integer, intent(inout) :: cuts
      type(error_t), allocatable :: plateau_error
      real(dp), allocatable :: motion(:), saved(:)
      logical, allocatable :: touching(:), saved_active(:)
      real(dp) :: dlambda
      integer :: contact, status, n, plateau_cuts
      logical :: found
      n = size(driver%state%u)
      allocate (motion(n), saved(n), touching(size(driver%state%active)), &
                saved_active(size(driver%state%active)), stat=status)
      if (status /= 0) return   ! no plateau tried: the failed step's error stands
      call plastic_plateau(model, driver%state, found, motion, dlambda, contact, touching, plateau_error)
      if (allocated(plateau_error)) then
         ! an array of the plateau refused: the run ends out of memory (not as the failed step)
         call move_alloc(plateau_error, error)
         return
      end if
      if (found) then
         if (.not. sqrt(sum(driver%state%map%metric*motion**2)) > &
             1.0e-12_dp*sqrt(sum(driver%state%map%metric*driver%state%u**2))) then
            error%message = error%message//'; the plateau at constant load to the contact of node '// &
                            integer_to_string(model%node_label(model%contacts(contact)%node))// &
                            ' has no length (it touches already): no progress'
            return
         end if
      end if
      saved(:) = driver%state%u
      saved_active(:) = driver%state%active
      if (.not. found) then
         if (.not. any(touching)) return
         ! The committed state with the touching contacts in its set: its tangent is that set's (the
         ! step's predictor and distance test then follow K_S⁻¹R of the set it starts with)
         touching(:) = driver%state%active .or. touching
         call path_change_working_set(model, driver%state, touching, plateau_error)
         if (.not. allocated(plateau_error)) &
            call path_advance(model, driver%state, driver%trace, plateau_error, plateau_cuts)
         if (allocated(plateau_error)) then
            if (plateau_error%out_of_memory) then
               call move_alloc(plateau_error, error)
               return
            end if
            error%message = error%message//'; nor with the contacts that touch out of the working set in it'
            ! the committed state with its own set again, and that set's tangent
            call path_change_working_set(model, driver%state, saved_active, plateau_error)
            if (allocated(plateau_error)) call move_alloc(plateau_error, error)
            return
         end if
         cuts = cuts + plateau_cuts
         deallocate (error)
         return
      end if
      driver%state%u(:) = driver%state%u + motion
      driver%state%active(:) = driver%state%active .or. touching
      driver%state%plateau_due = .true.
      driver%state%plateau_dlambda = dlambda
      if (allocated(driver%state%system)) then
         driver%state%system%holds_committed = .false.
         driver%state%system%holds_converged = .false.
      end if
      call path_advance(model, driver%state, driver%trace, plateau_error, plateau_cuts)
      driver%state%plateau_due = .false.
      driver%state%plateau_dlambda = 0.0_dp
      if (allocated(plateau_error)) then
         driver%state%u(:) = saved
         driver%state%active(:) = saved_active
         if (allocated(driver%state%system)) then
            driver%state%system%holds_committed = .false.
            driver%state%system%holds_converged = .false.
         end if
         error%message = error%message//'; the plateau at constant load to the contact of node '// &
                         integer_to_string(model%node_label(model%contacts(contact)%node))// &
                         ' did not converge either ('//plateau_error%message//')'
         return
      end if
      cuts = cuts + plateau_cuts
      deallocate (error)
   end subroutine follow_plateau

   !> A step whose working set let go of a structure held only by its contacts (docs/theory.md §2.8,
   !> "A working set that lets go"): the committed state is replaced by the same state at rest on the
   !> contacts the load pushed it against (uniarc_path_rest, rest_on_contacts), with the contacts that
   !> touch there in its working set (path_change_working_set: its tangent and point record are those
   !> of the state at rest). `before` (n_equations): the displacements before the step; `dlambda` its Δλ.
   !> Untouched when there is nothing to rest (the set holds the structure, or no load pushed it).
   !> Errors: rest_on_contacts' and path_change_working_set's (the state is then restored).
   subroutine rest_after_step(model, state, before, dlambda, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      real(dp), intent(in) :: before(:), dlambda
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: x(:), converged(:)
      logical, allocatable :: active(:), old_active(:)
      type(error_t), allocatable :: restore_error
      logical :: rested
      integer :: status
      call rest_on_contacts(model, state, before, dlambda, x, active, rested, error)
      if (allocated(error) .or. .not. rested) return
      allocate (converged(size(state%u)), old_active(size(state%active)), stat=status)
      call allocation_failure(status, 'the converged state before its rest on the contacts', &
                              8.0_dp*size(state%u) + 4.0_dp*size(state%active), error_analysis, error)
      if (allocated(error)) return
      converged(:) = state%u
      old_active(:) = state%active
      state%u(:) = x
      call path_change_working_set(model, state, active, error)
      if (allocated(error)) then
         ! back to the converged state as it was (its set and tangent)
         state%u(:) = converged
         call path_change_working_set(model, state, old_active, restore_error)
      end if
   end subroutine rest_after_step

   !> The committed state in the equations of `model`, whose supports differ from those it was numbered
   !> for (an analysis step that adds or removes supports, docs/theory.md §2.10): a new equation
   !> numbering; the unknowns of the free DOFs from the displacements at the committed state
   !> (`driver%displacement`, every DOF's, so that a released DOF starts where its support held it),
   !> the candidates' reactions carried over; the band matrices for the new numbering (path_restart
   !> assembles them), the warm starts of the eigenvalue iterations and a located bifurcation dropped.
   !> Errors (error_analysis): a structure held only by its contacts (its floating motions were found
   !> for the first supports, docs/theory.md §2.8); a band matrix that does not fit (error_input).
   subroutine renumber_supports(model, driver, error)
      type(model_t), intent(in) :: model
      type(path_driver_t), intent(inout) :: driver
      type(error_t), allocatable, intent(out) :: error
      type(dof_map_t) :: map
      real(dp), allocatable :: x(:), last_increment(:), fixed_load(:)
      integer :: i, k, c, n, status
      associate (state => driver%state)
         if (allocated(state%floating_equation)) then
            call make_error(error, 'supports changed between analysis steps of a structure held only by its '// &
                            'contacts (a rigid motion that only the contacts hold): not supported', error_analysis)
            return
         end if
         call build_dof_map(model, map, error, error_analysis)
         if (allocated(error)) return
         n = map%n_equations
         allocate (x(n), last_increment(n), fixed_load(n), stat=status)
         call allocation_failure(status, 'the vectors of the new numbering', 24.0_dp*n, error_analysis, error)
         if (allocated(error)) return
         x = 0.0_dp
         do i = 1, model%n_nodes
            do k = 1, size(map%equation, 1)
               if (map%equation(k, i) > 0) x(map%equation(k, i)) = driver%displacement(k, i)
            end do
         end do
         do c = 1, size(map%candidate_equation)
            if (map%candidate_equation(c) > 0 .and. state%map%candidate_equation(c) > 0) &
               x(map%candidate_equation(c)) = state%u(state%map%candidate_equation(c))
         end do
         call move_alloc(x, state%u)
         call move_map(map, state%map)
         last_increment = 0.0_dp
         fixed_load = 0.0_dp
         call move_alloc(last_increment, state%last_increment)
         call move_alloc(fixed_load, state%fixed_load)
         if (allocated(state%eigenvector)) deallocate (state%eigenvector)
         if (allocated(state%liftoff_mode)) deallocate (state%liftoff_mode)
         if (allocated(state%bifurcation)) deallocate (state%bifurcation)
         state%switch_due = .false.
         call band_allocate(state%system%tangent, n, map%half_bandwidth, map%half_bandwidth, error)
         if (allocated(error)) return
         call band_allocate(state%system%assembled, n, map%half_bandwidth, map%half_bandwidth, error)
         if (allocated(error)) return
         state%system%holds_committed = .false.
         state%system%holds_converged = .false.
      end associate
   end subroutine renumber_supports

   !> nodal (dofs_per_node, n_nodes) += the prescribed displacements of the held DOFs at λ (support
   !> settlements; uniarc_model_steps prescribed_at): the displacements of every DOF, for the tracks
   !> and the result files. Untouched when the model prescribes none.
   pure subroutine add_prescribed(model, lambda, nodal)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: lambda
      real(dp), intent(inout) :: nodal(:, :)
      real(dp) :: total
      integer :: node, k, j
      if (.not. has_prescribed(model)) return
      ! nodal + prescribed_at(model, lambda), entry by entry in its order: no function result
      do node = 1, size(nodal, 2)
         do k = 1, size(nodal, 1)
            total = 0.0_dp
            if (allocated(model%prescribed)) total = lambda*model%prescribed(k, node)
            if (allocated(model%held)) then
               do j = 1, size(model%held)
                  if (allocated(model%held(j)%prescribed)) &
                     total = total + model%held(j)%factor*model%held(j)%prescribed(k, node)
               end do
            end if
            nodal(k, node) = nodal(k, node) + total
         end do
      end do
   end subroutine add_prescribed

   !> The first stop rule that holds at a converged point (step, λ, tracked values), or stop_none.
   pure integer function stop_reason(rules, step, lambda, tracked) result(reason)
      type(stop_rules_t), intent(in) :: rules
      integer, intent(in) :: step
      real(dp), intent(in) :: lambda, tracked(:)
      reason = stop_none
      ! A step landed on a limit (docs/theory.md §2.11) reaches it to the round-off of λ + Δλ (or of
      ! u + Δu): within 1e-12 of it, far below any tolerance of a step, it counts as reached — not a
      ! further step of Δλ ≈ 1e-13 that would repeat the row at the same λ.
      if (abs(lambda) >= rules%lambda_max*(1.0_dp - 1.0e-12_dp)) then
         reason = stop_load_limit
      else if (rules%track > 0) then
         if (abs(tracked(rules%track)) >= rules%track_limit*(1.0_dp - 1.0e-12_dp)) reason = stop_track_limit
      end if
      if (reason == stop_none .and. step >= rules%max_steps) reason = stop_step_limit
   end function stop_reason

   !> The path (or the analysis step) ends at its committed state, a certified bearing collapse
   !> (docs/theory.md §3.9): the step's outcome is the `bearing_collapse` row at the step `previous`
   !> ended, with the tracked values of that state, and no advance.
   subroutine end_at_collapse(driver, previous, outcome)
      type(path_driver_t), intent(inout) :: driver
      type(path_point_t), intent(in) :: previous
      type(step_outcome_t), intent(inout) :: outcome
      driver%stop = stop_collapse
      outcome%stop = stop_collapse
      outcome%advanced = .false.
      outcome%iterations = 0
      outcome%events = [critical_event_t('bearing_collapse', real(previous%step, dp), driver%state%lambda, 0.0_dp)]
      outcome%event_tracked = reshape(driver%tracked, [size(driver%tracked), 1])
   end subroutine end_at_collapse

end module uniarc_path_driver
