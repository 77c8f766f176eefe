!> Linear static analysis: K u = λ R_r with λ = 1 on the initial geometry, with unilateral contact as
!> one linear complementarity problem (the paper's Eq. 31 at λ = 1, the bedded-beam analysis of
!> linings and footings).
!>
!> With contact candidates the unknowns are the augmented ones of the path following (displacements
!> and the reactions of the rigid or stiff candidates, uniarc_contact), the gaps are linearised at
!> u = 0 (g_c ≈ g_c(0) + a_c(0)ᵀu: the small-displacement contact of a linear analysis) and the
!> structure's stiffness is the linear K (uniarc_assembly). The LCP
!>     w = g(0) + A u + T r ≥ 0,   r ≥ 0,   wᵀr = 0,   K u = R + Aᵀ r
!> is solved by the project's contact LCP (uniarc_contact_lcp: the implicit operator of the augmented
!> matrix K_S of a working set S, block pivoting then Lemke) as one load step from the unloaded state
!> with the load constraint δλ = 1; the equations of the set it selects are then solved once.
!> Prescribed displacements of held DOFs (support settlements) load the free DOFs by −K_fp ū
!> (add_settlement_load) and are reported as the displacements of those DOFs (docs/theory.md §3.6).
module uniarc_linear_static
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, add_context, make_error, error_analysis, error_input
   use uniarc_memory, only: allocation_failure
   use uniarc_model, only: model_t, dofs_per_node, gap_circle_inside, gap_circle_outside, gap_fixed_direction
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_dof_map, only: dof_map_t, build_dof_map, candidate_live, element_equations, bed_deflection
   use uniarc_band, only: band_matrix_t, band_inertia
   use uniarc_assembly, only: assemble_reference_load, gather_nodal, scatter_add
   use uniarc_element, only: element_response_t, element_response, element_displacements, transformation_linear
   use uniarc_contact, only: candidate_gap
   use uniarc_path_mechanism, only: find_mechanism, floating_motions
   use uniarc_path_approach, only: rigid_approach
   use uniarc_lift_off, only: describe_lift_off
   use uniarc_floating_subspace, only: orthonormal_motions, unheld_motions
   use uniarc_contact_lcp, only: contact_linearization_t, contact_selection_t, select_contact_set
   use uniarc_static_set_search, only: switching_springs
   use uniarc_static_set, only: solve_set, single_exchanges, search_consistent_set, linearize_at_solution, &
                                assemble_set, touching, refine_solution, block_exchange, complementarity_tolerance, &
                                add_settlement_load
   implicit none
   private
   public :: solve_linear_static, explain_static_imbalance

   !> Rounds of LCP and solve: the LCP of a linear problem is solved in one; a second round only
   !> confirms a set that round-off of the first left in doubt (each LCP is posed at the refined
   !> solution of the last set, linearize_at_solution).
   integer, parameter :: max_rounds = 4
   !> Block exchanges of the refined solution before the LCP (block_exchange, Kostreva 1978; Júdice &
   !> Pires 1994): at most this many, stopped when the count of violations has not fallen for
   !> `block_backup` of them, or when at most `block_threshold` are left (the LCP's own values,
   !> uniarc_lcp_implicit).
   integer, parameter :: max_block_steps = 50, block_backup = 3, block_threshold = 4
   !> Re-linearisations of the gaps of curved and polyline obstacles (solve_linear_static, a sequential
   !> LCP): a smooth obstacle converges linearly with the ratio of its curvature's effect to the
   !> structure's stiffness, and a polyline's feature settles in one or two; more means no settling.
   integer, parameter :: max_relinearisations = 30

contains

   !> Solve the linear problem with its contacts, the gaps of curved and polyline obstacles exact.
   !> solve_linearised solves the structure with every gap linear, g_c(u) = g_c(b) + a_c(b)·(u − b), at
   !> the linearisation point b (b = 0 first); for planes (beds, springs, flat surfaces) that is the
   !> gap itself and one solve is the answer. A curved or polyline obstacle's gap is not linear: its
   !> plane at u = 0 faces the nearest feature there (a trench's corner, not its floor), and the
   !> solution may stop short of the obstacle or pass through it. So, as a sequential LCP, the true
   !> gaps (uniarc_obstacle_shapes) are evaluated at the solution u and re-linearised there (b = u),
   !> and the linear problem is solved again, until each candidate's linearised gap at its solution
   !> is its true gap within complementarity_tolerance of the largest displacement (the working set
   !> and each contact's feature then settle; the reactions act along the normals at u), at most
   !> max_relinearisations times. Out and errors: those of solve_linearised, and (error_analysis) the
   !> re-linearisations not settling (no state that penetrates an obstacle is returned).
   subroutine solve_linear_static(model, displacement, negative_pivots, error, reactions, active, lcp_pivots, &
                                  lcp_residual, deflections)
      type(model_t), intent(in) :: model
      real(dp), allocatable, intent(out) :: displacement(:, :)
      integer, intent(out) :: negative_pivots
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable, intent(out), optional :: reactions(:)
      logical, allocatable, intent(out), optional :: active(:)
      integer, intent(out), optional :: lcp_pivots
      real(dp), intent(out), optional :: lcp_residual
      real(dp), allocatable, intent(out), optional :: deflections(:)
      type(model_t) :: planar
      real(dp), allocatable :: base(:, :), r(:), d(:)
      logical, allocatable :: set(:), curved(:)
      real(dp) :: residual, mismatch, unit, length_scale
      integer :: round, pivots, total, status
      logical :: any_curved
      any_curved = .false.
      if (allocated(model%contacts)) any_curved = any(model%contacts%gap_kind /= gap_fixed_direction)
      if (.not. any_curved) then
         call solve_linearised(model, displacement, negative_pivots, error, reactions, active, lcp_pivots, &
                               lcp_residual, deflections)
         return
      end if
      call centre_on_node(model, error)
      if (allocated(error)) return
      allocate (base(dofs_per_node, model%n_nodes), curved(size(model%contacts)), stat=status)
      call allocation_failure(status, 'the linearisation point of the curved obstacles', &
                              8.0_dp*dofs_per_node*model%n_nodes + 4.0_dp*size(model%contacts), error_analysis, error)
      if (allocated(error)) return
      curved(:) = model%contacts%gap_kind /= gap_fixed_direction
      length_scale = max(maxval(model%coordinates) - minval(model%coordinates), tiny(1.0_dp))
      planar = model
      base(:, :) = 0.0_dp
      total = 0
      do round = 1, max_relinearisations
         call tangent_planes(model, curved, base, planar)
         call solve_linearised(planar, displacement, negative_pivots, error, r, set, pivots, residual, d)
         if (allocated(error)) return
         total = total + pivots
         base(:, :) = displacement
         if (allocated(model%prescribed)) base = base - model%prescribed
         unit = max(maxval(abs(base(1:2, :))), 1.0e-12_dp*length_scale)
         mismatch = plane_mismatch(model, planar, curved, base, set, r)
         if (mismatch <= complementarity_tolerance*unit) exit
         if (round == max_relinearisations) then
            call make_error(error, 'linear static analysis: the contacts with curved or polyline obstacles did '// &
                            'not settle after '//integer_to_string(max_relinearisations)//' re-linearisations of '// &
                            'their gaps at the solution (largest difference of a linearised and a true gap: '// &
                            trim(adjustl(real_to_string(mismatch, '(es10.3)')))//'); no result written', error_analysis)
            ! a load that drives the structure along a rigid motion its contacts cannot hold (a ring
            ! spun in a frictionless cavity) has no equilibrium: said so rather than that the gaps moved
            call explain_static_imbalance(model, error)
            deallocate (displacement)
            return
         end if
      end do
      if (present(reactions)) call move_alloc(r, reactions)
      if (present(active)) call move_alloc(set, active)
      if (present(deflections)) call move_alloc(d, deflections)
      if (present(lcp_pivots)) lcp_pivots = total
      if (present(lcp_residual)) lcp_residual = residual
   end subroutine solve_linear_static

   !> `planar`'s candidates on curved or polyline obstacles (`curved`) become the planes tangent to
   !> their gap at the nodal displacements `base`: g(u) = g(b) + a(b)·(u − b), a fixed-direction gap
   !> with direction a(b) and offset g(b) − a(b)·b (uniarc_model: g = offset + n·u). The others are
   !> the model's own.
   subroutine tangent_planes(model, curved, base, planar)
      type(model_t), intent(in) :: model
      logical, intent(in) :: curved(:)
      real(dp), intent(in) :: base(:, :)
      type(model_t), intent(inout) :: planar
      real(dp) :: gap, gradient(2), hessian(2, 2)
      integer :: c, node
      do c = 1, size(curved)
         if (.not. curved(c)) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), base(1:2, node), gap, gradient, hessian)
         planar%contacts(c)%gap_kind = gap_fixed_direction
         planar%contacts(c)%direction = gradient
         planar%contacts(c)%offset = gap - dot_product(gradient, base(1:2, node))
      end do
   end subroutine tangent_planes

   !> How far the solution `displacement` (the free DOFs' part, without settlements) of the tangent
   !> planes `planar` is from the true obstacles, as a length: the largest |g_true(u) − g_plane(u)| of
   !> the curved candidates, and for those in contact (set, r > 0) the turn of the normal
   !> |a_true(u) − a_plane| times the largest displacement (a reaction along a stale normal: a
   !> polyline's feature that changed while the gap still matches, at a corner).
   real(dp) function plane_mismatch(model, planar, curved, displacement, set, r) result(mismatch)
      type(model_t), intent(in) :: model, planar
      logical, intent(in) :: curved(:), set(:)
      real(dp), intent(in) :: displacement(:, :), r(:)
      real(dp) :: gap, gradient(2), hessian(2, 2), plane, unit
      integer :: c, node
      mismatch = 0.0_dp
      unit = maxval(abs(displacement(1:2, :)))
      do c = 1, size(curved)
         if (.not. curved(c)) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), displacement(1:2, node), gap, gradient, &
                            hessian)
         plane = planar%contacts(c)%offset + dot_product(planar%contacts(c)%direction, displacement(1:2, node))
         mismatch = max(mismatch, abs(gap - plane))
         if (set(c) .and. r(c) > 0.0_dp) &
            mismatch = max(mismatch, norm2(gradient - planar%contacts(c)%direction)*unit)
      end do
   end function plane_mismatch

   !> Solve the linear problem with its contacts.
   !> Out: `displacement` (3, n_nodes) nodal displacements; `negative_pivots`, the negative pivots of
   !> the structure's stiffness with the contact rows of the final set accounted for (non-zero: the
   !> supports and contacts leave a mechanism or K is not positive definite); optional `reactions`
   !> (one per candidate, force ≥ 0, exactly 0 out of contact), `active` (the candidates in contact or
   !> bonded), `lcp_pivots` (pivots the contact LCP spent), `lcp_residual` (largest relative violation
   !> of complementarity of the linearised gaps, docs/theory.md §3.4).
   !> Errors: a mechanism (input: the model moves as a rigid body with every contact closed,
   !> uniarc_path_mechanism); a singular matrix (analysis: the supports and the contacts of the set do not hold the
   !> structure); a contact LCP that is not solved (analysis).
   subroutine solve_linearised(model, displacement, negative_pivots, error, reactions, active, lcp_pivots, &
                               lcp_residual, deflections)
      type(model_t), intent(in) :: model
      real(dp), allocatable, intent(out) :: displacement(:, :)
      integer, intent(out) :: negative_pivots
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable, intent(out), optional :: reactions(:)
      logical, allocatable, intent(out), optional :: active(:)
      integer, intent(out), optional :: lcp_pivots
      real(dp), intent(out), optional :: lcp_residual
      !> (n_contacts) the Pasternak beds' surface deflections under each candidate (0 for the others)
      real(dp), allocatable, intent(out), optional :: deflections(:)
      type(dof_map_t) :: map
      type(band_matrix_t) :: assembled, factors
      type(contact_linearization_t) :: lin
      type(contact_selection_t) :: selection
      real(dp), allocatable :: residual(:), reference(:), rhs(:, :), x(:), r(:), g(:), zero_nodal(:, :), applied(:)
      !> the floating motions (n, k, orthonormal in the metric) of a structure held only by its contacts
      !> across a gap (unallocated: no approach)
      real(dp), allocatable :: floating(:, :)
      logical, allocatable :: set(:), start_set(:), previous(:), flip(:)
      logical :: singular, settled, block, unheld_set
      character(len=:), allocatable :: solver_message
      real(dp) :: length_scale, worst
      integer :: n, round, pivots, c, status, block_steps, fewest, stalled

      call build_dof_map(model, map, error, error_analysis)
      if (allocated(error)) return
      n = map%n_equations
      length_scale = max(maxval(model%coordinates) - minval(model%coordinates), tiny(1.0_dp))
      allocate (zero_nodal(dofs_per_node, model%n_nodes), reference(n), residual(n), rhs(n, 2), applied(n), x(n), &
                set(size(map%candidate_equation)), r(size(map%candidate_equation)), g(size(map%candidate_equation)), &
                previous(size(map%candidate_equation)), flip(size(map%candidate_equation)), stat=status)
      call allocation_failure(status, 'the load and residual vectors of the linear analysis', &
                              8.0_dp*(dofs_per_node*model%n_nodes + 6.0_dp*n) + 28.0_dp*size(map%candidate_equation), &
                              error_analysis, error)
      if (allocated(error)) return
      zero_nodal = 0.0_dp
      call centre_on_node(model, error)
      if (allocated(error)) return
      call assemble_reference_load(model, map, .true., reference)
      applied(:) = reference
      if (allocated(model%prescribed)) call add_settlement_load(model, map, reference)
      ! The first working set: candidates that touch at u = 0, and the bonded ones (as the path
      ! following starts): it holds what the contacts hold, so K_S is regular for a structure that
      ! rests on its medium without supports.
      ! A model that can move as a rigid body even with every contact closed is a mechanism: refused
      ! (error_input, exit 2) before any solve, by the path following's start-up test
      ! (uniarc_path_mechanism: relative pivot test, then the rigid-body test).
      do c = 1, size(set)
         set(c) = candidate_live(map, c)
      end do
      call assemble_set(model, map, zero_nodal, set, assembled, residual, error)
      if (allocated(error)) return
      call find_mechanism(model, map, assembled, error, error_analysis)
      if (allocated(error)) return
      call touching(model, map, length_scale, set)
      ! A structure held only by its contacts across a gap, that the load pushes along a free rigid
      ! translation (docs/theory.md §2.8): the first working set is the contacts its linearised gaps
      ! meet first along that translation (then along any floating motion the load still pushes and the
      ! set leaves free), and the floating motions no contact of a set holds are held.
      call approach_first_contact(model, map, reference, length_scale, assembled, residual, set, floating, error)
      if (allocated(error)) return
      pivots = 0
      worst = 0.0_dp
      ! the set of the unloaded state, where the search of a model with switching springs starts
      allocate (start_set(size(set)), stat=status)
      call allocation_failure(status, 'the first contact set of the linear analysis', 4.0_dp*size(set), &
                              error_analysis, error)
      if (allocated(error)) return
      start_set(:) = set
      settled = .false.
      block = .true.
      block_steps = 0
      fewest = huge(1)
      stalled = 0
      round = 0
      do
         call solve_set(model, map, zero_nodal, set, floating, residual, reference, applied, length_scale, &
                        assembled, factors, rhs, x, r, g, worst, error, unheld_set)
         if (allocated(error) .and. unheld_set .and. block_steps > 0 .and. block) then
            ! a block exchange that left the structure unheld: back to its set, the LCP goes on from it
            deallocate (error)
            set = previous
            block = .false.
            cycle
         end if
         if (allocated(error)) return
         if (worst <= complementarity_tolerance) then
            settled = .true.
            exit
         end if
         if (block) then
            call block_exchange(model, map, length_scale, x, reference, r, g, set, flip)
            if (count(flip) < fewest) then
               fewest = count(flip)
               stalled = 0
            else
               stalled = stalled + 1
            end if
            block = count(flip) > block_threshold .and. stalled < block_backup .and. block_steps < max_block_steps
            if (block) then
               previous = set
               set = set .neqv. flip
               block_steps = block_steps + 1
               pivots = pivots + count(flip)   ! principal pivots, as the LCP's block phase counts them
               cycle
            end if
         end if
         round = round + 1
         if (round > max_rounds) exit
         ! The LCP posed at the refined solution x of the set (its residual from the elements' forces),
         ! not at u = 0; `assembled` (refine_solution left the contact part of K_S in it) is its work
         ! space, then the set's K_S again.
         call linearize_at_solution(model, map, set, applied, factors, zero_nodal, length_scale, x, rhs(:, 2), &
                                    assembled, lin, error)
         if (allocated(error)) return
         call assemble_set(model, map, zero_nodal, set, assembled, residual, error, floating)
         if (allocated(error)) return
         call select_contact_set(model, map, lin, set, assembled, factors, selection, error)
         pivots = pivots + selection%report%pivots
         if (allocated(error)) then
            ! a load that lifts the structure off every contact that could hold it: no equilibrium
            ! exists (docs/theory.md §3.12), said so instead of the solver's words
            solver_message = error%message
            call lift_off_error(model, map, zero_nodal, assembled, error)
            if (error%message /= solver_message .or. switching_springs(model)) then
               call add_context(error, 'linear static analysis')
               return
            end if
            ! not that: the LCP's frames did not reach its accuracy (a breakdown, not a ray); the single
            ! exchanges of the refined solution below go on from the set of the last solve
            deallocate (error)
            exit
         end if
         set = selection%active
      end do
      if (.not. settled .and. .not. switching_springs(model)) then
         call single_exchanges(model, map, zero_nodal, floating, residual, reference, applied, length_scale, &
                               assembled, factors, rhs, x, r, g, set, worst, pivots, error)
         if (allocated(error)) return
      else if (.not. settled) then
         ! Tangential springs that switch with their radial contacts: the law is not an LCP and its
         ! rounds can cycle (docs/theory.md §3.8); the search by single changes from the set of the
         ! unloaded state (uniarc_static_set_search) finds a consistent set or says that none was reached.
         set = start_set
         call search_consistent_set(model, map, zero_nodal, floating, residual, reference, applied, length_scale, &
                                    assembled, factors, rhs, x, r, g, set, worst, error)
         if (allocated(error)) return
      end if

      call assemble_set(model, map, zero_nodal, set, assembled, residual, error, floating)
      if (allocated(error)) return
      ! Inertia of the final K_S: each contact row of the set adds one negative pivot to the
      ! saddle-point matrix (Haynsworth inertia additivity); what remains belongs to the structure.
      call band_inertia(assembled, negative_pivots, singular, status)
      call allocation_failure(status, 'a copy of the stiffness matrix for its inertia', &
                              8.0_dp*real(size(assembled%ab), dp), error_analysis, error)
      if (allocated(error)) return
      negative_pivots = max(0, negative_pivots - count(set .and. map%candidate_equation > 0))
      allocate (displacement(dofs_per_node, model%n_nodes), stat=status)
      call allocation_failure(status, 'the nodal displacements', 8.0_dp*dofs_per_node*model%n_nodes, error_analysis, &
                              error)
      if (allocated(error)) return
      call gather_nodal(map, x, displacement)
      if (allocated(model%prescribed)) displacement = displacement + model%prescribed
      ! the caller's contact arrays allocated with stat= and filled in place (an assignment that
      ! allocates, or a function result, is not checked)
      if (present(reactions)) then
         allocate (reactions(size(r)), stat=status)
         call allocation_failure(status, 'the contact reactions of the linear analysis', 8.0_dp*size(r), &
                                 error_analysis, error)
         if (allocated(error)) return
         reactions(:) = r
      end if
      if (present(active)) then
         allocate (active(size(set)), stat=status)
         call allocation_failure(status, 'the contact set of the linear analysis', 4.0_dp*size(set), &
                                 error_analysis, error)
         if (allocated(error)) return
         active(:) = set
      end if
      if (present(lcp_pivots)) lcp_pivots = pivots
      if (present(lcp_residual)) lcp_residual = worst
      if (present(deflections)) then
         allocate (deflections(size(map%candidate_equation)), stat=status)
         call allocation_failure(status, 'the bed deflections of the linear analysis', &
                                 8.0_dp*size(map%candidate_equation), error_analysis, error)
         if (allocated(error)) return
         do c = 1, size(deflections)
            deflections(c) = bed_deflection(map, c, x)
         end do
      end if
   end subroutine solve_linearised

   !> A structure held only by its contacts across a gap, that the reference load `reference` pushes
   !> along a rigid translation its supports leave free (docs/theory.md §2.8, uniarc_path_approach):
   !> `set` gets the candidates that the translation brings first to their linearised gap
   !> g(0) + a(0)·u = 0 (the gaps of the linear analysis stay linearised at u = 0: the solve with that
   !> set closes them, the translation being part of its solution), then, while the load still pushes
   !> along a floating motion the set leaves free (push_free_motions), those that motion brings first
   !> to theirs; `floating` (n, k) gets the structure's floating motions, orthonormal in the metric, of
   !> which assemble_set holds those no contact of a set holds (allocated only then: every other model
   !> is solved as before). The floating motions are those of the linear stiffness with the unilateral
   !> candidates open (`matrix`, `residual` work space). Untouched without unilateral candidates or
   !> such a motion.
   !> Errors (error_input): the load carries the structure away from every contact (rigid_approach).
   subroutine approach_first_contact(model, map, reference, length_scale, matrix, residual, set, floating, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: reference(:), length_scale
      type(band_matrix_t), intent(inout) :: matrix
      real(dp), intent(inout) :: residual(:)
      logical, intent(inout) :: set(:)
      real(dp), allocatable, intent(out) :: floating(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: motions(:, :), shift(:), zero_nodal(:, :)
      integer, allocatable :: equations(:)
      logical, allocatable :: bonded(:)
      integer :: c, contact, status
      logical :: unilateral
      unilateral = .false.
      do c = 1, size(map%candidate_equation)
         unilateral = unilateral .or. (candidate_live(map, c) .and. .not. model%contacts(c)%bilateral)
      end do
      if (.not. unilateral) return
      ! its arrays allocated with stat= (no array constructors of the candidates' length)
      allocate (zero_nodal(dofs_per_node, model%n_nodes), bonded(size(map%candidate_equation)), &
                shift(map%n_equations), stat=status)
      call allocation_failure(status, 'the vectors of the rigid approach of the linear analysis', &
                              8.0_dp*dofs_per_node*model%n_nodes + 8.0_dp*map%n_equations + &
                              4.0_dp*size(map%candidate_equation), error_analysis, error)
      if (allocated(error)) return
      zero_nodal(:, :) = 0.0_dp
      ! a spring with an uplift limit holds nothing once it yields: released, as in the path
      do c = 1, size(map%candidate_equation)
         bonded(c) = candidate_live(map, c) .and. model%contacts(c)%bilateral .and. &
                     .not. model%contacts(c)%uplift_force > 0.0_dp
      end do
      call assemble_set(model, map, zero_nodal, bonded, matrix, residual, error)
      if (allocated(error)) return
      call floating_motions(model, map, matrix, motions, equations, error)
      if (allocated(error) .or. .not. allocated(motions)) return
      call rigid_approach(model, map, motions, reference, zero_nodal, length_scale, .true., shift, contact, error)
      if (allocated(error) .or. contact == 0) return
      call close_touching(model, map, shift, length_scale, set, error)
      if (allocated(error)) return
      call orthonormal_motions(map, motions, floating, error)
      if (allocated(error)) return
      call push_free_motions(model, map, reference, length_scale, floating, shift, set, error)
   end subroutine approach_first_contact

   !> Candidates of `set`'s complement whose linearised gap g(0) + a(0)·u at the rigid displacement
   !> `shift` (n) is closed (within 1e-9 of the model size, uniarc_path_approach's touch fraction) join it.
   !> Errors (error_analysis, out of memory): its nodal displacements refused (`set` untouched).
   subroutine close_touching(model, map, shift, length_scale, set, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: shift(:), length_scale
      logical, intent(inout) :: set(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: moved(:, :)
      real(dp) :: gap, gradient(2), hessian(2, 2)
      integer :: c, node, status
      allocate (moved(dofs_per_node, model%n_nodes), stat=status)
      call allocation_failure(status, 'the nodal displacements of the rigid approach', &
                              8.0_dp*dofs_per_node*model%n_nodes, error_analysis, error)
      if (allocated(error)) return
      call gather_nodal(map, shift, moved)
      do c = 1, size(set)
         if (set(c) .or. .not. candidate_live(map, c)) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), [0.0_dp, 0.0_dp], gap, gradient, hessian)
         set(c) = gap + dot_product(gradient, moved(1:2, node)) <= 1.0e-9_dp*length_scale
      end do
   end subroutine close_touching

   !> The rigid approach continued over the whole floating subspace (docs/theory.md §2.8): while the
   !> reference load does work along the floating motions U (n, p) that `set` leaves free
   !> (unheld_motions) — d = U Uᵀ R, the load's direction in their span, with dᵀR = |UᵀR|² above
   !> push_tolerance of Σ|d_j R_j| (a load with no component there, a symmetric ring's weight along its
   !> free rotation, leaves round-off: ~1e-16 of it) — the structure, still rigid at `shift` (n), moves
   !> along d to the first linearised gap it closes; those candidates join `set` (the set's own contacts
   !> do not see d, so they stay closed). At most k rounds (each new contact holds one more direction).
   !> No candidate met along d (the load lifts the structure off the contacts that could hold it) ends
   !> the approach: the contact LCP then fails and the lift-off test explains it (docs/theory.md §3.12).
   !> Errors (error_analysis, out of memory): its vectors, nodal displacements or the unheld motions
   !> refused by the system.
   subroutine push_free_motions(model, map, reference, length_scale, floating, shift, set, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: reference(:), length_scale, floating(:, :)
      real(dp), intent(inout) :: shift(:)
      logical, intent(inout) :: set(:)
      type(error_t), allocatable, intent(out) :: error
      !> the approach's tolerances (uniarc_path_approach: push_tolerance, slope_tolerance)
      real(dp), parameter :: push_tolerance = 1.0e-9_dp, slope_tolerance = 1.0e-12_dp
      real(dp), allocatable :: unheld(:, :), d(:), moved(:, :), along(:, :)
      real(dp) :: gap, gradient(2), hessian(2, 2), slope, s, s_best
      integer :: round, c, node, met, status
      allocate (moved(dofs_per_node, model%n_nodes), along(dofs_per_node, model%n_nodes), d(size(shift)), &
                stat=status)
      call allocation_failure(status, 'the vectors of the rigid approach along the floating motions', &
                              16.0_dp*dofs_per_node*model%n_nodes + 8.0_dp*size(shift), error_analysis, error)
      if (allocated(error)) return
      do round = 1, size(floating, 2)
         call unheld_motions(model, map, set, floating, unheld, error)
         if (allocated(error)) return
         if (size(unheld, 2) == 0) return
         d(:) = matmul(unheld, matmul(transpose(unheld), reference))
         if (.not. dot_product(d, reference) > push_tolerance*sum(abs(d*reference))) return
         d = d/maxval(abs(map%metric*d))
         call gather_nodal(map, shift, moved)
         call gather_nodal(map, d, along)
         s_best = huge(1.0_dp)
         met = 0
         do c = 1, size(set)
            if (set(c) .or. .not. candidate_live(map, c)) cycle
            if (model%contacts(c)%bilateral .or. model%contacts(c)%tangential) cycle
            node = model%contacts(c)%node
            call candidate_gap(model%contacts(c), model%coordinates(:, node), [0.0_dp, 0.0_dp], gap, gradient, &
                               hessian)
            slope = dot_product(gradient, along(1:2, node))
            if (.not. slope < -slope_tolerance*norm2(gradient)) cycle
            s = max(gap + dot_product(gradient, moved(1:2, node)), 0.0_dp)/(-slope)
            if (s < s_best) then
               s_best = s
               met = c
            end if
         end do
         ! no contact along d: the load lifts the structure off what could hold it; the LCP and the
         ! lift-off test say so (docs/theory.md §3.12, lift_off_error), as before the approach
         if (met == 0) return
         shift = shift + s_best*d
         call close_touching(model, map, shift, length_scale, set, error)
         if (allocated(error)) return
         set(met) = .true.
      end do
   end subroutine push_free_motions

   !> A circular obstacle whose centre, moved whole by the deck's *MOVE (docs/theory.md §3.11), lies on
   !> a node that is its candidate: the gap |x − c| − R has no normal there (a node a radius deep), so
   !> no contact force has a direction. Errors (error_input): that node and obstacle.
   subroutine centre_on_node(model, error)
      type(model_t), intent(in) :: model
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: deck
      integer :: c, node
      if (.not. allocated(model%contacts)) return
      do c = 1, size(model%contacts)
         associate (contact => model%contacts(c))
            if (contact%gap_kind /= gap_circle_inside .and. contact%gap_kind /= gap_circle_outside) cycle
            node = contact%node
            if (norm2(model%coordinates(:, node) - contact%centre) > epsilon(1.0_dp)*contact%radius) cycle
            deck = ''
            if (allocated(model%deck_path)) deck = model%deck_path//': '
            call make_error(error, deck//'linear static analysis: node '//integer_to_string(model%node_label(node))// &
                            ' lies at the centre of the circular obstacle it touches (after the obstacle''s '// &
                            '*MOVE, applied whole): its gap has no normal there; move the obstacle less', &
                            error_input)
            return
         end associate
      end do
   end subroutine centre_on_node

   !> A linear result that failed the equilibrium check (uniarc_static_balance) of `model`: when the
   !> load lifts the structure off every contact that could hold it (docs/theory.md §3.12: a couple on a
   !> free beam resting on a tensionless bed has no resultant to push it along a translation, and the
   !> contact LCP may end on a working set whose K_S the factorisation does not find singular), `error`
   !> is replaced by the lift-off message (error_analysis); otherwise it is kept. Errors of the test
   !> itself (its numbering or band matrix) leave `error` as it was.
   subroutine explain_static_imbalance(model, error)
      type(model_t), intent(in) :: model
      type(error_t), allocatable, intent(inout) :: error
      type(dof_map_t) :: map
      type(band_matrix_t) :: assembled
      type(error_t), allocatable :: failure
      real(dp), allocatable :: zero_nodal(:, :)
      character(len=:), allocatable :: imbalance
      integer :: status
      if (.not. allocated(error)) return
      call build_dof_map(model, map, failure, error_analysis)
      if (allocated(failure)) return
      allocate (zero_nodal(dofs_per_node, model%n_nodes), stat=status)
      if (status /= 0) return
      zero_nodal = 0.0_dp
      imbalance = error%message
      call lift_off_error(model, map, zero_nodal, assembled, error)
      if (error%message /= imbalance) call add_context(error, 'linear static analysis')
   end subroutine explain_static_imbalance

   !> The lift-off test of a contact LCP that failed (uniarc_lift_off, docs/theory.md §3.12): the rigid
   !> motions that only the unilateral candidates hold (the stiffness with the bonded ones, as the
   !> path's find_floating) and the load with those candidates open. When the load lifts the
   !> structure off, `error` is replaced by the message that says so (error_analysis); else kept.
   !> `assembled` is work space.
   subroutine lift_off_error(model, map, zero_nodal, assembled, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: zero_nodal(:, :)
      type(band_matrix_t), intent(inout) :: assembled
      type(error_t), allocatable, intent(inout) :: error
      type(error_t), allocatable :: failure
      real(dp), allocatable :: residual(:), reference(:), motions(:, :)
      integer, allocatable :: equations(:)
      logical, allocatable :: bonded(:)
      character(len=:), allocatable :: text
      integer :: c, status
      ! its arrays allocated with stat=: refused, the message stays the solver's (the lift-off text is
      ! a hint, as those of a failed step)
      allocate (bonded(size(map%candidate_equation)), residual(map%n_equations), reference(map%n_equations), &
                stat=status)
      if (status /= 0) return
      do c = 1, size(map%candidate_equation)
         bonded(c) = candidate_live(map, c) .and. model%contacts(c)%bilateral .and. &
                     .not. model%contacts(c)%uplift_force > 0.0_dp
      end do
      call assemble_set(model, map, zero_nodal, bonded, assembled, residual, failure)
      if (allocated(failure)) return
      call floating_motions(model, map, assembled, motions, equations, failure)
      if (allocated(failure) .or. .not. allocated(motions)) return
      call assemble_reference_load(model, map, .true., reference)
      if (allocated(model%prescribed)) call add_settlement_load(model, map, reference)
      residual(:) = residual + reference   ! in place: no temporary of the sum
      call describe_lift_off(model, map, motions, zero_nodal, residual, text)
      if (.not. allocated(text)) return
      deallocate (error)
      call make_error(error, text, error_analysis)
   end subroutine lift_off_error

   !> Zero nodal displacements and reactions of the model, for the contact part at u = 0.

end module uniarc_linear_static
