!> The pace of a path: how long its steps were and how far λ went with them, kept step by step so that
!> a path that ends on its step limit (`steps` of *PATH, max_steps) can say whether it was creeping
!> (docs/contracts.md, "Progress and messages"): how many of its last steps were taken at the largest
!> step (max_increment times the first) or cut below the first, λ's change over the last 10 % of the
!> steps against its change over all of them, and whether λ's change per step fell at every step of
!> those (as it does where the path levels off toward a limit point, or where the steps are cut).
!> Facts of the steps taken only: no threshold, and no critical point, which only the locator places
!> (uniarc_path_locate, once a step has passed it).
!>
!> The path driver (uniarc_path_driver) starts a record with every analysis step and adds every
!> converged step to it; O(1) memory whatever the number of steps.
module uniarc_path_pace
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: pace_start, pace_record, pace_window_ratio, pace_level

   !> The pace of the steps of one analysis step so far.
   type, public :: pace_t
      integer :: steps = 0                !< converged steps recorded since pace_start
      integer :: max_steps = 1            !< the step limit the window is the last tenth of
      !> the window: the last max(1, max_steps/10) steps before the step limit
      integer :: window = 1
      real(dp) :: first_length = 0.0_dp   !< the first step's length (units of path_state_t%step_length)
      real(dp) :: cap_length = 0.0_dp     !< the largest step's length: max_increment × first_length
      real(dp) :: lambda_start = 0.0_dp   !< λ where the analysis step started
      real(dp) :: lambda_last = 0.0_dp    !< λ at the last recorded step
      !> λ before the window's first step, and whether the window has begun
      real(dp) :: window_lambda = 0.0_dp
      logical :: in_window = .false.
      !> Δλ of the window's first step and of the last step
      real(dp) :: window_first_change = 0.0_dp
      real(dp) :: last_change = 0.0_dp
      !> every step of the window so far changed λ the same way as the one before it, by less
      !> (|Δλ| strictly falling, never zero)
      logical :: falling = .false.
      integer :: at_cap = 0               !< the last steps in a row taken at cap_length
      integer :: below_first = 0          !< the last steps in a row taken shorter than first_length
   end type pace_t

contains

   !> Start the record of an analysis step at λ = `lambda`, with its step limit and step lengths
   !> (`first_length`, `cap_length` = max_increment × first_length, in the units of the step
   !> length: arc length, Δλ or Δu_c by the control).
   pure subroutine pace_start(pace, lambda, max_steps, first_length, cap_length)
      type(pace_t), intent(out) :: pace
      real(dp), intent(in) :: lambda, first_length, cap_length
      integer, intent(in) :: max_steps
      pace%max_steps = max(max_steps, 1)
      pace%window = max(1, pace%max_steps/10)
      pace%first_length = first_length
      pace%cap_length = cap_length
      pace%lambda_start = lambda
      pace%lambda_last = lambda
   end subroutine pace_start

   !> Add a converged step that ended at λ = `lambda`, taken with a step of `length` (the units of
   !> pace_start's lengths). A step at the cap is one of length >= cap_length: path_advance sets the
   !> next length to min(cap, ...) exactly, so a capped step equals the cap to the bit.
   pure subroutine pace_record(pace, lambda, length)
      type(pace_t), intent(inout) :: pace
      real(dp), intent(in) :: lambda, length
      real(dp) :: change
      pace%steps = pace%steps + 1
      change = lambda - pace%lambda_last
      if (length >= pace%cap_length) then
         pace%at_cap = pace%at_cap + 1
      else
         pace%at_cap = 0
      end if
      if (length < pace%first_length) then
         pace%below_first = pace%below_first + 1
      else
         pace%below_first = 0
      end if
      if (pace%steps == pace%max_steps - pace%window + 1) then
         ! the window's first step
         pace%in_window = .true.
         pace%window_lambda = pace%lambda_last
         pace%window_first_change = change
         pace%falling = change /= 0.0_dp
      else if (pace%in_window) then
         pace%falling = pace%falling .and. change*pace%last_change > 0.0_dp .and. abs(change) < abs(pace%last_change)
      end if
      pace%last_change = change
      pace%lambda_last = lambda
   end subroutine pace_record

   !> The mean factor by which |Δλ| fell per step over the window, (|Δλ_last|/|Δλ_first|)^(1/(k−1)) for
   !> k steps of the window recorded; 0 when the window has fewer than two steps or λ's change did not
   !> fall at every one of them (pace%falling).
   pure real(dp) function pace_window_ratio(pace) result(ratio)
      type(pace_t), intent(in) :: pace
      integer :: k
      ratio = 0.0_dp
      if (.not. (pace%in_window .and. pace%falling)) return
      k = pace%steps - (pace%max_steps - pace%window)
      if (k < 2) return
      ratio = (abs(pace%last_change)/abs(pace%window_first_change))**(1.0_dp/real(k - 1, dp))
   end function pace_window_ratio

   !> Where λ would level off if its change per step kept falling by the window's mean factor q
   !> (pace_window_ratio, 0 < q < 1): λ_n + Δλ_n q/(1 − q), the sum of the geometric series of the
   !> steps to come. An extrapolation of the steps taken, not a located critical point. `found` is
   !> false (and the value λ_n) when there is no such factor.
   pure subroutine pace_level(pace, level, found)
      type(pace_t), intent(in) :: pace
      real(dp), intent(out) :: level
      logical, intent(out) :: found
      real(dp) :: q
      q = pace_window_ratio(pace)
      found = q > 0.0_dp .and. q < 1.0_dp
      level = pace%lambda_last
      if (found) level = pace%lambda_last + pace%last_change*q/(1.0_dp - q)
   end subroutine pace_level

end module uniarc_path_pace
