!> Where a step's working set branches (docs/theory.md §2.3, "Contacts that tie"): two contact
!> candidates reach the end of their state together — the same reaction (or gap) and the same rate
!> along the path at the step's start, as a symmetric pair on a symmetric path — and the step changes
!> one of them but not the other. The contact LCP has several solutions there (release both, or either
!> one), and the working set it returns chooses a branch: the symmetric path of a whole arch goes on
!> with both released, an asymmetric branch with one. The step then leaves the branch it followed at
!> a branch point of the contact set, which neither the inertia nor a limit point shows; it is
!> reported as a `contact_branching` event in STEM.crit (Klarbring 1988, on the non-unique
!> continuation of unilateral contact problems where several contacts change at once).
module uniarc_path_contact_branch
   use uniarc_kinds, only: dp
   use uniarc_path_state, only: path_point_t
   use uniarc_critical_points, only: critical_event_t
   implicit none
   private
   public :: find_contact_branching, split_tie, tie_pair

   !> Two candidates tie when their values at the step's start agree to this fraction of the larger:
   !> round-off of mirror-image candidates is 1e-15 to 1e-8 of the values (the converged state's
   !> component along a nearly singular mode: 6.6e-9 below), while candidates that merely change in
   !> the same step differ at first order.
   real(dp), parameter :: tie_tolerance = 1.0e-8_dp
   !> ... and when their rates along the path agree to this fraction of the larger. The rates are read
   !> along the committed tangent K⁻¹R, whose round-off a nearly singular K_T amplifies by its
   !> condition: on the unstable symmetric branch of ex. 2 as a whole arch on its bed (200 elements,
   !> max_increment 0.04; μ = −1.9e-6 past the bifurcation at 117.948) the mirror candidates 40 and 162
   !> had gaps equal to 6.6e-9 and rates −2.91924801e-2 and −2.91924787e-2, 4.7e-8 apart; the step
   !> closed 40 alone and the path left the symmetric branch at λ = 118.86 with no row (review of
   !> issue 11). The path following's own test (split_tolerance) reads them to 1e-4 for the same
   !> reason; the values, of the converged state itself, keep tie_tolerance, which is what tells a
   !> mirror pair from candidates that change in the same step.
   real(dp), parameter :: rate_tie_tolerance = 1.0e-4_dp
   !> The tolerance of the path following's own test (split_tie in path_advance and the corner step):
   !> a step that splits a tied pair is cut and the pair moved together (docs/theory.md §2.3). Looser
   !> than the row's: the rates are read along the committed tangent, and where K_T is nearly singular
   !> (the pipeline over the hump past its limit: the lifted span's sideways mode is almost free) its
   !> round-off is amplified — mirror candidates 43 and 159 of steps_pipeline_hump_history.inp at
   !> step 82 had gaps equal to 7 digits and rates 8.501739e-6 and 8.501742e-6 (3.5e-7 apart). The
   !> corner step groups candidates with the same 1e-4 (uniarc_path_corner); two candidates that are
   !> no mirror pair agree in value and rate to 1e-4 only by accident.
   real(dp), parameter, public :: split_tolerance = 1.0e-4_dp

contains

   !> Append a `contact_branching` event to `events` if the step from `before` to `after` changed
   !> the state (in contact or free) of a candidate but not that of another candidate that tied with
   !> it at `before` (same state, value and rate). Its place: where the tied value, extrapolated along
   !> the path from `before`, reaches zero (fraction of the interval in path length); λ there along
   !> the tangent at `before` (the path has a kink at a change of the working set). At most one event
   !> per step. Points without contact data add nothing.
   pure subroutine find_contact_branching(before, after, events)
      type(path_point_t), intent(in) :: before, after
      type(critical_event_t), allocatable, intent(inout) :: events(:)
      type(critical_event_t) :: event
      real(dp) :: h
      integer :: c
      if (.not. allocated(before%in_contact) .or. .not. allocated(after%in_contact)) return
      if (size(before%in_contact) /= size(after%in_contact)) return
      h = after%s - before%s
      c = split_tie(before, before%in_contact, after%in_contact, h, tie_tolerance, rate_tie_tolerance)
      ! A step cut because a longer one split a tied pair, and that moved the pair together: the branch
      ! point passed on the branch followed (path_advance keeps tied contacts together).
      if (c == 0 .and. after%tie_kept) &
         c = moved_tie(before, before%in_contact, after%in_contact, h, split_tolerance)
      if (c == 0) return
      event%kind = 'contact_branching'
      event%fraction = 1.0_dp
      if (before%contact_rate(c) < 0.0_dp .and. h > 0.0_dp) then
         event%fraction = min(1.0_dp, max(0.0_dp, -before%contact_value(c)/(before%contact_rate(c)*h)))
      end if
      event%lambda = before%lambda + event%fraction*h*before%dlambda_ds
      ! The tangent's λ can leave the step where the path curves (the unloaded state's tangent
      ! of that ring reached λ = 2.0 across a step to 0.1155): the row lies within its step.
      event%lambda = min(max(event%lambda, min(before%lambda, after%lambda)), &
                         max(before%lambda, after%lambda))
      event%position = before%step + event%fraction
      events = [events, event]
   end subroutine find_contact_branching

   !> The first candidate that a step from `before` changed (its state `start` ≠ `finish`) while
   !> another candidate that tied with it at `before` (same state, value and rate) did not change:
   !> the step split a tied pair. 0 if none. `h` is the step's length along the path (the scale of a
   !> free candidate's round-off gap). Points without contact data split nothing.
   pure integer function split_tie(before, start, finish, h, tolerance, rate_tolerance) result(split)
      type(path_point_t), intent(in) :: before
      !> the fraction of the larger value, and of the larger rate, within which two candidates tie
      real(dp), intent(in) :: tolerance, rate_tolerance
      !> per candidate: in contact (or in the working set) at the step's start and at its end
      logical, intent(in) :: start(:), finish(:)
      real(dp), intent(in) :: h
      integer :: c, d
      split = 0
      if (.not. allocated(before%in_contact)) return
      if (size(before%in_contact) /= size(start) .or. size(start) /= size(finish)) return
      do c = 1, size(before%in_contact)
         if (start(c) .eqv. finish(c)) cycle
         ! A free candidate whose gap neither is open nor opens or closes at first order along the
         ! path (|gap| ≤ tie_tolerance of the step's length h, |d gap/ds| ≤ tie_tolerance, ds the
         ! length of the path's unit tangent) ties with every other such one, mirror image or not: its
         ! value and rate are round-off, no evidence of a branch. The ring in its rigid cavity at
         ! 1000 elements (half model, no mirror pair) touches everywhere at the unloaded state:
         ! candidates 206 and 188 had gap 0 and rates 4.8e-13 of identical bits in the Release build
         ! (other last bits in Debug), the step closed one, and a contact_branching row was written.
         if (.not. before%in_contact(c) .and. abs(before%contact_value(c)) <= tie_tolerance*abs(h) .and. &
             abs(before%contact_rate(c)) <= tie_tolerance) cycle
         do d = 1, size(before%in_contact)
            if (d == c) cycle
            if (.not. (before%in_contact(d) .eqv. before%in_contact(c))) cycle
            if (.not. (start(d) .eqv. finish(d))) cycle
            if (.not. tie_pair(before%contact_value(c), before%contact_value(d), before%contact_rate(c), &
                               before%contact_rate(d), h, tolerance, rate_tolerance)) cycle
            split = c
            return
         end do
      end do
   end function split_tie

   !> The first candidate that a step from `before` changed (`start` ≠ `finish`) together with another
   !> that tied with it at `before` (tie_pair): a tied pair moved together. 0 if none.
   pure integer function moved_tie(before, start, finish, h, tolerance) result(moved)
      type(path_point_t), intent(in) :: before
      logical, intent(in) :: start(:), finish(:)
      real(dp), intent(in) :: h, tolerance
      integer :: c, d
      moved = 0
      if (.not. allocated(before%in_contact)) return
      if (size(before%in_contact) /= size(start) .or. size(start) /= size(finish)) return
      do c = 1, size(before%in_contact)
         if (start(c) .eqv. finish(c)) cycle
         do d = c + 1, size(before%in_contact)
            if (start(d) .eqv. finish(d)) cycle
            if (.not. (before%in_contact(d) .eqv. before%in_contact(c))) cycle
            if (.not. tie_pair(before%contact_value(c), before%contact_value(d), before%contact_rate(c), &
                               before%contact_rate(d), h, tolerance, tolerance)) cycle
            moved = c
            return
         end do
      end do
   end function moved_tie

   !> Whether two candidates with values a, b and rates ra, rb along the path tie: the rates agree to
   !> `rate_tolerance` of the larger, and the values to `tolerance`, measured against the larger of
   !> themselves and of what the rates change in a step of length h. The second scale is that of candidates at their
   !> change: there the values are round-off about zero (gaps of 1e-21 and −3e-22 of a mirror pair
   !> past the pipeline's limit, steps_pipeline_hump_history.inp), which no relative test compares.
   pure logical function tie_pair(a, b, ra, rb, h, tolerance, rate_tolerance)
      real(dp), intent(in) :: a, b, ra, rb, h, tolerance, rate_tolerance
      tie_pair = abs(ra - rb) <= rate_tolerance*max(abs(ra), abs(rb)) .and. &
                 abs(a - b) <= tolerance*max(abs(a), abs(b), abs(ra*h), abs(rb*h))
   end function tie_pair


end module uniarc_path_contact_branch
