!> What the tables of `*OUTPUT, FORCES` report (docs/contracts.md, `STEM.forces` and `STEM.contact`):
!> the internal forces N, V, M at both ends of every element, and at every contact candidate its gap,
!> its tributary length and the contact pressure (reaction per unit length).
!>
!> End forces. The element layer (uniarc_element) gives the basic forces q = (N, M1, M2) of the
!> element's deformations; the loads that act on the element itself are added here, as the element
!> equations hold them (f_e = f_int(u) − λ f_load(u), the forces the nodes exert on the element):
!> - temperature changes are natural deformations, q = Kb (v − λ v0) = q_elastic − λ q0
!>   (uniarc_element_loads, thermal_basic_force; docs/theory.md §1.9): a clamped beam under a
!>   gradient carries the thermal moment EI α ΔT/h with no deformation at all;
!> - loads distributed on the span (fixed direction, pressure, follower pressure) enter through their
!>   consistent nodal loads f_load (the fixed-end forces of the Hermite element, uniarc_frame_linear,
!>   uniarc_corotational), whose components in the element's frame are subtracted at each end. For a
!>   straight prismatic element under a uniform load this is exact (Przemieniecki 1968, §5.4;
!>   McGuire, Gallagher & Ziemian 2000, §3.5): a cantilever under q shows M = −q (L − x)²/2 at every
!>   node.
!> The element's frame is the chord of the analysis' transformation (analysis_transformation): the
!> initial chord in a linear analysis, the current chord (corotational) in a nonlinear one, with the
!> unit tangent t (node 1 → node 2) and the left normal n (t turned by +90°). At each end the section
!> forces are in the beam convention of uniarc_transformation: N tension positive, M = EI κ positive
!> when the element bends toward n, V = dM/ds along t (so dV/ds = q_n, the load along n per length).
!> With f1, f2 the end forces on the element (force along t, along n, moment) at nodes 1 and 2:
!>     N_start = −f1·t, V_start = f1·n, M_start = −m1;   N_end = f2·t, V_end = −f2·n, M_end = m2.
!> In an analysis step (*STEP) the loads of the earlier steps, held at their factor (model%held,
!> uniarc_model_steps), are added the same way at that factor instead of λ.
module uniarc_output_forces
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, dofs_per_node, load_fixed_direction, load_pressure, analysis_linear, &
                           element_kind_of, load_pattern_t
   use uniarc_element, only: element_response_t, element_response, element_coordinates, element_displacements, &
                             analysis_transformation, transformation_linear, transformation_corotational
   use uniarc_element_loads, only: thermal_basic_force
   use uniarc_released_loads, only: released_basic_force, released_span_correction
   use uniarc_transformation, only: chord_t, transform_deformations, transform_end_forces
   use uniarc_frame_linear, only: fixed_direction_load_vector, pressure_load_vector
   use uniarc_corotational, only: follower_pressure
   use uniarc_contact_law, only: candidate_gap, tributary_lengths
   implicit none
   private
   public :: element_end_forces, candidate_gaps, candidate_lengths, tangential_springs

contains

   !> Section forces at both ends of every element at nodal displacements `displacement` (3, n_nodes)
   !> and load factor `lambda`: rows (N_start, V_start, M_start, N_end, V_end, M_end), shape
   !> (6, n_elements), in the deck's force and force × length units, in the element's frame and the
   !> beam convention of the module header. A truss has V = M = 0 (no transverse load on its span).
   !> `joint_plastic` (optional, (2, n_elements)): the committed plastic rotations of the joints with a
   !> moment limit (the path's state; uniarc_joint_plasticity), which the end moments depend on.
   !> `reactions` (optional, (n_contacts)): the reaction of every contact candidate at the state; with
   !> it, the elements of a foundation carry their share of the bed's distributed reaction (module
   !> header, bed_span_loads).
   !> status: the stat= of `forces` or of the work arrays (each of the elements' length) that the system
   !> refused (0: `forces` complete); bytes (optional) their size, for uniarc_memory's allocation_failure.
   pure subroutine element_end_forces(model, displacement, lambda, forces, status, bytes, joint_plastic, reactions)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: displacement(:, :)
      real(dp), intent(in) :: lambda
      real(dp), allocatable, intent(out) :: forces(:, :)
      integer, intent(out) :: status
      real(dp), intent(out), optional :: bytes
      real(dp), intent(in), optional :: joint_plastic(:, :)
      real(dp), intent(in), optional :: reactions(:)
      real(dp), allocatable :: thermal(:, :), span(:, :), held_thermal(:, :), held_span(:, :), bed(:, :)
      real(dp) :: deformation(3), q(3), end_forces(4), t(2), n(2), f(2*dofs_per_node)
      real(dp) :: k_unused(2*dofs_per_node, 2*dofs_per_node)
      type(element_response_t) :: response
      type(chord_t) :: chord
      integer :: e, i, transformation
      logical, allocatable :: loaded(:)
      logical :: has_held

      if (present(bytes)) bytes = 8.0_dp*(6 + 3 + 3*2*dofs_per_node + 3)*model%n_elements + &
                                  4.0_dp*model%n_elements
      allocate (forces(6, model%n_elements), thermal(3, model%n_elements), span(2*dofs_per_node, model%n_elements), &
                loaded(model%n_elements), held_thermal(3, model%n_elements), &
                held_span(2*dofs_per_node, model%n_elements), bed(2*dofs_per_node, model%n_elements), stat=status)
      if (status /= 0) return
      transformation = analysis_transformation(model%analysis%kind)
      thermal = 0.0_dp
      span = 0.0_dp
      loaded = .false.
      if (allocated(model%thermal_loads)) then
         do i = 1, size(model%thermal_loads)
            e = model%thermal_loads(i)%element
            thermal(:, e) = thermal(:, e) + released_basic_force(model, e, &
                                                                 thermal_basic_force(model%thermal_loads(i), &
                                                                 model%sections(model%element_section(e)), &
                                                                 element_kind_of(model, e)))
         end do
      end if
      if (allocated(model%distributed_loads)) then
         do i = 1, size(model%distributed_loads)
            associate (dload => model%distributed_loads(i))
               e = dload%element
               select case (dload%kind)
               case (load_fixed_direction)
                  f = fixed_direction_load_vector(element_coordinates(model, e), dload%qx, dload%qy)
               case (load_pressure)
                  if (dload%follower .and. model%analysis%kind /= analysis_linear) then
                     call follower_pressure(element_coordinates(model, e), &
                                            element_displacements(model, e, displacement), dload%pressure, f, k_unused)
                  else
                     f = pressure_load_vector(element_coordinates(model, e), dload%pressure)
                  end if
               case default
                  cycle
               end select
               f = f + span_release(model, e, dload%kind == load_pressure .and. dload%follower .and. &
                                    model%analysis%kind /= analysis_linear, dload%pressure, f, displacement)
               span(:, e) = span(:, e) + f
               loaded(e) = .true.
            end associate
         end do
      end if

      bed = 0.0_dp
      if (present(reactions)) then
         call bed_span_loads(model, displacement, reactions, bed, loaded, status)
         if (status /= 0) return
      end if

      has_held = .false.
      if (allocated(model%held)) has_held = size(model%held) > 0
      if (has_held) then
         held_thermal = 0.0_dp
         held_span = 0.0_dp
         do i = 1, size(model%held)
            call add_held_pattern(model, model%held(i), displacement, transformation, held_thermal, held_span, loaded)
         end do
      end if

      do e = 1, model%n_elements
         if (present(joint_plastic)) then
            call element_response(model, e, element_displacements(model, e, displacement), transformation, response, &
                                  joint_plastic(:, e))
         else
            call element_response(model, e, element_displacements(model, e, displacement), transformation, response)
         end if
         q = response%basic_force - lambda*thermal(:, e)
         if (has_held) q = q - held_thermal(:, e)
         call transform_deformations(transformation, element_coordinates(model, e), &
                                     element_displacements(model, e, displacement), chord, deformation)
         end_forces = transform_end_forces(chord, q)
         forces(:, e) = [end_forces(1), end_forces(2), end_forces(3), end_forces(1), end_forces(2), end_forces(4)]
         if (.not. loaded(e)) cycle
         ! f_e = f_int − λ f_load: the load's components along t and n at each end (module header).
         t = [chord%c, chord%s]
         n = [-chord%s, chord%c]
         f = lambda*span(:, e) + bed(:, e)
         if (has_held) f = f + held_span(:, e)
         forces(1, e) = forces(1, e) + dot_product(f(1:2), t)
         forces(2, e) = forces(2, e) - dot_product(f(1:2), n)
         forces(3, e) = forces(3, e) + f(3)
         forces(4, e) = forces(4, e) - dot_product(f(4:5), t)
         forces(5, e) = forces(5, e) + dot_product(f(4:5), n)
         forces(6, e) = forces(6, e) - f(6)
      end do
   end subroutine element_end_forces

   !> The share of the foundations' distributed reactions that each element of a bed carries on its
   !> span, as consistent nodal loads (6, global), added to `bed` (6, n_elements); those elements
   !> marked `loaded`.
   !>
   !> A Winkler bed (and the beds of *FOUNDATION with the other laws) enters the equations lumped to the
   !> nodes: candidate c, with tributary length L_c (candidate_lengths), carries the reaction r_c of
   !> the pressure p_c = r_c/L_c over its length (docs/theory.md §3.1). In the structure the bed
   !> pushes along the whole span, so the element's own equilibrium takes it as a load on the span:
   !> along the element the pressure p_c a_c (a_c the direction in which candidate c's reaction acts on
   !> its node, ∂g/∂u) interpolated linearly between its two nodes, per unit initial length, with the
   !> consistent loads of a linearly varying load on a Hermite beam in the initial chord's frame (t, n):
   !>     axial    F_1 = h (2 q_1 + q_2)/6,        F_2 = h (q_1 + 2 q_2)/6,
   !>     normal   F_1 = h (7 q_1 + 3 q_2)/20,     F_2 = h (3 q_1 + 7 q_2)/20,
   !>              M_1 = h² (3 q_1 + 2 q_2)/60,    M_2 = −h² (2 q_1 + 3 q_2)/60
   !> (Przemieniecki 1968, Theory of Matrix Structural Analysis, §5.4; fixed-end forces of a
   !> trapezoidal load), with the end releases' correction as for the other span loads. Uniform
   !> pressure (a rigid sinking) cancels a uniform load exactly: M = 0. Only the radial candidates of
   !> a foundation (not its tangential springs, not *SPRING or obstacles, which are point supports),
   !> on the elements of its set whose two nodes are both its candidates.
   pure subroutine bed_span_loads(model, displacement, reactions, bed, loaded, status)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: displacement(:, :), reactions(:)
      real(dp), intent(inout) :: bed(:, :)
      logical, intent(inout) :: loaded(:)
      integer, intent(out) :: status   !< the stat= of a work array (of the nodes' length) refused
      real(dp), allocatable :: lengths(:), line_load(:, :)
      integer, allocatable :: candidate_of(:)
      real(dp) :: gap, gradient(2), hessian(2, 2), x(2, 2), t(2), n(2), h, qt(2), qn(2), f(2*dofs_per_node)
      integer :: i, j, e, c, group
      status = 0
      if (.not. (allocated(model%foundations) .and. allocated(model%contacts))) return
      if (size(reactions) < size(model%contacts)) return
      call candidate_lengths(model, lengths, status)
      if (status /= 0) return
      allocate (line_load(2, model%n_nodes), candidate_of(model%n_nodes), stat=status)
      if (status /= 0) return
      do i = 1, size(model%foundations)
         group = model%foundations(i)%group
         line_load = 0.0_dp
         candidate_of = 0
         do c = 1, size(model%contacts)
            if (model%contacts(c)%group /= group .or. model%contacts(c)%tangential) cycle
            if (.not. lengths(c) > 0.0_dp) cycle
            associate (node => model%contacts(c)%node)
               call candidate_gap(model%contacts(c), model%coordinates(:, node), displacement(1:2, node), gap, &
                                  gradient, hessian)
               line_load(:, node) = reactions(c)/lengths(c)*gradient
               candidate_of(node) = c
            end associate
         end do
         if (.not. allocated(model%foundations(i)%elements)) cycle
         do j = 1, size(model%foundations(i)%elements)
            e = model%foundations(i)%elements(j)
            associate (ends => model%connectivity(:, e))
               if (candidate_of(ends(1)) == 0 .or. candidate_of(ends(2)) == 0) cycle
               x = element_coordinates(model, e)
               h = norm2(x(:, 2) - x(:, 1))
               if (.not. h > 0.0_dp) cycle
               t = (x(:, 2) - x(:, 1))/h
               n = [-t(2), t(1)]
               qt = [dot_product(line_load(:, ends(1)), t), dot_product(line_load(:, ends(2)), t)]
               qn = [dot_product(line_load(:, ends(1)), n), dot_product(line_load(:, ends(2)), n)]
               f(1:2) = h*(2.0_dp*qt(1) + qt(2))/6.0_dp*t + h*(7.0_dp*qn(1) + 3.0_dp*qn(2))/20.0_dp*n
               f(3) = h**2*(3.0_dp*qn(1) + 2.0_dp*qn(2))/60.0_dp
               f(4:5) = h*(qt(1) + 2.0_dp*qt(2))/6.0_dp*t + h*(3.0_dp*qn(1) + 7.0_dp*qn(2))/20.0_dp*n
               f(6) = -h**2*(2.0_dp*qn(1) + 3.0_dp*qn(2))/60.0_dp
               f = f + span_release(model, e, .false., 0.0_dp, f, displacement)
               bed(:, e) = bed(:, e) + f
               loaded(e) = .true.
            end associate
         end do
      end do
   end subroutine bed_span_loads

   !> The basic thermal forces and the consistent span loads of a held load pattern, times its factor,
   !> added to `thermal` (3, n_elements) and `span` (6, n_elements); its elements marked `loaded`.
   pure subroutine add_held_pattern(model, pattern, displacement, transformation, thermal, span, loaded)
      type(model_t), intent(in) :: model
      type(load_pattern_t), intent(in) :: pattern
      real(dp), intent(in) :: displacement(:, :)
      integer, intent(in) :: transformation
      real(dp), intent(inout) :: thermal(:, :), span(:, :)
      logical, intent(inout) :: loaded(:)
      real(dp) :: f(2*dofs_per_node), k_unused(2*dofs_per_node, 2*dofs_per_node)
      integer :: i, e
      do i = 1, size(pattern%thermal_loads)
         e = pattern%thermal_loads(i)%element
         thermal(:, e) = thermal(:, e) + pattern%factor*released_basic_force(model, e, &
                                                           thermal_basic_force(pattern%thermal_loads(i), &
                                                           model%sections(model%element_section(e)), &
                                                           element_kind_of(model, e)))
      end do
      do i = 1, size(pattern%distributed_loads)
         associate (dload => pattern%distributed_loads(i))
            e = dload%element
            if (dload%kind == load_fixed_direction) then
               f = fixed_direction_load_vector(element_coordinates(model, e), dload%qx, dload%qy)
            else if (dload%kind == load_pressure .and. dload%follower .and. &
                     transformation /= analysis_transformation(analysis_linear)) then
               call follower_pressure(element_coordinates(model, e), element_displacements(model, e, displacement), &
                                      dload%pressure, f, k_unused)
            else if (dload%kind == load_pressure) then
               f = pressure_load_vector(element_coordinates(model, e), dload%pressure)
            else
               cycle
            end if
            f = f + span_release(model, e, dload%kind == load_pressure .and. dload%follower .and. &
                                 transformation /= analysis_transformation(analysis_linear), dload%pressure, f, &
                                 displacement)
            span(:, e) = span(:, e) + pattern%factor*f
            loaded(e) = .true.
         end associate
      end do
   end subroutine add_held_pattern

   !> The gap g of every contact candidate at nodal displacements `displacement` (3, n_nodes), in
   !> length units (uniarc_contact_law, candidate_gap): positive open; negative in contact with an
   !> elastic medium, whose springs are then compressed by −g = r/k. `lambda` (default 0): the load
   !> factor, where a moving curved obstacle stands (a plane's λ ∂g/∂λ is the caller's; docs/theory.md
   !> §3.11).
   !> status: the stat= of `gaps` (n_contacts) refused by the system (0: complete).
   pure subroutine candidate_gaps(model, displacement, gaps, status, lambda)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: displacement(:, :)
      real(dp), allocatable, intent(out) :: gaps(:)
      integer, intent(out) :: status
      real(dp), intent(in), optional :: lambda
      real(dp) :: gradient(2), hessian(2, 2)
      integer :: c
      status = 0
      if (.not. allocated(model%contacts)) then
         allocate (gaps(0))
         return
      end if
      allocate (gaps(size(model%contacts)), stat=status)
      if (status /= 0) return
      do c = 1, size(model%contacts)
         associate (node => model%contacts(c)%node)
            call candidate_gap(model%contacts(c), model%coordinates(:, node), displacement(1:2, node), gaps(c), &
                               gradient, hessian, lambda)
         end associate
      end do
   end subroutine candidate_gaps

   !> The tangential spring (`*FOUNDATION, KT=`) of every contact candidate: the index of the candidate
   !> that is its foundation's tangential spring at the same node (uniarc_contact_law: one per node of a
   !> bed with K_t > 0, gap g = t·u along the tangent t, the bed's direction n turned by +90°), 0 where
   !> the candidate has none (a bed without K_t, springs, obstacles; and the tangential springs
   !> themselves). Shape (n_contacts).
   !> status: the stat= of an array refused by the system (0: `spring` complete).
   pure subroutine tangential_springs(model, spring, status)
      type(model_t), intent(in) :: model
      integer, allocatable, intent(out) :: spring(:)
      integer, intent(out) :: status
      integer, allocatable :: radial_at_node(:)
      integer :: g, k, c
      status = 0
      if (.not. allocated(model%contacts)) then
         allocate (spring(0))
         return
      end if
      allocate (spring(size(model%contacts)), stat=status)
      if (status /= 0) return
      spring = 0
      if (.not. allocated(model%contact_groups)) return
      if (.not. any(model%contacts%tangential)) return
      allocate (radial_at_node(model%n_nodes), stat=status)
      if (status /= 0) return
      radial_at_node = 0
      do g = 1, size(model%contact_groups)
         associate (members => model%contact_groups(g)%candidates)
            do k = 1, size(members)
               c = members(k)
               if (.not. model%contacts(c)%tangential) radial_at_node(model%contacts(c)%node) = c
            end do
            do k = 1, size(members)
               c = members(k)
               if (.not. model%contacts(c)%tangential) cycle
               if (radial_at_node(model%contacts(c)%node) > 0) spring(radial_at_node(model%contacts(c)%node)) = c
            end do
            do k = 1, size(members)
               radial_at_node(model%contacts(members(k))%node) = 0
            end do
         end associate
      end do
   end subroutine tangential_springs

   !> The tributary length of every contact candidate (initial geometry, length units), over which
   !> its reaction is spread as a contact pressure: for a foundation's candidate, half the lengths of
   !> the elements of the foundation's set that meet at its node — the length its Winkler spring k = K
   !> × length was lumped from (uniarc_contact_law), so that reaction/length is the bed's pressure K w;
   !> for a spring's or an obstacle's candidate, half the lengths of all the elements that meet at its
   !> node (the share of the structure's length the node stands for), so that reaction/length is the
   !> mean line load that the contact puts on the structure there.
   !> status: the stat= of an array refused by the system (0: `lengths` (n_contacts) complete).
   pure subroutine candidate_lengths(model, lengths, status)
      type(model_t), intent(in) :: model
      real(dp), allocatable, intent(out) :: lengths(:)
      integer, intent(out) :: status
      real(dp), allocatable :: structure(:), per_node(:)
      integer, allocatable :: every_node(:), every_element(:)
      integer :: c, i, group
      status = 0
      if (.not. allocated(model%contacts)) then
         allocate (lengths(0))
         return
      end if
      allocate (every_node(model%n_nodes), every_element(model%n_elements), stat=status)
      if (status /= 0) return
      do i = 1, model%n_nodes
         every_node(i) = i
      end do
      do i = 1, model%n_elements
         every_element(i) = i
      end do
      call tributary_lengths(model%coordinates, model%connectivity, every_element, every_node, structure, status)
      if (status /= 0) return
      allocate (lengths(size(model%contacts)), stat=status)
      if (status /= 0) return
      do c = 1, size(model%contacts)
         lengths(c) = structure(model%contacts(c)%node)
      end do
      if (.not. allocated(model%foundations)) return
      do i = 1, size(model%foundations)
         group = model%foundations(i)%group
         call tributary_lengths(model%coordinates, model%connectivity, model%foundations(i)%elements, every_node, &
                                per_node, status)
         if (status /= 0) return
         do c = 1, size(model%contacts)
            if (model%contacts(c)%group == group) lengths(c) = per_node(model%contacts(c)%node)
         end do
      end do
   end subroutine candidate_lengths

   !> The change (6, global) of the consistent nodal loads `f` (6) of a load on the span of element `e`
   !> from its end joints (uniarc_released_loads, released_span_correction): on the initial geometry,
   !> or for a follower pressure (`follower`, `pressure`) on the current chord at `displacement`
   !> (3, n_nodes), with the clamped moments on the initial geometry, as the equilibrium equations
   !> (uniarc_assembly, uniarc_equilibrium) hold it.
   pure function span_release(model, e, follower, pressure, f, displacement) result(df)
      type(model_t), intent(in) :: model
      integer, intent(in) :: e
      logical, intent(in) :: follower
      real(dp), intent(in) :: pressure, f(2*dofs_per_node), displacement(:, :)
      real(dp) :: df(2*dofs_per_node)
      real(dp) :: f0(2*dofs_per_node), dk(2*dofs_per_node, 2*dofs_per_node)
      real(dp), parameter :: at_rest(2*dofs_per_node) = 0.0_dp
      if (follower) then
         f0 = pressure_load_vector(element_coordinates(model, e), pressure)
         call released_span_correction(model, e, [f0(3), f0(6)], element_displacements(model, e, displacement), &
                                       transformation_corotational, df, dk)
      else
         call released_span_correction(model, e, [f(3), f(6)], at_rest, transformation_linear, df, dk)
      end if
   end function span_release

end module uniarc_output_forces
