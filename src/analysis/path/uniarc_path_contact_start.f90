!> The contact start of a step located by re-solving it (docs/theory.md §2.2, "Contact events").
!>
!> A step that begins with no candidate in contact and ends with some has passed the state where the
!> first gap closes. Up to that state the path is the old working set's piece: the structure without
!> the closing contacts. So the state is found on that piece itself: the step is re-solved from its
!> start with the old set kept (uniarc_path_newton, attempt_step with keep_set: no contact LCP, no
!> complementarity), for step lengths h ∈ (0, Δl), and the least gap g(h) of the candidates that are
!> in contact at the step's end is driven to zero by the Illinois variant of regula falsi (a secant
!> kept inside a bracket with g > 0 at one end and g < 0 at the other; the end kept twice in a row has
!> its value halved: Dahlquist & Björck, Numerical Methods, §6.2.2; superlinear). Past the touch the
!> old set's piece is no state of the path (the gap is negative there), but it is smooth through the
!> root, so the secant converges as on any smooth function; each probe is an equilibrium state, and
!> the one at the root is the contact start itself: its λ and its unknowns are those reported (the
!> tracked values of the `contact_start` row of STEM.crit are evaluated there, not interpolated
!> between the two converged steps). Where the old set's piece is linear in h (a structure that does
!> not move before it touches, a linear one between two steps) the first secant is exact.
!> The probes never change the committed state; the system of equations is returned holding the
!> committed tangent.
module uniarc_path_contact_start
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_model, only: model_t, dofs_per_node, control_load, control_displacement
   use uniarc_assembly, only: gather_nodal
   use uniarc_path_state, only: path_state_t, path_system_t, step_trial_t, masked_norm
   use uniarc_path_newton, only: attempt_step
   use uniarc_path_contact_set, only: candidate_state
   use uniarc_path_probe, only: restore_tangent
   use uniarc_foreign, only: interrupt_signal
   implicit none
   private
   public :: locate_contact_start

   !> Re-solutions per contact start: the secant converges in a handful where g is smooth; bisection,
   !> the safeguard, narrows the bracket below width_tolerance within 40.
   integer, parameter :: max_probes = 40
   !> The bracket is narrow enough at this fraction of the step: past it the probes' states differ
   !> by the round-off of h (the locator ends there if |g| has not met its tolerance before).
   real(dp), parameter :: width_tolerance = 1.0e-12_dp
   !> A located start whose gap did not meet its tolerance is still kept if the bracket is below
   !> this fraction of the step (the critical-point locator's bracket, uniarc_path_locate): it is then
   !> placed at the bracket's open end, a state of the path within 1e-3 of the step of the touch.
   real(dp), parameter :: kept_width = 1.0e-3_dp
   !> |g| at the root, relative to the size of the model: far above the round-off of a gap
   !> (coordinates of that size, ε ≈ 2e-16 of them) and far below the touching tolerance of the
   !> contact set (1e-9 of the size, uniarc_path_contact_set): a state with |g| below it touches.
   real(dp), parameter :: roundoff_gap = 1.0e-12_dp
   !> What is known of the far end hb of the bracket: its gap is not closed (the end of the step,
   !> where the old set's piece may have left the obstacle again), closed (g < 0), or its probe did
   !> not converge (past the touch: bisection).
   integer, parameter :: far_open = 0, far_closed = 1, far_failed = 2

contains

   !> Locate the contact start of the step from `before` (a copy of the committed state at its start,
   !> system not allocated) to `after` (the committed state it reached with a step of length `length`,
   !> the units of state%step_length), if no candidate is in contact at `before` and some are at
   !> `after`. On return after%point%contact_start_fraction (fraction of the interval in path
   !> length; −1: not located) and contact_start_lambda hold it, and after%contact_start_u the
   !> unknowns of the state there. Not located (the caller then reads the event along the tangent at
   !> `before`, uniarc_critical_points) where the old set's re-solution of the whole step does not
   !> converge or does not close the gap, or where the bracket could not be narrowed to kept_width.
   !> A candidate that closes while already in the working set at `before` (touching there with no
   !> force) places the start at `before` itself.
   !> `system` holds after's committed tangent on entry and on return (re-assembled if a probe used it).
   !> Errors: out of memory (error_analysis, flagged out_of_memory: the run ends).
   subroutine locate_contact_start(model, before, after, system, length, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: before
      type(path_state_t), intent(inout) :: after
      type(path_system_t), intent(inout) :: system
      real(dp), intent(in) :: length
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), reaction(:), gap(:), x(:), x_open(:), x_root(:)
      logical, allocatable :: closing(:)
      real(dp) :: ha, hb, fa, fb, hp, fp, h, f, lambda, lambda_open, lambda_root, tolerance, g_start
      integer :: k, m, n, side, status, far
      logical :: probed, ok, found, have_previous
      type(step_trial_t) :: trial
      after%point%contact_start_fraction = -1.0_dp
      after%point%contact_start_lambda = 0.0_dp
      if (allocated(after%contact_start_u)) deallocate (after%contact_start_u)
      if (.not. (allocated(before%point%in_contact) .and. allocated(after%point%in_contact))) return
      m = size(after%point%in_contact)
      if (size(before%point%in_contact) /= m .or. m == 0) return
      if (any(before%point%in_contact) .or. .not. any(after%point%in_contact)) return
      if (.not. (length > 0.0_dp)) return
      n = size(before%u)
      allocate (nodal(dofs_per_node, model%n_nodes), reaction(m), gap(m), x(n), x_open(n), x_root(n), closing(m), &
                stat=status)
      call allocation_failure(status, 'the work arrays of the contact start''s location', &
                              8.0_dp*(dofs_per_node*model%n_nodes + 2*m + 3*n) + 4.0_dp*m, error_analysis, error)
      if (allocated(error)) return
      closing(:) = after%point%in_contact
      if (any(closing .and. before%active)) then
         ! It touches at the step's start already, in the set with no force: the start is there.
         call keep(0.0_dp, before%lambda, before%u)
         return
      end if
      ! g at the step's start (the old set's state itself)
      x_open(:) = before%u
      lambda_open = before%lambda
      g_start = least_gap(before%u, before%lambda)
      if (.not. (g_start > roundoff_gap*before%length_scale)) then
         ! closed (to round-off) at the start already
         call keep(0.0_dp, before%lambda, before%u)
         return
      end if
      ha = 0.0_dp
      fa = g_start
      have_previous = .false.
      hp = 0.0_dp
      fp = 0.0_dp
      found = .false.
      side = 0
      ! The whole step with the old set: the far end of the bracket if the gap is closed there.
      ! (Not always: past the touch the old set's piece may leave the obstacle again — a node pushed
      ! along a line across a circle's rim comes out on its far side — and a probe past the touch
      ! may not converge.)
      probed = .false.
      hb = length
      far = far_open
      call solve(length, ok, f, lambda)
      if (allocated(error)) return
      if (.not. ok) then
         far = far_failed
      else if (f >= 0.0_dp .and. f <= tolerance) then
         found = .true.
         h = length
         x_root(:) = x
         lambda_root = lambda
      else if (f < 0.0_dp) then
         far = far_closed
         fb = f
      end if
      do k = 1, max_probes
         if (found) exit
         if (far /= far_open .and. hb - ha <= width_tolerance*length) exit
         if (interrupt_signal() /= 0) exit
         select case (far)
         case (far_closed)
            ! regula falsi (Illinois) in the bracket
            h = ha + fa*(hb - ha)/(fa - fb)
         case (far_failed)
            h = 0.5_dp*(ha + hb)
         case default
            ! No closed end known yet: the first probe where the gaps read along the tangent at the
            ! step's start close (find_contact_events' estimate), then the secant through the last
            ! two open states — it approaches the root from the open side where g is convex (a
            ! curved obstacle) and passes it, closing the bracket, where g is concave — else the
            ! middle of what is left below hb.
            if (k == 1) then
               h = tangent_guess()
            else if (have_previous .and. fa < fp) then
               h = ha - fa*(ha - hp)/(fa - fp)
            else
               h = 0.5_dp*(ha + hb)
            end if
         end select
         if (.not. (h > ha .and. h < hb)) h = 0.5_dp*(ha + hb)
         call solve(h, ok, f, lambda)
         if (allocated(error)) return
         if (.not. ok) then
            ! The old set's piece does not reach h: past the touch (up to it the piece is the path
            ! the step converged along); bisection from here.
            hb = h
            far = far_failed
            side = 0
            cycle
         end if
         ! (on the open side only: a state of the path, its gap not closed past the touch)
         if (f >= 0.0_dp .and. f <= tolerance) then
            found = .true.
            x_root(:) = x
            lambda_root = lambda
            exit
         end if
         if (f > 0.0_dp .and. far == far_open .and. .not. f < fa) then
            ! The gap, closing at the step's start, has not closed further: the old set's piece
            ! passed its closest approach (or the obstacle's far rim) before h, and the root lies
            ! below it.
            hb = h
            cycle
         end if
         if (f > 0.0_dp) then
            have_previous = .true.
            hp = ha
            fp = fa
            ha = h
            fa = f
            x_open(:) = x
            lambda_open = lambda
            if (side == 1 .and. far == far_closed) fb = 0.5_dp*fb
            side = 1
         else
            if (side == 2 .and. far == far_closed) fa = 0.5_dp*fa
            hb = h
            fb = f
            far = far_closed
            side = 2
         end if
      end do
      if (found) then
         call keep(h/length, lambda_root, x_root)
      else if (far /= far_open .and. hb - ha <= kept_width*length) then
         call keep(ha/length, lambda_open, x_open)
      end if
      call finish()

   contains

      !> The old set's state at step length step_h from `before`: ok, its least gap `g` and λ (its
      !> unknowns in x); the tolerance of |g| at that state.
      subroutine solve(step_h, ok, g, lambda)
         real(dp), intent(in) :: step_h
         logical, intent(out) :: ok
         real(dp), intent(out) :: g, lambda
         g = 0.0_dp
         lambda = before%lambda
         ! (the system holds after's factors, not before's: the attempt assembles its own)
         system%holds_committed = .false.
         trial%length = step_h
         call attempt_step(model, before, system, trial, keep_set=.true.)
         probed = .true.
         if (allocated(trial%fatal)) then
            call move_alloc(trial%fatal, error)   ! out of memory: the run ends
            ok = .false.
            return
         end if
         ok = trial%converged
         if (.not. ok) return
         x(:) = before%u + trial%increment
         lambda = before%lambda + trial%dlambda
         g = least_gap(x, lambda)
         ! The probe's displacements are converged to the displacement tolerance of its increment
         ! (Newton's test, uniarc_path_newton): its gap is known to that and no better, and never
         ! below the round-off of a gap.
         tolerance = max(model%analysis%displacement_tolerance*masked_norm(before%map, trial%increment), &
                         roundoff_gap*before%length_scale)
      end subroutine solve

      !> The step length (the units of `length`) at which the first closing candidate's gap, read
      !> along the tangent at the step's start, reaches zero: the path length to it along the tangent
      !> (the candidates' rates per unit path length) in the step's parameter — λ under load control,
      !> the controlled displacement under displacement control, the arc length itself — ; half the
      !> step where the tangent does not close a gap within it.
      real(dp) function tangent_guess()
         real(dp) :: s_touch, per_s
         integer :: c
         tangent_guess = 0.5_dp*length
         s_touch = huge(1.0_dp)
         do c = 1, m
            if (.not. closing(c)) cycle
            if (before%point%contact_rate(c) < 0.0_dp) &
               s_touch = min(s_touch, -before%point%contact_value(c)/before%point%contact_rate(c))
         end do
         if (.not. (s_touch < huge(1.0_dp))) return
         select case (model%analysis%control)
         case (control_load)
            per_s = abs(before%point%dlambda_ds)
         case (control_displacement)
            per_s = 0.0_dp
            if (before%control_equation > 0 .and. allocated(before%point%rate)) &
               per_s = abs(before%point%rate(before%control_equation))
         case default
            per_s = 1.0_dp
         end select
         if (per_s*s_touch > 0.0_dp .and. per_s*s_touch < length) tangent_guess = per_s*s_touch
      end function tangent_guess

      !> The least gap of the closing candidates at unknowns `y`, load factor `lambda_y`.
      real(dp) function least_gap(y, lambda_y)
         real(dp), intent(in) :: y(:), lambda_y
         call gather_nodal(before%map, y, nodal)
         call candidate_state(model, before%map, y, nodal, before%active, reaction, gap, before%slip, &
                              before%yielding, lambda_y)
         least_gap = minval(gap, mask=closing)
      end function least_gap

      !> The located start: fraction t of the interval, λ, unknowns y.
      subroutine keep(t, lambda_y, y)
         real(dp), intent(in) :: t, lambda_y, y(:)
         allocate (after%contact_start_u(size(y)), stat=status)
         call allocation_failure(status, 'the state at the contact start', 8.0_dp*size(y), error_analysis, error)
         if (allocated(error)) return
         after%contact_start_u(:) = y
         after%point%contact_start_fraction = min(1.0_dp, max(0.0_dp, t))
         after%point%contact_start_lambda = lambda_y
      end subroutine keep

      !> The committed tangent back in the system after probes.
      subroutine finish()
         type(error_t), allocatable :: restore_error
         if (.not. probed) return
         ! (the last probe's assembly is not the committed state's: restore_tangent assembles that)
         system%holds_converged = .false.
         call restore_tangent(model, after, system, restore_error)
         if (allocated(restore_error)) then
            if (allocated(error)) return
            call move_alloc(restore_error, error)
         end if
      end subroutine finish

   end subroutine locate_contact_start

end module uniarc_path_contact_start
