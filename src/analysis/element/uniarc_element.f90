!> The element layer: the one entry point through which every element loop (assembly of the
!> equilibrium equations, the linear stiffness, the output of element forces) gets an element's response.
!>
!> An element is a coordinate transformation (uniarc_transformation: linear or corotational) around a
!> basic element (uniarc_basic_beam, uniarc_basic_truss), as OpenSees splits Element and CrdTransf:
!>
!>   u (global, 6) → transformation → v = (e, θ̄1, θ̄2) → basic element → q = (N, M1, M2), Kb
!>                 → transformation → f_int = Bᵀ q, K_T, end forces (N, V, M_start, M_end)
!>
!> The basic element is chosen by the kind stored in the model (model%element_kind, element_kind_of);
!> the transformation by the analysis: linear for the linear static analysis, corotational for path
!> following (analysis_transformation). A new kind of element (a Timoshenko beam, a curved element
!> with the same end DOFs) is one basic-element module and one case in `element_response`.
!> docs/theory.md §1 and §1.8 give the equations.
module uniarc_element
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, dofs_per_node, element_kind_of, element_truss, analysis_linear, &
                           element_timoshenko, end_joint_t, end_joints_of
   use uniarc_transformation, only: chord_t, transformation_linear, transformation_corotational, &
                                    transform_deformations, transform_to_global, transform_end_forces
   use uniarc_basic_beam, only: beam_basic_response
   use uniarc_basic_truss, only: truss_basic_response
   use uniarc_basic_timoshenko, only: timoshenko_basic_response, beam_bending_flexibility, beam_shear_flexibility
   use uniarc_end_joints, only: jointed_basic_response, has_joints
   use uniarc_joint_plasticity, only: plastic_joint_response, has_moment_limit
   implicit none
   private
   public :: element_response_t, element_response, analysis_transformation, element_stiffness_scale
   public :: element_coordinates, element_displacements
   public :: transformation_linear, transformation_corotational

   !> What an element returns: the global vectors the equilibrium equations need and the forces the
   !> output writes. Global vectors are ordered (u_x1, u_y1, θ1, u_x2, u_y2, θ2).
   type :: element_response_t
      real(dp) :: internal_force(2*dofs_per_node) = 0.0_dp   !< f_int = Bᵀ q, global (forces, moments)
      !> K_T = ∂f_int/∂u (6×6), symmetric; a truss leaves the rotation rows and columns zero.
      real(dp) :: tangent(2*dofs_per_node, 2*dofs_per_node) = 0.0_dp
      real(dp) :: basic_force(3) = 0.0_dp   !< q = (N, M1, M2): tension positive, end moments counter-clockwise
      real(dp) :: axial_force = 0.0_dp      !< N, tension positive
      real(dp) :: shear_force = 0.0_dp      !< V = dM/ds = (M1 + M2)/L (no load on the span)
      !> Bending moments (M_start, M_end) at node 1 and node 2, beam convention M = EI κ (positive when
      !> the element bends towards its left normal): (−M1, M2).
      real(dp) :: end_moments(2) = 0.0_dp
      !> Plastic rotations (radian) of the joints at node 1 and node 2 at this trial state: the committed
      !> ones plus the increments of the return mapping (uniarc_joint_plasticity); 0 without a moment limit.
      real(dp) :: plastic_rotation(2) = 0.0_dp
   end type element_response_t

contains

   !> The response of element `e` of `model` at its total global end displacements `u` (6; see
   !> element_displacements) under `transformation` (transformation_linear or
   !> transformation_corotational, see analysis_transformation).
   !>
   !> Dispatch: the basic element is the element's kind (element_kind_of: the Euler–Bernoulli
   !> beam-column by default, the truss, or the Timoshenko beam of uniarc_basic_timoshenko); its section
   !> gives EA (and EI for a beam, κGA for the Timoshenko beam). A beam with a hinge or a rotational
   !> spring at an end (end_joints_of) takes its bending law from uniarc_end_joints, the joints in
   !> series with the member's flexibility. The basic law is referred to the initial length L0 (small
   !> strains). A joint with a moment limit (`*RELEASE, MY=`) is elastic–perfectly plastic
   !> (uniarc_joint_plasticity): `plastic` (2, optional; 0 when absent) are its committed plastic
   !> rotations at node 1 and node 2, response%plastic_rotation the trial ones. No errors: the deck
   !> guarantees a section (with κGA > 0 for a Timoshenko beam) and a nonzero length for every element.
   pure subroutine element_response(model, e, u, transformation, response, plastic)
      type(model_t), intent(in) :: model
      integer, intent(in) :: e
      real(dp), intent(in) :: u(2*dofs_per_node)
      integer, intent(in) :: transformation
      type(element_response_t), intent(out) :: response
      real(dp), intent(in), optional :: plastic(2)
      type(chord_t) :: chord
      real(dp) :: deformation(3), basic_stiffness(3, 3), end_forces(4), committed(2)
      type(end_joint_t) :: joints(2)

      call transform_deformations(transformation, element_coordinates(model, e), u, chord, deformation)
      joints = end_joints_of(model, e)
      associate (section => model%sections(model%element_section(e)))
         select case (element_kind_of(model, e))
         case (element_truss)
            call truss_basic_response(chord%initial_length, section%ea, deformation, response%basic_force, &
                                      basic_stiffness)
         case (element_timoshenko)
            if (has_moment_limit(joints)) then
               committed = 0.0_dp
               if (present(plastic)) committed = plastic
               call plastic_joint_response(section%ea/chord%initial_length, &
                                           beam_bending_flexibility(chord%initial_length, section%ei, 0.0_dp), &
                                           joints, deformation, committed, response%basic_force, basic_stiffness, &
                                           response%plastic_rotation, &
                                           shear=beam_shear_flexibility(chord%initial_length, section%gas))
            else if (has_joints(joints)) then
               call jointed_basic_response(section%ea/chord%initial_length, &
                                           beam_bending_flexibility(chord%initial_length, section%ei, 0.0_dp), &
                                           joints, deformation, response%basic_force, basic_stiffness, &
                                           shear=beam_shear_flexibility(chord%initial_length, section%gas))
            else
               call timoshenko_basic_response(chord%initial_length, section%ea, section%ei, section%gas, &
                                              deformation, response%basic_force, basic_stiffness)
            end if
         case default
            if (has_moment_limit(joints)) then
               committed = 0.0_dp
               if (present(plastic)) committed = plastic
               call plastic_joint_response(section%ea/chord%initial_length, &
                                           beam_bending_flexibility(chord%initial_length, section%ei, 0.0_dp), &
                                           joints, deformation, committed, response%basic_force, basic_stiffness, &
                                           response%plastic_rotation)
            else if (has_joints(joints)) then
               call jointed_basic_response(section%ea/chord%initial_length, &
                                           beam_bending_flexibility(chord%initial_length, section%ei, 0.0_dp), &
                                           joints, deformation, response%basic_force, basic_stiffness)
            else
               call beam_basic_response(chord%initial_length, section%ea, section%ei, deformation, &
                                        response%basic_force, basic_stiffness)
            end if
         end select
      end associate
      call transform_to_global(transformation, chord, response%basic_force, basic_stiffness, &
                               response%internal_force, response%tangent)
      end_forces = transform_end_forces(chord, response%basic_force)
      response%axial_force = end_forces(1)
      response%shear_force = end_forces(2)
      response%end_moments = end_forces(3:4)
   end subroutine element_response

   !> The transformation of an analysis kind: transformation_linear for analysis_linear (the
   !> small-displacement forces a linear solution is in equilibrium with), else transformation_corotational.
   pure integer function analysis_transformation(analysis_kind) result(transformation)
      integer, intent(in) :: analysis_kind
      transformation = transformation_corotational
      if (analysis_kind == analysis_linear) transformation = transformation_linear
   end function analysis_transformation

   !> The largest stiffness of element `e` against a displacement of one end (force per length) on its
   !> initial length L0: EA/L0 + 12 EI/L0³ for the beam-column (axial plus clamped-clamped transverse),
   !> EA/L0 for the truss. Scales the round-off of the element forces (uniarc_equilibrium).
   pure real(dp) function element_stiffness_scale(model, e) result(scale)
      type(model_t), intent(in) :: model
      integer, intent(in) :: e
      real(dp) :: x(2, 2), length
      x = element_coordinates(model, e)
      length = norm2(x(:, 2) - x(:, 1))
      associate (section => model%sections(model%element_section(e)))
         select case (element_kind_of(model, e))
         case (element_truss)
            scale = section%ea/length
         case default
            scale = section%ea/length + 12.0_dp*section%ei/length**3
         end select
      end associate
   end function element_stiffness_scale

   !> Initial end coordinates (2×2) of element `e`: column i is node i of the element.
   pure function element_coordinates(model, e) result(x)
      type(model_t), intent(in) :: model
      integer, intent(in) :: e
      real(dp) :: x(2, 2)
      x(:, 1) = model%coordinates(:, model%connectivity(1, e))
      x(:, 2) = model%coordinates(:, model%connectivity(2, e))
   end function element_coordinates

   !> The 6 global displacements of element `e` from the nodal array `displacement` (3, n_nodes).
   pure function element_displacements(model, e, displacement) result(u)
      type(model_t), intent(in) :: model
      integer, intent(in) :: e
      real(dp), intent(in) :: displacement(:, :)
      real(dp) :: u(2*dofs_per_node)
      u(1:3) = displacement(:, model%connectivity(1, e))
      u(4:6) = displacement(:, model%connectivity(2, e))
   end function element_displacements

end module uniarc_element
