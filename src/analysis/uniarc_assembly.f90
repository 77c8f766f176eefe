!> Assembly of global band matrices and load vectors from element contributions through DOF maps.
module uniarc_assembly
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, dofs_per_node, load_fixed_direction, load_pressure
   use uniarc_dof_map, only: dof_map_t, element_equations
   use uniarc_band, only: band_matrix_t, band_add_element, band_zero
   use uniarc_frame_linear, only: fixed_direction_load_vector, pressure_load_vector
   use uniarc_element, only: element_response_t, element_response, element_coordinates, transformation_linear
   use uniarc_element_loads, only: thermal_load_vector
   use uniarc_released_loads, only: released_span_correction
   implicit none
   private
   public :: assemble_linear_stiffness, assemble_reference_load, gather_nodal, scatter_add

contains

   !> K = Σ_e B0ᵀ Kb B0: the tangents of the elements (uniarc_element, any kind) under the linear
   !> transformation at u = 0, on the initial geometry.
   subroutine assemble_linear_stiffness(model, map, stiffness)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(band_matrix_t), intent(inout) :: stiffness
      real(dp), parameter :: at_rest(2*dofs_per_node) = 0.0_dp
      type(element_response_t) :: response
      integer :: e
      call band_zero(stiffness)
      do e = 1, model%n_elements
         call element_response(model, e, at_rest, transformation_linear, response)
         call band_add_element(stiffness, element_equations(model, map, e), response%tangent)
      end do
   end subroutine assemble_linear_stiffness

   !> Reference load vector R_r (paper Eq. 17) in equation numbering: nodal loads plus consistent nodal
   !> loads of the distributed loads on the initial geometry. The loads that depend on the displacements
   !> — follower pressure and temperature changes (B0ᵀ q0, uniarc_element_loads) — are included only
   !> when `include_follower` is true (the linear analysis); the nonlinear analysis evaluates them on the
   !> current geometry (uniarc_equilibrium).
   pure subroutine assemble_reference_load(model, map, include_follower, load)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      logical, intent(in) :: include_follower
      real(dp), intent(out) :: load(:)
      integer :: i, k, e
      real(dp) :: f(2*dofs_per_node), k_unused(2*dofs_per_node, 2*dofs_per_node), df(2*dofs_per_node)
      real(dp), parameter :: at_rest(2*dofs_per_node) = 0.0_dp
      load = 0.0_dp
      do i = 1, model%n_nodes
         do k = 1, dofs_per_node
            if (map%equation(k, i) > 0) load(map%equation(k, i)) = load(map%equation(k, i)) + model%nodal_load(k, i)
         end do
      end do
      if (include_follower .and. allocated(model%thermal_loads)) then
         do i = 1, size(model%thermal_loads)
            e = model%thermal_loads(i)%element
            call thermal_load_vector(model, model%thermal_loads(i), at_rest, transformation_linear, f, k_unused)
            call scatter_add(element_equations(model, map, e), f, load)
         end do
      end if
      if (.not. allocated(model%distributed_loads)) return
      do i = 1, size(model%distributed_loads)
         associate (dload => model%distributed_loads(i))
            e = dload%element
            select case (dload%kind)
            case (load_fixed_direction)
               f = fixed_direction_load_vector(element_coordinates(model, e), dload%qx, dload%qy)
            case (load_pressure)
               if (dload%follower .and. .not. include_follower) cycle
               f = pressure_load_vector(element_coordinates(model, e), dload%pressure)
            case default
               cycle
            end select
            ! End joints in series: the fixed-end forces of the released member (uniarc_released_loads).
            call released_span_correction(model, e, [f(3), f(6)], at_rest, transformation_linear, df, k_unused)
            call scatter_add(element_equations(model, map, e), f + df, load)
         end associate
      end do
   end subroutine assemble_reference_load

   !> global(eq) += element(a) for every equation a of the steering vector that is not eliminated.
   pure subroutine scatter_add(equations, element_vector, global)
      integer, intent(in) :: equations(:)
      real(dp), intent(in) :: element_vector(:)
      real(dp), intent(inout) :: global(:)
      integer :: a
      do a = 1, size(equations)
         if (equations(a) > 0) global(equations(a)) = global(equations(a)) + element_vector(a)
      end do
   end subroutine scatter_add

   !> Nodal displacements (3, n_nodes) from the vector of unknowns; eliminated DOFs are zero.
   pure subroutine gather_nodal(map, x, nodal)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: x(:)
      real(dp), intent(out) :: nodal(:, :)
      integer :: i, k
      nodal = 0.0_dp
      do i = 1, size(nodal, 2)
         do k = 1, size(nodal, 1)
            if (map%equation(k, i) > 0) nodal(k, i) = x(map%equation(k, i))
         end do
      end do
   end subroutine gather_nodal

end module uniarc_assembly
