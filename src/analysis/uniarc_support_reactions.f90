!> The forces the supports apply to the structure, and the force of the prescribed displacements
!> (support settlements, moving supports) along their motion: the path file's `prescribed_force`
!> column (docs/contracts.md, docs/theory.md §2.9).
!>
!> A support's reaction is what equilibrium leaves at its DOF: r = F(u) − F_ext(u, λ), F the internal
!> forces of the elements and F_ext the loads, both assembled for every DOF, held or free (the model
!> with its supports taken away numbers them all). The nonlinear analysis assembles them as its
!> equilibrium does (uniarc_equilibrium: corotational elements, follower loads on the current
!> geometry, the held patterns of earlier steps); the linear one from the elements' forces of their
!> small deformations on the initial geometry (B0ᵀ Kb B0 u_e − R, uniarc_element), which is K u − R. At a free DOF r is the residual, zero at a converged state.
module uniarc_support_reactions
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_model, only: model_t, dofs_per_node, analysis_step_t
   use uniarc_model_copy, only: copy_model
   use uniarc_memory, only: allocation_failure
   use uniarc_dof_map, only: dof_map_t, build_dof_map
   use uniarc_band, only: band_matrix_t, band_allocate
   use uniarc_assembly, only: assemble_reference_load, gather_nodal, scatter_add
   use uniarc_dof_map, only: element_equations
   use uniarc_element, only: element_response_t, element_response, element_displacements, transformation_linear
   use uniarc_equilibrium, only: assemble_equilibrium
   implicit none
   private
   public :: support_reactions, prescribed_force

contains

   !> The reactions (dofs_per_node, n_nodes) of the supports at nodal displacements `displacement`
   !> (dofs_per_node, n_nodes; every DOF's, the prescribed ones included) and load factor λ: force
   !> (moment at θ) that the support applies to the structure at each held DOF, 0 at the free ones.
   !> `linear`: the linear analysis's equations (initial geometry) instead of the nonlinear ones.
   !> Contact reactions at a node are not in it (they are the contact columns'): at a held DOF the
   !> support's value includes the contact force there. The nonlinear analysis's band matrix is
   !> that of the analysis with the held DOFs numbered and without the contact unknowns, a size the
   !> analysis has already allocated (the memory check, uniarc_check), so it is allocated without a
   !> returned error; the linear one needs none.
   !> `joint_plastic` (optional, (2, n_elements)): the committed plastic rotations of the joints with a
   !> moment limit (the path's state), passed to the equilibrium as the path following does.
   subroutine support_reactions(model, displacement, lambda, linear, reactions, joint_plastic, error, loads)
      type(model_t), intent(inout) :: model   !< unchanged (inout for copy_model)
      real(dp), intent(in) :: displacement(:, :)
      real(dp), intent(in) :: lambda
      logical, intent(in) :: linear
      real(dp), allocatable, intent(out) :: reactions(:, :)
      real(dp), intent(in), optional :: joint_plastic(:, :)
      !> an allocation of the numbering the system refused (error_analysis)
      type(error_t), allocatable, intent(out) :: error
      !> (dofs_per_node, n_nodes) the loads λR at every DOF, held or free (the balance of the linear
      !> analysis, uniarc_static_balance)
      real(dp), allocatable, intent(out), optional :: loads(:, :)
      type(element_response_t) :: response
      type(model_t) :: unsupported
      type(dof_map_t) :: map
      type(band_matrix_t) :: stiffness
      real(dp), allocatable :: x(:), internal(:), reference(:), fixed_load(:)
      real(dp) :: force_scale, bytes
      integer :: i, k, j, status
      type(analysis_step_t), allocatable :: steps(:)
      ! Every DOF free; the displacements given are already the total ones, so the model's prescribed
      ! patterns must not be added again by the equilibrium.
      call move_alloc(model%steps, steps)
      call copy_model(model, unsupported, status, bytes)
      call move_alloc(steps, model%steps)
      call allocation_failure(status, 'an array of the copy of the model for the support reactions', bytes, &
                              error_analysis, error)
      if (allocated(error)) return
      unsupported%fixed = .false.
      if (allocated(unsupported%prescribed)) deallocate (unsupported%prescribed)
      if (allocated(unsupported%steps)) deallocate (unsupported%steps)
      if (allocated(unsupported%contacts)) deallocate (unsupported%contacts)
      allocate (unsupported%contacts(0))
      if (allocated(unsupported%held)) then
         do j = 1, size(unsupported%held)
            if (allocated(unsupported%held(j)%prescribed)) deallocate (unsupported%held(j)%prescribed)
         end do
      end if
      call build_dof_map(unsupported, map, error, error_analysis)
      if (allocated(error)) return
      allocate (x(map%n_equations), internal(map%n_equations), reference(map%n_equations), &
                fixed_load(map%n_equations), reactions(dofs_per_node, model%n_nodes), stat=status)
      call allocation_failure(status, 'the vectors of the support reactions', &
                              8.0_dp*(4*map%n_equations + dofs_per_node*model%n_nodes), error_analysis, error)
      if (allocated(error)) return
      x = 0.0_dp
      do i = 1, model%n_nodes
         do k = 1, dofs_per_node
            x(map%equation(k, i)) = displacement(k, i)
         end do
      end do
      if (linear) then
         ! The elements' forces of their deformations, B0ᵀ Kb (B0 u_e), not K u: a member that moves
         ! nearly as a rigid body has forces far smaller than the terms of K u that cancel in them
         ! (uniarc_linear_static, refine_solution), and each element's forces balance to the last bit.
         internal = 0.0_dp
         do j = 1, model%n_elements
            call element_response(unsupported, j, element_displacements(unsupported, j, displacement), &
                                  transformation_linear, response)
            call scatter_add(element_equations(unsupported, map, j), response%internal_force, internal)
         end do
         call assemble_reference_load(unsupported, map, .true., reference)
      else
         call band_allocate(stiffness, map%n_equations, map%half_bandwidth, map%half_bandwidth, error, &
                            error_analysis)
         if (allocated(error)) return
         call assemble_reference_load(unsupported, map, .false., fixed_load)
         if (present(joint_plastic)) then
            call assemble_equilibrium(unsupported, map, displacement, lambda, fixed_load, stiffness, internal, &
                                      reference, force_scale, error, joint_plastic=joint_plastic)
         else
            call assemble_equilibrium(unsupported, map, displacement, lambda, fixed_load, stiffness, internal, &
                                      reference, force_scale, error)
         end if
         if (allocated(error)) return
      end if
      internal = internal - lambda*reference   ! in place: no temporary (unchecked in the Release build)
      call gather_nodal(map, internal, reactions)
      if (present(loads)) then
         allocate (loads(dofs_per_node, model%n_nodes), stat=status)
         call allocation_failure(status, 'the loads of the balance check', 8.0_dp*dofs_per_node*model%n_nodes, &
                                 error_analysis, error)
         if (allocated(error)) return
         reference = lambda*reference   ! in place: no temporary (unchecked in the Release build)
         call gather_nodal(map, reference, loads)
      end if
      where (.not. model%fixed) reactions = 0.0_dp
   end subroutine support_reactions

   !> The force of the prescribed displacements along their motion: P = Σ_d ū_d r_d / max_d |ū_d| over
   !> the held DOFs, ū the pattern that moves with λ (the model's own prescribed displacements, those
   !> of its analysis step) and r the reactions (support_reactions). For one moving DOF it is the
   !> support's reaction along the motion; for a rigid plate (equal ū at its nodes) the resultant of its
   !> reactions along the motion: the force that pushes the support. 0 when the model has no pattern
   !> of its own.
   pure real(dp) function prescribed_force(model, reactions) result(force)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: reactions(:, :)
      force = 0.0_dp
      if (.not. allocated(model%prescribed)) return
      if (.not. any(model%prescribed /= 0.0_dp)) return
      force = sum(model%prescribed*reactions)/maxval(abs(model%prescribed))
   end function prescribed_force

end module uniarc_support_reactions
