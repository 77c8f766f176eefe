!> Mechanisms: a model that can move as a rigid body without deforming (docs/theory.md §2.4).
!>
!> `find_mechanism` works on any unfactorised stiffness of the model (the path's tangent at the
!> unloaded state, the linear stiffness of *STATIC): two stages, both scaled so that large held models
!> pass.
!> 1. The relative pivot test (uniarc_band, band_weakest_pivot): Gaussian elimination without
!>    interchanges, each pivot against the diagonal entry of its own row before elimination. A free
!>    motion leaves round-off there; a held model leaves more, but on large models not much more (a
!>    cantilever of 1e4 elements numbered from its support: 1.0e-12; a ring of 1e5 elements: 1.9e-13),
!>    so a pivot at most 1e-10 of its diagonal only calls for stage 2.
!> 2. The rigid-body test: the plane rigid motions — every translation, and the rotation about every
!>    point (a rotation about the centroid plus the translation that best cancels its forces) — are
!>    put through the stiffness. A motion is held if some row keeps a term it does not cancel (a
!>    support: the coupling to the held DOF) or if its energy vᵀKv, a coherent sum, stands above the
!>    round-off of the rows (springs or closed contacts spread over the model, each far below the
!>    bending terms of its row on a fine mesh); a motion held by neither is free (function `held`).
!> 3. Mechanisms inside the model (a chain of hinges between supports, a part with no support of its
!>    own), when stage 1 found a weak pivot and stage 2 no free rigid motion: the least mode of the
!>    stiffness relative to its diagonal by shifted inverse iteration, free if it passes the round-off
!>    test of stage 2 (free_internal_motion).
!> The model is refused (error_input, exit code 2) with the free motion and the node it moves most
!> (stage 3: the nodes and elements it takes).
module uniarc_path_mechanism
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_model, only: model_t
   use uniarc_dof_map, only: dof_map_t, candidate_live
   use uniarc_band, only: band_matrix_t, band_weakest_pivot, band_row_terms, band_product, band_allocate, &
                          band_add, band_get, band_copy, band_factorize, band_solve
   use uniarc_assembly, only: assemble_linear_stiffness
   use uniarc_contact, only: assemble_contact
   use uniarc_model, only: dofs_per_node
   use uniarc_path_state, only: path_state_t, path_system_t, equilibrium_at
   implicit none
   private
   public :: find_mechanism, check_mechanism, check_model_mechanism, floating_motions, closed_linear_stiffness

   !> Stage 1: a pivot at most this fraction of its row's diagonal calls for stage 2.
   real(dp), parameter :: pivot_tolerance = 1.0e-10_dp
   !> Stage 2: a rigid motion is free if no row keeps more than this share of its terms ...
   real(dp), parameter :: residual_tolerance = 1.0e3_dp*epsilon(1.0_dp)
   !> ... and its energy is at most this many times the random walk of the rows' round-off.
   real(dp), parameter :: energy_factor = 3.0_dp

contains

   !> The path's check at the unloaded state: the tangent with every contact candidate closed (held
   !> as if bonded), so that a model that contacts will hold once they touch (a liner floating in a
   !> cavity) passes. `system` is work space (its tangent is overwritten); nodal (dofs_per_node,
   !> n_nodes) the displacements of state%u. Errors: find_mechanism's; its arrays refused by the
   !> system (error_analysis, out of memory).
   subroutine check_mechanism(model, state, system, nodal, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(path_system_t), intent(inout) :: system
      real(dp), intent(in) :: nodal(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: internal(:), reference(:)
      logical, allocatable :: closed(:)
      real(dp) :: element_scale
      integer :: c, status
      allocate (internal(state%map%n_equations), reference(state%map%n_equations), &
                closed(size(state%map%candidate_equation)), stat=status)
      call allocation_failure(status, 'the vectors of the mechanism check', &
                              16.0_dp*state%map%n_equations + 4.0_dp*size(state%map%candidate_equation), &
                              error_analysis, error)
      if (allocated(error)) return
      do c = 1, size(closed)
         closed(c) = candidate_live(state%map, c)
      end do
      call equilibrium_at(model, state, system, state%u, 0.0_dp, closed, nodal, internal, reference, element_scale, &
                          error)
      if (allocated(error)) return
      call find_mechanism(model, state%map, system%tangent, error, error_analysis)
   end subroutine check_mechanism

   !> The rigid motions (n, k ≤ 3) that `stiffness` (unfactorised, n × n: the structure with its supports
   !> and bilateral contacts, the unilateral ones open) leaves free — a liner floating in a cavity, held
   !> only by its contacts once they touch (docs/theory.md §2.8) — and for each the equation where it
   !> moves most, at which the tangent holds it while no contact does. Found one at a time by the
   !> module's test (free_rigid_motion), each held at its equation (a spring of the size of the
   !> diagonal there) before the next is looked for. `motions` unallocated: none.
   !> Once one motion is found the stiffness is known to be singular, and the relative pivot test
   !> (stage 1) says nothing about the next: the elimination of a flexible structure held at one DOF
   !> leaves its last free motion a pivot of the round-off of an ill-conditioned elimination, which
   !> grows with the mesh (a beam of EI = 1, L = 8 on a bed, held in x at its middle: 1.7e-10,
   !> 1.0e-9, 2.5e-10 of the diagonal with 200, 500, 1000 elements, above stage 1's 1e-10, so its
   !> second motion was missed), so the second and third motions are looked for by stage 2 alone.
   !> Errors: a copy or a vector refused by the system (error_analysis, out of memory).
   subroutine floating_motions(model, map, stiffness, motions, equations, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(band_matrix_t), intent(in) :: stiffness
      real(dp), allocatable, intent(out) :: motions(:, :)
      integer, allocatable, intent(out) :: equations(:)
      type(error_t), allocatable, intent(out) :: error
      type(band_matrix_t) :: work
      real(dp), allocatable :: motion(:), found(:, :)
      real(dp) :: ratio, diagonal
      character(len=:), allocatable :: what
      integer :: row, k, j, status
      call band_copy(stiffness, work, error, error_analysis)
      if (allocated(error)) return
      allocate (found(map%n_equations, 3), equations(0), stat=status)
      call allocation_failure(status, 'the floating motions', 24.0_dp*map%n_equations, error_analysis, error)
      if (allocated(error)) return
      do k = 1, 3
         call free_rigid_motion(model, map, work, motion, ratio, row, what, error, error_analysis, screen=k == 1)
         if (allocated(error)) return
         if (.not. allocated(motion)) exit
         j = maxloc(abs(map%metric*motion), 1)
         found(:, k) = motion
         equations = [equations, j]
         diagonal = abs(band_get(work, j, j))
         if (.not. (diagonal > 0.0_dp)) diagonal = 1.0_dp
         call band_add(work, j, j, diagonal)
      end do
      if (size(equations) == 0) then
         deallocate (equations)
         return
      end if
      allocate (motions(map%n_equations, size(equations)), stat=status)
      call allocation_failure(status, 'the floating motions', 8.0_dp*map%n_equations*size(equations), &
                              error_analysis, error)
      if (allocated(error)) return
      motions(:, :) = found(:, 1:size(equations))
   end subroutine floating_motions

   !> Refuse a model whose unfactorised stiffness `stiffness` (n × n, n = map%n_equations, with the
   !> supports, springs and contacts that hold the model) lets it move as a rigid body.
   !> Errors (error_input): the model is a mechanism: which rigid motion, the node it moves most and
   !> the component there. A work array refused by the system: out of memory, of `category`
   !> (error_input, the default, before the analysis: the model does not fit in memory; error_analysis
   !> once it has started).
   subroutine find_mechanism(model, map, stiffness, error, category)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(band_matrix_t), intent(in) :: stiffness
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in), optional :: category
      real(dp), allocatable :: motion(:)
      real(dp) :: ratio
      character(len=:), allocatable :: what, deck
      integer :: row, node, dof, largest, label, memory_category
      memory_category = error_input
      if (present(category)) memory_category = category
      call free_rigid_motion(model, map, stiffness, motion, ratio, row, what, error, memory_category, axes=.true.)
      if (allocated(error)) return
      if (.not. allocated(motion)) then
         ! Stage 3: a weak pivot that no rigid motion of the whole explains may be a mechanism inside
         ! the model (a chain of hinges, a part held by nothing of its own).
         if (row == 0 .or. ratio > pivot_tolerance) return
         call free_internal_motion(map, stiffness, motion, error, memory_category)
         if (allocated(error)) return
         if (.not. allocated(motion)) return
         call internal_mechanism_error(model, map, motion, ratio, row, error, memory_category)
         return
      end if
      largest = maxloc(abs(map%metric*motion), 1)
      node = 0
      dof = 0
      do node = 1, size(map%equation, 2)
         dof = findloc(map%equation(:, node), largest, 1)
         if (dof > 0) exit
      end do
      deck = 'the model'
      if (allocated(model%deck_path)) deck = model%deck_path//': the model'
      label = node
      if (allocated(model%node_label)) label = model%node_label(node)
      call make_error(error, deck//' is a mechanism (its stiffness is singular): it can move as a rigid body, '// &
                      what//', without deforming anything that holds it (even with every contact closed; '// &
                      'weakest pivot '//trim(real_to_string(ratio, '(es9.2)'))//' of its diagonal, at equation '// &
                      integer_to_string(row)//'); the motion is largest at node '//integer_to_string(label)//', '// &
                      component_name(dof)//'; hold it with supports (*BOUNDARY)', error_input)

   end subroutine find_mechanism

   !> The check of a model on its own, before any analysis (`uniarc --check`, *STATIC): the linear
   !> stiffness of the unloaded structure — the tangent of the path's unloaded state, which carries no
   !> stress — with every contact candidate closed (closed_linear_stiffness), through find_mechanism.
   !> Errors: a band matrix that cannot be allocated (band_allocate); find_mechanism's (error_input,
   !> exit code 2).
   subroutine check_model_mechanism(model, map, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(error_t), allocatable, intent(out) :: error
      type(band_matrix_t) :: stiffness
      if (map%n_equations == 0) return
      call closed_linear_stiffness(model, map, stiffness, error)
      if (allocated(error)) return
      call find_mechanism(model, map, stiffness, error)
   end subroutine check_model_mechanism

   !> The linear stiffness of the unloaded structure (n × n, unfactorised, n = map%n_equations > 0)
   !> with every contact candidate closed (held as if bonded; augmented rows for those with a reaction
   !> unknown). Errors: a band matrix or a vector that cannot be allocated (error_input: the model does
   !> not fit in memory).
   subroutine closed_linear_stiffness(model, map, stiffness, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(band_matrix_t), intent(out) :: stiffness
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: at_rest(:, :), no_reactions(:), internal(:)
      logical, allocatable :: closed(:)
      integer :: c, status
      call band_allocate(stiffness, map%n_equations, map%half_bandwidth, map%half_bandwidth, error)
      if (allocated(error)) return
      call assemble_linear_stiffness(model, map, stiffness)
      if (size(map%candidate_equation) > 0) then
         allocate (at_rest(dofs_per_node, model%n_nodes), no_reactions(size(map%candidate_equation)), &
                   internal(map%n_equations), closed(size(map%candidate_equation)), stat=status)
         call allocation_failure(status, 'the vectors of the closed structure''s stiffness', &
                                 8.0_dp*(dofs_per_node*model%n_nodes + map%n_equations) + &
                                 12.0_dp*size(map%candidate_equation), error_input, error)
         if (allocated(error)) return
         at_rest = 0.0_dp
         no_reactions = 0.0_dp
         internal = 0.0_dp
         do c = 1, size(closed)
            closed(c) = candidate_live(map, c)
         end do
         call assemble_contact(model, map, at_rest, no_reactions, closed, stiffness, internal)
      end if
   end subroutine closed_linear_stiffness

   !> The rigid motion (n, unit rotation or translation) that `stiffness` does not hold, if any
   !> (`motion` unallocated otherwise): stage 1 and 2 of the module's test. `ratio` and `row`: the
   !> weakest pivot over its diagonal and its equation; `what`: the motion in words. `screen` (default
   !> .true.): stage 1 first, stage 2 only where it finds a weak pivot; .false.: stage 2 alone (ratio
   !> huge, row 0), for a stiffness known to be singular (floating_motions).
   !> Errors: its vectors refused by the system (out of memory, of `category`, uniarc_memory).
   !> With `axes` true, a translation whose direction is within 1e-12 of an axis is tried along the
   !> axis itself too (the refusal of a mechanism; not the floating motions of a model held by its
   !> contacts, whose detection it would change).
   subroutine free_rigid_motion(model, map, stiffness, motion, ratio, row, what, error, category, axes, screen)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(band_matrix_t), intent(in) :: stiffness
      real(dp), allocatable, intent(out) :: motion(:)
      real(dp), intent(out) :: ratio
      integer, intent(out) :: row
      character(len=:), allocatable, intent(out) :: what
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in) :: category
      logical, intent(in), optional :: axes
      logical, intent(in), optional :: screen
      real(dp), allocatable :: modes(:, :), forces(:, :), candidate(:), rotation(:), product(:), magnitude(:)
      real(dp) :: centre(2), gram(2, 2), angle, shift(2), det, best, residual, extent, largest_force, direction(2)
      integer :: below, node, dof, status, n
      logical :: snap
      what = ''
      ratio = huge(1.0_dp)
      row = 0
      if (map%n_equations == 0) return
      ! A copy the system refuses leaves row 0: no mechanism named (the caller's message stands).
      if (.not. present(screen)) then
         call band_weakest_pivot(stiffness, pivot_tolerance, row, ratio, below, status)
         if (row == 0 .or. ratio > pivot_tolerance) return
      else if (screen) then
         call band_weakest_pivot(stiffness, pivot_tolerance, row, ratio, below, status)
         if (row == 0 .or. ratio > pivot_tolerance) return
      end if
      ! The rigid motions about the centroid: translation x, translation y, rotation (Przemieniecki
      ! 1968, §2: u = a − θ(y − y_c), v = b + θ(x − x_c), rz = θ), on the free equations.
      centre = sum(model%coordinates, 2)/real(max(1, model%n_nodes), dp)
      n = map%n_equations
      allocate (modes(n, 3), forces(n, 3), candidate(n), rotation(n), product(n), magnitude(n), stat=status)
      call allocation_failure(status, 'the vectors of the mechanism search', 80.0_dp*n, category, error)
      if (allocated(error)) return
      modes = 0.0_dp
      forces = 0.0_dp
      do node = 1, model%n_nodes
         call put(1, node, 1, 1.0_dp)
         call put(2, node, 2, 1.0_dp)
         call put(3, node, 1, -(model%coordinates(2, node) - centre(2)))
         call put(3, node, 2, model%coordinates(1, node) - centre(1))
         call put(3, node, 3, 1.0_dp)
      end do
      do dof = 1, 3
         call band_product(stiffness, modes(:, dof), forces(:, dof))
      end do
      ! One common scale for the three force vectors: the angle and the shift below are ratios of
      ! their products (invariant under it), and stiffnesses up to the accepted 1e150 per element
      ! would overflow the Gram determinant's fourth powers unscaled. A power of two: the scaling is
      ! exact, the results those of the unscaled vectors wherever these did not overflow.
      largest_force = maxval(abs(forces))
      if (largest_force > 0.0_dp) forces = forces/set_exponent(1.0_dp, exponent(largest_force))
      ! The translation least held: the eigenvector of the least eigenvalue of the 2×2 Gram matrix of
      ! the translations' forces (its angle in closed form).
      gram(1, 1) = dot_product(forces(:, 1), forces(:, 1))
      gram(2, 2) = dot_product(forces(:, 2), forces(:, 2))
      gram(1, 2) = dot_product(forces(:, 1), forces(:, 2))
      angle = 0.5_dp*atan2(2.0_dp*gram(1, 2), gram(1, 1) - gram(2, 2)) + 2.0_dp*atan(1.0_dp)
      direction = [cos(angle), sin(angle)]
      candidate(:) = direction(1)*modes(:, 1) + direction(2)*modes(:, 2)
      best = held(candidate)
      snap = .false.
      if (present(axes)) snap = axes
      if (snap .and. best > 1.0_dp .and. any(abs(direction) <= 1.0e-12_dp)) then
         ! cos and sin of an axis direction leave round-off (sin π = 1.2e-16): on a model whose other
         ! translation is held (a beam on two rollers) that sliver meets the supports, and the free
         ! translation looked held. The axis itself is tried too.
         where (abs(direction) <= 1.0e-12_dp) direction = 0.0_dp
         direction = direction/norm2(direction)
         rotation(:) = direction(1)*modes(:, 1) + direction(2)*modes(:, 2)
         residual = held(rotation)
         if (residual < best) then
            best = residual
            candidate(:) = rotation
         else
            direction = [cos(angle), sin(angle)]
         end if
      end if
      what = 'a translation in the direction ('//trim(adjustl(real_to_string(direction(1), '(f6.3)')))// &
             ', '//trim(adjustl(real_to_string(direction(2), '(f6.3)')))//')'
      ! The rotation least held: about the centroid plus the translation that minimises its forces
      ! (least squares), i.e. a rotation about the point centre + (−shift(2), shift(1)).
      gram(2, 1) = gram(1, 2)
      det = gram(1, 1)*gram(2, 2) - gram(1, 2)**2
      shift = 0.0_dp
      if (det > epsilon(1.0_dp)*(gram(1, 1)*gram(2, 2))) then
         shift(1) = -(gram(2, 2)*dot_product(forces(:, 1), forces(:, 3)) - gram(1, 2)*dot_product(forces(:, 2), &
                      forces(:, 3)))/det
         shift(2) = -(gram(1, 1)*dot_product(forces(:, 2), forces(:, 3)) - gram(1, 2)*dot_product(forces(:, 1), &
                      forces(:, 3)))/det
      end if
      rotation(:) = modes(:, 3) + shift(1)*modes(:, 1) + shift(2)*modes(:, 2)
      residual = held(rotation)
      ! A rotation about the one point where every free DOF is (a single free node whose rotation is
      ! held, as a truss node's) moves none of them: no motion of the model, whatever it holds. Its
      ! free components are the distances to that point (lengths) and unit rotations; below √ε of the
      ! model's extent they are the round-off of the least-squares centre.
      extent = -huge(1.0_dp)
      do node = 1, model%n_nodes
         extent = max(extent, abs(model%coordinates(1, node) - centre(1)), abs(model%coordinates(2, node) - centre(2)))
      end do
      if (.not. (extent > 0.0_dp)) extent = 1.0_dp
      if (maxval(abs(rotation)) <= sqrt(epsilon(1.0_dp))*extent) residual = huge(1.0_dp)
      if (residual < best) then
         best = residual
         candidate(:) = rotation
         what = 'a rotation about ('//trim(real_to_string(centre(1) - shift(2), '(es10.3)'))//', '// &
                trim(real_to_string(centre(2) + shift(1), '(es10.3)'))//')'
      end if
      if (best > 1.0_dp) return
      call move_alloc(candidate, motion)

   contains

      !> How firmly a rigid motion v (n) is held, in units of its threshold (≤ 1: not at all). Held
      !> locally: some row keeps a term that the motion does not cancel, |(K v)_i| > 1e3 ε Σ_j|K_ij v_j|
      !> (a support: the coupling to the held DOF, a fraction of order 1 of the row). Held by many
      !> small springs: the energy vᵀK v, a coherent sum of their terms, above 3 times the random walk
      !> of the rows' round-off, ε (Σ_i (v_i Σ_j|K_ij v_j|)²)^½. Measured: a ring of 1e5 elements in
      !> the benchmarks' Winkler bed (each row's spring 1e-16 of its bending terms) 99 and 200 times
      !> that round-off for its rotation and translation; an arch with no support 0.024 and 0.15.
      real(dp) function held(v)
         real(dp), intent(in) :: v(:)
         real(dp) :: local, noise
         integer :: i
         call band_row_terms(stiffness, v, product, magnitude)
         local = 0.0_dp
         do i = 1, size(v)
            if (magnitude(i) > 0.0_dp) local = max(local, abs(product(i))/magnitude(i))
         end do
         noise = epsilon(1.0_dp)*norm2(v*magnitude)
         held = local/residual_tolerance
         if (noise > 0.0_dp) held = max(held, abs(dot_product(v, product))/(energy_factor*noise))
      end function held

      !> modes(equation of (component, node), mode) = value, where the component is free.
      subroutine put(mode, at_node, component, value)
         integer, intent(in) :: mode, at_node, component
         real(dp), intent(in) :: value
         if (map%equation(component, at_node) > 0) modes(map%equation(component, at_node), mode) = value
      end subroutine put

   end subroutine free_rigid_motion

   !> Stage 3 (docs/theory.md §2.4): the motion of least stiffness of `stiffness` (unfactorised, n × n)
   !> relative to its own diagonal D — the eigenvector of the least eigenvalue of the pencil (K, D) —
   !> by inverse iteration on K + σD, σ = 1e-14 (Golub & Van Loan 2013, §7.6.1, §8.2.1 for the
   !> symmetric-definite pencil): four solves amplify a null vector over a mode of relative stiffness
   !> 1e-12 (a cantilever of 1e4 elements, the softest held model measured) 100⁴-fold. The motion is
   !> free (`motion` allocated, n) when the module's round-off test (`free_by_roundoff`) finds that no
   !> row holds it; a held model's softest mode stores energy far above that round-off. Rows with no
   !> diagonal (rigid contact rows of the augmented system) are not shifted.
   !> Errors: its copy or vectors refused by the system (out of memory, of `category`).
   subroutine free_internal_motion(map, stiffness, motion, error, category)
      type(dof_map_t), intent(in) :: map
      type(band_matrix_t), intent(in) :: stiffness
      real(dp), allocatable, intent(out) :: motion(:)
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in) :: category
      type(band_matrix_t) :: shifted
      type(error_t), allocatable :: failure
      real(dp), allocatable :: diagonal(:), x(:, :), product(:), magnitude(:)
      integer :: i, k, status
      allocate (diagonal(map%n_equations), x(map%n_equations, 1), product(map%n_equations), &
                magnitude(map%n_equations), stat=status)
      call allocation_failure(status, 'the vectors of the mechanism search', 32.0_dp*map%n_equations, category, error)
      if (allocated(error)) return
      do i = 1, map%n_equations
         diagonal(i) = abs(band_get(stiffness, i, i))
      end do
      call band_copy(stiffness, shifted, error, category)
      if (allocated(error)) return
      do i = 1, map%n_equations
         if (diagonal(i) > 0.0_dp) call band_add(shifted, i, i, 1.0e-14_dp*diagonal(i))
      end do
      call band_factorize(shifted, failure)
      if (allocated(failure)) return
      ! A generic start with a component along every motion (no symmetry of the model can hide one).
      do i = 1, map%n_equations
         x(i, 1) = 1.0_dp + 0.5_dp*sin(1.7_dp*real(i, dp))
      end do
      do k = 1, 4
         x(:, 1) = diagonal*x(:, 1)
         call band_solve(shifted, x, failure)
         if (allocated(failure)) return
         if (.not. all(abs(x) <= huge(1.0_dp))) return
         ! a start that the diagonal annihilates (every row of the motion without stiffness of its own)
         ! gives no direction to iterate on: no internal motion is found so
         if (maxval(abs(x)) <= 0.0_dp) return
         x = x/maxval(abs(x))
      end do
      if (.not. free_by_roundoff(stiffness, x(:, 1), product, magnitude)) return
      allocate (motion(map%n_equations), stat=status)
      call allocation_failure(status, 'the motion of a mechanism', 8.0_dp*map%n_equations, category, error)
      if (allocated(error)) return
      motion(:) = x(:, 1)
   end subroutine free_internal_motion

   !> Whether a motion v (n) passes through `stiffness` as round-off only: no row keeps a term it does
   !> not cancel beyond 1e3 ε of the row's terms (or of ε times the largest row's, for rows the motion
   !> hardly reaches), and its energy vᵀKv is at most 3 times the random
   !> walk of the rows' round-off (the criteria of `held` in free_rigid_motion; Higham 2002, §3.1).
   !> product, magnitude (size(v)): work space of the caller.
   logical function free_by_roundoff(stiffness, v, product, magnitude) result(free)
      type(band_matrix_t), intent(in) :: stiffness
      real(dp), intent(in) :: v(:)
      real(dp), intent(out) :: product(:), magnitude(:)
      real(dp) :: noise, floor
      integer :: i
      call band_row_terms(stiffness, v, product, magnitude)
      free = .true.
      ! A row whose terms are all round-off of the largest (the axial DOFs of a transverse mechanism,
      ! left at 1e-54 by the iteration) tells nothing: measured against ε times the largest row.
      floor = epsilon(1.0_dp)*maxval(magnitude)
      do i = 1, size(v)
         if (abs(product(i)) > residual_tolerance*max(magnitude(i), floor)) free = .false.
      end do
      noise = epsilon(1.0_dp)*norm2(v*magnitude)
      if (abs(dot_product(v, product)) > energy_factor*noise) free = .false.
   end function free_by_roundoff

   !> The message of a mechanism inside the model (error_input): the nodes that move (labels, the
   !> first ten) with the node and component where the motion is largest, and the elements that move
   !> with them. Its arrays (nodes' and elements' length) allocated with stat=: one the system refuses
   !> is out of memory, of `category` (find_mechanism), in place of the message.
   subroutine internal_mechanism_error(model, map, motion, ratio, row, error, category)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: motion(:), ratio
      integer, intent(in) :: row
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in) :: category
      real(dp), allocatable :: size_at(:)
      logical, allocatable :: moving(:), element_moving(:)
      integer, allocatable :: labels(:)
      character(len=:), allocatable :: deck, nodes, elements
      real(dp) :: largest
      integer :: node, dof, e, worst_node, worst_dof, status
      allocate (size_at(model%n_nodes), moving(model%n_nodes), element_moving(model%n_elements), &
                labels(max(model%n_nodes, model%n_elements)), stat=status)
      call allocation_failure(status, 'the arrays of a mechanism''s message', &
                              13.0_dp*model%n_nodes + 5.0_dp*model%n_elements + &
                              4.0_dp*max(model%n_nodes, model%n_elements), category, error)
      if (allocated(error)) return
      size_at = 0.0_dp
      largest = 0.0_dp
      worst_node = 1
      worst_dof = 1
      do node = 1, model%n_nodes
         do dof = 1, dofs_per_node
            if (map%equation(dof, node) == 0) cycle
            size_at(node) = max(size_at(node), abs(motion(map%equation(dof, node))))
            if (abs(motion(map%equation(dof, node))) > largest) then
               largest = abs(motion(map%equation(dof, node)))
               worst_node = node
               worst_dof = dof
            end if
         end do
      end do
      ! A node moves with the mechanism when it moves at least 1e-3 of the largest motion.
      moving = size_at > 1.0e-3_dp*largest
      do node = 1, model%n_nodes
         labels(node) = label_of_node(node)
      end do
      nodes = listed(count(moving), labels(1:model%n_nodes), moving)
      do e = 1, model%n_elements
         labels(e) = label_of_element(e)
         element_moving(e) = any(moving(model%connectivity(:, e)))
      end do
      elements = listed(count(element_moving), labels(1:model%n_elements), element_moving)
      deck = 'the model'
      if (allocated(model%deck_path)) deck = model%deck_path//': the model'
      call make_error(error, deck//' is a mechanism (its stiffness is singular): a part of it can move without '// &
                      'deforming anything (even with every contact closed; weakest pivot '// &
                      trim(real_to_string(ratio, '(es9.2)'))//' of its diagonal, at equation '// &
                      integer_to_string(row)//'); the motion takes nodes '//nodes//' (largest at node '// &
                      integer_to_string(label_of_node(worst_node))//', '//component_name(worst_dof)// &
                      ') and elements '//elements//'; hold it with supports (*BOUNDARY) or remove hinges (*RELEASE)', &
                      error_input)

   contains

      integer function label_of_node(i)
         integer, intent(in) :: i
         label_of_node = i
         if (allocated(model%node_label)) label_of_node = model%node_label(i)
      end function label_of_node

      integer function label_of_element(i)
         integer, intent(in) :: i
         label_of_element = i
         if (allocated(model%element_label)) label_of_element = model%element_label(i)
      end function label_of_element

      !> The labels where `mask` holds, the first ten, then "and N more".
      function listed(total, labels, mask) result(text)
         integer, intent(in) :: total, labels(:)
         logical, intent(in) :: mask(:)
         character(len=:), allocatable :: text
         integer :: i, shown
         text = ''
         shown = 0
         do i = 1, size(labels)
            if (.not. mask(i)) cycle
            if (shown == 10) then
               text = text//' and '//integer_to_string(total - shown)//' more'
               exit
            end if
            if (shown > 0) text = text//', '
            text = text//integer_to_string(labels(i))
            shown = shown + 1
         end do
      end function listed

   end subroutine internal_mechanism_error

   !> The deck's name of a nodal component (1, 2, 3).
   pure function component_name(dof) result(name)
      integer, intent(in) :: dof
      character(len=2) :: name
      select case (dof)
      case (1)
         name = 'UX'
      case (2)
         name = 'UY'
      case default
         name = 'RZ'
      end select
   end function component_name

end module uniarc_path_mechanism
