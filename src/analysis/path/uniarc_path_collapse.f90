!> The bearing collapse of a structure on elastic–perfectly plastic beds and springs (`QU=`, `TU=`;
!> docs/theory.md §3.9, "Collapse"): the certificate that a converged state is (within a bracket) the
!> collapse load of limit analysis, so that a path whose next step cannot converge there ends with a
!> result (a `bearing_collapse` row of STEM.crit, exit code 0) instead of a failure.
!>
!> At the committed state (λ_n, reactions r_c), let the floating motions v_j (j ≤ 3: the rigid motions
!> that only contacts hold, docs/theory.md §2.8) span the candidate mechanisms φ = Σ y_j v_j. The
!> candidates split into
!> - holders: in the working set, elastic, and not within `near_yield` of a limit — they resist any φ
!>   with a_c·φ ≠ 0, so φ must lie in the null space of their rows a_c·v_j;
!> - yielding ones (at a limit, or elastic within `near_yield` of it): φ must move them further the way
!>   they yield (a_c·φ ≤ 0 in bearing, ≥ 0 in uplift), else they unload elastically and hold;
!> - open unilateral ones: φ must not close them (a_c·φ ≥ 0); so too one of the working set that touches
!>   with a force within `near_yield` of nothing (the edge of a contact region): φ may lift it off, its
!>   force then lost (r_lim = 0).
!> For such a φ with R·φ > 0 (R the reference load), the incremental virtual work of the rigid motion
!> (the elements do none: φ is rigid) gives the largest load increment the media can balance along φ,
!>     Δλ(φ) = Σ_c (r_lim,c − r_c)(−a_c·φ) / (R·φ) ≥ 0,
!> r_lim the limit force of each yielding candidate (q_c, or −t_c in uplift). By the upper-bound
!> theorem of limit analysis (a kinematically admissible mechanism; Neal 1977, ch. 2; for Winkler-type
!> plastic supports Maier 1968) the collapse load is at most λ_n + min_φ Δλ(φ); the committed state is
!> statically admissible (lower bound), so the collapse load lies in [λ_n, λ_n + Δλ_min]. The minimum of
!> the linear-fractional Δλ over the polyhedral cone of admissible φ is on one of its extreme rays,
!> found by enumeration (d ≤ 3: the rays orthogonal to one constraint row in 2-D, to two in 3-D). To
!> first order in the structure's rotation (the floating motions are those of the initial geometry).
!>
!> With joints at their moment limit (`*RELEASE, MY=`) the mechanisms are those of the structure's
!> parts cut at them (hinge_mechanisms, uniarc_path_hinges), each joint one more row (it turns the way
!> its moment flows, sign(M) Δθ ≥ 0) and its slack MY − |M| times that turn one more term of Δλ(φ)
!> (docs/theory.md §3.9, "Collapse with hinges").
module uniarc_path_collapse
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, dofs_per_node, end_joint_t, end_joints_of, has_moment_limits
   use uniarc_element, only: element_response_t, element_response, element_displacements, transformation_corotational
   use uniarc_path_hinges, only: hinge_parts_t, hinge_parts, motion_of, hinge_rotation
   use uniarc_dof_map, only: candidate_live
   use uniarc_contact, only: candidate_gap, in_set
   use uniarc_assembly, only: gather_nodal
   use uniarc_path_state, only: path_state_t
   use uniarc_strings, only: real_to_string
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   implicit none
   private
   public :: bearing_collapse, plastic_plateau, near_yield, collapse_bracket

   !> An elastic candidate whose reaction is within this fraction of its limit counts as yielding for
   !> the mechanism: the step that failed was cut to 1e-6 of the first (docs/input.md, min_increment),
   !> so the last one to yield may be short of its limit by the load of that sliver; its slack enters
   !> the bracket Δλ, which the certificate bounds separately (collapse_bracket).
   real(dp), parameter :: near_yield = 1.0e-3_dp
   !> The collapse is certified when the bracket Δλ_min is at most this fraction of the upper bound
   !> λ_n + Δλ_min (the load is then known to 0.1 %, the precision of near_yield).
   real(dp), parameter :: collapse_bracket = 1.0e-3_dp
   !> A row a_c·v with |a_c·v| at most this fraction of |a_c| max|v| sees no motion (as
   !> uniarc_path_state's floating_tolerance: a contact across the motion to 1e-6 rad).
   real(dp), parameter :: row_tolerance = 1.0e-6_dp
   !> In 3-D (a structure held in no direction but by its media) the rays from pairs of the first
   !> max_pairs constraint rows only: a mechanism missed so is a collapse not certified (the run then
   !> ends as a failed step), never a false one.
   integer, parameter :: max_pairs = 300
   !> A joint with a moment limit counts as a hinge of the mechanism when its moment is within this
   !> fraction of MY (strict: the test that names the joints at their limit in a failed step's message,
   !> uniarc_path_state yielded_joints), or within near_yield of it (a state from which the next step
   !> failed, as the candidates).
   real(dp), parameter :: hinge_at_limit = 1.0e-6_dp
   !> The parts the hinges may cut the structure into: each moves rigidly (3 unknowns), and the
   !> mechanisms must be at most 3 (the enumeration of the cone's rays); more parts than this, and
   !> the certificate keeps the rigid motions of the whole structure.
   integer, parameter :: max_parts = 4
   !> A contact out of the working set whose gap is at most this fraction of the largest displacement
   !> touches (round-off of a plateau that closed it; the model's size, which the working set's
   !> touching test takes, can exceed the gaps of a lift-off on a fine mesh).
   real(dp), parameter :: touch_tolerance = 1.0e-9_dp

contains

   !> Whether the committed `state` of `model` is at a bearing collapse (module header). On .true.:
   !> `upper` the upper bound λ_n + Δλ_min of the collapse load (λ_n = state%lambda the lower bound),
   !> `count` the candidates at or within near_yield of their limits that the mechanism moves, and
   !> `nodes` their node labels (comma-separated, the first ones). .false. when the model has no
   !> floating motion, no candidate at a limit, no admissible mechanism that the load drives, or a
   !> bracket wider than collapse_bracket; then `finding` (if present) says which, in words for a
   !> message (e.g. "no mechanism that the load drives is admissible", or the bracket it found).
   !> Errors (error_analysis, out of memory; collapsed = .false.): its arrays of the candidates' or the
   !> equations' length (candidate_kinds, the constraint rows, the load's work) refused by the system.
   subroutine bearing_collapse(model, state, strict, collapsed, upper, count, nodes, error, finding, bound_only, &
                               joints)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      !> .true.: only the candidates of the yielding set count as yielding (a converged state that is
      !> itself a collapse, Δλ_min = 0); .false.: those within near_yield of a limit too (a state from
      !> which the next step failed)
      logical, intent(in) :: strict
      logical, intent(out) :: collapsed
      real(dp), intent(out) :: upper
      integer, intent(out) :: count
      character(len=:), allocatable, intent(out) :: nodes
      type(error_t), allocatable, intent(out) :: error
      !> why the certificate refused (collapsed = .false.), or '' when it certified the collapse
      character(len=:), allocatable, intent(out), optional :: finding
      !> .true.: every candidate of the set with a limit counts as yielding, its slack to the limit in
      !> Δλ(φ) (strict ignored): the upper bound λ_n + Δλ_min holds for every admissible mechanism
      !> (the upper-bound theorem needs no candidate at its limit), so `upper` bounds the collapse load
      !> of the small-displacement problem from any statically admissible state; collapsed then says
      !> that the bracket [λ_n, upper] is within collapse_bracket
      logical, intent(in), optional :: bound_only
      !> on .true., the joints at their moment limit that are hinges of the mechanism ('' when it is a
      !> rigid motion of the whole structure), e.g. "element 40 end 2" (not with bound_only)
      character(len=:), allocatable, intent(out), optional :: joints
      real(dp), allocatable :: nodal(:, :), rate(:, :), basis(:, :), hold(:, :)
      real(dp), allocatable :: constraint(:, :), slack(:), load(:), gap_now(:), mode(:), motions(:, :)
      real(dp), allocatable :: hinge_rate(:, :), hinge_slack(:), wider(:, :)
      integer, allocatable :: kind(:)
      character(len=:), allocatable :: hinge_names
      real(dp) :: best, y(3), margin
      integer :: n_c, m, c, d, n_con, a, b, k, status, j
      logical :: every, hinged
      collapsed = .false.
      upper = state%lambda
      count = 0
      nodes = ''
      if (present(joints)) joints = ''
      if (present(finding)) finding = 'the structure has no rigid motion held only by its contacts'
      if (.not. (allocated(state%floating_motion) .and. allocated(state%yielding) .and. &
                 allocated(state%reactions) .and. allocated(state%reference))) return
      m = size(state%floating_motion, 2)
      n_c = size(state%active)
      if (m == 0 .or. n_c == 0) return
      margin = near_yield
      if (strict) margin = 0.0_dp
      every = .false.
      if (present(bound_only)) every = bound_only
      if (every) margin = 1.0_dp
      if (present(finding)) finding = 'no contact point at or within 0.1 % of its limit'
      if (strict .and. .not. every .and. .not. any(state%yielding .and. state%active)) return
      ! Joints at their moment limit are hinges of the mechanisms (not for the bound before a step:
      ! every joint with a limit a hinge would cut the structure into too many parts to enumerate)
      hinged = .false.
      if (.not. every .and. has_moment_limits(model)) then
         call hinge_mechanisms(model, state, strict, motions, hinge_rate, hinge_slack, hinge_names, hinged, error)
         if (allocated(error)) return
      end if
      if (.not. hinged) then
         ! (the hinges' arrays, if hinge_mechanisms made them before it gave up, dropped)
         if (allocated(motions)) deallocate (motions)
         if (allocated(hinge_rate)) deallocate (hinge_rate)
         if (allocated(hinge_slack)) deallocate (hinge_slack)
         allocate (motions(size(state%floating_motion, 1), m), stat=status)
         call allocation_failure(status, 'the rigid motions of the collapse certificate', &
                                 8.0_dp*size(state%floating_motion), error_analysis, error)
         if (allocated(error)) return
         motions(:, :) = state%floating_motion
         allocate (hinge_rate(0, m), hinge_slack(0), stat=status)
         call allocation_failure(status, 'the hinges of the collapse certificate', 0.0_dp, error_analysis, error)
         if (allocated(error)) return
         hinge_names = ''
      end if
      m = size(motions, 2)
      call candidate_kinds(model, state, motions, margin, every .or. .not. strict, nodal, rate, kind, slack, gap_now, &
                           error)
      if (allocated(error)) return
      if (.not. any(kind == 2 .or. kind == 3)) return
      ! The null space of the holders' rows (m ≤ 3 columns): the mechanisms they do not resist.
      call holder_rows(rate, kind, hold, error)
      if (allocated(error)) return
      call null_space(hold, basis)
      d = size(basis, 2)
      if (present(finding)) finding = 'the elastic contacts hold every rigid motion'
      if (d == 0) return
      ! The load's work on each basis motion, and the constraint rows (one per yielding or open
      ! candidate that the subspace moves), oriented so that an admissible φ = basis·y has row·y ≥ 0:
      ! bearing a·φ ≤ 0 (the penetration grows), uplift and open a·φ ≥ 0 (an open one not closed).
      ! (the motion of each basis vector in a work vector allocated with stat=, not a temporary)
      allocate (load(d), mode(size(motions, 1)), stat=status)
      call allocation_failure(status, 'the load''s work on the rigid motions of the collapse certificate', &
                              8.0_dp*(d + size(motions, 1)), error_analysis, error)
      if (allocated(error)) return
      do k = 1, d
         mode(:) = matmul(motions, basis(:, k))
         load(k) = dot_product(state%reference, mode)
      end do
      if (present(finding)) finding = 'the load does no work on the rigid motions the elastic contacts leave free'
      if (maxval(abs(load)) <= 0.0_dp) return
      call constraint_rows(rate, kind, basis, .true., constraint, n_con, error)
      if (allocated(error)) return
      if (size(hinge_slack) > 0) then
         ! a joint at its limit turns the way its moment flows (sign(M) Δθ ≥ 0, §1.11), else it unloads
         ! elastically and holds: one more row each, oriented as the candidates' (hinge_rate is signed)
         allocate (wider(d, n_con + size(hinge_slack)), stat=status)
         call allocation_failure(status, 'the hinges'' rows of the collapse certificate', &
                                 8.0_dp*d*(n_con + size(hinge_slack)), error_analysis, error)
         if (allocated(error)) return
         wider(:, 1:n_con) = constraint(:, 1:n_con)
         do j = 1, size(hinge_slack)
            wider(:, n_con + j) = matmul(hinge_rate(j, :), basis)
         end do
         n_con = n_con + size(hinge_slack)
         call move_alloc(wider, constraint)
      end if
      ! Extreme rays of {y : constraintᵀy ≥ 0}: in 1-D ±1; in 2-D the normals to one row; in 3-D the
      ! cross products of two rows; with fewer rows than needed, the load's own direction too.
      best = huge(1.0_dp)
      select case (d)
      case (1)
         call try([1.0_dp])
         call try([-1.0_dp])
      case (2)
         call try(load)
         do a = 1, n_con
            call try([-constraint(2, a), constraint(1, a)])
            call try([constraint(2, a), -constraint(1, a)])
         end do
      case default
         call try(load)
         do a = 1, min(n_con, max_pairs)
            ! the load's direction projected onto the plane of one row (a face of the cone)
            call try(load - dot_product(load, constraint(:, a))/dot_product(constraint(:, a), constraint(:, a)) &
                     *constraint(:, a))
            do b = a + 1, min(n_con, max_pairs)
               y = cross(constraint(:, a), constraint(:, b))
               call try(y)
               call try(-y)
            end do
         end do
      end select
      if (present(finding)) finding = 'no rigid motion that the load drives is admissible (each would close an '// &
                                      'open contact or unload a yielded one)'
      if (best == huge(1.0_dp)) return
      upper = state%lambda + best
      collapsed = best <= collapse_bracket*abs(upper)
      if (present(finding)) then
         finding = ''
         if (.not. collapsed) finding = 'a rigid mechanism bounding the collapse load only by lambda <= '// &
                                        real_to_string(upper, '(es12.5)')//', not within 0.1 % of lambda = '//real_to_string(state%lambda, '(es12.5)')
      end if
      if (.not. collapsed) return
      if (present(joints)) joints = hinge_names
      ! the candidates at their limits (for the message)
      do c = 1, n_c
         if (kind(c) /= 2 .and. kind(c) /= 3) cycle
         count = count + 1
         if (len(nodes) > 60) cycle
         if (len(nodes) > 0) nodes = nodes//', '
         nodes = nodes//int_text(model%node_label(model%contacts(c)%node))
         if (len(nodes) > 60) nodes = nodes//', ...'
      end do

   contains

      !> Keep Δλ(φ) of φ = basis·y if φ is admissible (every constraint row·y ≥ 0 to round-off) and
      !> the load drives it (R·φ > 0).
      subroutine try(direction)
         real(dp), intent(in) :: direction(:)
         real(dp) :: norm, work_load, dissipation, row
         integer :: i
         norm = norm2(direction)
         if (.not. (norm > 0.0_dp)) return
         work_load = dot_product(load, direction)/norm
         if (.not. (work_load > row_tolerance*norm2(load))) return
         do i = 1, n_con
            row = dot_product(constraint(:, i), direction)/norm
            if (row < -row_tolerance*norm2(constraint(:, i))) return
         end do
         dissipation = 0.0_dp
         do i = 1, n_c
            if (kind(i) == 2 .or. kind(i) == 3 .or. kind(i) == 5) &
               dissipation = dissipation + slack(i)*(-dot_product(matmul(rate(i, :), basis), direction))/norm
         end do
         ! the hinges: their moment's slack MY − |M| times their turn the way they flow
         do i = 1, size(hinge_slack)
            dissipation = dissipation + hinge_slack(i)*dot_product(matmul(hinge_rate(i, :), basis), direction)/norm
         end do
         best = min(best, max(0.0_dp, dissipation)/work_load)
      end subroutine try

   end subroutine bearing_collapse

   !> A plateau of the path at constant load (docs/theory.md §3.9, "Plateaus"): at the committed
   !> `state`, from which the next step failed, a rigid mechanism φ that the load drives (R·φ > 0),
   !> that the elastic contacts (holders) do not resist, that moves every candidate at or within
   !> near_yield of a limit the way it yields (or lifts off one touching with no force) — the
   !> certificate's admissibility (bearing_collapse, strict = .false.) — but that closes an open
   !> contact. Along it the loads stay in equilibrium with the limit forces at the load
   !> λ_n + Δλ(φ) (the virtual work of φ, Δλ(φ) the slack of the candidates short of their limits,
   !> at most collapse_bracket of λ), so the structure sinks at that load, its yielded supports
   !> flowing, until the first open contact closes: the perfectly plastic law's segment of constant
   !> load (Maier 1968; Neal 1977, ch. 2: a mechanism of the yielded supports is a motion at the
   !> limit load; here it is bounded by a contact that re-engages).
   !> Of the admissible φ (a cone, d ≤ 3 floating motions left free by the holders), the one most
   !> aligned with the load in the displacement metric: max R·φ/‖φ‖ (the metric projection of the
   !> load onto the cone, as rigid_approach takes the load's resultant): the unconstrained maximiser,
   !> or on a face or an edge of the cone, enumerated.
   !> On found = .true.: `motion` (n_equations) the rigid motion α φ to the contact it closes
   !> (first order in the rotation: the plateau step's Newton corrects the rest), `dlambda` = Δλ(φ)
   !> ≥ 0, `contact` the candidate that closes first. found = .false. when there is no such φ, or no
   !> open contact that it closes (then it is no plateau but a collapse, bearing_collapse's case).
   !> A contact out of the set that touches (gap within touch_tolerance of the largest displacement)
   !> may be lifted by φ, not pressed, and closes no plateau (docs/theory.md §3.9, "Plateau of no
   !> length"). `touching` (candidates): on found, those out of the set that φ keeps touching and,
   !> when φ keeps any candidate touching with no force (in the set or out), `contact` — the plateau
   !> step's working set adds them; otherwise every touching one.
   !> Errors (error_analysis, out of memory; found = .false.): its arrays of the candidates' or the
   !> equations' length (candidate_kinds, the constraint rows, the basis' motions) refused by the system.
   subroutine plastic_plateau(model, state, found, motion, dlambda, contact, touching, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      logical, intent(out) :: found
      real(dp), intent(out) :: motion(:)
      real(dp), intent(out) :: dlambda
      integer, intent(out) :: contact
      logical, intent(out) :: touching(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), rate(:, :), basis(:, :), hold(:, :)
      real(dp), allocatable :: constraint(:, :), slack(:), load(:), gap_now(:), modes(:, :)
      integer, allocatable :: kind(:)
      real(dp) :: best, y(3), chosen(3)
      real(dp) :: gram(3, 3), work_load, distance, along, dissipation, touch_gap
      logical :: pivot
      integer :: n_c, m, c, j, d, n_con, a, b, k, status
      found = .false.
      motion = 0.0_dp
      dlambda = 0.0_dp
      contact = 0
      touching = .false.
      if (.not. (allocated(state%floating_motion) .and. allocated(state%yielding) .and. &
                 allocated(state%reactions) .and. allocated(state%reference))) return
      m = size(state%floating_motion, 2)
      n_c = size(state%active)
      if (m == 0 .or. n_c == 0) return
      ! the candidates' kinds as the certificate's with strict = .false. (1 holder, 2 bearing, 3 uplift,
      ! 4 open, 5 lifting)
      call candidate_kinds(model, state, state%floating_motion, near_yield, .true., nodal, rate, kind, slack, &
                           gap_now, error)
      if (allocated(error)) return
      touch_gap = touch_tolerance*maxval(abs(nodal(1:2, :)))
      do c = 1, n_c
         ! one that touches already (within the working set's touching tolerance) but is not in the
         ! set: φ may lift it off but not press it (it would hold elastically), as one of the set with
         ! no force — it ends no plateau (that would be one of no length)
         if (kind(c) == 4 .and. gap_now(c) <= touch_gap) then
            kind(c) = 5
            touching(c) = .true.
         end if
      end do
      if (.not. any(kind == 2 .or. kind == 3)) return
      call holder_rows(rate, kind, hold, error)
      if (allocated(error)) return
      call null_space(hold, basis)
      d = size(basis, 2)
      if (d == 0) return
      ! the motions of the basis, their load work and their Gram matrix in the displacement metric
      allocate (modes(size(state%floating_motion, 1), d), load(d), stat=status)
      call allocation_failure(status, 'the rigid motions of the plateau', 8.0_dp*(size(state%floating_motion, 1) + 1)*d, &
                              error_analysis, error)
      if (allocated(error)) return
      modes(:, :) = matmul(state%floating_motion, basis)
      gram = 0.0_dp
      do k = 1, d
         load(k) = dot_product(state%reference, modes(:, k))
         do j = 1, d
            gram(k, j) = sum(state%map%metric*modes(:, k)*modes(:, j))
         end do
      end do
      if (maxval(abs(load)) <= 0.0_dp) return
      ! the admissibility rows (yielding: the way they yield; lifting: opened, not closed); the open
      ! contacts are no rows: the plateau ends where the first of them closes
      call constraint_rows(rate, kind, basis, .false., constraint, n_con, error)
      if (allocated(error)) return
      best = -huge(1.0_dp)
      chosen = 0.0_dp
      call consider(solve_gram(load))
      select case (d)
      case (1)
         call consider([1.0_dp])
         call consider([-1.0_dp])
      case (2)
         do a = 1, n_con
            call consider(on_face(constraint(:, a)))
            call consider([-constraint(2, a), constraint(1, a)])
            call consider([constraint(2, a), -constraint(1, a)])
         end do
      case default
         do a = 1, min(n_con, max_pairs)
            call consider(on_face(constraint(:, a)))
            do b = a + 1, min(n_con, max_pairs)
               y = cross(constraint(:, a), constraint(:, b))
               call consider(y)
               call consider(-y)
            end do
         end do
      end select
      if (best == -huge(1.0_dp)) return
      ! the load at which the limit forces balance the loads along φ (the slack's virtual work)
      work_load = dot_product(load, chosen(1:d))
      dissipation = 0.0_dp
      do c = 1, n_c
         if (kind(c) == 2 .or. kind(c) == 3 .or. kind(c) == 5) &
            dissipation = dissipation + slack(c)*(-dot_product(matmul(rate(c, :), basis), chosen(1:d)))
      end do
      dlambda = max(0.0_dp, dissipation)/work_load
      if (dlambda > collapse_bracket*abs(state%lambda + dlambda)) return
      ! the first open contact that φ closes: g + α a·φ = 0 (first order)
      distance = huge(1.0_dp)
      do c = 1, n_c
         if (kind(c) /= 4) cycle
         along = dot_product(matmul(rate(c, :), basis), chosen(1:d))
         if (.not. along < 0.0_dp) cycle
         if (max(gap_now(c), 0.0_dp)/(-along) < distance) then
            distance = max(gap_now(c), 0.0_dp)/(-along)
            contact = c
         end if
      end do
      if (contact == 0) return
      ! (the product in place: no temporary of the equations' length)
      motion(:) = matmul(modes(:, 1:d), chosen(1:d))
      motion(:) = distance*motion
      ! the touching ones (out of the set, or in it with no force) that φ lifts off are out of the
      ! step's set; those it keeps touching are in, and then the contact it closes too (φ turns about
      ! them: alone in the set they would leave that turn free, the step's tangent singular along it)
      pivot = .false.
      do c = 1, n_c
         if (kind(c) /= 5) cycle
         along = distance*dot_product(matmul(rate(c, :), basis), chosen(1:d))
         if (touching(c)) along = along + gap_now(c)
         if (along <= touch_gap) then
            pivot = .true.
         else
            touching(c) = .false.
         end if
      end do
      if (pivot) touching(contact) = .true.
      found = .true.

   contains

      !> y maximising load·y/‖y‖ (‖y‖² = yᵀ gram y) on the plane row·y = 0: gram⁻¹(load − μ row).
      function on_face(row) result(y_face)
         real(dp), intent(in) :: row(:)
         real(dp) :: y_face(size(row))
         real(dp) :: g_load(size(row)), g_row(size(row)), mu
         g_load = solve_gram(load)
         g_row = solve_gram(row)
         mu = 0.0_dp
         if (abs(dot_product(row, g_row)) > 0.0_dp) mu = dot_product(row, g_load)/dot_product(row, g_row)
         y_face = g_load - mu*g_row
      end function on_face

      !> gram⁻¹ v (d ≤ 3, Gaussian elimination with partial pivoting; gram is positive definite: the
      !> motions are independent).
      function solve_gram(v) result(x)
         real(dp), intent(in) :: v(:)
         real(dp) :: x(size(v))
         real(dp) :: aug(3, 4), t(4)
         integer :: i, p, r
         aug = 0.0_dp
         aug(1:d, 1:d) = gram(1:d, 1:d)
         aug(1:d, 4) = v
         do i = 1, d
            p = i - 1 + maxloc(abs(aug(i:d, i)), 1)
            t = aug(i, :)
            aug(i, :) = aug(p, :)
            aug(p, :) = t
            if (.not. abs(aug(i, i)) > 0.0_dp) then
               x = 0.0_dp
               return
            end if
            do r = i + 1, d
               aug(r, :) = aug(r, :) - aug(r, i)/aug(i, i)*aug(i, :)
            end do
         end do
         do i = d, 1, -1
            x(i) = (aug(i, 4) - dot_product(aug(i, i + 1:d), x(i + 1:d)))/aug(i, i)
         end do
      end function solve_gram

      !> Keep y if it is admissible (every row·y ≥ 0 to round-off), the load drives it, and it is
      !> better aligned with the load than the best so far.
      subroutine consider(direction)
         real(dp), intent(in) :: direction(:)
         real(dp) :: norm, score
         integer :: i
         norm = sqrt(max(0.0_dp, dot_product(direction, matmul(gram(1:d, 1:d), direction))))
         if (.not. norm > 0.0_dp) return
         score = dot_product(load, direction)/norm
         if (.not. score > row_tolerance*norm2(load)/sqrt(maxval([(gram(i, i), i=1, d)]))) return
         do i = 1, n_con
            if (dot_product(constraint(:, i), direction)/norm2(direction) < -row_tolerance*norm2(constraint(:, i))) return
         end do
         if (score > best) then
            best = score
            chosen(1:d) = direction/norm2(direction)
         end if
      end subroutine consider

   end subroutine plastic_plateau

   !> The mechanisms of the committed `state` with its joints at their moment limit as hinges
   !> (uniarc_path_hinges; docs/theory.md §3.9, "Collapse with hinges"): `motions` (n_equations, m ≤ 3)
   !> the motions of the parts that agree at the hinges and the supports, `hinge_rate` (hinges, m) each
   !> joint's turn along them oriented the way its moment flows (sign(M) Δθ, §1.11), `hinge_slack`
   !> MY − |M| of each, `names` the joints ("element E end i", the first ones). found = .false. (the
   !> rigid motions of the whole structure are then the certificate's) when no joint is at its limit,
   !> the hinges cut the structure into more than max_parts parts or leave more than 3 mechanisms or
   !> none, or a hinge's node is rigid to no part (its turn is not fixed by the parts).
   !> Errors (error_analysis, out of memory): the arrays of the joints, the parts and the motions.
   subroutine hinge_mechanisms(model, state, strict, motions, hinge_rate, hinge_slack, names, found, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      logical, intent(in) :: strict
      real(dp), allocatable, intent(out) :: motions(:, :), hinge_rate(:, :), hinge_slack(:)
      character(len=:), allocatable, intent(out) :: names
      logical, intent(out) :: found
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), z(:, :), moment(:, :)
      logical, allocatable :: hinge(:, :), at_limit(:, :)
      type(end_joint_t) :: ends(2)
      type(element_response_t) :: response
      type(hinge_parts_t) :: parts
      real(dp) :: tolerance, turn
      integer :: e, i, k, j, status
      logical :: known
      found = .false.
      names = ''
      if (.not. allocated(state%joint_plastic)) return
      tolerance = near_yield
      if (strict) tolerance = hinge_at_limit
      allocate (nodal(dofs_per_node, model%n_nodes), hinge(2, model%n_elements), at_limit(2, model%n_elements), &
                moment(2, model%n_elements), stat=status)
      call allocation_failure(status, 'the joints of the collapse certificate', &
                              8.0_dp*(dofs_per_node*model%n_nodes + 3*model%n_elements), error_analysis, error)
      if (allocated(error)) return
      call gather_nodal(state%map, state%u, nodal)
      hinge = .false.
      at_limit = .false.
      moment = 0.0_dp
      do e = 1, model%n_elements
         ends = end_joints_of(model, e)
         hinge(:, e) = ends%hinge
         if (.not. any(ends%moment_limit > 0.0_dp)) cycle
         call element_response(model, e, element_displacements(model, e, nodal), transformation_corotational, &
                               response, state%joint_plastic(:, e))
         do i = 1, 2
            if (.not. ends(i)%moment_limit > 0.0_dp) cycle
            if (abs(response%basic_force(1 + i)) < (1.0_dp - tolerance)*ends(i)%moment_limit) cycle
            at_limit(i, e) = .true.
            hinge(i, e) = .true.
            moment(i, e) = response%basic_force(1 + i)
         end do
      end do
      if (.not. any(at_limit)) return
      call hinge_parts(model, state%map, hinge, max_parts, parts, status)
      call allocation_failure(status, 'the parts of the structure cut at its hinges', &
                              8.0_dp*(model%n_elements + 2*model%n_nodes), error_analysis, error)
      if (allocated(error)) return
      if (parts%n_parts > max_parts) return
      call null_space(parts%rows, z)
      if (size(z, 2) == 0 .or. size(z, 2) > 3) return
      allocate (motions(state%map%n_equations, size(z, 2)), hinge_rate(count(at_limit), size(z, 2)), &
                hinge_slack(count(at_limit)), stat=status)
      call allocation_failure(status, 'the mechanisms with hinges of the collapse certificate', &
                              8.0_dp*(state%map%n_equations + count(at_limit) + 1)*size(z, 2), error_analysis, error)
      if (allocated(error)) return
      do k = 1, size(z, 2)
         call motion_of(model, state%map, parts, z(:, k), motions(:, k))
      end do
      j = 0
      do e = 1, model%n_elements
         ends = end_joints_of(model, e)
         do i = 1, 2
            if (.not. at_limit(i, e)) cycle
            j = j + 1
            do k = 1, size(z, 2)
               call hinge_rotation(model, parts, e, i, z(:, k), turn, known)
               if (.not. known) return
               hinge_rate(j, k) = sign(1.0_dp, moment(i, e))*turn
            end do
            hinge_slack(j) = max(0.0_dp, ends(i)%moment_limit - abs(moment(i, e)))
            if (len(names) > 60) cycle
            if (len(names) > 0) names = names//', '
            names = names//'element '//int_text(model%element_label(e))//' end '//int_text(i)
            if (len(names) > 60) names = names//', ...'
         end do
      end do
      found = .true.
   end subroutine hinge_mechanisms

   !> The candidates of the committed `state` as the certificate and the plateau see them (one
   !> procedure for both): `rate` (n_c, m) = a_c·v_j, the first-order gap change of candidate c along
   !> the motion v_j of `motions` (the floating motions, or the certificate's mechanisms with hinges)
   !> (0 within row_tolerance of |a_c| max|v_j|); `kind` (n_c): 0 none (dead or
   !> bonded out of the set), 1 holder, 2 bearing yield, 3 uplift yield, 4 open unilateral, 5 in the set
   !> touching with at most `margin` of its release scale (its bearing limit, else the set's largest
   !> reaction); `slack` (n_c) the force r_lim − r to the limit of kinds 2, 3 and 5 (r_lim = 0 for 5);
   !> `gap_now` (n_c) the gap at the committed displacements `nodal` (dofs_per_node, n_nodes), with
   !> the slip of a tangential spring. A candidate of the set counts as yielding when it is in
   !> state%yielding or, with `widened`, when its reaction is within `margin` of its limit.
   !> Errors (error_analysis, out of memory): an array refused by the system (each allocated with stat=).
   subroutine candidate_kinds(model, state, motions, margin, widened, nodal, rate, kind, slack, gap_now, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: motions(:, :)   !< (n_equations, m) the mechanisms (floating motions, or with hinges)
      real(dp), intent(in) :: margin
      logical, intent(in) :: widened
      real(dp), allocatable, intent(out) :: nodal(:, :), rate(:, :), slack(:), gap_now(:)
      integer, allocatable, intent(out) :: kind(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: motion_nodal(:, :)
      real(dp) :: gap, gradient(2), hessian(2, 2), limit, reaction, scale, force_scale
      integer :: n_c, m, c, j, node, status
      n_c = size(state%active)
      m = size(motions, 2)
      allocate (nodal(dofs_per_node, model%n_nodes), motion_nodal(dofs_per_node, model%n_nodes), rate(n_c, m), &
                kind(n_c), slack(n_c), gap_now(n_c), stat=status)
      call allocation_failure(status, 'the kinds and rates of the contacts for the collapse certificate', &
                              16.0_dp*dofs_per_node*model%n_nodes + 8.0_dp*n_c*m + 20.0_dp*n_c, error_analysis, error)
      if (allocated(error)) return
      rate(:, :) = 0.0_dp
      kind(:) = 0
      slack(:) = 0.0_dp
      gap_now(:) = 0.0_dp
      call gather_nodal(state%map, state%u, nodal)
      do j = 1, m
         call gather_nodal(state%map, motions(:, j), motion_nodal)
         scale = maxval(abs(motion_nodal(1:2, :)))
         do c = 1, n_c
            if (.not. candidate_live(state%map, c)) cycle
            node = model%contacts(c)%node
            call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, gradient, &
                               hessian, state%lambda)
            gap_now(c) = gap
            if (allocated(state%slip)) gap_now(c) = gap + state%slip(c)
            rate(c, j) = dot_product(gradient, motion_nodal(1:2, node))
            if (abs(rate(c, j)) <= row_tolerance*norm2(gradient)*scale) rate(c, j) = 0.0_dp
         end do
      end do
      force_scale = 0.0_dp
      do c = 1, n_c
         if (in_set(model, state%active, c)) force_scale = max(force_scale, abs(state%reactions(c)))
      end do
      do c = 1, n_c
         if (.not. candidate_live(state%map, c)) cycle
         associate (candidate => model%contacts(c))
            if (.not. in_set(model, state%active, c)) then
               if (.not. candidate%bilateral) kind(c) = 4
               cycle
            end if
            reaction = state%reactions(c)
            kind(c) = 1
            if (candidate%yield_force > 0.0_dp .and. (state%yielding(c) .or. &
                (widened .and. reaction >= (1.0_dp - margin)*candidate%yield_force)) .and. &
                reaction >= 0.0_dp) then
               kind(c) = 2
               limit = candidate%yield_force
            else if (candidate%uplift_force > 0.0_dp .and. (state%yielding(c) .or. &
                     (widened .and. reaction <= -(1.0_dp - margin)*candidate%uplift_force)) .and. &
                     reaction < 0.0_dp) then
               kind(c) = 3
               limit = -candidate%uplift_force
            end if
            if (kind(c) >= 2) then
               slack(c) = limit - reaction
            else if (.not. candidate%bilateral) then
               ! touching with (almost) no force, at the edge of the contact region: the mechanism
               ! may lift it off (a·φ ≥ 0), its force r then lost to the media (r_lim = 0)
               scale = force_scale
               if (candidate%yield_force > 0.0_dp) scale = candidate%yield_force
               if (reaction <= margin*scale) then
                  kind(c) = 5
                  slack(c) = -reaction
               end if
            end if
         end associate
      end do
   end subroutine candidate_kinds

   !> `hold` (h, m): the rows of `rate` (n_c, m) of the holders (kind 1), in order; allocated with stat=
   !> (no array constructor or pack of the candidates' length). Errors: out of memory (error_analysis).
   subroutine holder_rows(rate, kind, hold, error)
      real(dp), intent(in) :: rate(:, :)
      integer, intent(in) :: kind(:)
      real(dp), allocatable, intent(out) :: hold(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer :: c, h, status
      h = 0
      do c = 1, size(kind)
         if (kind(c) == 1) h = h + 1
      end do
      allocate (hold(h, size(rate, 2)), stat=status)
      call allocation_failure(status, 'the holders'' rows of the collapse certificate', 8.0_dp*h*size(rate, 2), &
                              error_analysis, error)
      if (allocated(error)) return
      h = 0
      do c = 1, size(kind)
         if (kind(c) /= 1) cycle
         h = h + 1
         hold(h, :) = rate(c, :)
      end do
   end subroutine holder_rows

   !> The admissibility rows (d, n_con) on the null-space `basis` (m, d) of the candidates of kind 2, 3
   !> and 5 — and 4 (open) with `open_rows` — that the subspace moves (y = rateᵀ basis above
   !> row_tolerance of the candidate's largest rate), oriented so that an admissible φ = basis·y has
   !> row·y ≥ 0 (bearing: sign changed). `constraint` allocated with stat= for every such candidate, its
   !> first `n_con` columns in use (no growth by reshape per row). Errors: out of memory (error_analysis).
   subroutine constraint_rows(rate, kind, basis, open_rows, constraint, n_con, error)
      real(dp), intent(in) :: rate(:, :), basis(:, :)
      integer, intent(in) :: kind(:)
      logical, intent(in) :: open_rows
      real(dp), allocatable, intent(out) :: constraint(:, :)
      integer, intent(out) :: n_con
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: y(3)
      integer :: c, d, status
      d = size(basis, 2)
      n_con = 0
      do c = 1, size(kind)
         if (row_kind(kind(c))) n_con = n_con + 1
      end do
      allocate (constraint(d, n_con), stat=status)
      call allocation_failure(status, 'the admissibility rows of the collapse certificate', 8.0_dp*d*n_con, &
                              error_analysis, error)
      if (allocated(error)) return
      n_con = 0
      do c = 1, size(kind)
         if (.not. row_kind(kind(c))) cycle
         y(1:d) = matmul(rate(c, :), basis)
         if (maxval(abs(y(1:d))) <= row_tolerance*maxval(abs(rate(c, :)))) cycle
         if (kind(c) == 2) y(1:d) = -y(1:d)
         n_con = n_con + 1
         constraint(:, n_con) = y(1:d)
      end do

   contains

      logical function row_kind(k)
         integer, intent(in) :: k
         row_kind = k == 2 .or. k == 3 .or. k == 5 .or. (open_rows .and. k == 4)
      end function row_kind

   end subroutine constraint_rows

   !> An orthonormal basis (m, d) of the null space of `rows` (n, m ≤ 3), each row scaled to unit
   !> length, by the eigenvectors of rowsᵀrows (m × m, Jacobi rotations) whose eigenvalues are at most
   !> (row_tolerance)² of the largest possible (n rows of unit length). No rows: the identity.
   subroutine null_space(rows, basis)
      real(dp), intent(in) :: rows(:, :)
      real(dp), allocatable, intent(out) :: basis(:, :)
      real(dp) :: gram(size(rows, 2), size(rows, 2)), vectors(size(rows, 2), size(rows, 2)), norm
      real(dp) :: theta, t, cs, sn, g_pq, rotated(size(rows, 2), size(rows, 2)), threshold
      integer :: m, i, p, q, sweep
      logical :: keep(size(rows, 2))
      m = size(rows, 2)
      gram = 0.0_dp
      do i = 1, size(rows, 1)
         norm = norm2(rows(i, :))
         if (norm > 0.0_dp) gram = gram + spread(rows(i, :)/norm, 2, m)*spread(rows(i, :)/norm, 1, m)
      end do
      vectors = 0.0_dp
      do i = 1, m
         vectors(i, i) = 1.0_dp
      end do
      ! cyclic Jacobi on the symmetric m × m Gram matrix (Golub & Van Loan, §8.5)
      do sweep = 1, 50
         if (sum([((gram(p, q)**2, p=1, q - 1), q=1, m)]) <= (epsilon(1.0_dp)*max(sum(abs(gram)), tiny(1.0_dp)))**2) &
            exit
         do p = 1, m - 1
            do q = p + 1, m
               g_pq = gram(p, q)
               if (g_pq == 0.0_dp) cycle
               theta = (gram(q, q) - gram(p, p))/(2.0_dp*g_pq)
               t = sign(1.0_dp, theta)/(abs(theta) + sqrt(theta**2 + 1.0_dp))
               cs = 1.0_dp/sqrt(t**2 + 1.0_dp)
               sn = t*cs
               rotated = identity_rotation(m, p, q, cs, sn)
               gram = matmul(transpose(rotated), matmul(gram, rotated))
               vectors = matmul(vectors, rotated)
            end do
         end do
      end do
      threshold = real(max(size(rows, 1), 1), dp)*row_tolerance**2
      keep = [(gram(i, i) <= threshold, i=1, m)]
      basis = vectors(:, pack([(i, i=1, m)], keep))
   end subroutine null_space

   pure function identity_rotation(m, p, q, cs, sn) result(r)
      integer, intent(in) :: m, p, q
      real(dp), intent(in) :: cs, sn
      real(dp) :: r(m, m)
      integer :: i
      r = 0.0_dp
      do i = 1, m
         r(i, i) = 1.0_dp
      end do
      r(p, p) = cs
      r(q, q) = cs
      r(p, q) = sn
      r(q, p) = -sn
   end function identity_rotation

   pure function cross(a, b) result(c)
      real(dp), intent(in) :: a(3), b(3)
      real(dp) :: c(3)
      c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
   end function cross

   pure function int_text(i) result(text)
      integer, intent(in) :: i
      character(len=:), allocatable :: text
      character(len=12) :: buffer
      write (buffer, '(i0)') i
      text = trim(buffer)
   end function int_text

end module uniarc_path_collapse

