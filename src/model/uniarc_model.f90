!> The model: what a deck describes, independent of how it is analysed.
!>
!> Built through uniarc_model_builder (by the deck reader and by tests), read by the analysis. Nodes and elements are stored in the
!> order the deck created them (internal indices 1..n); user labels are kept for messages and output.
!> The equation numbering (bandwidth reduction, eliminated DOFs) belongs to the analysis, not here.
module uniarc_model
   use uniarc_kinds, only: dp
   use uniarc_strings, only: same_text
   implicit none
   private
   public :: model_t, section_t, node_set_t, element_set_t, distributed_load_t, track_t
   public :: analysis_options_t, output_options_t
   public :: dofs_per_node, dof_ux, dof_uy, dof_rz
   public :: load_fixed_direction, load_pressure
   public :: element_beam_column, element_truss, element_kind_of
   public :: analysis_linear, analysis_nonlinear
   public :: control_load, control_displacement, control_arclength
   public :: iteration_chan, iteration_cylindrical, iteration_riks
   public :: find_node_set, find_element_set, element_length, tracked_values
   public :: contact_candidate_t, contact_group_t
   public :: move_obstacles
   public :: gap_fixed_direction, gap_circle_inside, gap_circle_outside
   public :: foundation_t, foundation_winkler, foundation_pasternak
   public :: tangential_contact, tangential_bonded
   public :: side_left, side_right, side_inner, side_outer, side_direction
   public :: thermal_load_t
   public :: element_timoshenko, end_joint_t, end_joints_of
   public :: has_moment_limits
   public :: gap_ellipse_inside, gap_ellipse_outside, gap_polyline
   public :: load_pattern_t, analysis_step_t

   !> Degrees of freedom per node of the 2-D frame: u_x, u_y, θ_z (counter-clockwise positive).
   integer, parameter :: dofs_per_node = 3
   integer, parameter :: dof_ux = 1, dof_uy = 2, dof_rz = 3

   !> Kinds of distributed load.
   integer, parameter :: load_fixed_direction = 1 !< force per unit initial length, global (qx, qy)
   integer, parameter :: load_pressure = 2        !< normal pressure along the element's left normal

   !> Kinds of element (the basic element of docs/theory.md §1.8; every kind has the same six element
   !> DOFs (u_x1, u_y1, θ1, u_x2, u_y2, θ2), a truss leaving its rotations untouched).
   integer, parameter :: element_beam_column = 1 !< Euler–Bernoulli beam-column: N, M1, M2 (the default)
   integer, parameter :: element_truss = 2       !< bar: axial force N only, pinned ends
   integer, parameter :: element_timoshenko = 3  !< shear-deformable (Timoshenko) beam-column: N, M1, M2

   !> Kinds of analysis.
   integer, parameter :: analysis_linear = 1
   integer, parameter :: analysis_nonlinear = 2

   !> Cross-section stiffnesses of a beam (Euler–Bernoulli: axial EA, bending EI).
   type :: section_t
      character(len=:), allocatable :: name
      real(dp) :: ea = 0.0_dp
      real(dp) :: ei = 0.0_dp
      real(dp) :: gas = 0.0_dp   !< shear stiffness κGA (force) of a Timoshenko beam; 0: none given
      !> *SECTION, WEIGHT= and ALPHA=: the weight per unit length (force/length, for *DLOAD WEIGHT) and
      !> the coefficient of thermal expansion (1/temperature, for *TEMPERATURE) of its elements
      logical :: has_weight = .false., has_alpha = .false.
      real(dp) :: weight = 0.0_dp
      real(dp) :: alpha = 0.0_dp
   end type section_t

   !> The joint between an element end and its node (docs/input.md `*RELEASE`): rigid (the default), a
   !> hinge (no moment passes), or a linear rotational spring M = k (θ_node − θ_end) of compliance 1/k,
   !> optionally elastic–perfectly plastic: M = k (θ_node − θ_end − θ_p), |M| ≤ M_y (`*RELEASE, MY=`).
   type :: end_joint_t
      logical :: hinge = .false.
      real(dp) :: compliance = 0.0_dp   !< 1/k (radian per moment) of a spring; 0: rigid
      real(dp) :: moment_limit = 0.0_dp !< M_y > 0 of a spring with a moment limit; 0: none (linear)
   end type end_joint_t

   !> A named set of nodes (internal indices).
   type :: node_set_t
      character(len=:), allocatable :: name
      integer, allocatable :: nodes(:)
   end type node_set_t

   !> A named set of elements (internal indices).
   type :: element_set_t
      character(len=:), allocatable :: name
      integer, allocatable :: elements(:)
   end type element_set_t

   !> A distributed load on one element, per unit initial length, scaled by the load parameter λ.
   type :: distributed_load_t
      integer :: element = 0
      integer :: kind = load_fixed_direction
      real(dp) :: qx = 0.0_dp        !< global x component (fixed-direction load)
      real(dp) :: qy = 0.0_dp        !< global y component (fixed-direction load)
      real(dp) :: pressure = 0.0_dp  !< along the left normal of node 1 → node 2 (pressure load)
      logical :: follower = .false.  !< pressure follows the deformed normal
   end type distributed_load_t

   !> A temperature change of one element (*TEMPERATURE), scaled by the load parameter λ: ΔT at the
   !> element's axis (axial strain α ΔT) and the difference ΔT_left − ΔT_right between its faces over
   !> the depth h (curvature −α (ΔT_left − ΔT_right)/h, positive toward the left normal). The thermal
   !> strains are natural deformations of the basic element (uniarc_element_loads, docs/theory.md).
   type :: thermal_load_t
      integer :: element = 0
      real(dp) :: alpha = 0.0_dp        !< coefficient of thermal expansion (1/temperature)
      real(dp) :: delta_t = 0.0_dp      !< ΔT at the axis
      real(dp) :: difference = 0.0_dp   !< ΔT_left − ΔT_right (0: uniform through the depth)
      real(dp) :: depth = 0.0_dp        !< h, the depth between the two faces (> 0 when difference ≠ 0)
   end type thermal_load_t

   !> A displacement component written as a column of the path file: scale * u(dof) of one node.
   type :: track_t
      character(len=:), allocatable :: name
      integer :: node = 0
      integer :: dof = dof_uy
      real(dp) :: scale = 1.0_dp
   end type track_t

   !> How the gap of a contact candidate follows from the current position x of its node.
   integer, parameter :: gap_fixed_direction = 1 !< g = offset + n·u (foundation bed, spring, flat surface)
   integer, parameter :: gap_circle_inside = 2   !< g = R − |x − c|: the node inside a circular cavity
   integer, parameter :: gap_circle_outside = 3  !< g = |x − c| − R: the node outside a rigid cylinder
   integer, parameter :: gap_ellipse_inside = 4  !< signed distance to an ellipse, the node inside it
   integer, parameter :: gap_ellipse_outside = 5 !< signed distance to an ellipse, the node outside it
   integer, parameter :: gap_polyline = 6        !< signed distance to a polyline, free side on its left

   !> One contact candidate: a node that a unilateral medium may push (paper §4: one row of A, one
   !> entry of T). The reaction r ≥ 0 acts on the node along ∂g/∂u, the direction in which the gap opens.
   type :: contact_candidate_t
      integer :: node = 0
      integer :: gap_kind = gap_fixed_direction
      real(dp) :: direction(2) = 0.0_dp  !< fixed-direction gap: unit n, pointing to the free side
      real(dp) :: offset = 0.0_dp        !< fixed-direction gap: initial gap g0 (0 for a bonded bed)
      real(dp) :: centre(2) = 0.0_dp     !< circular obstacle: centre
      real(dp) :: radius = 0.0_dp        !< circular obstacle: radius
      real(dp) :: semi_axes(2) = 0.0_dp  !< elliptical obstacle (centre `centre`): semi-axes a, b
      real(dp) :: axis(2) = [1.0_dp, 0.0_dp] !< elliptical obstacle: unit direction of the semi-axis a
      !> polyline obstacle: (2, n ≥ 2) vertices in order, the free side on the left of 1 → n; the first
      !> and last segments go on as rays, so that the line divides the plane
      real(dp), allocatable :: vertices(:, :)
      real(dp) :: flexibility = 0.0_dp   !< T_cc = 1/k of an elastic medium; 0 for rigid contact
      logical :: bilateral = .false.     !< bonded: reacts in tension too (always active)
      integer :: group = 0               !< the foundation/obstacle card that made it
      real(dp) :: coordinate = 0.0_dp    !< position along its group for the contact-region output
      !> a tangential (shear) spring of a foundation, along the tangent of its node; not a contact
      !> reaction, so not counted in the contact output. It is `bilateral` (never a variable of the
      !> contact LCP): bonded when `partner` = 0, else acting only while candidate `partner` (its radial
      !> spring) is in the working set
      logical :: tangential = .false.
      integer :: partner = 0
      !> elastic–perfectly plastic in compression (*FOUNDATION or *SPRING, QU=): the reaction is at most
      !> `yield_force` (force), beyond which the medium deforms plastically (docs/theory.md §3.9); in
      !> tension too with `uplift_force` below
      logical :: plastic = .false.
      real(dp) :: yield_force = 0.0_dp
      !> with an uplift (tension) resistance too (TU=): the limit t_c > 0 (force) of the tension the
      !> medium bears, r ≥ −uplift_force; such a candidate is `bilateral` (bonded while elastic) and
      !> shares one slip between both limits (docs/theory.md §3.9); 0: compression-only
      real(dp) :: uplift_force = 0.0_dp
      !> the flexibility 1/k_u of its uplift branch (KU=, with an uplift limit): the elastic law is
      !> r = δ/flexibility for δ ≥ 0 and r = δ/uplift_flexibility for δ < 0, δ = −(g + s) its elastic
      !> deformation (docs/theory.md §3.9, "Two stiffnesses"); 0: one stiffness (no KU=, or k_u = k)
      real(dp) :: uplift_flexibility = 0.0_dp
      !> a point of a Pasternak bed (foundation_pasternak): the contact is rigid (flexibility 0) with the
      !> bed's surface, whose deflection d (into the bed, along −direction) is an unknown of its own, and
      !> the gap is g0 + n·u + d. `bed_stiffness` is the candidate's row of the bed stiffness K_b
      !> (force per length; docs/theory.md §3.10): coupling to the previous point of the bed, itself, the
      !> next one; `bed_previous`, `bed_next` those points' candidate indices (0: none). Not a bed point
      !> when bed_stiffness(2) = 0.
      real(dp) :: bed_stiffness(3) = 0.0_dp
      integer :: bed_previous = 0
      integer :: bed_next = 0
      !> a moving plane obstacle (*MOVE, docs/theory.md §3.11): ∂g/∂λ = −n·d of the analysis step's own
      !> translation d, so that the gap at load factor λ is g(u) + λ gap_rate (moves of earlier steps are
      !> in `offset`); 0: the obstacle does not move in the step
      real(dp) :: gap_rate = 0.0_dp
      !> a moving curved obstacle (circle, ellipse, polyline; *MOVE, docs/theory.md §3.11): the analysis
      !> step's own translation d (length), so that at load factor λ the obstacle stands translated by
      !> λ d and the gap is the shape's at the shifted point, g(x0 + u − λ d), exactly (moves of earlier
      !> steps are in its `centre` or `vertices`); 0: it does not move in the step. Planes use `gap_rate`.
      real(dp) :: motion(2) = 0.0_dp
   end type contact_candidate_t

   !> A foundation or obstacle of the deck: its name and the candidates it made, in order.
   type :: contact_group_t
      character(len=:), allocatable :: name
      integer, allocatable :: candidates(:)
   end type contact_group_t

   !> Laws of a foundation (the reaction of the bed against the deflection toward it).
   integer, parameter :: foundation_winkler = 1  !< Winkler (1867): independent springs, K per unit length
   !> Pasternak (1954): Winkler's springs under a shear layer of stiffness G_p (force), so that the bed's
   !> surface deflection w satisfies K w − G_p w'' = p (Kerr 1964); G_p = 0 is Winkler's bed
   integer, parameter :: foundation_pasternak = 2

   !> Laws of a foundation's tangential springs (*FOUNDATION, TANGENTIAL=).
   integer, parameter :: tangential_contact = 1  !< acting where the node's radial spring is in contact
   integer, parameter :: tangential_bonded = 2   !< always acting

   !> Where a foundation lies, which fixes the direction n in which it pushes (docs/input.md, *FOUNDATION).
   integer, parameter :: side_left = 1       !< on the left of the elements: n = −(nodal left normal)
   integer, parameter :: side_right = 2      !< on the right: n = +(nodal left normal)
   integer, parameter :: side_inner = 3      !< on the concave side: n points away from it
   integer, parameter :: side_outer = 4      !< on the convex side: n points toward the concave side
   integer, parameter :: side_direction = 5  !< a fixed direction n, the same at every node

   !> A foundation of the deck as described, before it is lumped to nodes: the model keeps it so that
   !> laws other than Winkler's can be derived from it. Its candidates (`contact_candidate_t`, one per node
   !> of the element set) are derived by uniarc_contact_law and form contact group `group`.
   type :: foundation_t
      character(len=:), allocatable :: name        !< the name of its contact group
      integer :: law = foundation_winkler
      real(dp) :: modulus = 0.0_dp                 !< K: force per unit length per unit deflection (≥ 0)
      integer :: side = side_direction
      real(dp) :: direction(2) = 0.0_dp            !< side_direction: the unit n in which the bed pushes
      character(len=:), allocatable :: element_set !< the element set (or label) as the deck names it
      integer, allocatable :: elements(:)          !< its elements (internal indices), in set order
      logical :: bilateral = .false.               !< bonded: reacts in tension too
      real(dp) :: gap = 0.0_dp                     !< initial gap g0 at every node (0: in touch at start)
      real(dp) :: scale = 1.0_dp                   !< arc length → coordinate of the contact output
      integer :: group = 0                         !< the contact group of its candidates
      !> K_t: modulus of tangential springs (force per unit length per unit tangential displacement,
      !> ≥ 0; 0: frictionless, the default), acting as `tangential_law` says
      real(dp) :: tangential_modulus = 0.0_dp
      integer :: tangential_law = tangential_contact
      !> q_u: bearing limit of the bed, force per unit length (> 0); 0: no limit (elastic), the default
      real(dp) :: bearing_limit = 0.0_dp
      !> t_u: uplift (tension) limit of the bed, force per unit length (> 0, with a bearing limit); 0: none
      real(dp) :: uplift_limit = 0.0_dp
      !> k_u: modulus of the bed's uplift branch (KU=, per unit length, > 0); 0: the bearing modulus
      real(dp) :: uplift_modulus = 0.0_dp
      !> G_p: the shear-layer stiffness of a Pasternak bed (force, i.e. force per unit width; ≥ 0)
      real(dp) :: shear_modulus = 0.0_dp
      !> whether the Pasternak bed goes on beyond the set's (start, end) in chain order (an end spring
      !> √(K G_p) there) or ends with it (free shear layer, G_p w' = 0: also a symmetry plane)
      logical :: continues(2) = .true.
   end type foundation_t

   !> Path-following controls (paper §5; Crisfield 1991 ch. 9).
   integer, parameter :: control_load = 1          !< fixed load increments
   integer, parameter :: control_displacement = 2  !< fixed increments of one displacement
   integer, parameter :: control_arclength = 3     !< fixed length of the step in displacement space
   !> Iteration strategies: the constraint that gives the load correction δλ at each iteration.
   integer, parameter :: iteration_chan = 1        !< minimum residual displacement (Chan 1988)
   integer, parameter :: iteration_cylindrical = 2 !< cylindrical arc length (Crisfield 1981)
   integer, parameter :: iteration_riks = 3        !< linearised, updated normal plane (Riks/Ramm)

   !> What to run and, for a nonlinear path, how to follow it.
   type :: analysis_options_t
      integer :: kind = analysis_linear
      integer :: control = control_arclength
      integer :: iteration = iteration_chan
      real(dp) :: first_increment = 0.0_dp   !< first load increment Δλ (or Δu of the controlled DOF)
      real(dp) :: min_increment = 1.0e-6_dp  !< smallest step, relative to the first
      real(dp) :: max_increment = 4.0_dp     !< largest step, relative to the first
      integer :: desired_iterations = 5      !< step size adapts as sqrt(desired/used)
      integer :: max_iterations = 25         !< per attempt, then the step is cut
      integer :: max_cuts = 12               !< halvings of one step before the run fails
      integer :: max_steps = 200
      real(dp) :: lambda_max = huge(1.0_dp)  !< stop when |λ| exceeds this
      integer :: stop_track = 0              !< index into tracks (0: none)
      real(dp) :: stop_value = 0.0_dp        !< stop when |tracked value| reaches it
      real(dp) :: force_tolerance = 1.0e-8_dp        !< ||g|| relative to the load scale
      real(dp) :: displacement_tolerance = 1.0e-8_dp !< ||δu|| relative to ||Δu||
      integer :: control_node = 0            !< displacement control: node and DOF
      integer :: control_dof = 0
      integer :: shape_every = 10            !< write a shape snapshot every so many steps
      !> *PATH, SWITCH=n: follow the secondary branch from the n-th located bifurcation (0: stay on the
      !> primary path; docs/theory.md §2.6)
      integer :: switch_bifurcation = 0
      !> *PATH, TIES=KEEP: a step that changes one of two tied contacts and not the other is cut, and the
      !> pair moved together, unless the branch followed goes nowhere else but back (docs/theory.md
      !> §2.3, "Contacts that tie"); TIES=SPLIT (the default): the contact LCP's choice is taken
      logical :: keep_ties = .false.
      !> *IMPERFECTION without FILE=: add the mode of the perfect structure's n-th located bifurcation,
      !> computed in a first run, scaled to a largest nodal translation `imperfection_amplitude` (length)
      !> (0: none; uniarc_path_imperfection)
      integer :: imperfection_bifurcation = 0
      real(dp) :: imperfection_amplitude = 0.0_dp
   end type analysis_options_t

   !> Extra result files a deck asks for with `*OUTPUT` (docs/input.md); the path, critical-point and
   !> shape files are always written.
   type :: output_options_t
      logical :: vtk = .false.   !< ParaView snapshots `STEM_NNNN.vtk` and their collection `STEM.pvd`
      integer :: vtk_every = 0   !< a VTK snapshot every so many steps; 0: as the shape file (shape_every)
      !> The tables of internal forces `STEM.forces` and contact pressures `STEM.contact` (*OUTPUT, FORCES)
      logical :: forces = .false.
      integer :: forces_every = 0              !< every so many steps; 0: as the shape file, unless listed
      integer, allocatable :: forces_steps(:)  !< the steps listed on the card's data lines (may be unallocated)
      !> The buckling modes at the located bifurcations, `STEM.modes` (*OUTPUT, MODES)
      logical :: modes = .false.
   end type output_options_t

   !> The loads of one analysis step (*STEP, docs/input.md): its reference nodal loads, distributed loads
   !> and temperature changes. `factor` is the multiplier of a held pattern (`model_t%held`): the λ at
   !> which the step that applied it ended (docs/theory.md, analysis steps).
   type :: load_pattern_t
      real(dp) :: factor = 1.0_dp
      real(dp), allocatable :: nodal_load(:, :)                  !< (3, n_nodes)
      type(distributed_load_t), allocatable :: distributed_loads(:)
      type(thermal_load_t), allocatable :: thermal_loads(:)
      !> (3, n_nodes) prescribed displacements of held DOFs (*BOUNDARY with a value inside the step),
      !> scaled like the loads; unallocated: none
      real(dp), allocatable :: prescribed(:, :)
      !> (2, n_contact_groups) rigid translations d of plane obstacles (*MOVE inside the step), scaled
      !> like the loads; unallocated: none
      real(dp), allocatable :: moves(:, :)
   end type load_pattern_t

   !> One analysis step of a deck with *STEP cards: its name, its own load pattern (scaled by the
   !> step's λ) and its analysis (*STATIC or *PATH with its controls).
   type :: analysis_step_t
      character(len=:), allocatable :: name
      type(load_pattern_t) :: loads
      type(analysis_options_t) :: analysis
      !> (3, n_nodes) the DOFs held during the step (*BOUNDARY inside *STEP adds supports, *BOUNDARY,
      !> REMOVE takes them away; docs/theory.md §2.10); unallocated: those of the model
      logical, allocatable :: fixed(:, :)
      !> Where the step's first *BOUNDARY, REMOVE card is (line, column of its REMOVE; 0: none) and
      !> that line's text, for a message that points at it (a step left a mechanism, uniarc_run_checks)
      integer :: remove_line = 0, remove_column = 0
      character(len=:), allocatable :: remove_text
   end type analysis_step_t

   !> The whole model.
   type :: model_t
      character(len=:), allocatable :: deck_path   !< file it was read from (messages)
      character(len=:), allocatable :: title
      integer :: n_nodes = 0
      integer :: n_elements = 0
      real(dp), allocatable :: coordinates(:, :)   !< (2, n_nodes) initial x, y
      integer, allocatable :: node_label(:)        !< (n_nodes) user number
      integer, allocatable :: connectivity(:, :)   !< (2, n_elements) internal node indices
      integer, allocatable :: element_label(:)     !< (n_elements) user number
      integer, allocatable :: element_section(:)   !< (n_elements) index into sections
      !> (n_elements) element_beam_column or element_truss; unallocated means every element is a
      !> beam-column (models built field by field, as in the unit tests). Read it through element_kind_of.
      integer, allocatable :: element_kind(:)
      !> (2, n_elements) the joint at each end of each element; unallocated means every joint is rigid.
      !> Read it through end_joints_of.
      type(end_joint_t), allocatable :: end_joints(:, :)
      type(section_t), allocatable :: sections(:)
      type(node_set_t), allocatable :: node_sets(:)
      type(element_set_t), allocatable :: element_sets(:)
      logical, allocatable :: fixed(:, :)          !< (3, n_nodes) DOF held at zero
      real(dp), allocatable :: nodal_load(:, :)    !< (3, n_nodes) reference nodal forces/moments
      type(distributed_load_t), allocatable :: distributed_loads(:)
      type(track_t), allocatable :: tracks(:)
      type(contact_candidate_t), allocatable :: contacts(:)  !< every contact candidate (may be empty)
      type(contact_group_t), allocatable :: contact_groups(:)
      type(foundation_t), allocatable :: foundations(:)      !< the foundations as described (may be empty)
      type(analysis_options_t) :: analysis
      type(output_options_t) :: output
      type(thermal_load_t), allocatable :: thermal_loads(:)  !< temperature changes (may be unallocated: none)
      !> (3, n_nodes) prescribed displacements of held DOFs (support settlements), scaled by λ like the
      !> loads; unallocated: none (every held DOF stays at zero).
      real(dp), allocatable :: prescribed(:, :)
      !> The analysis steps of a deck with *STEP cards, in order (unallocated: a deck without *STEP,
      !> whose loads and analysis are the fields above). uniarc_model_steps makes the model of each step.
      type(analysis_step_t), allocatable :: steps(:)
      !> Loads held at fixed value while this model's own loads are scaled by λ: the patterns of the
      !> earlier steps, each times its factor (unallocated or empty: none). Set by uniarc_model_steps.
      type(load_pattern_t), allocatable :: held(:)
   end type model_t

contains

   !> Translate the plane obstacles of `model` by `factor` × `moves(:, g)` (2, n_contact_groups; the
   !> groups' translations d, *MOVE): with `own` the step's own pattern, scaled by the step's λ, each
   !> candidate's gap gets the rate ∂g/∂λ = −factor n·d (gap_rate); else the translation is held, the
   !> gap's offset lowered by factor n·d (a plane moved by d toward the node closes g = offset + n·u by
   !> n·d; docs/theory.md §3.11). A curved obstacle (circle, ellipse, polyline) is moved exactly: with
   !> `own` its candidates get the motion factor d (contact_candidate_t%motion, the gap evaluated at the
   !> point shifted by −λ d); else its centre or vertices are translated by factor d.
   pure subroutine move_obstacles(model, moves, factor, own)
      type(model_t), intent(inout) :: model
      real(dp), intent(in) :: moves(:, :)
      real(dp), intent(in) :: factor
      logical, intent(in) :: own
      real(dp) :: closing
      integer :: g, i, c, k
      if (.not. allocated(model%contact_groups)) return
      do g = 1, min(size(moves, 2), size(model%contact_groups))
         if (all(moves(:, g) == 0.0_dp)) cycle
         do i = 1, size(model%contact_groups(g)%candidates)
            c = model%contact_groups(g)%candidates(i)
            if (model%contacts(c)%gap_kind /= gap_fixed_direction) then
               if (own) then
                  model%contacts(c)%motion = model%contacts(c)%motion + factor*moves(:, g)
               else if (allocated(model%contacts(c)%vertices)) then
                  do k = 1, size(model%contacts(c)%vertices, 2)
                     model%contacts(c)%vertices(:, k) = model%contacts(c)%vertices(:, k) + factor*moves(:, g)
                  end do
               else
                  model%contacts(c)%centre = model%contacts(c)%centre + factor*moves(:, g)
               end if
               cycle
            end if
            closing = factor*dot_product(model%contacts(c)%direction, moves(:, g))
            if (own) then
               model%contacts(c)%gap_rate = model%contacts(c)%gap_rate - closing
            else
               model%contacts(c)%offset = model%contacts(c)%offset - closing
            end if
         end do
      end do
   end subroutine move_obstacles

   !> Index of the node set called `name` (case-insensitive), 0 if there is none.
   pure function find_node_set(model, name) result(index)
      type(model_t), intent(in) :: model
      character(len=*), intent(in) :: name
      integer :: index
      integer :: i
      index = 0
      if (.not. allocated(model%node_sets)) return
      do i = 1, size(model%node_sets)
         if (same_text(model%node_sets(i)%name, name)) then
            index = i
            return
         end if
      end do
   end function find_node_set

   !> Index of the element set called `name` (case-insensitive), 0 if there is none.
   pure function find_element_set(model, name) result(index)
      type(model_t), intent(in) :: model
      character(len=*), intent(in) :: name
      integer :: index
      integer :: i
      index = 0
      if (.not. allocated(model%element_sets)) return
      do i = 1, size(model%element_sets)
         if (same_text(model%element_sets(i)%name, name)) then
            index = i
            return
         end if
      end do
   end function find_element_set

   !> Initial length of element `e`.
   pure function element_length(model, e) result(length)
      type(model_t), intent(in) :: model
      integer, intent(in) :: e
      real(dp) :: length
      real(dp) :: d(2)
      d = model%coordinates(:, model%connectivity(2, e)) - model%coordinates(:, model%connectivity(1, e))
      length = norm2(d)
   end function element_length

   !> Kind of element `e` (element_beam_column or element_truss): model%element_kind(e), or the
   !> beam-column when the model has no element kinds.
   pure integer function element_kind_of(model, e) result(kind)
      type(model_t), intent(in) :: model
      integer, intent(in) :: e
      kind = element_beam_column
      if (allocated(model%element_kind)) kind = model%element_kind(e)
   end function element_kind_of

   !> The joints (2) at node 1 and node 2 of element `e`: model%end_joints(:, e), or rigid ones when the
   !> model has no joints.
   pure function end_joints_of(model, e) result(joints)
      type(model_t), intent(in) :: model
      integer, intent(in) :: e
      type(end_joint_t) :: joints(2)
      if (allocated(model%end_joints)) joints = model%end_joints(:, e)
   end function end_joints_of

   !> True when a joint of the model has a moment limit (`*RELEASE, MY=`): its elements then carry a
   !> plastic rotation per end as history (docs/theory.md §1.11).
   pure logical function has_moment_limits(model)
      type(model_t), intent(in) :: model
      has_moment_limits = .false.
      if (allocated(model%end_joints)) has_moment_limits = any(model%end_joints%moment_limit > 0.0_dp)
   end function has_moment_limits

   !> Values of the tracked quantities (`*TRACK`, one per track, in the order of `tracks`):
   !> scale × u(dof, node), from the nodal displacements `displacement` (dofs_per_node, n_nodes).
   pure function tracked_values(model, displacement) result(values)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: displacement(:, :)
      real(dp), allocatable :: values(:)
      integer :: i
      if (.not. allocated(model%tracks)) then
         allocate (values(0))
         return
      end if
      allocate (values(size(model%tracks)))
      do i = 1, size(model%tracks)
         values(i) = model%tracks(i)%scale*displacement(model%tracks(i)%dof, model%tracks(i)%node)
      end do
   end function tracked_values

end module uniarc_model
