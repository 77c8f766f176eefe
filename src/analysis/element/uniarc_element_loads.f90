!> Element loads that are not forces on the span: temperature changes as natural deformations of the
!> basic element (docs/theory.md §1.9).
!>
!> A temperature change ΔT at the axis and a difference ΔT_left − ΔT_right between the faces (depth h)
!> give the element stress-free deformations v0 = (L0 α ΔT, −κ_T L0/2, κ_T L0/2), κ_T = −α (ΔT_left −
!> ΔT_right)/h (a uniform curvature, positive toward the left normal). The basic forces are
!> q = Kb (v − λ v0) = Kb v − λ q0, q0 = Kb v0 (thermal_basic_force), so the element's internal force
!> is Bᵀ Kb v − λ B(u)ᵀ q0: the thermal part acts as a load λ B(u)ᵀ q0 that turns with the chord
!> (corotational B(u); the linear analysis takes B0), and its derivative ∂(B(u)ᵀ q0)/∂u is the
!> initial-stress matrix Ks(q0) of the transformation (uniarc_transformation, transform_to_global with
!> Kb = 0). In equilibrium g = λ R(u) − F(u) it enters R with the load stiffness −λ Ks(q0).
module uniarc_element_loads
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, thermal_load_t, section_t, element_truss, element_kind_of
   use uniarc_transformation, only: chord_t, transform_deformations, transform_to_global
   use uniarc_element, only: element_coordinates
   use uniarc_released_loads, only: released_basic_force
   implicit none
   private
   public :: thermal_basic_force, thermal_load_vector

contains

   !> The basic forces q0 = Kb v0 = (EA α ΔT, −EI κ_T, EI κ_T) (force, force × length) that hold the
   !> thermal deformations of `load` restrained: a bar held at both ends carries N = −EA α ΔT, a
   !> clamped beam under a gradient the moment EI κ_T (Timoshenko & Goodier 1970, §150; Przemieniecki
   !> 1968, §5.7). For element kind `kind` (a truss has no moments) of section `section`.
   pure function thermal_basic_force(load, section, kind) result(q0)
      type(thermal_load_t), intent(in) :: load
      type(section_t), intent(in) :: section
      integer, intent(in) :: kind
      real(dp) :: q0(3)
      real(dp) :: curvature
      curvature = 0.0_dp
      if (load%difference /= 0.0_dp .and. load%depth > 0.0_dp) curvature = -load%alpha*load%difference/load%depth
      q0 = [section%ea*load%alpha*load%delta_t, -section%ei*curvature, section%ei*curvature]
      if (kind == element_truss) q0(2:3) = 0.0_dp
   end function thermal_basic_force

   !> The equivalent nodal load f = B(u)ᵀ q0 (6, global, per unit λ) of thermal load `load` of `model` at
   !> the element's total displacements u (6), its end joints in series (q0 = Kj v0, uniarc_released_loads), under `transformation` (linear: B0 on the initial chord;
   !> corotational: B on the current chord), and k_load = −∂f/∂u (6×6, symmetric; zero for the linear
   !> transformation), so that the assembled tangent is K_int + λ k_load.
   pure subroutine thermal_load_vector(model, load, u, transformation, f, k_load)
      type(model_t), intent(in) :: model
      type(thermal_load_t), intent(in) :: load
      real(dp), intent(in) :: u(6)
      integer, intent(in) :: transformation
      real(dp), intent(out) :: f(6), k_load(6, 6)
      real(dp), parameter :: no_stiffness(3, 3) = 0.0_dp
      type(chord_t) :: chord
      real(dp) :: deformation(3), q0(3)
      integer :: e
      e = load%element
      q0 = thermal_basic_force(load, model%sections(model%element_section(e)), element_kind_of(model, e))
      q0 = released_basic_force(model, e, q0)   ! end joints in series (uniarc_released_loads)
      call transform_deformations(transformation, element_coordinates(model, e), u, chord, deformation)
      call transform_to_global(transformation, chord, q0, no_stiffness, f, k_load)
      k_load = -k_load
   end subroutine thermal_load_vector

end module uniarc_element_loads
