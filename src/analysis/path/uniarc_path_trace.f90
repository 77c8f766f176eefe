!> The memory of the path traced so far that guards a step against going back or round a loop
!> (docs/theory.md §2.3 "back along the path", §2.12 "loops of corners"): the last committed states of
!> the analysis step (displacements, λ, step number) and the committed states at which the last corners
!> were passed; and the state where the branch being traced began (the unloaded state, the start of an
!> analysis step, the bifurcation a branch switch left from), against which a path that closes on
!> itself is recognised (§2.3, "closed loops"); and the committed states of the last steps that passed
!> a critical point or a corner, against which a path that comes round to the same state again is
!> recognised (trace_event_revisited).
!>
!> Both are ring buffers allocated once, with stat=, for the path's number of unknowns (again only if an
!> analysis step renumbers the equations), and held by the caller of the path following (the path
!> driver), not in the committed state: a copy of the state (the start of a step, a probe, a landing)
!> does not copy them. Their work vectors are allocated with them. A refused allocation leaves the
!> memory empty: it only guards, so the path goes on without the guard (as a state forgotten).
!> Counted in the memory estimate (uniarc_memory: traced_vectors vectors per equation).
module uniarc_path_trace
   use uniarc_kinds, only: dp
   use uniarc_dof_map, only: dof_map_t
   use uniarc_path_state, only: masked_dot, masked_norm
   implicit none
   private
   public :: path_trace_t, traced_kept, corners_kept, traced_vectors
   public :: trace_allocate, trace_forget, trace_remember, trace_retraced_step, trace_remember_corner, &
             trace_corner_revisited, trace_set_origin, trace_closed_loop, trace_event_revisited, &
             trace_remember_event

   !> Committed states kept for the test of a step going back along the path (trace_retraced_step).
   !> A path that comes back to the piece it left through a loop of its branches goes back along it
   !> from where the loop ends: ex. 2 as a whole arch on its bed at 200 elements went back along the
   !> segment traced 32 steps before, the circular liner in its host along the one traced 58 steps
   !> before (docs/theory.md §2.3). A piece traced longer ago is not compared.
   integer, parameter :: traced_kept = 64
   !> Corners kept for the test of a loop of corners (trace_corner_revisited): a loop of more corners
   !> than that is not recognised.
   integer, parameter :: corners_kept = 8
   !> Committed states of steps that passed a critical point or a corner kept for the test of a path
   !> that comes round to one of them again (trace_event_revisited): a loop through more such steps
   !> than that is not recognised.
   integer, parameter :: events_kept = 8
   !> Vectors of the number of unknowns a path_trace_t holds: the kept states, the kept corners, the
   !> branch's origin and two work vectors (uniarc_memory's estimate counts them).
   integer, parameter :: traced_vectors = traced_kept + corners_kept + events_kept + 3
   !> A state lies along a traced segment when within this share of the segment's chord of it: the
   !> arc of a step deviates from its chord by its sagitta, |chord| tan(θ/4)/2 ≈ |chord| θ/8 for a turn θ
   !> between its end tangents, 0.05 |chord| for the turns of at most 2 × 22° measured away from folds
   !> (docs/theory.md §2.3); the pieces a corner step folds back onto run within 0.013 to 0.05 of the
   !> chords of the steps they go back over (pipeline over the hump, weight then axial force), while
   !> a new piece leaving a corner at an angle is off at first order.
   real(dp), parameter :: sagitta_share = 0.15_dp

   !> The kept states and corners. Components private: only the procedures below read and change them.
   type :: path_trace_t
      private
      integer :: n = -1                     !< length of the vectors held (-1: nothing allocated)
      real(dp), allocatable :: u(:, :)      !< (n, traced_kept) displacements of the kept states (ring)
      real(dp) :: lambda(traced_kept) = 0.0_dp
      integer :: step(traced_kept) = 0
      integer :: neg_pivots(traced_kept) = 0   !< the count of negative pivots of each kept state
      integer :: count = 0                  !< states kept
      integer :: newest = 0                 !< column of the newest kept state
      real(dp), allocatable :: corner_u(:, :)   !< (n, corners_kept) committed states of the corners (ring)
      integer :: corner_step(corners_kept) = 0
      integer :: corners = 0                !< corners kept
      integer :: corner_newest = 0
      real(dp), allocatable :: event_u(:, :)    !< (n, events_kept) committed states past an event (ring)
      real(dp) :: event_lambda(events_kept) = 0.0_dp
      integer :: event_step(events_kept) = 0
      integer :: events = 0                 !< event states kept
      integer :: event_newest = 0
      real(dp), allocatable :: chord(:), offset(:)   !< (n) work vectors
      real(dp), allocatable :: origin_u(:)  !< (n) the state where the branch traced began
      real(dp) :: origin_lambda = 0.0_dp
      integer :: origin_step = 0
      logical :: has_origin = .false.
      !> the largest distance (masked norm of the displacements) of a kept state from the origin
      real(dp) :: reach = 0.0_dp
   end type path_trace_t

contains

   !> The trace for a path of `n` unknowns, empty. Allocated only if it has none of that size; a refused
   !> allocation leaves it without arrays (no guard), which is not an error.
   subroutine trace_allocate(trace, n)
      type(path_trace_t), intent(inout) :: trace
      integer, intent(in) :: n
      integer :: status
      trace%count = 0
      trace%newest = 0
      trace%corners = 0
      trace%corner_newest = 0
      trace%events = 0
      trace%event_newest = 0
      trace%has_origin = .false.
      if (trace%n == n) return
      if (allocated(trace%u)) deallocate (trace%u)
      if (allocated(trace%corner_u)) deallocate (trace%corner_u)
      if (allocated(trace%chord)) deallocate (trace%chord)
      if (allocated(trace%offset)) deallocate (trace%offset)
      if (allocated(trace%origin_u)) deallocate (trace%origin_u)
      if (allocated(trace%event_u)) deallocate (trace%event_u)
      trace%n = -1
      allocate (trace%u(n, traced_kept), trace%corner_u(n, corners_kept), trace%chord(n), trace%offset(n), &
                trace%origin_u(n), trace%event_u(n, events_kept), stat=status)
      if (status /= 0) then
         if (allocated(trace%u)) deallocate (trace%u)
         if (allocated(trace%corner_u)) deallocate (trace%corner_u)
         if (allocated(trace%event_u)) deallocate (trace%event_u)
         if (allocated(trace%chord)) deallocate (trace%chord)
         if (allocated(trace%offset)) deallocate (trace%offset)
         if (allocated(trace%origin_u)) deallocate (trace%origin_u)
         return
      end if
      trace%n = n
   end subroutine trace_allocate

   !> The kept states, the event states and the origin are forgotten (the start of an analysis step:
   !> its λ measures another load pattern). The corners are kept.
   pure subroutine trace_forget(trace)
      type(path_trace_t), intent(inout) :: trace
      trace%count = 0
      trace%newest = 0
      trace%events = 0
      trace%event_newest = 0
      trace%has_origin = .false.
   end subroutine trace_forget

   !> The state (u (n), λ, its step) where the branch now traced begins: the unloaded state, the start
   !> of an analysis step, or the bifurcation a branch switch leaves from (trace_closed_loop).
   subroutine trace_set_origin(trace, u, lambda, step)
      type(path_trace_t), intent(inout) :: trace
      real(dp), intent(in) :: u(:), lambda
      integer, intent(in) :: step
      trace%has_origin = .false.
      if (.not. ready(trace, size(u))) return
      trace%origin_u(:) = u
      trace%origin_lambda = lambda
      trace%origin_step = step
      trace%reach = 0.0_dp
      trace%has_origin = .true.
   end subroutine trace_set_origin

   !> The step of the origin (trace_set_origin) when the last traced segment — the two newest kept
   !> states a, b, the step just committed — passes through it, or −1 (docs/theory.md §2.3, "closed
   !> loops"). A path that comes back to the state where its branch began has closed on itself:
   !> followed on, it goes round the same loop again (a secondary branch that is a closed curve
   !> through its bifurcation). Distances are those of the arc length, in (u, ψλ) (ψ = lambda_scale,
   !> the displacement a unit of λ moves at the start, > 0; `map` gives the norm of the displacements,
   !> masked_dot): through the origin means its projection on the chord b − a between −sagitta_share
   !> and 1 + sagitta_share of the way from a to b (a step may end on the origin or start from it) and
   !> its distance from the chord within sagitta_share of the chord's length, as for a step going back
   !> (trace_retraced_step); and the path has gone away first: some kept state of this branch was
   !> farther from the origin than four chords (the first steps out of the origin, or a cut-back step
   !> near it, are not a return). Called once for each committed step (it keeps the branch's reach).
   !> Out: step, the origin's step or −1; lambda, the origin's λ (0 when step is −1).
   subroutine trace_closed_loop(trace, map, lambda_scale, step, lambda)
      type(path_trace_t), intent(inout) :: trace   !< its kept states unchanged (work vectors used)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: lambda_scale
      integer, intent(out) :: step
      real(dp), intent(out) :: lambda
      real(dp) :: length2, t, reach_before, chord_lambda, offset_lambda, distance2
      integer :: a, b
      step = -1
      lambda = 0.0_dp
      if (.not. trace%has_origin .or. trace%count < 2) return
      a = column(trace%count - 1, trace%count, trace%newest, traced_kept)
      b = trace%newest
      if (trace%step(a) < trace%origin_step) return
      ! the reach before this step (the newest state's own distance is what is being tested)
      reach_before = trace%reach
      trace%offset(:) = trace%u(:, b) - trace%origin_u
      offset_lambda = lambda_scale*(trace%lambda(b) - trace%origin_lambda)
      trace%reach = max(trace%reach, sqrt(masked_dot(map, trace%offset, trace%offset) + offset_lambda**2))
      trace%chord(:) = trace%u(:, b) - trace%u(:, a)
      chord_lambda = lambda_scale*(trace%lambda(b) - trace%lambda(a))
      length2 = masked_dot(map, trace%chord, trace%chord) + chord_lambda**2
      if (.not. (length2 > 0.0_dp)) return
      if (reach_before <= 4.0_dp*sqrt(length2)) return
      trace%offset(:) = trace%origin_u - trace%u(:, a)
      offset_lambda = lambda_scale*(trace%origin_lambda - trace%lambda(a))
      t = (masked_dot(map, trace%offset, trace%chord) + offset_lambda*chord_lambda)/length2
      if (.not. (t >= -sagitta_share .and. t <= 1.0_dp + sagitta_share)) return
      trace%offset(:) = trace%offset - t*trace%chord
      distance2 = masked_dot(map, trace%offset, trace%offset) + (offset_lambda - t*chord_lambda)**2
      if (distance2 > sagitta_share**2*length2) return
      step = trace%origin_step
      lambda = trace%origin_lambda
   end subroutine trace_closed_loop

   !> Whether the trace holds vectors of length n (reallocated for n if not: an analysis step that
   !> renumbered the equations starts empty).
   logical function ready(trace, n)
      type(path_trace_t), intent(inout) :: trace
      integer, intent(in) :: n
      if (trace%n /= n) call trace_allocate(trace, n)
      ready = trace%n == n
   end function ready

   !> The column of the k-th oldest of `count` entries of a ring whose newest is in column `newest` of
   !> `kept`.
   pure integer function column(k, count, newest, kept)
      integer, intent(in) :: k, count, newest, kept
      column = modulo(newest - count + k - 1, kept) + 1
   end function column

   !> The committed state (u, λ, its step) appended to the kept states (the last traced_kept); if none
   !> is kept, the start of the step (u_before, λ_before, its step) first.
   subroutine trace_remember(trace, u, lambda, step, neg_pivots, u_before, lambda_before, step_before, &
                             neg_pivots_before)
      type(path_trace_t), intent(inout) :: trace
      real(dp), intent(in) :: u(:), u_before(:)
      real(dp), intent(in) :: lambda, lambda_before
      integer, intent(in) :: step, step_before
      !> the count of negative pivots of the state and of the one before it
      integer, intent(in) :: neg_pivots, neg_pivots_before
      if (.not. ready(trace, size(u))) return
      if (trace%count == 0) call push(trace, u_before, lambda_before, step_before, neg_pivots_before)
      call push(trace, u, lambda, step, neg_pivots)
   end subroutine trace_remember

   !> One state into the ring of kept states.
   pure subroutine push(trace, u, lambda, step, neg_pivots)
      type(path_trace_t), intent(inout) :: trace
      real(dp), intent(in) :: u(:), lambda
      integer, intent(in) :: step, neg_pivots
      trace%newest = modulo(trace%newest, traced_kept) + 1
      trace%count = min(trace%count + 1, traced_kept)
      trace%u(:, trace%newest) = u
      trace%lambda(trace%newest) = lambda
      trace%step(trace%newest) = step
      trace%neg_pivots(trace%newest) = neg_pivots
   end subroutine push

   !> The step number at the start of a traced segment (two consecutive kept states a, b, before the
   !> step that started at step `step_before`) along which the committed state (u (n), λ) lies, going
   !> back; 0 if none (docs/theory.md §2.3, "back along the path"). Along the segment: the
   !> displacements' projection on its chord b − a between −sagitta_share and 1 + sagitta_share of the
   !> way from a to b and within sagitta_share of the chord's length of it, λ within sagitta_share of
   !> the segment's Δλ of its range; going back: the step's `increment` (n) makes an obtuse angle with
   !> b − a and its Δλ `dlambda` has the other sign than the segment's (a piece whose displacements run
   !> back near the traced ones while λ goes on the same way is another piece: pipeline_hump_corner_100
   !> past its corner at step 137, λ falling with two contacts where it fell with four). The working set
   !> is not compared: the piece a corner step folds back onto differs from the traced one by a contact
   !> of almost no reaction (pipeline over the hump, weight then axial force: one node). The segment
   !> that ends at the step's start is not tested: going back over it is the reversal test's (and a
   !> corner may turn back by more than a right angle there, §2.12). `neg_pivots` ≥ 0: only segments
   !> whose two ends have that count of negative pivots (a state of a smooth piece goes back along the
   !> path only where it lies on it, with its inertia; the far side of a regular fold has the count of
   !> the near side changed by one); −1: any segment.
   integer function trace_retraced_step(trace, map, u, lambda, step_before, increment, dlambda, neg_pivots) &
      result(step)
      type(path_trace_t), intent(inout) :: trace   !< its kept states unchanged (work vectors used)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: u(:), lambda, increment(:), dlambda
      integer, intent(in) :: step_before, neg_pivots
      real(dp) :: length2, t, low, high
      integer :: k, a, b
      step = 0
      if (trace%n /= size(u)) return
      do k = 1, trace%count - 1
         a = column(k, trace%count, trace%newest, traced_kept)
         b = column(k + 1, trace%count, trace%newest, traced_kept)
         if (trace%step(b) >= step_before) cycle
         if (neg_pivots >= 0 .and. (trace%neg_pivots(a) /= neg_pivots .or. trace%neg_pivots(b) /= neg_pivots)) &
            cycle
         if (dlambda*(trace%lambda(b) - trace%lambda(a)) >= 0.0_dp) cycle
         trace%chord(:) = trace%u(:, b) - trace%u(:, a)
         length2 = masked_dot(map, trace%chord, trace%chord)
         if (length2 <= 0.0_dp) cycle
         if (masked_dot(map, increment, trace%chord) >= 0.0_dp) cycle
         if (dlambda*(trace%lambda(b) - trace%lambda(a)) >= 0.0_dp) cycle
         trace%offset(:) = u - trace%u(:, a)
         t = masked_dot(map, trace%offset, trace%chord)/length2
         if (t < -sagitta_share .or. t > 1.0_dp + sagitta_share) cycle
         trace%offset(:) = trace%offset - t*trace%chord
         if (masked_norm(map, trace%offset) > sagitta_share*sqrt(length2)) cycle
         low = min(trace%lambda(a), trace%lambda(b))
         high = max(trace%lambda(a), trace%lambda(b))
         if (lambda < low - sagitta_share*(high - low) .or. lambda > high + sagitta_share*(high - low)) cycle
         step = trace%step(a)
         return
      end do
   end function trace_retraced_step

   !> The committed state u (n) at step `step` kept as a corner passed (the last corners_kept).
   subroutine trace_remember_corner(trace, u, step)
      type(path_trace_t), intent(inout) :: trace
      real(dp), intent(in) :: u(:)
      integer, intent(in) :: step
      if (.not. ready(trace, size(u))) return
      trace%corner_newest = modulo(trace%corner_newest, corners_kept) + 1
      trace%corners = min(trace%corners + 1, corners_kept)
      trace%corner_u(:, trace%corner_newest) = u
      trace%corner_step(trace%corner_newest) = step
   end subroutine trace_remember_corner

   !> The step at which the path passed a corner at the committed state u (n) before (the same
   !> displacements to 1e-9 of their size: a loop comes back to the same converged state up to the
   !> round-off of its corrections, 1e-11 measured on pipeline_hump_corner_200; distinct corners of
   !> a path differ in their displacements by far more), or 0. The oldest corner is compared first.
   integer function trace_corner_revisited(trace, u) result(step)
      type(path_trace_t), intent(inout) :: trace   !< its corners unchanged (work vector used)
      real(dp), intent(in) :: u(:)
      integer :: k, c
      step = 0
      if (trace%n /= size(u)) return
      do k = 1, trace%corners
         c = column(k, trace%corners, trace%corner_newest, corners_kept)
         if (same_displacements(trace, u, trace%corner_u(:, c))) then
            step = trace%corner_step(c)
            return
         end if
      end do
   end function trace_corner_revisited

   !> The committed state (u (n), λ) of step `step`, a step that passed a critical point or a corner,
   !> kept (the last events_kept) for trace_event_revisited.
   subroutine trace_remember_event(trace, u, lambda, step)
      type(path_trace_t), intent(inout) :: trace
      real(dp), intent(in) :: u(:), lambda
      integer, intent(in) :: step
      if (.not. ready(trace, size(u))) return
      trace%event_newest = modulo(trace%event_newest, events_kept) + 1
      trace%events = min(trace%events + 1, events_kept)
      trace%event_u(:, trace%event_newest) = u
      trace%event_lambda(trace%event_newest) = lambda
      trace%event_step(trace%event_newest) = step
   end subroutine trace_remember_event

   !> The step of a kept event state (trace_remember_event) that the committed state (u (n), λ) of a
   !> step past a critical point or a corner repeats, or 0 (docs/theory.md §2.3, "closed loops"): the
   !> same displacements to 1e-9 of their size and λ to 1e-9 of the larger |λ|, as for a corner
   !> revisited (trace_corner_revisited; the tolerance is that of the round-off of a converged state,
   !> distinct states of a path differ at first order). The path following is deterministic: from
   !> the same state with the same step length it takes the same steps, so a path whose steps come
   !> back to a state they passed goes round the same loop for ever. Its steps need not land on the
   !> same states on a second pass, but once one pass has taken the steps of the one before, every
   !> state repeats; comparing the states past an event (few, and at the same place of each pass)
   !> finds it at the first repeat. The oldest kept state is compared first.
   integer function trace_event_revisited(trace, u, lambda) result(step)
      type(path_trace_t), intent(inout) :: trace   !< its event states unchanged (work vector used)
      real(dp), intent(in) :: u(:), lambda
      integer :: k, c
      step = 0
      if (trace%n /= size(u)) return
      do k = 1, trace%events
         c = column(k, trace%events, trace%event_newest, events_kept)
         if (abs(lambda - trace%event_lambda(c)) > 1.0e-9_dp*max(abs(lambda), abs(trace%event_lambda(c)))) cycle
         if (same_displacements(trace, u, trace%event_u(:, c))) then
            step = trace%event_step(c)
            return
         end if
      end do
   end function trace_event_revisited

   !> The displacements u (n) are those of a kept state `kept` (n) to 1e-9 of the size of u: the
   !> round-off of a converged state (trace_corner_revisited, trace_event_revisited).
   logical function same_displacements(trace, u, kept)
      type(path_trace_t), intent(inout) :: trace   !< work vector used
      real(dp), intent(in) :: u(:), kept(:)
      trace%offset(:) = u - kept
      same_displacements = norm2(trace%offset) <= 1.0e-9_dp*max(norm2(u), tiny(1.0_dp))
   end function same_displacements

end module uniarc_path_trace
