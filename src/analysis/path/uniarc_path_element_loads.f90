!> The size of a step's element loads where its reference load R has nothing on the free DOFs: a
!> structure restrained so that the supports take every equivalent nodal force of its element loads (a
!> bar heated between two pins: its thermal equivalent forces ±EA α ΔT sit on held DOFs; a clamped
!> beam under a gradient: ±EI α ΔT_d/h on held rotations). The loads still load the elements (their
!> natural deformations, docs/theory.md §1.9), so the path has something to follow — in λ alone, as
!> where the contacts carry the whole reference load (docs/theory.md §2.7) — but R on the free DOFs
!> cannot size it. This module gives the two sizes the path following needs from the element loads
!> themselves, held DOFs included:
!>   - `element_load_norm`: ‖f‖ of the element equivalent forces on every DOF (the load norm that the
!>     convergence test measures the residual against, and that says the step is loaded at all);
!>   - `natural_deformation_scale`: ψ, the displacement a unit of λ would give the elements left free,
!>     sqrt(Σ_e (α ΔT L_e)² + (α ΔT_d L_e/h)²) — the free elongation and the free relative end rotation
!>     of each heated element (Timoshenko & Goodier 1970, §150: the free thermal strain α ΔT and
!>     curvature α ΔT_d/h) — the measure of λ of an arc length that no displacement measures.
module uniarc_path_element_loads
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, dofs_per_node, load_pressure, load_fixed_direction
   use uniarc_element, only: element_coordinates, element_displacements, transformation_corotational
   use uniarc_frame_linear, only: fixed_direction_load_vector, pressure_load_vector
   use uniarc_element_loads, only: thermal_load_vector
   implicit none
   private
   public :: element_load_norm, natural_deformation_scale

contains

   !> ‖f‖ over every DOF of the model (held ones included) of the equivalent nodal forces of the step's
   !> element loads (temperature changes on the current geometry, distributed loads on the initial one)
   !> at nodal displacements u (3, n_nodes) — per unit λ. total: a work array (3, n_nodes) of the
   !> caller's (allocated with stat=, docs/contracts.md, "Memory"), overwritten by the nodal forces.
   function element_load_norm(model, displacement, total) result(norm)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: displacement(:, :)
      real(dp), intent(out) :: total(:, :)
      real(dp) :: norm
      real(dp) :: f(2*dofs_per_node), k(2*dofs_per_node, 2*dofs_per_node)
      integer :: i, e
      total = 0.0_dp
      if (allocated(model%thermal_loads)) then
         do i = 1, size(model%thermal_loads)
            e = model%thermal_loads(i)%element
            call thermal_load_vector(model, model%thermal_loads(i), element_displacements(model, e, displacement), &
                                     transformation_corotational, f, k)
            call add_to_nodes(e, f)
         end do
      end if
      if (allocated(model%distributed_loads)) then
         do i = 1, size(model%distributed_loads)
            associate (dload => model%distributed_loads(i))
               e = dload%element
               if (dload%kind == load_fixed_direction) then
                  f = fixed_direction_load_vector(element_coordinates(model, e), dload%qx, dload%qy)
               else if (dload%kind == load_pressure) then
                  f = pressure_load_vector(element_coordinates(model, e), dload%pressure)
               else
                  cycle
               end if
               call add_to_nodes(e, f)
            end associate
         end do
      end if
      norm = norm2(total)

   contains

      !> total += the element vector f (6) at the element's two nodes.
      subroutine add_to_nodes(element, vector)
         integer, intent(in) :: element
         real(dp), intent(in) :: vector(2*dofs_per_node)
         integer :: a, node
         do a = 1, 2
            node = model%connectivity(a, element)
            total(:, node) = total(:, node) + vector((a - 1)*dofs_per_node + 1:a*dofs_per_node)
         end do
      end subroutine add_to_nodes
   end function element_load_norm

   !> ψ of the step's temperature changes: sqrt(Σ (α ΔT L0)² + (α ΔT_d L0/h)²) over its thermal loads,
   !> L0 the element's initial length (module header); 0 without temperature changes.
   function natural_deformation_scale(model) result(scale)
      type(model_t), intent(in) :: model
      real(dp) :: scale
      real(dp) :: x(2, 2), length, rotation
      integer :: i
      scale = 0.0_dp
      if (.not. allocated(model%thermal_loads)) return
      do i = 1, size(model%thermal_loads)
         associate (load => model%thermal_loads(i))
            x = element_coordinates(model, load%element)
            length = norm2(x(:, 2) - x(:, 1))
            rotation = 0.0_dp
            if (load%depth > 0.0_dp) rotation = load%alpha*load%difference*length/load%depth
            scale = scale + (load%alpha*load%delta_t*length)**2 + rotation**2
         end associate
      end do
      scale = sqrt(scale)
   end function natural_deformation_scale

end module uniarc_path_element_loads
