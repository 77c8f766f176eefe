!> Fixed-end forces of a loaded member with end joints (hinges, rotational springs) in series.
!>
!> The loads on an element's span (uniarc_frame_linear, uniarc_corotational) and its temperature
!> changes (uniarc_element_loads) are written as the fixed-end forces of a member clamped at both
!> ends: the basic end moments Mf = (M1f, M2f) that hold its ends at zero rotation. With a joint of
!> compliance c_i between end i and its node (uniarc_end_joints, docs/theory.md §1.10) the node can be
!> held while the member end turns: with the nodes fixed, the member's end rotations θm and the joint
!> moments M obey M = Kb θm + Mf (member) and θm + C M = 0 (joints in series, C = diag(c1, c2)), so
!>
!>   M = (F + C)⁻¹ F Mf = Kj F Mf,          F = Kb⁻¹ the member's bending flexibility,
!>
!> Kj the jointed bending stiffness of uniarc_end_joints (a hinge's row and column condensed out, its
!> moment zero). The shears follow by statics. For a uniform load q on a beam of length L hinged at
!> end 2: Mf = (−qL²/12, qL²/12) gives M = (−qL²/8, 0), the propped cantilever (McGuire, Gallagher &
!> Ziemian 2000, Matrix Structural Analysis, 2nd ed., the fixed-end forces of members with releases;
!> Przemieniecki 1968, §5.4). For the natural deformations v0 of a temperature change the clamped
!> moments are Mf = Kb v0 and the released ones Kj v0 = Kj F Mf: the same map. A joint with a moment
!> limit enters with its elastic compliance (its plastic rotations are carried by the element law).
module uniarc_released_loads
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, end_joint_t, end_joints_of, element_kind_of, element_truss, element_timoshenko
   use uniarc_end_joints, only: jointed_basic_response, has_joints
   use uniarc_basic_timoshenko, only: beam_bending_flexibility, beam_shear_flexibility
   use uniarc_transformation, only: chord_t, transformation_linear, transform_deformations, transform_to_global
   implicit none
   private
   public :: released_basic_force, released_span_correction

contains

   !> The basic forces (N, M1, M2) (3) of element `e` of `model` whose ends are held, from those
   !> `clamped` (3) of the member clamped at both ends: M = Kj F Mf (module header); N unchanged.
   !> Returns `clamped` unchanged for a truss or a beam without joints.
   pure function released_basic_force(model, e, clamped) result(q)
      type(model_t), intent(in) :: model
      integer, intent(in) :: e
      real(dp), intent(in) :: clamped(3)
      real(dp) :: q(3)
      type(end_joint_t) :: joints(2)
      real(dp) :: flexibility(2, 2), force(3), stiffness(3, 3), length, gas
      real(dp), parameter :: at_rest(3) = 0.0_dp
      integer :: kind
      q = clamped
      kind = element_kind_of(model, e)
      if (kind == element_truss) return
      joints = end_joints_of(model, e)
      if (.not. has_joints(joints)) return
      length = norm2(model%coordinates(:, model%connectivity(2, e)) - model%coordinates(:, model%connectivity(1, e)))
      associate (section => model%sections(model%element_section(e)))
         gas = 0.0_dp
         if (kind == element_timoshenko) gas = section%gas
         flexibility = beam_bending_flexibility(length, section%ei, gas)
         call jointed_basic_response(0.0_dp, beam_bending_flexibility(length, section%ei, 0.0_dp), joints, at_rest, &
                                     force, stiffness, shear=beam_shear_flexibility(length, gas))
      end associate
      q(2:3) = matmul(stiffness(2:3, 2:3), matmul(flexibility, clamped(2:3)))
   end function released_basic_force

   !> The change (df, 6, global; dk, 6×6) of the consistent nodal loads `f` (6, global, per unit λ:
   !> the clamped member's, as uniarc_frame_linear and uniarc_corotational give them) of a load on the
   !> span of element `e` when its ends carry joints. `clamped_moments` (2) are the load's nodal end
   !> moments (f(3), f(6)) on the initial geometry: the clamped basic moments are their negatives, and
   !> the released ones change them by Δq = (0, M − Mf); the nodal loads change by df = −B(u)ᵀ Δq, the
   !> end shears by statics. B is that of `transformation` at the element's total displacements `u`
   !> (6): the linear one (B0, no stiffness) for loads on the initial geometry, the corotational one for
   !> a follower pressure, whose load stiffness changes by dk = −∂df/∂u = Ks(Δq), the initial-stress
   !> matrix of the transformation. Zero for a truss or a beam without joints.
   pure subroutine released_span_correction(model, e, clamped_moments, u, transformation, df, dk)
      type(model_t), intent(in) :: model
      integer, intent(in) :: e
      real(dp), intent(in) :: clamped_moments(2)
      real(dp), intent(in) :: u(6)
      integer, intent(in) :: transformation
      real(dp), intent(out) :: df(6), dk(6, 6)
      real(dp), parameter :: no_stiffness(3, 3) = 0.0_dp
      type(chord_t) :: chord
      real(dp) :: clamped(3), change(3), deformation(3), x(2, 2)
      df = 0.0_dp
      dk = 0.0_dp
      clamped = [0.0_dp, -clamped_moments(1), -clamped_moments(2)]
      change = released_basic_force(model, e, clamped) - clamped
      if (all(change == 0.0_dp)) return
      x(:, 1) = model%coordinates(:, model%connectivity(1, e))
      x(:, 2) = model%coordinates(:, model%connectivity(2, e))
      call transform_deformations(transformation, x, u, chord, deformation)
      call transform_to_global(transformation, chord, change, no_stiffness, df, dk)
      df = -df
   end subroutine released_span_correction

end module uniarc_released_loads
