!> Benchmarks of the nonlinear analysis (docs/benchmarks.md has the tables and what they show).
!>
!>   bench_path [ROOT [LARGEST_N]]      ROOT: the repository (default .), LARGEST_N: default 100000
!>
!> 1. Walker's arch (input/walker_arch.inp, 20 elements on the half arch) traced to its stop: steps,
!>    Newton iterations, wall time of the analysis.
!> 2. Scaling: a ring of n = 1e2 … LARGEST_N elements (bench/bench_ring.inp) traced to its stop, then
!>    one Newton iteration taken apart (assembly, band LU, solve) and the per-step extras (inertia).
!>    The cost of an iteration should be O(n·b²) with a half-bandwidth b that does not grow with n.
!> 3. Round-off floor: the smallest force residual Newton reaches on a ring of fixed radius
!>    (bench/bench_pinched_ring.inp) as its elements get shorter.
!>
!> Why a program and not a script over whole runs: it calls the library (read_deck with -D overrides,
!> the path driver of uniarc_path_driver, which the program uses too: same steps, stop rules and
!> critical points) so that the analysis is timed apart from reading the deck and writing the result
!> files, and it can time the parts of one iteration, which a whole run cannot show. The time of a
!> step is that of driver_step: path_advance and the driver's O(n) bookkeeping after it (nodal
!> displacements, tracked values, critical points).
!> Times are wall-clock (system_clock); a run is repeated and the fastest kept, because the machine is
!> shared and other loads only ever add time.
program bench_path
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit, int64
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t
   use uniarc_foreign, only: exit_program
   use uniarc_model, only: model_t, dofs_per_node
   use uniarc_deck, only: parameter_override_t, read_deck
   use uniarc_path_following, only: path_state_t, path_trace_t, path_initialize
   use uniarc_path_driver, only: path_driver_t, step_outcome_t, driver_start, driver_step, stop_none, &
                                 stop_load_limit, stop_track_limit, stop_step_limit
   use uniarc_band, only: band_matrix_t, band_factorize, band_solve, band_inertia
   use uniarc_equilibrium, only: assemble_equilibrium
   use uniarc_assembly, only: gather_nodal
   implicit none

   !> What one traced path cost.
   type :: path_run_t
      integer :: steps = 0
      integer :: iterations = 0           !< Newton iterations of the converged attempts
      integer :: cuts = 0                 !< step halvings (their iterations are not in `iterations`)
      real(dp) :: seconds = 0.0_dp        !< driver_start + every driver_step
      real(dp) :: lambda = 0.0_dp         !< at the last step
      real(dp) :: limit_lambda = 0.0_dp   !< first limit point (Hermite interpolation)
      logical :: has_limit = .false.
      character(len=:), allocatable :: stop_reason
   end type path_run_t

   !> Seconds per call of the parts of a Newton iteration at one state.
   type :: iteration_parts_t
      real(dp) :: assembly = 0.0_dp       !< K_T, F and R of all elements, scattered into the band
      real(dp) :: factorization = 0.0_dp  !< dgbtrf
      real(dp) :: solve = 0.0_dp          !< dgbtrs with the two right-hand sides of an iteration
      real(dp) :: inertia = 0.0_dp        !< negative pivots, once per converged step
      real(dp) :: eigenvalue = 0.0_dp     !< 30 one-rhs solves of the inverse iteration, once per step
   end type iteration_parts_t

   character(len=:), allocatable :: root
   integer :: largest_n

   call read_arguments(root, largest_n)
   call bench_walker(root//'/input/walker_arch.inp')
   call bench_scaling(root//'/bench/bench_ring.inp', largest_n)
   call bench_round_off(root//'/bench/bench_pinched_ring.inp', largest_n)

contains

   !> ROOT (default .) and LARGEST_N (default 1e5, at least 1e2) from the command line.
   subroutine read_arguments(root, largest_n)
      character(len=:), allocatable, intent(out) :: root
      integer, intent(out) :: largest_n
      character(len=4096) :: buffer
      integer :: status
      root = '.'
      largest_n = 100000
      if (command_argument_count() >= 1) then
         call get_command_argument(1, buffer)
         root = trim(buffer)
      end if
      if (command_argument_count() >= 2) then
         call get_command_argument(2, buffer)
         read (buffer, *, iostat=status) largest_n
         if (status /= 0 .or. largest_n < 100) then
            write (error_unit, '(a)') 'error: LARGEST_N must be a whole number >= 100, found '//trim(buffer)
            call exit_program(2)
         end if
      end if
   end subroutine read_arguments

   ! ================================================================================================
   ! 1. Walker's arch
   ! ================================================================================================

   !> Table 1: Walker's arch traced to its stop, the fastest of 20 runs.
   subroutine bench_walker(deck)
      character(len=*), intent(in) :: deck
      type(model_t) :: model
      type(path_run_t) :: run
      real(dp) :: read_seconds
      integer, parameter :: repeats = 20
      call load_model(deck, [override('n', '20')], model, read_seconds)
      call trace_fastest(model, repeats, run)
      write (output_unit, '(a)') '## Walker''s arch: input/walker_arch.inp, -D n=20 (20 elements on the half arch)'
      write (output_unit, '(a)') ''
      write (output_unit, '(a)') '| elements | equations | steps | iterations | cuts | lambda_end | K_lim | analysis s | s/iteration | stop |'
      write (output_unit, '(a)') '|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|'
      write (output_unit, '(a,i0,a,i0,a,i0,a,i0,a,i0,a,f0.2,a,f0.3,a,es9.2,a,es9.2,a,a,a)') &
         '| ', model%n_elements, ' | ', equations_of(model), ' | ', run%steps, ' | ', run%iterations, ' | ', &
         run%cuts, ' | ', run%lambda, ' | ', run%limit_lambda, ' | ', run%seconds, ' | ', &
         run%seconds/max(run%iterations, 1), ' | ', run%stop_reason, ' |'
      write (output_unit, '(a,es9.2,a,i0,a)') '(deck read ', read_seconds, ' s; fastest of ', repeats, ' runs)'
      write (output_unit, '(a)') ''
   end subroutine bench_walker

   ! ================================================================================================
   ! 2. Cost per Newton iteration against the number of elements
   ! ================================================================================================

   !> Tables 2: the ring of n = 1e2, 1e3 … largest_n elements traced to its stop, then one iteration
   !> taken apart.
   subroutine bench_scaling(deck, largest_n)
      character(len=*), intent(in) :: deck
      integer, intent(in) :: largest_n
      type(model_t) :: model
      type(path_run_t) :: run
      type(path_state_t) :: state
      type(iteration_parts_t) :: parts
      real(dp) :: read_seconds, per_iteration
      real(dp), allocatable :: read_times(:), part_rows(:, :)
      integer, allocatable :: sizes(:), bandwidths(:)
      integer :: n, k, j
      character(len=16) :: text
      sizes = [integer ::]
      n = 100
      do
         sizes = [sizes, n]
         if (n > largest_n/10) exit
         n = 10*n
      end do
      allocate (read_times(size(sizes)), part_rows(5, size(sizes)), bandwidths(size(sizes)))
      write (output_unit, '(a)') '## Scaling: bench/bench_ring.inp, ring of n elements on supports every 10'
      write (output_unit, '(a)') ''
      write (output_unit, '(a)') '| n | equations | half-bandwidth | steps | iterations | cuts | analysis s | s/iteration | s/iteration/element |'
      write (output_unit, '(a)') '|---:|---:|---:|---:|---:|---:|---:|---:|---:|'
      do k = 1, size(sizes)
         write (text, '(i0)') sizes(k)
         call load_model(deck, [override('n', trim(text))], model, read_seconds)
         read_times(k) = read_seconds
         call trace_fastest(model, max(3, min(20, 20000/sizes(k))), run, state)
         bandwidths(k) = state%map%half_bandwidth
         per_iteration = run%seconds/max(run%iterations, 1)
         write (output_unit, '(a,i0,a,i0,a,i0,a,i0,a,i0,a,i0,a,es9.2,a,es9.2,a,es9.2,a)') &
            '| ', sizes(k), ' | ', state%map%n_equations, ' | ', state%map%half_bandwidth, ' | ', run%steps, &
            ' | ', run%iterations, ' | ', run%cuts, ' | ', run%seconds, ' | ', per_iteration, ' | ', &
            per_iteration/sizes(k), ' |'
         flush (output_unit)
         call time_iteration_parts(model, state, max(5, 200000/sizes(k)), parts)
         part_rows(:, k) = [parts%assembly, parts%factorization, parts%solve, parts%inertia, parts%eigenvalue]
      end do
      write (output_unit, '(a)') ''
      write (output_unit, '(a)') 'One Newton iteration taken apart at the last converged state, seconds per call'
      write (output_unit, '(a)') '(and microseconds per element):'
      write (output_unit, '(a)') ''
      write (output_unit, '(a)') '| n | half-bandwidth | assembly | band LU (dgbtrf) | solve, 2 rhs (dgbtrs) '// &
         '| per step: inertia | per step: 30 solves, 1 rhs | deck read (not analysis) |'
      write (output_unit, '(a)') '|---:|---:|---:|---:|---:|---:|---:|---:|'
      do k = 1, size(sizes)
         write (output_unit, '(a,i0,a,i0,5(a,es9.2,a,f6.3,a),a,es9.2,a)') '| ', sizes(k), ' | ', bandwidths(k), &
            (' | ', part_rows(j, k), ' (', 1.0e6_dp*part_rows(j, k)/sizes(k), ')', j=1, 5), &
            ' | ', read_times(k), ' |'
      end do
      write (output_unit, '(a)') ''
   end subroutine bench_scaling

   !> Time the parts of one Newton iteration (as attempt_step of uniarc_path_newton does it) at the
   !> committed state of `state`, each the fastest of `repeats` calls.
   subroutine time_iteration_parts(model, state, repeats, parts)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      integer, intent(in) :: repeats
      type(iteration_parts_t), intent(out) :: parts
      type(band_matrix_t) :: assembled, factors
      real(dp), allocatable :: nodal(:, :), internal(:), reference(:), rhs(:, :), vector(:, :)
      type(error_t), allocatable :: error
      integer(int64) :: start
      real(dp) :: element_scale
      integer :: r, n, k, negative
      logical :: singular
      n = state%map%n_equations
      allocate (nodal(dofs_per_node, model%n_nodes), internal(n), reference(n), rhs(n, 2), vector(n, 1))
      call gather_nodal(state%map, state%u, nodal)
      assembled = state%system%tangent
      parts%assembly = huge(1.0_dp)
      parts%factorization = huge(1.0_dp)
      parts%solve = huge(1.0_dp)
      parts%inertia = huge(1.0_dp)
      parts%eigenvalue = huge(1.0_dp)
      do r = 1, repeats
         start = clock()
         call assemble_equilibrium(model, state%map, nodal, state%lambda, state%fixed_load, assembled, &
                                   internal, reference, element_scale, error)
         if (allocated(error)) call fail('assembly: '//error%message)
         parts%assembly = min(parts%assembly, seconds_since(start))
      end do
      do r = 1, repeats
         factors = assembled
         start = clock()
         call band_factorize(factors, error)
         parts%factorization = min(parts%factorization, seconds_since(start))
         if (allocated(error)) call fail('factorisation of the ring: '//error%message)
      end do
      do r = 1, repeats
         rhs(:, 1) = state%lambda*reference - internal
         rhs(:, 2) = reference
         start = clock()
         call band_solve(factors, rhs, error)
         parts%solve = min(parts%solve, seconds_since(start))
         if (allocated(error)) call fail('solve of the ring: '//error%message)
      end do
      do r = 1, repeats
         start = clock()
         call band_inertia(assembled, negative, singular)
         parts%inertia = min(parts%inertia, seconds_since(start))
      end do
      ! The inverse iteration of uniarc_path_stability (least_eigenvalue): 30 solves with one
      ! right-hand side and a normalisation each, after every converged step.
      do r = 1, max(1, repeats/10)
         vector(:, 1) = 1.0_dp/sqrt(real(n, dp))
         start = clock()
         do k = 1, 30
            call band_solve(factors, vector, error)
            vector = vector/norm2(vector)
         end do
         parts%eigenvalue = min(parts%eigenvalue, seconds_since(start))
         if (allocated(error)) call fail('inverse iteration on the ring: '//error%message)
      end do
   end subroutine time_iteration_parts

   ! ================================================================================================
   ! 3. Round-off floor of the force residual
   ! ================================================================================================

   !> Newton at fixed load λ = 0.3 (pinch about 2 % of R) from u = 0 on the pinched ring, 30
   !> iterations. Newton converges in about 5; after that ||g||/||λR|| wanders on a plateau, the
   !> round-off floor, reported as the median over iterations 11…30. The convergence test of
   !> uniarc_path_newton needs ||g|| <= tolerance × ||λR||, so where the floor exceeds the
   !> tolerance (default 1e-8) no step can converge, however small.
   subroutine bench_round_off(deck, largest_n)
      character(len=*), intent(in) :: deck
      integer, intent(in) :: largest_n
      real(dp), parameter :: lambda = 0.3_dp
      integer, parameter :: iterations = 30
      real(dp), parameter :: default_tolerance = 1.0e-8_dp
      real(dp), parameter :: radius = 100.0_dp   !< R of bench/bench_pinched_ring.inp
      type(model_t) :: model
      type(path_state_t) :: state
      type(path_trace_t) :: trace
      type(error_t), allocatable :: error
      real(dp), allocatable :: u(:), nodal(:, :), internal(:), reference(:), rhs(:, :)
      real(dp) :: read_seconds, ratios(0:iterations), plateau(iterations - 10), floor, slenderness, element_scale
      integer :: n, k
      character(len=16) :: text
      write (output_unit, '(a)') '## Round-off floor: bench/bench_pinched_ring.inp, ring of fixed R, load factor 0.3'
      write (output_unit, '(a)') ''
      write (output_unit, '(a)') '| n | R/L | floor of ||g||/||lambda R|| | floor / (eps (R/L)^3) | below 1e-8 |'
      write (output_unit, '(a)') '|---:|---:|---:|---:|---|'
      n = 100
      do
         write (text, '(i0)') n
         call load_model(deck, [override('n', trim(text))], model, read_seconds)
         call path_initialize(model, state, trace, error)
         if (allocated(error)) call fail('pinched ring: '//error%message)
         allocate (u(state%map%n_equations), source=0.0_dp)
         allocate (nodal(dofs_per_node, model%n_nodes), internal(size(u)), reference(size(u)), rhs(size(u), 1))
         do k = 0, iterations
            call gather_nodal(state%map, u, nodal)
            call assemble_equilibrium(model, state%map, nodal, lambda, state%fixed_load, state%system%tangent, &
                                      internal, reference, element_scale, error)
            if (allocated(error)) call fail('pinched ring: '//error%message)
            rhs(:, 1) = lambda*reference - internal
            ratios(k) = norm2(rhs(:, 1))/norm2(lambda*reference)
            call band_factorize(state%system%tangent, error)
            if (allocated(error)) call fail('pinched ring: '//error%message)
            call band_solve(state%system%tangent, rhs, error)
            if (allocated(error)) call fail('pinched ring: '//error%message)
            u = u + rhs(:, 1)
         end do
         plateau = ratios(11:iterations)
         floor = median(plateau)
         slenderness = radius/norm2(model%coordinates(:, model%connectivity(2, 1)) - &
                                    model%coordinates(:, model%connectivity(1, 1)))
         write (output_unit, '(a,i0,a,f0.1,a,es9.2,a,f0.1,a,a,a)') '| ', n, ' | ', slenderness, ' | ', floor, &
            ' | ', floor/(epsilon(1.0_dp)*slenderness**3), ' | ', merge('yes', 'no ', floor < default_tolerance), ' |'
         flush (output_unit)
         deallocate (u, nodal, internal, reference, rhs)
         if (n > largest_n/10) exit
         n = 10*n
      end do
      write (output_unit, '(a)') ''
   end subroutine bench_round_off

   ! ================================================================================================
   ! Shared pieces
   ! ================================================================================================

   !> Trace the model's path `repeats` times and keep the fastest; `state` is left at the last step.
   subroutine trace_fastest(model, repeats, run, state)
      type(model_t), intent(in) :: model
      integer, intent(in) :: repeats
      type(path_run_t), intent(out) :: run
      type(path_state_t), intent(out), optional :: state
      type(path_state_t) :: final
      type(path_run_t) :: attempt
      integer :: r
      do r = 1, repeats
         call trace_path(model, attempt, final)
         if (r == 1 .or. attempt%seconds < run%seconds) run = attempt
      end do
      if (present(state)) state = final
   end subroutine trace_fastest

   !> Trace the path of `model` to its stop with the path driver (its stop rules, cut-back count and
   !> critical points), timing only driver_start and driver_step.
   subroutine trace_path(model, run, state)
      type(model_t), intent(in) :: model
      type(path_run_t), intent(out) :: run
      type(path_state_t), intent(out) :: state
      type(error_t), allocatable :: error
      type(path_driver_t) :: driver
      type(step_outcome_t) :: outcome
      integer(int64) :: start
      integer :: k
      start = clock()
      call driver_start(model, driver, error)
      run%seconds = seconds_since(start)
      if (allocated(error)) call fail('driver_start: '//error%message)
      do while (driver%stop == stop_none)
         start = clock()
         call driver_step(model, driver, outcome, error)
         run%seconds = run%seconds + seconds_since(start)
         if (allocated(error)) call fail('driver_step: '//error%message)
         run%steps = outcome%step
         run%iterations = run%iterations + outcome%iterations
         run%cuts = run%cuts + outcome%cuts
         run%lambda = outcome%lambda
         do k = 1, size(outcome%events)
            if (run%has_limit .or. outcome%events(k)%kind(1:5) /= 'limit') cycle
            run%limit_lambda = outcome%events(k)%lambda
            run%has_limit = .true.
         end do
      end do
      select case (driver%stop)
      case (stop_load_limit)
         run%stop_reason = 'lambda_max'
      case (stop_track_limit)
         run%stop_reason = 'stop_track'
      case (stop_step_limit)
         run%stop_reason = 'steps'
      end select
      state = driver%state
   end subroutine trace_path

   !> Read a deck with -D overrides and time the reading (the deck reader is not part of the analysis).
   subroutine load_model(deck, overrides, model, seconds)
      character(len=*), intent(in) :: deck
      type(parameter_override_t), intent(in) :: overrides(:)
      type(model_t), intent(out) :: model
      real(dp), intent(out) :: seconds
      type(error_t), allocatable :: error
      integer(int64) :: start
      start = clock()
      call read_deck(deck, overrides, model, error)
      seconds = seconds_since(start)
      if (allocated(error)) call fail(error%message)
   end subroutine load_model

   !> Median of a short list (insertion sort of a copy).
   pure real(dp) function median(values)
      real(dp), intent(in) :: values(:)
      real(dp) :: sorted(size(values)), item
      integer :: i, j
      sorted = values
      do i = 2, size(sorted)
         item = sorted(i)
         j = i - 1
         do while (j >= 1)
            if (sorted(j) <= item) exit
            sorted(j + 1) = sorted(j)
            j = j - 1
         end do
         sorted(j + 1) = item
      end do
      median = 0.5_dp*(sorted((size(sorted) + 1)/2) + sorted(size(sorted)/2 + 1))
   end function median

   !> The `-D name=value` of the command line, as read_deck takes it.
   pure function override(name, value) result(item)
      character(len=*), intent(in) :: name, value
      type(parameter_override_t) :: item
      item%name = name
      item%value = value
   end function override

   !> Number of unknowns: the DOFs no support holds.
   pure integer function equations_of(model) result(n)
      type(model_t), intent(in) :: model
      n = count(.not. model%fixed)
   end function equations_of

   !> The wall clock, in counts of system_clock.
   integer(int64) function clock()
      call system_clock(clock)
   end function clock

   !> Wall-clock seconds since the count `start` of clock().
   real(dp) function seconds_since(start)
      integer(int64), intent(in) :: start
      integer(int64) :: now, rate
      call system_clock(now, rate)
      seconds_since = real(now - start, dp)/real(rate, dp)
   end function seconds_since

   !> Print the error and stop with exit code 1 (a program may stop; the library never does).
   subroutine fail(message)
      character(len=*), intent(in) :: message
      write (error_unit, '(a)') 'error: '//message
      call exit_program(1)
   end subroutine fail

end program bench_path
