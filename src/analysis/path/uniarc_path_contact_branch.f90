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
   public :: find_contact_branching

   !> Two candidates tie when their values and their rates at the step's start agree to this fraction
   !> of the larger: round-off of mirror-image candidates is 1e-15 to 1e-12 of the values, while
   !> candidates that merely change in the same step differ at first order.
   real(dp), parameter :: tie_tolerance = 1.0e-8_dp

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
      integer :: c, d
      if (.not. allocated(before%in_contact) .or. .not. allocated(after%in_contact)) return
      if (size(before%in_contact) /= size(after%in_contact)) return
      h = after%s - before%s
      do c = 1, size(before%in_contact)
         if (before%in_contact(c) .eqv. after%in_contact(c)) cycle
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
            if (.not. (after%in_contact(d) .eqv. before%in_contact(d))) cycle
            if (.not. ties(before%contact_value(c), before%contact_value(d))) cycle
            if (.not. ties(before%contact_rate(c), before%contact_rate(d))) cycle
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
            return
         end do
      end do
   end subroutine find_contact_branching

   !> Whether two values agree to tie_tolerance of the larger (both zero tie).
   pure logical function ties(a, b)
      real(dp), intent(in) :: a, b
      ties = abs(a - b) <= tie_tolerance*max(abs(a), abs(b))
   end function ties

end module uniarc_path_contact_branch
