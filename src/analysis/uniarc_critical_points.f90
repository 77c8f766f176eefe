!> Critical points between two converged points of the path (docs/contracts.md: `STEM.crit`).
!>
!> A limit point is where dλ/ds changes sign along the direction of travel; it is located on the cubic
!> Hermite interpolant of λ(s) built from the values and slopes at both points (error O(h⁴) in λ, so
!> the located load is far more accurate than the nearest step). A bifurcation is a change of the
!> number of negative pivots of K_T that no limit point explains, nor a change of the working set at
!> which the locator found it (a contact that closes or opens: the least eigenvalue jumps there, the
!> tangent is not singular). The path following locates it by re-solving the step (uniarc_path_locate,
!> on a bracket of 1e-3 of the step, where the least eigenvalue, linear across it, vanishes), and the
!> point record carries it. Where it was not located so (a step the locator does not re-solve, or
!> whose bracket it could not narrow), the bifurcation is placed at a converged point beside the
!> change — the end of the interval, or of the locator's bracket so far, nearer to where the least
!> eigenvalue, linear between them, vanishes (the end where the count is seen changed when it does
!> not change sign) — and the event says so (`located` false), never at an interpolated or middle
!> place that may lie off the path.
module uniarc_critical_points
   use uniarc_kinds, only: dp
   use uniarc_path_state, only: path_point_t
   implicit none
   private
   public :: critical_event_t, find_critical_events, find_contact_events, sort_events, opposite_signs, same_signs

   !> A sign change of dλ/ds is a limit point only if λ turns there by more than this fraction of |λ|
   !> beyond both converged points (or the count of negative pivots changes across them, or the
   !> working set does): the files carry 13 significant digits, and a smaller turn is the round-off of
   !> the slope where the path is flat — the first steps of a secondary branch from a symmetric
   !> bifurcation, where dλ/ds = 0 at the switch point (docs/input.md's strut_switch: a limit_min 8e-11
   !> below the bifurcation, at the λ of the step itself, across which the count did not change).
   real(dp), parameter :: roundoff_turn = 1.0e-12_dp

   !> A step is flat when λ changes over it by at most this fraction of |λ|, both converged (the change
   !> between its ends) and along the tangent at either end (|dλ/ds| Δs): then neither the sign of
   !> dλ/ds nor the count of negative pivots says anything (docs/theory.md §2.6). On the strut's
   !> post-buckling branch on a tensionless bed (docs/input.md's strut_switch, max_increment = 1), flat
   !> to 1e-10, λ rose by 1e-13 to 2.7e-12 a step (2.7e-11 of λ) while dλ/ds changed sign and the count
   !> on the cone went 0/1 with round-off (6 limit and 5 unilateral_bifurcation rows at one λ); a step
   !> that passes a limit point or a bifurcation moves λ by far more than 1e-9 of it, a share of the
   !> equilibrium tolerance (1e-8 of the load scale) that the converged λ cannot resolve anyway.
   real(dp), parameter :: flat_share = 1.0e-9_dp

   !> A contact_corner whose fraction of the step is within this of the located contact start of the
   !> same step is that start (find_critical_events): ten times the corner's bracket (1e-3 of the
   !> step, uniarc_path_locate), across which its tangent-intersection placement lies (measured
   !> 2.2e-3 on ex. 4's arch at gap 4.98); a later corner at another contact lies farther on.
   real(dp), parameter :: start_corner_share = 1.0e-2_dp

   !> One critical point: its kind, where it lies between the two steps, and the state there.
   type :: critical_event_t
      !> limit_max, limit_min, contact_corner, bifurcation, unilateral_bifurcation or a contact event
      character(len=:), allocatable :: kind
      real(dp) :: position = 0.0_dp           !< step number, fractional (e.g. 12.4)
      real(dp) :: lambda = 0.0_dp
      real(dp) :: fraction = 0.0_dp           !< 0..1 between the two points
      !> bifurcation: how many eigenvalues of K_T vanish there (2 for a double eigenvalue, the count of
      !> negative pivots changing by two across the locator's final bracket); 1 otherwise
      integer :: multiplicity = 1
      !> false for a bifurcation that could not be bracketed by re-solving the step: it is placed at
      !> a converged point beside the change of the count of negative pivots (its λ that point's)
      logical :: located = .true.
   end type critical_event_t

contains

   !> Whether `a` and `b` are nonzero and of opposite signs: a sign change of dλ/ds (a limit point) or of
   !> an eigenvalue between two points. Compared by signs, not by the product a·b < 0, which overflows
   !> (a SIGFPE under the Debug build's traps) where |a|, |b| exceed 1e154 — dλ/ds = 1/||K⁻¹R|| of a
   !> reference load of 1e-150 — and underflows to 0 (no change seen) where both are tiny. False if
   !> either is 0 or NaN.
   elemental logical function opposite_signs(a, b)
      real(dp), intent(in) :: a, b
      opposite_signs = (a < 0.0_dp .and. b > 0.0_dp) .or. (a > 0.0_dp .and. b < 0.0_dp)
   end function opposite_signs

   !> Whether `a` and `b` are nonzero and of the same sign (the product a·b > 0, compared by signs as
   !> opposite_signs). False if either is 0 or NaN.
   elemental logical function same_signs(a, b)
      real(dp), intent(in) :: a, b
      same_signs = (a > 0.0_dp .and. b > 0.0_dp) .or. (a < 0.0_dp .and. b < 0.0_dp)
   end function same_signs

   !> Critical points between the converged points `before` and `after` (consecutive steps).
   pure subroutine find_critical_events(before, after, events)
      type(path_point_t), intent(in) :: before, after
      type(critical_event_t), allocatable, intent(out) :: events(:)
      type(critical_event_t) :: event
      integer :: unexplained
      allocate (events(0))
      ! A flat step (flat_share) with the same working set: its sign change of dλ/ds and its change of
      ! the count are round-off, no row (a contact event across it is still reported, below).
      if (flat_step(before, after) .and. .not. contact_changes(before, after)) return
      unexplained = abs(after%neg_pivots - before%neg_pivots)
      if (opposite_signs(before%dlambda_ds, after%dlambda_ds)) then
         if (after%limit_fraction >= 0.0_dp) then
            ! Located by re-solving the step (uniarc_path_locate).
            event%fraction = after%limit_fraction
            event%lambda = after%limit_lambda
         else if (contact_changes(before, after)) then
            ! The load turns where a contact starts or ends (a kink of the path, not a smooth limit):
            ! the extremum is at the contact event, on the branch that leads to it.
            event%fraction = first_contact_change(before, after)
            event%lambda = before%lambda + event%fraction*(after%s - before%s)*before%dlambda_ds
         else
            event%fraction = hermite_stationary_point(before, after)
            event%lambda = hermite_lambda(before, after, event%fraction)
         end if
         ! A maximum of λ between two converged points is at least as high as both of them (a minimum
         ! at most as low): an interpolant or an extrapolation to a contact event that says otherwise
         ! is off by its own error, and the converged value is the better estimate.
         if (before%dlambda_ds > 0.0_dp) then
            event%kind = 'limit_max'
            event%lambda = max(event%lambda, before%lambda, after%lambda)
         else
            event%kind = 'limit_min'
            event%lambda = min(event%lambda, before%lambda, after%lambda)
         end if
         ! Located at a change of the working set (uniarc_path_locate): a corner of the path, a contact
         ! event at which λ turns (docs/theory.md §2.12), not a limit point.
         if (after%limit_by_contact) event%kind = 'contact_corner'
         ! A corner in a step that begins with no contact and whose contact start was located by
         ! re-solving (uniarc_path_contact_start), within start_corner_share of it: the corner is that
         ! start, the kink where the first contact closes, and λ turns at the state located there (the
         ! corner's own placement, where the tangents of the two pieces meet across its bracket, is an
         ! estimate of it: ex. 4's arch, gap 4.98, 2.2e-3 of the step and 2.2e-7 in λ away).
         if (after%limit_by_contact .and. after%contact_start_fraction >= 0.0_dp) then
            if (abs(event%fraction - after%contact_start_fraction) <= start_corner_share) then
               event%fraction = after%contact_start_fraction
               event%lambda = after%contact_start_lambda
            end if
         end if
         event%position = before%step + event%fraction
         if (real_turn(event)) then
            events = [events, event]
            unexplained = max(0, unexplained - 1)
         end if
      end if
      ! A change of the count located where the working set changes is a change of stability at a
      ! contact event (uniarc_path_locate), not a critical point: a row of its own, so that every
      ! change of the count is explained by a row (docs/contracts.md, STEM.crit).
      if (after%stability_by_contact .and. unexplained > 0) then
         event%kind = 'contact_stability'
         event%fraction = after%stability_fraction
         event%lambda = after%stability_lambda
         event%position = before%step + event%fraction
         events = [events, event]
         unexplained = 0
      end if
      if (unexplained > 0) then
         ! A change of the count on the tangent with touching contacts released is a lift-off
         ! (unilateral) bifurcation: the structure buckles away from contacts that carry no force.
         if (before%liftoff .or. after%liftoff) then
            event%kind = 'unilateral_bifurcation'
         else
            event%kind = 'bifurcation'
         end if
         if (after%bifurcation_fraction >= 0.0_dp) then
            ! Located by re-solving the step (uniarc_path_locate), or, when its bracket could not be
            ! narrowed, placed at the converged end of the bracket so far where the count changed.
            event%fraction = after%bifurcation_fraction
            event%lambda = after%bifurcation_lambda
            event%located = .not. after%bifurcation_unbracketed
            ! (Not at a lift-off, whose count is that of a piece of the cone test, docs/theory.md §2.2.)
            if (after%bifurcation_multiplicity > 1 .and. after%bifurcation_multiplicity == unexplained .and. &
                event%kind == 'bifurcation') event%multiplicity = after%bifurcation_multiplicity
         else
            ! Not re-solved (a step the locator does not re-solve: a release step, the first step
            ! from a working set changed in place, or one that also passed a limit point): at one of
            ! the two converged points, and said so — the one nearer to where the least eigenvalue,
            ! linear between them, vanishes, or `after`, where the count is seen changed, when it
            ! does not change sign. (The middle of the interval, or λ interpolated there, may lie off
            ! the path: the pipeline over its hump, steps_pipeline_hump_history.inp, had
            ! unilateral_bifurcation rows at steps 299.5 and 631.5 with λ outside the range of both
            ! neighbours.)
            event%fraction = 1.0_dp
            event%lambda = after%lambda
            if (opposite_signs(before%min_eigenvalue, after%min_eigenvalue)) then
               if (before%min_eigenvalue/(before%min_eigenvalue - after%min_eigenvalue) < 0.5_dp) then
                  event%fraction = 0.0_dp
                  event%lambda = before%lambda
               end if
            end if
            event%located = .false.
         end if
         event%position = before%step + event%fraction
         events = [events, event]
      end if

   contains

      !> Whether the turn of λ at `turn` (a limit or corner between before and after) is a real
      !> extremum: λ there beyond both points by more than roundoff_turn of |λ|, or the count of
      !> negative pivots or the working set changing across the interval (which a turn explains).
      pure logical function real_turn(turn)
         type(critical_event_t), intent(in) :: turn
         real(dp) :: beyond
         if (turn%kind == 'limit_max') then
            beyond = turn%lambda - max(before%lambda, after%lambda)
         else if (turn%kind == 'limit_min') then
            beyond = min(before%lambda, after%lambda) - turn%lambda
         else
            real_turn = .true.
            return
         end if
         real_turn = beyond > roundoff_turn*max(abs(before%lambda), abs(after%lambda)) .or. &
                     after%neg_pivots /= before%neg_pivots .or. contact_changes(before, after)
      end function real_turn

   end subroutine find_critical_events

   !> Whether λ changes over the step from `before` to `after` by at most flat_share of |λ|: between the
   !> converged ends and along the tangent at each end (|dλ/ds| times the step's path length).
   pure logical function flat_step(before, after)
      type(path_point_t), intent(in) :: before, after
      real(dp) :: scale, length
      scale = flat_share*max(abs(before%lambda), abs(after%lambda))
      length = abs(after%s - before%s)
      flat_step = scale > 0.0_dp .and. abs(after%lambda - before%lambda) <= scale .and. &
                  abs(before%dlambda_ds)*length <= scale .and. abs(after%dlambda_ds)*length <= scale
   end function flat_step

   !> The events of one interval in path order: by position, stable (events at the same position keep
   !> the order they were found in). Insertion sort: an interval holds a handful.
   pure subroutine sort_events(events)
      type(critical_event_t), intent(inout) :: events(:)
      type(critical_event_t) :: moving
      integer :: i, j
      do i = 2, size(events)
         moving = events(i)
         j = i - 1
         do while (j >= 1)
            if (.not. events(j)%position > moving%position) exit
            events(j + 1) = events(j)
            j = j - 1
         end do
         events(j + 1) = moving
      end do
   end subroutine sort_events

   !> Contact start (no candidate in contact before, some after) and loss (the reverse) between two
   !> converged points. A start located by re-solving the step with the old working set
   !> (uniarc_path_contact_start: after%contact_start_fraction ≥ 0) is the state where the first gap
   !> closes, with its λ. Otherwise each candidate's gap (free) or reaction (in contact) is
   !> extrapolated along the path from `before` with its rate: the start is where the first gap
   !> closes, the loss where the last reaction vanishes, λ read along the tangent at `before`.
   pure subroutine find_contact_events(before, after, events)
      type(path_point_t), intent(in) :: before, after
      type(critical_event_t), allocatable, intent(inout) :: events(:)
      type(critical_event_t) :: event
      real(dp) :: h
      integer :: c
      logical :: starts, ends
      if (.not. allocated(before%in_contact) .or. .not. allocated(after%in_contact)) return
      starts = .not. any(before%in_contact) .and. any(after%in_contact)
      ends = any(before%in_contact) .and. .not. any(after%in_contact)
      if (.not. (starts .or. ends)) return
      h = after%s - before%s
      if (starts .and. after%contact_start_fraction >= 0.0_dp) then
         ! Located on the path: its λ is that of an equilibrium state between the two (no reading
         ! along a tangent to bound).
         event%kind = 'contact_start'
         event%fraction = after%contact_start_fraction
         event%lambda = after%contact_start_lambda
         event%position = before%step + event%fraction
         events = [events, event]
         return
      end if
      if (starts) then
         event%kind = 'contact_start'
         event%fraction = 1.0_dp
         do c = 1, size(after%in_contact)
            if (.not. after%in_contact(c)) cycle
            event%fraction = min(event%fraction, crossing(c))
         end do
      else
         event%kind = 'contact_lost'
         event%fraction = 0.0_dp
         do c = 1, size(before%in_contact)
            if (.not. before%in_contact(c)) cycle
            event%fraction = max(event%fraction, crossing(c))
         end do
      end if
      ! The path has a kink where the contact set changes: λ is extrapolated along the tangent at
      ! `before`, on the smooth branch that leads to the event, not read on a cubic across the kink.
      event%lambda = before%lambda + event%fraction*h*before%dlambda_ds
      ! Where λ does not turn in the interval (dλ/ds of one sign at both ends: no limit point or
      ! corner there, find_critical_events) it is monotone between the two converged states, and every
      ! state of the path between them has its λ between theirs. An extrapolation beyond that range
      ! (the tangent at `before` is not the path's up to the event: a bed that unloads along a curve
      ! extrapolated 0.85 past the end of its analysis step) is no state of the path: the event is
      ! placed at the converged state where the set is seen changed, `after`, with its λ.
      if (same_signs(before%dlambda_ds, after%dlambda_ds) .and. &
          (event%lambda < min(before%lambda, after%lambda) .or. event%lambda > max(before%lambda, after%lambda))) then
         event%fraction = 1.0_dp
         event%lambda = after%lambda
      end if
      ! Where λ turns in the interval at a point located by re-solving the step (a limit, or a corner
      ! at the contact event itself: uniarc_path_locate), that λ is the extremum of every state of the
      ! path between the two converged states: a reading along the tangent beyond it (ex. 4's arch,
      ! gap 4.98: its contact_start 5e-5 below the corner located at λ = 0.66494) is bounded by it.
      if (opposite_signs(before%dlambda_ds, after%dlambda_ds) .and. after%limit_fraction >= 0.0_dp) then
         if (before%dlambda_ds > 0.0_dp) then
            event%lambda = min(event%lambda, after%limit_lambda)
         else
            event%lambda = max(event%lambda, after%limit_lambda)
         end if
      end if
      event%position = before%step + event%fraction
      events = [events, event]

   contains

      !> Fraction of the interval where candidate c's value, extrapolated from `before`, reaches 0.
      pure real(dp) function crossing(c)
         integer, intent(in) :: c
         crossing = 1.0_dp
         if (before%contact_rate(c) < 0.0_dp .and. h > 0.0_dp) then
            crossing = min(1.0_dp, max(0.0_dp, -before%contact_value(c)/(before%contact_rate(c)*h)))
         end if
      end function crossing

   end subroutine find_contact_events

   !> Whether any candidate enters or leaves contact between the two points.
   pure logical function contact_changes(before, after)
      type(path_point_t), intent(in) :: before, after
      contact_changes = .false.
      if (.not. allocated(before%in_contact) .or. .not. allocated(after%in_contact)) return
      if (size(before%in_contact) /= size(after%in_contact)) return
      contact_changes = any(before%in_contact .neqv. after%in_contact)
   end function contact_changes

   !> Fraction of the interval where the first candidate that changes state reaches zero (its gap or
   !> reaction extrapolated from `before` with its rate along the path).
   pure real(dp) function first_contact_change(before, after) result(fraction)
      type(path_point_t), intent(in) :: before, after
      real(dp) :: h
      integer :: c
      h = after%s - before%s
      fraction = 1.0_dp
      do c = 1, size(before%in_contact)
         if (before%in_contact(c) .eqv. after%in_contact(c)) cycle
         if (before%contact_rate(c) < 0.0_dp .and. h > 0.0_dp) then
            fraction = min(fraction, max(0.0_dp, -before%contact_value(c)/(before%contact_rate(c)*h)))
         end if
      end do
   end function first_contact_change

   !> λ on the cubic Hermite interpolant at fraction t of the interval.
   pure function hermite_lambda(a, b, t) result(lambda)
      type(path_point_t), intent(in) :: a, b
      real(dp), intent(in) :: t
      real(dp) :: lambda, h
      h = b%s - a%s
      lambda = (2*t**3 - 3*t**2 + 1)*a%lambda + (t**3 - 2*t**2 + t)*h*a%dlambda_ds &
               + (-2*t**3 + 3*t**2)*b%lambda + (t**3 - t**2)*h*b%dlambda_ds
   end function hermite_lambda

   !> Fraction t in [0, 1] where the Hermite interpolant of λ is stationary (dλ/ds changes sign there).
   pure function hermite_stationary_point(a, b) result(t)
      type(path_point_t), intent(in) :: a, b
      real(dp) :: t
      real(dp) :: h, c2, c1, c0, discriminant, roots(2)
      integer :: k
      h = b%s - a%s
      ! dλ/dt = c2 t² + c1 t + c0 of the Hermite cubic
      c2 = 6*a%lambda + 3*h*a%dlambda_ds - 6*b%lambda + 3*h*b%dlambda_ds
      c1 = -6*a%lambda - 4*h*a%dlambda_ds + 6*b%lambda - 2*h*b%dlambda_ds
      c0 = h*a%dlambda_ds
      ! Linear interpolation of the slope is the fallback (and the answer when c2 vanishes).
      t = a%dlambda_ds/(a%dlambda_ds - b%dlambda_ds)
      if (abs(c2) <= epsilon(1.0_dp)*(abs(c1) + abs(c0))) then
         if (abs(c1) > tiny(1.0_dp)) t = -c0/c1
      else
         discriminant = c1**2 - 4*c2*c0
         if (discriminant >= 0.0_dp) then
            roots(1) = (-c1 + sqrt(discriminant))/(2*c2)
            roots(2) = (-c1 - sqrt(discriminant))/(2*c2)
            do k = 1, 2
               if (roots(k) >= 0.0_dp .and. roots(k) <= 1.0_dp) then
                  t = roots(k)
                  exit
               end if
            end do
         end if
      end if
      t = min(1.0_dp, max(0.0_dp, t))
   end function hermite_stationary_point

end module uniarc_critical_points
