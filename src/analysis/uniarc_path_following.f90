!> Incremental-iterative path following (paper §5, Fig. 3, without contact; Crisfield 1991 ch. 9).
!>
!> Each step: a tangent predictor sized by the control (load, displacement or arc length), then full
!> Newton–Raphson corrections in which the load correction δλ comes from the iteration strategy —
!> Chan's (1988) minimum residual displacement (the paper's choice), Crisfield's cylindrical arc length,
!> or Riks/Ramm's updated normal plane. A step that does not converge is reverted and cut; the step
!> size adapts to the iterations used. The committed state is only changed by a converged step.
!>
!> Predictor sign: the predictor goes along +K⁻¹R or −K⁻¹R, whichever makes a positive angle with the
!> previous converged increment (Feng, Perić & Owen 1996). Unlike the sign of det K, which changes at
!> bifurcation points too and cannot follow a snap-back, the angle criterion keeps the direction of
!> travel along the path through limit points, turning points and snap-back.
module uniarc_path_following
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_model, only: model_t, analysis_options_t, dofs_per_node, control_load, control_displacement, &
                           control_arclength, iteration_chan, iteration_cylindrical, iteration_riks
   use uniarc_dof_map, only: dof_map_t, build_dof_map
   use uniarc_band, only: band_matrix_t, band_allocate, band_factorize, band_solve, band_inertia
   use uniarc_assembly, only: assemble_reference_load, gather_nodal
   use uniarc_equilibrium, only: assemble_equilibrium
   implicit none
   private
   public :: path_state_t, path_point_t, path_initialize, path_advance, nodal_displacements

   !> What a converged point of the path tells the critical-point detector.
   type :: path_point_t
      integer :: step = 0
      real(dp) :: s = 0.0_dp            !< path length Σ ||Δu|| up to this point
      real(dp) :: lambda = 0.0_dp
      real(dp) :: dlambda_ds = 0.0_dp   !< slope of the path in the direction of travel
      real(dp), allocatable :: rate(:)  !< du/ds (equations) in the direction of travel
      integer :: neg_pivots = 0         !< negative pivots of K_T (Sylvester: negative eigenvalues)
      real(dp) :: min_eigenvalue = 0.0_dp   !< eigenvalue of K_T of least magnitude (inverse iteration)
      integer :: iterations = 0
   end type path_point_t

   !> The committed state of the path and what the next step needs.
   type :: path_state_t
      type(dof_map_t) :: map
      type(band_matrix_t) :: tangent            !< K_T at the committed state, factorised
      real(dp), allocatable :: u(:)             !< committed total displacements (equations)
      real(dp) :: lambda = 0.0_dp
      real(dp), allocatable :: fixed_load(:)    !< u-independent part of the reference load R_r
      real(dp), allocatable :: reference(:)     !< R(u) at the committed state
      real(dp), allocatable :: tangent_displacement(:)  !< K_T⁻¹ R at the committed state
      real(dp), allocatable :: last_increment(:)
      real(dp) :: step_length = 0.0_dp          !< Δl, Δλ or Δu_c of the next step (by the control)
      real(dp) :: first_length = 0.0_dp
      real(dp) :: load_norm = 0.0_dp            !< ||R_r|| · first Δλ: the force scale of the problem
      integer :: direction = 1                  !< +1/−1: predictor along ±K⁻¹R
      integer :: control_equation = 0
      type(path_point_t) :: point
   end type path_state_t

contains

   !> Number the equations, assemble at the unloaded state and size the first step.
   subroutine path_initialize(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(out) :: state
      type(error_t), allocatable, intent(out) :: error
      associate (options => model%analysis)
         call build_dof_map(model, state%map)
         call band_allocate(state%tangent, state%map%n_equations, state%map%half_bandwidth, &
                            state%map%half_bandwidth)
         allocate (state%u(state%map%n_equations), source=0.0_dp)
         allocate (state%last_increment(state%map%n_equations), source=0.0_dp)
         allocate (state%fixed_load(state%map%n_equations))
         call assemble_reference_load(model, state%map, .false., state%fixed_load)
         if (options%control == control_displacement) then
            state%control_equation = state%map%equation(options%control_dof, options%control_node)
            if (state%control_equation == 0) then
               call make_error(error, 'displacement control of a DOF held by a support', error_analysis)
               return
            end if
         end if
         call tangent_at_committed_state(model, state, error)
         if (allocated(error)) then
            call add_where(error, 'unloaded state', state)
            return
         end if
         select case (options%control)
         case (control_arclength)
            state%first_length = abs(options%first_increment)*norm2(state%tangent_displacement)
         case default
            state%first_length = abs(options%first_increment)
         end select
         state%step_length = state%first_length
         state%direction = 1
         if (options%first_increment < 0.0_dp) state%direction = -1
         state%load_norm = abs(options%first_increment)*norm2(state%reference)
         if (options%control == control_displacement) state%load_norm = norm2(state%reference)
         if (state%first_length <= 0.0_dp .or. state%load_norm <= 0.0_dp) then
            call make_error(error, 'the first increment or the reference load is zero: nothing to follow', &
                            error_analysis)
            return
         end if
         call describe_point(state, 0, 0)
      end associate
   end subroutine path_initialize

   !> Advance one converged step, cutting the step length on failure; error if it cannot be done.
   subroutine path_advance(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: increment(:)
      real(dp) :: dlambda, length, factor
      integer :: cuts, iterations
      logical :: converged
      character(len=:), allocatable :: reason
      associate (options => model%analysis)
         length = state%step_length
         do cuts = 0, options%max_cuts
            call try_step(model, state, length, increment, dlambda, iterations, converged, reason)
            if (converged) exit
            length = 0.5_dp*length
            if (length < options%min_increment*state%first_length) exit
         end do
         if (.not. converged) then
            call make_error(error, 'no convergence ('//reason//') after cutting the step down to '// &
                            real_text(length/state%first_length)//' of the first', error_analysis)
            call add_where(error, 'step '//int_text(state%point%step + 1), state)
            return
         end if
         state%u = state%u + increment
         state%lambda = state%lambda + dlambda
         state%last_increment = increment
         state%point%s = state%point%s + norm2(increment)
         call tangent_at_committed_state(model, state, error)
         if (allocated(error)) then
            call add_where(error, 'step '//int_text(state%point%step + 1)//' (converged state)', state)
            return
         end if
         select case (options%control)
         case (control_arclength)
            ! Keep travelling forward: positive angle between the new tangent and the last increment.
            if (dot_product(increment, state%tangent_displacement) < 0.0_dp) then
               state%direction = -1
            else
               state%direction = 1
            end if
         end select
         call describe_point(state, state%point%step + 1, iterations)
         factor = sqrt(real(options%desired_iterations, dp)/real(max(iterations, 1), dp))
         factor = min(2.0_dp, max(0.25_dp, factor))
         state%step_length = min(options%max_increment*state%first_length, &
                                 max(options%min_increment*state%first_length, length*factor))
      end associate
   end subroutine path_advance

   !> One attempt at a step of the given length; the committed state is not touched.
   subroutine try_step(model, state, length, increment, dlambda, iterations, converged, reason)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      real(dp), intent(in) :: length
      real(dp), allocatable, intent(out) :: increment(:)
      real(dp), intent(out) :: dlambda
      integer, intent(out) :: iterations
      logical, intent(out) :: converged
      character(len=:), allocatable, intent(out) :: reason
      real(dp), allocatable :: nodal(:, :), internal(:), reference(:), rhs(:, :), trial(:)
      real(dp) :: lambda, dl, residual_norm, force_scale
      type(error_t), allocatable :: error
      logical :: small_correction
      integer :: n
      n = state%map%n_equations
      allocate (nodal(dofs_per_node, model%n_nodes), internal(n), reference(n), rhs(n, 2), trial(n))
      converged = .false.
      reason = 'iteration limit'
      associate (options => model%analysis, ut => state%tangent_displacement)
         ! Predictor along the committed tangent.
         select case (options%control)
         case (control_arclength)
            dlambda = state%direction*length/norm2(ut)
         case (control_displacement)
            dlambda = state%direction*length/ut(state%control_equation)
         case default
            dlambda = state%direction*length
         end select
         increment = dlambda*ut
         small_correction = .false.
         do iterations = 0, options%max_iterations
            lambda = state%lambda + dlambda
            trial = state%u + increment
            call gather_nodal(state%map, trial, nodal)
            call assemble_equilibrium(model, state%map, nodal, lambda, state%fixed_load, state%tangent, &
                                      internal, reference)
            rhs(:, 1) = lambda*reference - internal
            residual_norm = norm2(rhs(:, 1))
            force_scale = max(state%load_norm, norm2(lambda*reference))
            if (.not. (residual_norm < huge(1.0_dp))) then   ! NaN or overflow
               reason = 'the residual is not finite'
               exit
            end if
            if (iterations > 0 .and. small_correction .and. &
                residual_norm <= options%force_tolerance*force_scale) then
               converged = .true.
               exit
            end if
            if (iterations == options%max_iterations) exit
            call band_factorize(state%tangent, error)
            if (allocated(error)) then
               reason = 'singular tangent'
               exit
            end if
            rhs(:, 2) = reference
            call band_solve(state%tangent, rhs, error)
            if (allocated(error)) then
               reason = 'solve failed'
               exit
            end if
            ! rhs(:, 1) = δu_g (residual displacement), rhs(:, 2) = δu_t (tangent displacement)
            select case (options%control)
            case (control_load)
               dl = 0.0_dp
            case (control_displacement)
               dl = -rhs(state%control_equation, 1)/rhs(state%control_equation, 2)
            case default
               call load_correction(options, increment, rhs(:, 1), rhs(:, 2), length, dl, reason)
               if (len(reason) == 0) then
                  reason = 'iteration limit'
               else
                  exit
               end if
            end select
            increment = increment + rhs(:, 1) + dl*rhs(:, 2)
            dlambda = dlambda + dl
            small_correction = norm2(rhs(:, 1) + dl*rhs(:, 2)) <= &
                               options%displacement_tolerance*max(norm2(increment), tiny(1.0_dp))
         end do
      end associate
   end subroutine try_step

   !> Load correction δλ of an arc-length iteration; `reason` is empty on success.
   pure subroutine load_correction(options, increment, du_residual, du_tangent, length, dl, reason)
      type(analysis_options_t), intent(in) :: options
      real(dp), intent(in) :: increment(:), du_residual(:), du_tangent(:), length
      real(dp), intent(out) :: dl
      character(len=:), allocatable, intent(out) :: reason
      real(dp) :: a, b, c, discriminant, root(2), cosine(2)
      integer :: k
      reason = ''
      select case (options%iteration)
      case (iteration_chan)
         ! Minimum residual displacement (Chan 1988): δλ minimises ||δu_g + δλ δu_t||.
         dl = -dot_product(du_tangent, du_residual)/dot_product(du_tangent, du_tangent)
      case (iteration_riks)
         ! Updated normal plane (Ramm 1981): the correction is orthogonal to the current increment.
         dl = -dot_product(increment, du_residual)/dot_product(increment, du_tangent)
      case (iteration_cylindrical)
         ! ||Δu + δu_g + δλ δu_t|| = Δl (Crisfield 1981): the root closer in angle to the increment.
         a = dot_product(du_tangent, du_tangent)
         b = 2.0_dp*dot_product(du_tangent, increment + du_residual)
         c = dot_product(increment + du_residual, increment + du_residual) - length**2
         discriminant = b**2 - 4.0_dp*a*c
         if (discriminant < 0.0_dp) then
            reason = 'the arc-length constraint has no real root'
            dl = 0.0_dp
            return
         end if
         root(1) = (-b + sqrt(discriminant))/(2.0_dp*a)
         root(2) = (-b - sqrt(discriminant))/(2.0_dp*a)
         do k = 1, 2
            cosine(k) = dot_product(increment, increment + du_residual + root(k)*du_tangent)
         end do
         dl = root(maxloc(cosine, 1))
      case default
         dl = 0.0_dp
         reason = 'unknown iteration strategy'
      end select
   end subroutine load_correction

   !> Assemble and factorise K_T at the committed state; its inertia, K⁻¹R and least eigenvalue.
   subroutine tangent_at_committed_state(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), internal(:), rhs(:, :)
      logical :: singular
      integer :: n
      n = state%map%n_equations
      allocate (internal(n), rhs(n, 1))
      call nodal_displacements(model, state, nodal)
      if (.not. allocated(state%reference)) allocate (state%reference(n))
      call assemble_equilibrium(model, state%map, nodal, state%lambda, state%fixed_load, state%tangent, &
                                internal, state%reference)
      call band_inertia(state%tangent, state%point%neg_pivots, singular)
      call band_factorize(state%tangent, error)
      if (allocated(error)) return
      rhs(:, 1) = state%reference
      call band_solve(state%tangent, rhs, error)
      if (allocated(error)) return
      state%tangent_displacement = rhs(:, 1)
      state%point%min_eigenvalue = least_eigenvalue(state%tangent)
   end subroutine tangent_at_committed_state

   !> Fill the point record of the committed state.
   subroutine describe_point(state, step, iterations)
      type(path_state_t), intent(inout) :: state
      integer, intent(in) :: step, iterations
      real(dp) :: norm
      state%point%step = step
      state%point%lambda = state%lambda
      state%point%iterations = iterations
      ! Unit tangent of the path in (u, λ) with the arc-length metric ds² = ||du||² (cylindrical):
      ! du/ds = ±K⁻¹R/||K⁻¹R||, dλ/ds = ±1/||K⁻¹R||, signed by the direction of travel.
      norm = norm2(state%tangent_displacement)
      state%point%dlambda_ds = real(state%direction, dp)/norm
      state%point%rate = (real(state%direction, dp)/norm)*state%tangent_displacement
   end subroutine describe_point

   !> Eigenvalue of least magnitude of a factorised matrix by inverse iteration (Rayleigh quotient of
   !> K⁻¹); used only to place bifurcation points between steps, so a few digits suffice.
   function least_eigenvalue(matrix) result(mu)
      type(band_matrix_t), intent(in) :: matrix
      real(dp) :: mu
      real(dp), allocatable :: x(:, :), y(:)
      real(dp) :: nu
      type(error_t), allocatable :: error
      integer :: k, i
      mu = 0.0_dp
      if (matrix%n == 0) return
      allocate (x(matrix%n, 1))
      x(:, 1) = [(1.0_dp + 0.1_dp*sin(real(i, dp)), i=1, matrix%n)]
      x = x/norm2(x)
      nu = 0.0_dp
      do k = 1, 30
         y = x(:, 1)
         call band_solve(matrix, x, error)
         if (allocated(error)) return
         nu = dot_product(y, x(:, 1))
         x = x/norm2(x)
      end do
      if (abs(nu) > tiny(1.0_dp)) mu = 1.0_dp/nu
   end function least_eigenvalue

   !> Nodal displacements (3, n_nodes) of the committed state.
   subroutine nodal_displacements(model, state, nodal)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), allocatable, intent(out) :: nodal(:, :)
      allocate (nodal(dofs_per_node, model%n_nodes))
      call gather_nodal(state%map, state%u, nodal)
   end subroutine nodal_displacements

   subroutine add_where(error, where, state)
      type(error_t), intent(inout) :: error
      character(len=*), intent(in) :: where
      type(path_state_t), intent(in) :: state
      error%message = where//', from lambda = '//real_text(state%lambda)//': '//error%message
   end subroutine add_where

   pure function int_text(i) result(text)
      integer, intent(in) :: i
      character(len=:), allocatable :: text
      character(len=16) :: buffer
      write (buffer, '(i0)') i
      text = trim(buffer)
   end function int_text

   pure function real_text(x) result(text)
      real(dp), intent(in) :: x
      character(len=:), allocatable :: text
      character(len=24) :: buffer
      write (buffer, '(es12.5)') x
      text = trim(adjustl(buffer))
   end function real_text

end module uniarc_path_following
