!> The nonlinear equilibrium equations of the structure at a state (u, λ):
!>   g(u, λ) = λ R(u) − F(u) = 0,   K_T = ∂F/∂u − λ ∂R/∂u
!> F the internal forces of the elements (uniarc_element under the corotational transformation), R the
!> reference load (paper Eq. 17: R = λ R_r; fixed-direction loads do not depend on u, follower pressure
!> does). With analysis steps (uniarc_model_steps) the loads of earlier steps are held at fixed value:
!>   g(u, λ) = H(u) + λ R(u) − F(u),   K_T = ∂F/∂u − ∂H/∂u − λ ∂R/∂u,
!> H = Σ_j λ_j R_j(u) the held patterns (model%held); H is assembled into F with its sign reversed, so
!> that every caller keeps reading g = λ R − F.
!>
!> Prescribed displacements of held DOFs (support settlements, uniarc_model_steps prescribed_at): the
!> held DOFs have no equation; they are displaced by ū(λ) = λ ū + Σ_j λ_j ū_j, so that F = F(u_f, ū(λ))
!> and ∂g/∂λ = R − K_fp ū (K_fp the tangent's columns of the held DOFs). So that the path following
!> (which takes R as ∂g/∂λ) stays consistent, −K_fp ū is added to R and λ times it to F: g is unchanged,
!> and K_T too (the derivatives of the two additions cancel) (docs/theory.md §2.9).
module uniarc_equilibrium
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, dofs_per_node, load_pressure, load_fixed_direction, load_pattern_t
   use uniarc_dof_map, only: dof_map_t, element_equations
   use uniarc_band, only: band_matrix_t, band_add_element, band_zero
   use uniarc_assembly, only: scatter_add
   use uniarc_element, only: element_response_t, element_response, element_stiffness_scale, &
                             element_coordinates, element_displacements, transformation_corotational, &
                             transformation_linear
   use uniarc_corotational, only: follower_pressure
   use uniarc_frame_linear, only: fixed_direction_load_vector, pressure_load_vector
   use uniarc_element_loads, only: thermal_load_vector
   use uniarc_released_loads, only: released_span_correction
   use uniarc_model_steps, only: has_prescribed
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   implicit none
   private
   public :: assemble_equilibrium

contains

   !> Tangent K_T (band), internal forces F and reference load R(u) at nodal displacements u (3, n)
   !> and load factor λ (λ enters K_T only through the load stiffness of follower pressure).
   !> `force_scale` = sqrt(Σ_e ‖f_e‖²), the size of the element forces that cancel in F: round-off in
   !> the residual is proportional to it, so convergence tests measure the residual against it too.
   !> `roundoff` (optional) = 100 ε sqrt(Σ_e (k_e |x_e|)²), k_e = element_stiffness_scale (EA/L0 +
   !> 12 EI/L0³ for a beam-column, EA/L0 for a truss): the residual that round-off of the node positions
   !> alone leaves (a chord computed from coordinates of size |x| carries ε|x|, times the largest axial
   !> or bending stiffness of the element); no iteration can go below it, so it
   !> is a floor of the convergence test (it matters for rings of many short elements far from the origin).
   !> `joint_plastic` (optional, (2, n_elements)): the committed plastic rotations of the joints with a
   !> moment limit (uniarc_joint_plasticity), the history the elements' return mapping starts from.
   !> Without prescribed displacements `displacement` is used as it is (no copy: nothing allocated of
   !> the model's length, docs/contracts.md, "Memory"); with them, the total displacements are formed in
   !> a work array first, allocated with stat=.
   !> Errors: that work array refused by the system (error_analysis, out of memory, uniarc_memory).
   subroutine assemble_equilibrium(model, map, displacement, lambda, fixed_load, tangent, internal, reference, &
                                   force_scale, error, roundoff, joint_plastic)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: displacement(:, :)
      real(dp), intent(in) :: lambda
      real(dp), intent(in) :: fixed_load(:)
      type(band_matrix_t), intent(inout) :: tangent
      real(dp), intent(out) :: internal(:)
      real(dp), intent(out) :: reference(:)
      real(dp), intent(out) :: force_scale
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(out), optional :: roundoff
      real(dp), intent(in), optional :: joint_plastic(:, :)
      real(dp), allocatable :: total(:, :)
      integer :: j, status
      ! The displacements of every DOF: the free ones given, the held ones prescribed (module header).
      if (.not. has_prescribed(model)) then
         call assemble_at(model, map, displacement, lambda, fixed_load, tangent, internal, reference, &
                          force_scale, roundoff, joint_plastic)
         return
      end if
      ! total = displacement + prescribed_at(model, lambda), formed in place (no function result)
      allocate (total(size(displacement, 1), size(displacement, 2)), stat=status)
      call allocation_failure(status, 'the displacements with the prescribed ones', 8.0_dp*size(displacement), &
                              error_analysis, error)
      if (allocated(error)) return
      total = 0.0_dp
      if (allocated(model%prescribed)) total = lambda*model%prescribed
      if (allocated(model%held)) then
         do j = 1, size(model%held)
            if (allocated(model%held(j)%prescribed)) total = total + model%held(j)%factor*model%held(j)%prescribed
         end do
      end if
      total = displacement + total
      call assemble_at(model, map, total, lambda, fixed_load, tangent, internal, reference, &
                       force_scale, roundoff, joint_plastic)
   end subroutine assemble_equilibrium

   !> assemble_equilibrium at the displacements `total` of every DOF.
   subroutine assemble_at(model, map, total, lambda, fixed_load, tangent, internal, reference, &
                          force_scale, roundoff, joint_plastic)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: total(:, :)
      real(dp), intent(in) :: lambda
      real(dp), intent(in) :: fixed_load(:)     !< the u-independent part of R (assemble_reference_load)
      type(band_matrix_t), intent(inout) :: tangent
      real(dp), intent(out) :: internal(:)
      real(dp), intent(out) :: reference(:)
      real(dp), intent(out) :: force_scale
      real(dp), intent(out), optional :: roundoff
      real(dp), intent(in), optional :: joint_plastic(:, :)
      real(dp) :: position_noise, x(2, 2), u(2*dofs_per_node)
      real(dp) :: f(2*dofs_per_node), k(2*dofs_per_node, 2*dofs_per_node), rate(2*dofs_per_node)
      real(dp) :: f0(2*dofs_per_node), df(2*dofs_per_node), dk(2*dofs_per_node, 2*dofs_per_node)
      type(element_response_t) :: response
      integer :: e, i
      logical :: moving
      moving = has_prescribed(model)
      call band_zero(tangent)
      internal = 0.0_dp
      reference = fixed_load
      force_scale = 0.0_dp
      position_noise = 0.0_dp
      do e = 1, model%n_elements
         u = element_displacements(model, e, total)
         if (present(joint_plastic)) then
            call element_response(model, e, u, transformation_corotational, response, joint_plastic(:, e))
         else
            call element_response(model, e, u, transformation_corotational, response)
         end if
         call band_add_element(tangent, element_equations(model, map, e), response%tangent)
         call scatter_add(element_equations(model, map, e), response%internal_force, internal)
         if (moving .and. allocated(model%prescribed)) then
            ! −K_e ū_e of the step's own prescribed pattern: R += it, F += λ times it (module header).
            rate = element_displacements(model, e, model%prescribed)
            if (any(rate /= 0.0_dp)) then
               f = -matmul(response%tangent, rate)
               call scatter_add(element_equations(model, map, e), f, reference)
               call scatter_add(element_equations(model, map, e), lambda*f, internal)
            end if
         end if
         force_scale = force_scale + dot_product(response%internal_force, response%internal_force)
         x = element_coordinates(model, e)
         position_noise = position_noise + (element_stiffness_scale(model, e) &
                                            *max(maxval(abs(x(:, 1) + u(1:2))), maxval(abs(x(:, 2) + u(4:5)))))**2
      end do
      force_scale = sqrt(force_scale)
      if (present(roundoff)) roundoff = 100.0_dp*epsilon(1.0_dp)*sqrt(position_noise)
      if (allocated(model%thermal_loads)) then
         do i = 1, size(model%thermal_loads)
            e = model%thermal_loads(i)%element
            call thermal_load_vector(model, model%thermal_loads(i), element_displacements(model, e, total), &
                                     transformation_corotational, f, k)
            call scatter_add(element_equations(model, map, e), f, reference)
            call band_add_element(tangent, element_equations(model, map, e), lambda*k)
         end do
      end if
      if (allocated(model%held)) then
         do i = 1, size(model%held)
            call subtract_held_pattern(model, map, model%held(i), total, tangent, internal)
         end do
      end if
      if (.not. allocated(model%distributed_loads)) return
      do i = 1, size(model%distributed_loads)
         associate (dload => model%distributed_loads(i))
            if (dload%kind /= load_pressure .or. .not. dload%follower) cycle
            e = dload%element
            call follower_pressure(element_coordinates(model, e), element_displacements(model, e, total), &
                                   dload%pressure, f, k)
            ! End joints in series (uniarc_released_loads): the clamped moments on the initial geometry.
            f0 = pressure_load_vector(element_coordinates(model, e), dload%pressure)
            call released_span_correction(model, e, [f0(3), f0(6)], element_displacements(model, e, total), &
                                          transformation_corotational, df, dk)
            call scatter_add(element_equations(model, map, e), f + df, reference)
            call band_add_element(tangent, element_equations(model, map, e), lambda*(k + dk))
         end associate
      end do
   end subroutine assemble_at

   !> internal −= c R_p(u) and tangent += c (load stiffness of R_p), c = pattern%factor: a load pattern
   !> held at fixed value (an earlier analysis step's loads at the λ where that step ended), assembled
   !> as the reference load is (nodal and fixed-direction loads and non-follower pressure on the initial
   !> geometry, follower pressure and temperature changes on the current one).
   subroutine subtract_held_pattern(model, map, pattern, displacement, tangent, internal)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(load_pattern_t), intent(in) :: pattern
      real(dp), intent(in) :: displacement(:, :)
      type(band_matrix_t), intent(inout) :: tangent
      real(dp), intent(inout) :: internal(:)
      real(dp) :: f(2*dofs_per_node), k(2*dofs_per_node, 2*dofs_per_node)
      real(dp) :: f0(2*dofs_per_node), df(2*dofs_per_node), dk(2*dofs_per_node, 2*dofs_per_node)
      real(dp), parameter :: at_rest(2*dofs_per_node) = 0.0_dp
      integer :: i, j, e
      do i = 1, model%n_nodes
         do j = 1, dofs_per_node
            if (map%equation(j, i) > 0) internal(map%equation(j, i)) = internal(map%equation(j, i)) &
                                                                      - pattern%factor*pattern%nodal_load(j, i)
         end do
      end do
      do i = 1, size(pattern%thermal_loads)
         e = pattern%thermal_loads(i)%element
         call thermal_load_vector(model, pattern%thermal_loads(i), element_displacements(model, e, displacement), &
                                  transformation_corotational, f, k)
         call scatter_add(element_equations(model, map, e), -pattern%factor*f, internal)
         call band_add_element(tangent, element_equations(model, map, e), pattern%factor*k)
      end do
      do i = 1, size(pattern%distributed_loads)
         associate (dload => pattern%distributed_loads(i))
            e = dload%element
            k = 0.0_dp
            if (dload%kind == load_fixed_direction) then
               f = fixed_direction_load_vector(element_coordinates(model, e), dload%qx, dload%qy)
            else if (dload%kind == load_pressure .and. .not. dload%follower) then
               f = pressure_load_vector(element_coordinates(model, e), dload%pressure)
            else if (dload%kind == load_pressure) then
               call follower_pressure(element_coordinates(model, e), element_displacements(model, e, displacement), &
                                      dload%pressure, f, k)
               f0 = pressure_load_vector(element_coordinates(model, e), dload%pressure)
               call released_span_correction(model, e, [f0(3), f0(6)], &
                                             element_displacements(model, e, displacement), &
                                             transformation_corotational, df, dk)
               f = f + df
               call band_add_element(tangent, element_equations(model, map, e), pattern%factor*(k + dk))
            else
               cycle
            end if
            if (.not. (dload%kind == load_pressure .and. dload%follower)) then
               ! End joints in series (uniarc_released_loads): loads on the initial geometry.
               call released_span_correction(model, e, [f(3), f(6)], at_rest, transformation_linear, df, dk)
               f = f + df
            end if
            call scatter_add(element_equations(model, map, e), -pattern%factor*f, internal)
         end associate
      end do
   end subroutine subtract_held_pattern

end module uniarc_equilibrium
