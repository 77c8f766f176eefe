!> Critical points between two converged steps located by re-solving (docs/theory.md §2.2).
!>
!> A limit point or a bifurcation that the step has passed is bracketed by the step: the state at its
!> start (`before`) is on one side, the converged state (`after`) on the other. The locator re-solves
!> the step from `before` with shorter lengths h ∈ (0, Δl) — each a converged equilibrium state, with
!> its tangent, inertia and least eigenvalue — and narrows the bracket: for a limit point on the sign
!> of dλ/ds, for a bifurcation on whether the count of negative pivots has changed, the new h by the
!> secant (regula falsi) on dλ/ds or on the least eigenvalue, safeguarded by bisection (Crisfield
!> 1997, Non-linear Finite Element Analysis of Solids and Structures vol. 2, ch. 21: locating critical
!> points). Every probe must lie on the piece of path between the bracket's ends (its λ between
!> theirs where λ is monotone, beyond the lower end's towards a limit): a re-solution that converges
!> elsewhere — at a state where the arc-length sphere meets another equilibrium, a contact set the
!> path does not take — ends the narrowing as one that does not converge. On the final bracket
!> (below 1e-3 of the step) a limit point is placed by the cubic Hermite
!> interpolant of uniarc_critical_points, a bifurcation where the least eigenvalue vanishes, between
!> two converged states that close together; a located limit is as high (a minimum as low) as every
!> converged state around it. A bifurcation whose bracket could not be narrowed is placed at a
!> converged end of the bracket so far (the one nearer to where the least eigenvalue, linear between
!> them, vanishes), and flagged, never interpolated across a wide bracket. The probes never change the committed state; the system of equations
!> is returned holding the committed tangent.
module uniarc_path_locate
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, control_displacement
   use uniarc_path_state, only: path_state_t, path_point_t, path_system_t, &
                                bifurcation_state_t, masked_norm
   use uniarc_path_probe, only: re_solve_step, restore_tangent
   use uniarc_path_state_copy, only: copy_state, move_state, copy_point_record, move_point
   use uniarc_error, only: error_t, error_analysis
   use uniarc_foreign, only: interrupt_signal
   use uniarc_memory, only: allocation_failure
   use uniarc_critical_points, only: critical_event_t, find_critical_events, opposite_signs, same_signs
   use uniarc_path_integrator, only: degenerate_tangent
   use uniarc_path_stability, only: cone_mode
   implicit none
   private
   public :: locate_critical_points

   !> Re-solved states per located point: the bracket shrinks by a factor ≥ 2 every other probe, so
   !> 16 reach the bracket tolerance from any step.
   integer, parameter :: max_probes = 16
   !> The bracket is narrowed to this fraction of the step length. Across it the cubic interpolant
   !> of λ has an error O(w⁴) of 1e-12 of the step's own, far below the equilibrium tolerance.
   real(dp), parameter :: bracket_tolerance = 1.0e-3_dp
   !> The bracket of a bifurcation the path is to switch branches at (`*PATH, SWITCH=n`): the state the
   !> secondary branch leaves from is the one re-solved at the located point, and its λ is within
   !> 1e-6 (relative) of the located bifurcation's (docs/contracts.md) when the bracket is 1e-7 of the
   !> step (λ varies across it by 1e-7 of the step's Δλ; Walker's whole arch: 4.8e-6 absolute, 7e-8
   !> relative, at 1e-3; below 1e-9 at 1e-7). Bisection from 1e-3 to 1e-7 takes 14 more probes.
   real(dp), parameter :: switch_bracket_tolerance = 1.0e-7_dp
   integer, parameter :: switch_max_probes = 32
   !> The two converged ends of a bifurcation's final bracket are on one branch if their distance is
   !> at most this many times the bracket's share of the step's chord ||Δu||·(h_b − h_a)/Δl. On a
   !> branch the ratio is 1 up to the curvature across 1e-3 of a step (most decks of the repository
   !> that locate a bifurcation: 1.0000 to 1.00004); Walker's whole arch with a crown imperfection of
   !> 1e-4, whose step jumped across the near-bifurcation: 616. Not enough alone: near a true
   !> bifurcation the probes may converge on the bifurcated branch (the pressurised rings: 165 to
   !> 3e5), so the load must also see the critical mode at both ends (mode_load_cosine).
   real(dp), parameter :: gap_ratio = 10.0_dp
   !> The reference load sees the least eigenvector when |φᵀR| exceeds this fraction of |φ||R|: at
   !> the bifurcations of the repository's symmetric decks it is round-off (at most 3e-8, the
   !> pressurised rings, on the bifurcated branch), at the near-bifurcation of Walker's whole arch with
   !> a crown imperfection of 1e-4 it is 1.9e-4 and 1.1e-2 (it scales with the imperfection).
   real(dp), parameter :: mode_load_cosine = 1.0e-6_dp
   !> The count changes at a contact event (the least eigenvalue μ jumps across zero where the working
   !> set changes) only if, with m = (h_b − h_a)/Δl |μ_after − μ_before| the change of μ that a smooth
   !> piece makes across the final bracket (its share of μ's change over the step), μ changes across
   !> the bracket by more than jump_ratio m and is more than regular_ratio m away from zero at both of
   !> its ends: the tangent is regular on either side. A smooth zero crossing inside the bracket leaves
   !> both ends within about m of zero (regular_ratio allows for μ's curvature over the step); a
   !> contact event that shares its bracket does not make it one. Measured, as (change, nearer end)/m:
   !> the perfect oval liner in its host at its three-lobed bifurcation, a contact opening within the
   !> bracket, (0.64, 0.17) at om = 0.001 (Release), (136, 0.33) at om = 0.02 (Debug: the far end of
   !> the bracket re-solved 0.013 higher in λ, on another set) — bifurcations; the bed pairs touching
   !> Walker's whole arch (2190, 616) at 80 elements, (2800, 504) at 120, (200, 14.7) at 160 (at
   !> 146.6) — contact events.
   real(dp), parameter :: jump_ratio = 10.0_dp
   real(dp), parameter :: regular_ratio = 2.0_dp
   !> A probe is on the piece of path between the bracket's ends if its λ is within their range
   !> (where λ is monotone; towards a limit, on the far side of the lower end's λ), widened by
   !> piece_slack of the whole step's change of λ plus round_slack of |λ|. A state on the piece lies
   !> inside; the slack is for the probes' own error, which near a bifurcation is more than the
   !> equilibrium tolerance: there a re-solution may converge on the bifurcated branch, or along the
   !> near-singular mode, a little off the primary path (Walker's whole arch at its bifurcation
   !> 66.3952, Debug build: probes 1.6e-9 of λ outside brackets of 1e-7 of the step, and one 2.7e-4
   !> outside a bracket in a step of Δλ = 0.03, 1 % of it). The probes off the path that this rejects
   !> lie 10 % to 25 % of the step's change of λ and more outside the bracket: ex. 3 as a whole arch,
   !> arch_above_full.inp at k = 1e6, re-solved 0.9375 of step 26 at λ = 55.13 on a contact set of 20,
   !> 1.2 below the bracket's range (56.67 to 56.31; the step's Δλ 4.69) where the path has 22
   !> contacts, and placed a bifurcation at 55.26, 2.4 % below a fine trace's path at its w_crown; the
   !> pipeline over its hump (steps_pipeline_hump_history.inp) and the round liner in its host (eps =
   !> 2e-3) wrote rows 10 % to 55 % of their step's Δλ outside their neighbours.
   real(dp), parameter :: piece_slack = 5.0e-2_dp
   real(dp), parameter :: round_slack = 1.0e-9_dp

contains

   !> Locate the limit point (dλ/ds changes sign between before%point and after%point) or, if there
   !> is none, the bifurcation (the number of negative pivots changes) that the step from `before`
   !> (a copy of the committed state at its start, system not allocated) to `after` (the committed
   !> state it reached with a step of length `length`, the units of state%step_length) passed.
   !> On return after%point%limit_fraction/limit_lambda or bifurcation_fraction/bifurcation_lambda
   !> hold it (fraction of the interval in path length, λ). A probe that does not converge, or that
   !> converges off the piece of path between the bracket's ends (on_piece), ends the narrowing (the
   !> bracket so far is used; a bifurcation is then placed at one of its converged ends,
   !> after%point%bifurcation_unbracketed). `system` holds after's committed tangent on entry and on
   !> return (re-assembled if a probe used it). A failure leaves the fields at −1; the only errors are
   !> out of memory (error_analysis, flagged out_of_memory: the run ends).
   !> A located bifurcation also sets after%point%bifurcation_multiplicity, the change of the count
   !> across the final bracket once it is narrowed to its tolerance (2 at a double eigenvalue; 0 if
   !> the bracket could not be narrowed), and after%bifurcation: the converged state at the located
   !> point (one more re-solution; if it fails or lands off the bracket's piece, the end of the final
   !> bracket whose least eigenvalue is of smaller magnitude; the end it is placed at where
   !> unbracketed) and its least
   !> eigenvector,
   !> the buckling mode (of K_T, or of the tangent with the touching contacts released at a lift-off).
   !> `left_branch`: the count changed across a final bracket whose two converged ends are more than
   !> gap_ratio times farther apart than the bracket's share of the step's chord, and where the load
   !> sees the least eigenvector at both ends (a limit point, φᵀR ≠ 0, that λ did not turn at) — the
   !> step left the branch it followed (nothing is located; the caller rejects the step).
   !> `unresolved`: a re-solution failed before the bracket of a limit point was narrowed to its
   !> tolerance, or a re-solution of either kind of point converged off the piece of path between the
   !> bracket's ends (the point is placed from the bracket so far; the caller may cut the step and
   !> locate it again); or one failed before the bracket of a bifurcation was narrowed, where the load
   !> sees the least eigenvector at both of its ends (a near-bifurcation that the gap test cannot judge).
   !> `unexplained_limit`: λ turns (a limit point, located as usual) while the count of negative pivots
   !> at the step's end is that of its start, with one working set across the final bracket and the
   !> load seeing the least eigenvector at both of its ends (φᵀR ≠ 0: a limit point, where one eigenvalue
   !> crosses zero) — the step passed a second critical point, or landed on another branch; the caller
   !> cuts it. (Where φᵀR is round-off, λ turns at a symmetric pitchfork passed along its bifurcated
   !> branch, whose two sides are mirror images with the same count: a path of its own, kept.)
   !> Errors: out of memory in a re-solution (error_analysis; the run ends).
   subroutine locate_critical_points(model, before, after, system, length, left_branch, unresolved, &
                                     unexplained_limit, error, switching)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: before   !< unchanged (inout for copy_state)
      type(path_state_t), intent(inout) :: after
      type(path_system_t), intent(inout) :: system
      real(dp), intent(in) :: length
      logical, intent(out) :: left_branch
      !> a re-solution inside the bracket did not converge before it was narrowed to the tolerance
      logical, intent(out) :: unresolved
      !> a limit point that the load sees, passed with the count of negative pivots unchanged
      logical, intent(out) :: unexplained_limit
      !> the path switches branches at the bifurcation if the step passed one: a finer bracket
      logical, intent(in), optional :: switching
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: tolerance
      integer :: probes
      type(path_point_t) :: pa, pb, probe
      type(path_state_t) :: probe_state, state_a, state_b
      type(critical_event_t), allocatable :: events(:)
      real(dp) :: ha, hb, h, fa, fb, fp, width, t
      !> the most extreme λ of the converged probes (highest past a maximum, lowest past a minimum)
      !> and the step parameter h of its probe
      real(dp) :: extreme_lambda, extreme_h
      logical :: have_extreme
      integer :: k, same_side, last_side, side, status
      logical :: limit, bifurcation, probed, converged
      logical, allocatable :: set_a(:), set_b(:)
      after%point%limit_fraction = -1.0_dp
      after%point%bifurcation_fraction = -1.0_dp
      after%point%bifurcation_multiplicity = 0
      after%point%bifurcation_unbracketed = .false.
      after%point%stability_by_contact = .false.
      after%point%stability_fraction = -1.0_dp
      after%point%limit_by_contact = .false.
      left_branch = .false.
      unresolved = .false.
      unexplained_limit = .false.
      tolerance = bracket_tolerance
      probes = max_probes
      if (present(switching)) then
         if (switching) then
            tolerance = switch_bracket_tolerance
            probes = switch_max_probes
         end if
      end if
      limit = opposite_signs(before%point%dlambda_ds, after%point%dlambda_ds)
      bifurcation = .not. limit .and. before%point%neg_pivots /= after%point%neg_pivots
      if (.not. (limit .or. bifurcation)) return
      if (.not. (length > 0.0_dp)) return
      ha = 0.0_dp
      hb = length
      call copy_point_record(before%point, pa, 'the point at the start of the step', error)
      if (.not. allocated(error)) call copy_point_record(after%point, pb, 'the point at the end of the step', error)
      if (allocated(error)) return
      fa = indicator(pa)
      fb = indicator(pb)
      set_a = before%active
      set_b = after%active
      ! (a limit with the count unchanged keeps the bracket's states too, for their modes)
      if (bifurcation .or. (limit .and. before%point%neg_pivots == after%point%neg_pivots)) then
         call copy_state(before, state_a, 'the state at the start of the step', error)
         if (.not. allocated(error)) call copy_state(after, state_b, 'the state at the end of the step', error)
         if (allocated(error)) return
      end if
      probed = .false.
      have_extreme = .false.
      extreme_lambda = 0.0_dp
      extreme_h = 0.0_dp
      last_side = 0
      same_side = 0
      do k = 1, probes
         width = hb - ha
         if (width <= tolerance*length) exit
         ! A SIGINT or SIGTERM ends the search; the step it serves is abandoned (path_driver: driver_step).
         if (interrupt_signal() /= 0) exit
         ! Secant (regula falsi) on the indicator when it changes sign across the bracket, kept 5 %
         ! inside it; bisection when it does not or when one end has moved twice in a row (the
         ! regula falsi's one-sided stall).
         h = ha + 0.5_dp*width
         if (opposite_signs(fa, fb) .and. same_side < 2) then
            h = ha + width*fa/(fa - fb)
            h = min(hb - 0.05_dp*width, max(ha + 0.05_dp*width, h))
         end if
         call re_solve(h, probe, probe_state, converged)
         if (allocated(error)) return
         if (.not. converged) then
            ! The bracket cannot be narrowed: the interpolation across it may place the point far
            ! from the path's (ex. 3 as a whole arch: a limit_min at 130.81 across a step whose
            ! contact set changed, where a fine trace has three limits between 131.56 and 133.58).
            ! (Limit points only: a bifurcation bracketed so far is placed by the least eigenvalue,
            ! linear across it; cutting such steps changed the step sequence of ex. 2 as a whole arch
            ! at k = 5e4, 160 elements, where the path then left its symmetric branch at a corner.)
            unresolved = limit .and. width > tolerance*length
            exit
         end if
         probed = .true.
         if (.not. on_piece(probe, pa, pb)) then
            ! Converged off the piece of path between the bracket's ends: no bracket point. As a
            ! probe that does not converge, it ends the narrowing; the step is cut and located again
            ! in a shorter one if it may be (uniarc_path_following), else the point is placed from
            ! the bracket so far (a bifurcation at its end where the count changed).
            unresolved = width > tolerance*length
            exit
         end if
         fp = indicator(probe)
         if (limit) call keep_extreme(probe%lambda, h)
         if (passed(probe)) then
            hb = h
            call move_point(probe, pb)
            fb = fp
            set_b = probe_state%active
            side = 1
            if (allocated(state_b%u)) call move_state(probe_state, state_b)
         else
            ha = h
            call move_point(probe, pa)
            fa = fp
            set_a = probe_state%active
            side = -1
            if (allocated(state_a%u)) call move_state(probe_state, state_a)
         end if
         if (side == last_side) then
            same_side = same_side + 1
         else
            same_side = 1
         end if
         last_side = side
      end do
      ! The point on the final bracket. Its fraction of the step is measured in the step parameter h
      ! (the path length of the probes is not monotone in h where the tangent is near-singular: its
      ! round-off mode enters the increments). A limit: the interpolation of the detector between pa
      ! and pb (cubic in the path length, or the higher end if their path lengths are out of order); a
      ! bifurcation: where the least eigenvalue, linear between them, vanishes (the middle if it is
      ! the same at both).
      t = 0.5_dp
      if (limit) then
         after%point%limit_lambda = pa%lambda
         if (pb%s > pa%s) then
            call find_critical_events(pa, pb, events)
            do k = 1, size(events)
               if (events(k)%kind /= 'limit_max' .and. events(k)%kind /= 'limit_min') cycle
               t = events(k)%fraction
               after%point%limit_lambda = events(k)%lambda
               exit
            end do
         end if
         if (before%point%dlambda_ds > 0.0_dp) then
            after%point%limit_lambda = max(after%point%limit_lambda, pa%lambda, pb%lambda)
         else
            after%point%limit_lambda = min(after%point%limit_lambda, pa%lambda, pb%lambda)
         end if
         after%point%limit_fraction = min(1.0_dp, max(0.0_dp, (ha + t*(hb - ha))/length))
         ! Every probe is a converged state of the piece of path between the step's ends, on which λ
         ! has this one extremum: the limit is at least as extreme as each of them. Where the fold is
         ! almost a corner of λ(s) and Chan's corrections spread the probes along the path more than
         ! their lengths h differ, the final bracket (narrowed in h) can hold a spurious pair of
         ! slopes while a probe outside it lay nearer the extremum: ex. 3's long path with 160
         ! elements and steps up to 15 times the first bracketed its fourth limit_min between
         ! −208.940 and −208.958, interpolated −208.96 and reported the step's end, −208.966, while a
         ! probe had converged at −208.9717 (the limit of a trace with 4 times smaller steps,
         ! −208.97175: docs/theory.md §2.2). That probe's λ is then the point's.
         if (have_extreme) then
            if (before%point%dlambda_ds > 0.0_dp .and. extreme_lambda > after%point%limit_lambda .or. &
                before%point%dlambda_ds < 0.0_dp .and. extreme_lambda < after%point%limit_lambda) then
               after%point%limit_lambda = extreme_lambda
               ! (its place too, if it lies outside the final bracket)
               if (extreme_h < ha .or. extreme_h > hb) &
                  after%point%limit_fraction = min(1.0_dp, max(0.0_dp, extreme_h/length))
            end if
         end if
         ! dλ/ds jumps across the sign change where the working set changes: the ends of the final
         ! bracket (narrowed on the sign of dλ/ds) have different sets, and at least half of the
         ! step's change of dλ/ds happens across that bracket (on a smooth piece the change across it
         ! is its width's share, 1e-3; arch_pressure_flat where the crown touches: -0.067 to +3.2
         ! across 2.6e-3 of the step, 108 % of the step's change). A corner of the path, where λ turns
         ! without a smooth extremum — a contact event, not a limit point (docs/theory.md §2.12).
         if (any(set_a .neqv. set_b) .and. abs(fb - fa) >= &
             0.5_dp*abs(after%point%dlambda_ds - before%point%dlambda_ds)) then
            after%point%limit_by_contact = .true.
            after%point%limit_fraction = min(1.0_dp, max(0.0_dp, ha/length))
            after%point%limit_lambda = pa%lambda
            ! Each piece is smooth up to the corner: λ there is where the two pieces' tangent lines
            ! meet, λ_a + (dλ/ds)_a (s − s_a) = λ_b + (dλ/ds)_b (s − s_b), with s between s_a and s_b
            ! (error O(curvature × bracket²) against O(slope × bracket) for pa's own λ: ex. 3 as a
            ! whole arch, arch_above_full.inp, maxima where contacts close 1.1e-4 to 3.7e-4 below a
            ! trace with steps 25 times smaller at pa, within 2e-7 of it here). Else pa's λ.
            if (pb%s > pa%s .and. fa*fb < 0.0_dp) then
               t = (pb%lambda - pa%lambda - fb*(pb%s - pa%s))/((fa - fb)*(pb%s - pa%s))
               if (t >= 0.0_dp .and. t <= 1.0_dp) after%point%limit_lambda = pa%lambda + fa*t*(pb%s - pa%s)
            end if
         end if
         ! A smooth limit point is a simple zero of det K_T whose eigenvector the load sees: the
         ! count changes by one across it. Where the count at the step's end is that of its start
         ! and the narrowed bracket's ends (one working set, no lift-off) both see their mode in
         ! the load, the step went past another critical point as well, or landed on another branch
         ! (docs/theory.md §2.3, "a limit that the inertia does not see"). |φᵀR|/(|φ||R|) measured
         ! there: Walker's whole arch with a crown load of 1e-6 to 1e-5 P, whose steps jumped across
         ! the broken bifurcations at its limits (66.39, −35.72) onto the mirror image of the path,
         ! 2.7e-4 to 1.1e-3; the switched branch of the whole arch on its bed (SWITCH=1, 120
         ! elements) passing through the symmetric pitchfork at its top, 146.97, and back through
         ! its bifurcation at 118.27: 5.6e-8 to 7.1e-8 and 9e-13 (the φᵀR of a symmetric mode,
         ! round-off; mode_load_cosine lies between).
         if (allocated(state_a%u) .and. allocated(state_b%u) .and. hb - ha <= tolerance*length .and. &
             .not. after%point%limit_by_contact .and. .not. any(set_a .neqv. set_b) .and. &
             .not. (pa%liftoff .or. pb%liftoff)) &
            unexplained_limit = load_sees_mode(state_a) .and. load_sees_mode(state_b)
      else if (hb - ha <= tolerance*length .and. any(state_a%active .neqv. state_b%active) .and. &
               jumps_at_contact()) then
         ! The count changes where the working set does (within 1e-3 of the step): a contact closing
         ! or opening adds or removes its stiffness, and the least eigenvalue jumps across zero there
         ! (ex. 2 as a whole arch at k = 5e4: from -4.3e-6 to +9.1e-6 where a pair of nodes touches the
         ! bed) without the tangent being singular on either side. Not a bifurcation: no branch
         ! crosses, and no mode to switch to (docs/theory.md §2.2); a `contact_stability` row, placed
         ! at the converged end of the final bracket where the count has changed (a state of the path,
         ! within 1e-3 of the step of the change). (Where μ passes through zero smoothly in a bracket that
         ! a contact event happens to share, jumps_at_contact is false: a bifurcation, below.)
         after%point%stability_by_contact = .true.
         after%point%stability_fraction = min(1.0_dp, max(0.0_dp, hb/length))
         after%point%stability_lambda = pb%lambda
      else if (hb - ha <= tolerance*length .and. .not. in_lambda_alone() .and. &
               load_sees_mode(state_a) .and. load_sees_mode(state_b) .and. &
               masked_norm(after%map, state_b%u - state_a%u)*length > &
               gap_ratio*(hb - ha)*masked_norm(after%map, after%u - before%u)) then
         ! The ends of the final bracket are far apart for their distance in h: the re-solved states
         ! change branch there, no branch crosses. The step went past a near-bifurcation of an
         ! imperfect structure (where its path turns sharply to a limit point) onto the
         ! complementary path (docs/theory.md §2.3): the caller rejects it and cuts the step.
         left_branch = .true.
      else if (hb - ha > tolerance*length) then
         ! The bracket could not be narrowed (a re-solution failed, or converged off the piece of path
         ! between the bracket's ends): the bifurcation is placed at one of its converged ends, and
         ! flagged — not interpolated across the bracket so far: at pa if the least eigenvalue,
         ! linear between them, vanishes nearer to it, else at pb, where the count is seen changed.
         ! Its state and mode are that end's.
         after%point%bifurcation_unbracketed = .true.
         ! Where the load sees the least eigenvector at both ends of that wide bracket, the count
         ! changed at a limit point (φᵀR ≠ 0) that λ did not turn at, as at the near-bifurcation of
         ! an imperfect structure, whose step may have gone past it onto the complementary path —
         ! the gap test above needs the narrowed bracket to tell. Walker's whole arch with an
         ! antisymmetric imperfection of amplitude 1e-6: a probe failed on a bracket of 0.018 of the
         ! step, |φᵀR|/(|φ||R|) 5.1e-4 and 1.8e-3 at its ends, and the step had landed on the
         ! complementary path (the crown's sideways displacement from +2.8e-5 to −1.4e-5; a
         ! `bifurcation` at 66.39 and the perfect arch's limit 76.43 followed). Located like a limit
         ! point that could not be bracketed: the caller cuts the step while it can (docs/theory.md
         ! §2.3); at the smallest step the bifurcation placed here is kept.
         if (.not. in_lambda_alone()) &
            unresolved = unresolved .or. (load_sees_mode(state_a) .and. load_sees_mode(state_b))
         t = 1.0_dp
         if (opposite_signs(pa%min_eigenvalue, pb%min_eigenvalue)) then
            if (pa%min_eigenvalue/(pa%min_eigenvalue - pb%min_eigenvalue) < 0.5_dp) t = 0.0_dp
         end if
         if (t < 0.5_dp) then
            after%point%bifurcation_lambda = pa%lambda
            after%point%bifurcation_fraction = min(1.0_dp, max(0.0_dp, ha/length))
            call keep_bifurcation(state_a)
         else
            after%point%bifurcation_lambda = pb%lambda
            after%point%bifurcation_fraction = min(1.0_dp, max(0.0_dp, hb/length))
            call keep_bifurcation(state_b)
         end if
      else
         ! Linear in the least eigenvalue, clamped to the bracket: at pa it may be a round-off zero
         ! of either sign (pa within 1e-11 of the point).
         if (pa%min_eigenvalue /= pb%min_eigenvalue) then
            t = min(1.0_dp, max(0.0_dp, pa%min_eigenvalue/(pa%min_eigenvalue - pb%min_eigenvalue)))
         end if
         after%point%bifurcation_lambda = pa%lambda + t*(pb%lambda - pa%lambda)
         after%point%bifurcation_fraction = min(1.0_dp, max(0.0_dp, (ha + t*(hb - ha))/length))
         ! How many eigenvalues vanish there: the change of the count across the final bracket (a
         ! double eigenvalue changes it by two at one point; two simple bifurcations inside the step
         ! leave a probe between them with the count changed by one, and the bracket narrows onto
         ! the first).
         after%point%bifurcation_multiplicity = abs(pb%neg_pivots - pa%neg_pivots)
         ! The state at the located point itself, re-solved, for its mode and branch switching
         ! (uniarc_path_branch); if it does not converge, or converges off the bracket's piece of
         ! path, the end of the bracket nearer to it.
         call re_solve(ha + t*(hb - ha), probe, probe_state, converged)
         if (allocated(error)) return
         if (converged) then
            probed = .true.
            converged = on_piece(probe, pa, pb)
         end if
         if (converged) then
            call keep_bifurcation(probe_state)
         else if (abs(pa%min_eigenvalue) <= abs(pb%min_eigenvalue)) then
            call keep_bifurcation(state_a)
         else
            call keep_bifurcation(state_b)
         end if
      end if
      ! The system holds the last probe's tangent: the committed one again for the next step.
      if (allocated(error)) return
      if (probed) call restore_tangent(model, after, system, error)

   contains

      !> Whether a converged probe lies on the piece of path between the bracket's ends `low_end` and
      !> `high_end` (either order): for a bifurcation, where λ is monotone along the step (dλ/ds of one
      !> sign at both ends), its λ within their range; towards a maximum of λ (a minimum) not below
      !> the lower (above the higher) of theirs, which bounds λ on a piece with one extremum. Within
      !> piece_slack of the step's change of λ plus round_slack of |λ|.
      pure logical function on_piece(point, low_end, high_end)
         type(path_point_t), intent(in) :: point, low_end, high_end
         real(dp) :: low, high, slack
         low = min(low_end%lambda, high_end%lambda)
         high = max(low_end%lambda, high_end%lambda)
         slack = piece_slack*abs(after%point%lambda - before%point%lambda) + round_slack*max(abs(low), abs(high))
         if (.not. limit) then
            on_piece = point%lambda >= low - slack .and. point%lambda <= high + slack
         else if (before%point%dlambda_ds > 0.0_dp) then
            on_piece = point%lambda >= low - slack
         else
            on_piece = point%lambda <= high + slack
         end if
      end function on_piece

      !> Keep the λ of a converged probe (step parameter h) if it is the most extreme so far in the
      !> sense of the limit (highest towards a maximum, lowest towards a minimum).
      subroutine keep_extreme(lambda, h)
         real(dp), intent(in) :: lambda, h
         if (have_extreme) then
            if (before%point%dlambda_ds > 0.0_dp .and. .not. lambda > extreme_lambda) return
            if (before%point%dlambda_ds < 0.0_dp .and. .not. lambda < extreme_lambda) return
         end if
         have_extreme = .true.
         extreme_lambda = lambda
         extreme_h = h
      end subroutine keep_extreme

      !> The quantity whose zero is the point: dλ/ds for a limit, the least eigenvalue for a
      !> bifurcation.
      pure real(dp) function indicator(point)
         type(path_point_t), intent(in) :: point
         if (limit) then
            indicator = point%dlambda_ds
         else
            indicator = point%min_eigenvalue
         end if
      end function indicator

      !> Whether the least eigenvalue jumps across zero over the final bracket [pa, pb] rather than
      !> passing through it smoothly (jump_ratio, regular_ratio).
      logical function jumps_at_contact()
         real(dp) :: share
         share = ((hb - ha)/length)*abs(after%point%min_eigenvalue - before%point%min_eigenvalue)
         jumps_at_contact = abs(pb%min_eigenvalue - pa%min_eigenvalue) > jump_ratio*share .and. &
                            min(abs(pa%min_eigenvalue), abs(pb%min_eigenvalue)) > regular_ratio*share
      end function jumps_at_contact

      !> Whether the reference load has a component along the least eigenvector of `near`'s tangent
      !> above round-off (|φᵀR| > mode_load_cosine |φ||R|): the critical point there is a limit
      !> point (φᵀR ≠ 0), not a bifurcation (φᵀR = 0), docs/theory.md §2.2.
      !> |R| is the larger of R's norm on the free DOFs and the force scale of the step's loads per
      !> unit λ (state%load_norm, which counts the element loads' equivalent forces on held DOFs too):
      !> a heated bar whose supports take every thermal force (steps_bed_heated_bar.inp) has R of
      !> round-off on the free DOFs (|R| 8.1e-14 against 136 = √2 EA α ΔT, the two ends' forces), and
      !> the cosine of φ with that round-off vector is 0.94 (it rejected the step past the bar's
      !> bifurcation as `left_branch`, and the cut step's round-off tangent turned the path back onto
      !> the buckled branch at 2.0846); against the loads' own size |φᵀR| is 5.6e-16 |φ||R|.
      logical function load_sees_mode(near)
         type(path_state_t), intent(in) :: near
         real(dp) :: size_mode, size_load, unit_load
         load_sees_mode = .false.
         if (.not. (allocated(near%eigenvector) .and. allocated(near%reference))) return
         size_mode = norm2(near%eigenvector)
         unit_load = near%load_norm
         if (model%analysis%control /= control_displacement .and. abs(model%analysis%first_increment) > 0.0_dp) &
            unit_load = unit_load/abs(model%analysis%first_increment)
         size_load = max(norm2(near%reference), unit_load)
         load_sees_mode = abs(dot_product(near%eigenvector, near%reference)) > mode_load_cosine*size_mode*size_load
      end function load_sees_mode

      !> Whether the step went in λ alone (its displacement round-off: a load step where the supports
      !> or the contacts take the whole reference load, docs/theory.md §2.7): its chord ||Δu|| is
      !> round-off, no measure of the distance between the bracket's ends.
      logical function in_lambda_alone()
         in_lambda_alone = .true.
         if (.not. (abs(after%lambda - before%lambda) > 0.0_dp)) return
         in_lambda_alone = degenerate_tangent(before, (after%u - before%u)/abs(after%lambda - before%lambda))
      end function in_lambda_alone

      !> Whether the point lies beyond the critical point (on the side of `after`).
      pure logical function passed(point)
         type(path_point_t), intent(in) :: point
         if (limit) then
            passed = .not. same_signs(point%dlambda_ds, before%point%dlambda_ds)
         else
            passed = point%neg_pivots /= before%point%neg_pivots
         end if
      end function passed

      !> The bifurcation's nearest converged state `near` and its mode into after%bifurcation.
      !> (`near`'s arrays are moved, not copied: it is not used after.)
      subroutine keep_bifurcation(near)
         type(path_state_t), intent(inout) :: near
         real(dp) :: pressed
         ! A lift-off mode is put on the cone of admissible directions (signed to open the contacts
         ! that touch without force, none of them pressed; docs/theory.md §2.6).
         if (near%point%liftoff .and. allocated(near%liftoff_mode)) then
            call cone_mode(model, near, model%analysis%displacement_tolerance, near%liftoff_mode, pressed, error)
            if (allocated(error)) return
         end if
         allocate (after%bifurcation, stat=status)
         call allocation_failure(status, 'the state at the bifurcation', &
                                 real(storage_size(after%bifurcation)/8, dp), error_analysis, error)
         if (allocated(error)) return
         call move_alloc(near%u, after%bifurcation%u)
         call move_alloc(near%active, after%bifurcation%active)
         after%bifurcation%lambda = near%lambda
         after%bifurcation%located_lambda = after%point%bifurcation_lambda
         after%bifurcation%position = before%point%step + after%point%bifurcation_fraction
         after%bifurcation%s = near%point%s
         after%bifurcation%liftoff = near%point%liftoff
         if (allocated(near%joint_plastic)) call move_alloc(near%joint_plastic, after%bifurcation%joint_plastic)
         if (near%point%liftoff .and. allocated(near%liftoff_mode)) then
            call move_alloc(near%liftoff_mode, after%bifurcation%mode)
         else if (allocated(near%eigenvector)) then
            call move_alloc(near%eigenvector, after%bifurcation%mode)
         else
            deallocate (after%bifurcation)
         end if
      end subroutine keep_bifurcation

      !> The converged state of a step of length step_h from `before`, as a point record and a state.
      subroutine re_solve(step_h, point, state, ok)
         real(dp), intent(in) :: step_h
         type(path_point_t), intent(out) :: point
         type(path_state_t), intent(out) :: state
         logical, intent(out) :: ok
         call re_solve_step(model, before, system, step_h, state, ok, error)
         if (ok) call copy_point_record(state%point, point, 'the point of a probe of the step', error)
         if (allocated(error)) ok = .false.
      end subroutine re_solve

   end subroutine locate_critical_points


end module uniarc_path_locate
