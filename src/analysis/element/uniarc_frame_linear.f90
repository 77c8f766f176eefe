!> Linear 2-D Euler–Bernoulli frame element (3 DOF per node: u_x, u_y, θ_z) and consistent loads.
!>
!> DOF order of an element vector: (u_x1, u_y1, θ1, u_x2, u_y2, θ2) in global axes.
!> `linear_frame_stiffness` is the linear transformation (uniarc_transformation) around the basic beam
!> (uniarc_basic_beam, N = EA/L e, [M1; M2] = EI/L [4 2; 2 4] [θ̄1; θ̄2], Crisfield 1991, §7.2) for one
!> element given by its coordinates, as the element layer (uniarc_element) computes it for a model's
!> beam-column. The consistent loads of distributed loads on the element (Hermite shape functions) are
!> the loads of every analysis, on the initial geometry or, for follower pressure, the current one.
module uniarc_frame_linear
   use uniarc_kinds, only: dp
   use uniarc_transformation, only: chord_t, transformation_linear, transform_deformations, transform_to_global
   use uniarc_basic_beam, only: beam_basic_response
   implicit none
   private
   public :: linear_frame_stiffness
   public :: fixed_direction_load_vector, pressure_load_vector

contains

   !> Global linear stiffness (6×6) of the element with end coordinates x(:, 1), x(:, 2): Bᵀ Kb B.
   pure function linear_frame_stiffness(x, ea, ei) result(k)
      real(dp), intent(in) :: x(2, 2), ea, ei
      real(dp) :: k(6, 6)
      real(dp), parameter :: at_rest(6) = 0.0_dp
      type(chord_t) :: chord
      real(dp) :: deformation(3), q(3), kb(3, 3), f(6)
      call transform_deformations(transformation_linear, x, at_rest, chord, deformation)
      call beam_basic_response(chord%initial_length, ea, ei, deformation, q, kb)
      call transform_to_global(transformation_linear, chord, q, kb, f, k)
   end function linear_frame_stiffness

   !> Consistent nodal loads (6) of a uniform load (qx, qy) per unit length in fixed global directions on
   !> a straight element of length L: forces q L/2 at each end and end moments ±q⊥ L²/12, q⊥ being the
   !> component normal to the element (Hermite shape functions).
   pure function fixed_direction_load_vector(x, qx, qy) result(f)
      real(dp), intent(in) :: x(2, 2), qx, qy
      real(dp) :: f(6)
      real(dp) :: d(2), length, c, s, q_normal
      d = x(:, 2) - x(:, 1)
      length = norm2(d)
      c = d(1)/length
      s = d(2)/length
      q_normal = -s*qx + c*qy        ! component along the left normal (-s, c)
      f = [qx*length/2, qy*length/2, q_normal*length**2/12, &
           qx*length/2, qy*length/2, -q_normal*length**2/12]
   end function fixed_direction_load_vector

   !> Consistent nodal loads (6) of a uniform pressure p per unit length along the element's left normal
   !> (the tangent node 1 → node 2 turned by +90°), on the geometry x (initial or current).
   !> A chord of zero length (two ends that round-off of huge displacements, or a collapse, makes equal)
   !> carries the resultant p L = 0: the loads are then zero, not the 0/0 of its undefined normal.
   pure function pressure_load_vector(x, pressure) result(f)
      real(dp), intent(in) :: x(2, 2), pressure
      real(dp) :: f(6)
      real(dp) :: d(2), length
      d = x(:, 2) - x(:, 1)
      length = norm2(d)
      if (length == 0.0_dp) then
         f = 0.0_dp
         return
      end if
      f = fixed_direction_load_vector(x, -pressure*d(2)/length, pressure*d(1)/length)
   end function pressure_load_vector

end module uniarc_frame_linear
