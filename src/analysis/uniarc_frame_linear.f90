!> Linear 2-D Euler–Bernoulli frame element (3 DOF per node: u_x, u_y, θ_z) and consistent loads.
!>
!> DOF order of an element vector: (u_x1, u_y1, θ1, u_x2, u_y2, θ2) in global axes.
!> The element's basic (natural) stiffness relates the chord elongation e and the two end rotations
!> relative to the chord (θ̄1, θ̄2) to the axial force N and end moments (M1, M2):
!>   N = EA/L e,  [M1; M2] = EI/L [4 2; 2 4] [θ̄1; θ̄2]     (e.g. Crisfield 1991, §7.2)
!> The corotational element of the nonlinear analysis reuses this basic stiffness.
module uniarc_frame_linear
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: basic_stiffness, basic_to_global, linear_frame_stiffness
   public :: fixed_direction_load_vector, pressure_load_vector

contains

   !> Basic stiffness (3×3) relating (e, θ̄1, θ̄2) to (N, M1, M2) of a straight element of length `length`.
   pure function basic_stiffness(length, ea, ei) result(kb)
      real(dp), intent(in) :: length, ea, ei
      real(dp) :: kb(3, 3)
      kb = 0.0_dp
      kb(1, 1) = ea/length
      kb(2, 2) = 4.0_dp*ei/length
      kb(3, 3) = 4.0_dp*ei/length
      kb(2, 3) = 2.0_dp*ei/length
      kb(3, 2) = 2.0_dp*ei/length
   end function basic_stiffness

   !> Compatibility matrix B (3×6): (de, dθ̄1, dθ̄2) = B du for a chord of direction (c, s) and length L.
   pure function basic_to_global(c, s, length) result(b)
      real(dp), intent(in) :: c, s, length
      real(dp) :: b(3, 6)
      b(1, :) = [-c, -s, 0.0_dp, c, s, 0.0_dp]
      b(2, :) = [-s/length, c/length, 1.0_dp, s/length, -c/length, 0.0_dp]
      b(3, :) = [-s/length, c/length, 0.0_dp, s/length, -c/length, 1.0_dp]
   end function basic_to_global

   !> Global linear stiffness (6×6) of the element with end coordinates x(:, 1), x(:, 2): Bᵀ Kb B.
   pure function linear_frame_stiffness(x, ea, ei) result(k)
      real(dp), intent(in) :: x(2, 2), ea, ei
      real(dp) :: k(6, 6)
      real(dp) :: d(2), length, b(3, 6)
      d = x(:, 2) - x(:, 1)
      length = norm2(d)
      b = basic_to_global(d(1)/length, d(2)/length, length)
      k = matmul(transpose(b), matmul(basic_stiffness(length, ea, ei), b))
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
   pure function pressure_load_vector(x, pressure) result(f)
      real(dp), intent(in) :: x(2, 2), pressure
      real(dp) :: f(6)
      real(dp) :: d(2), length
      d = x(:, 2) - x(:, 1)
      length = norm2(d)
      f = fixed_direction_load_vector(x, -pressure*d(2)/length, pressure*d(1)/length)
   end function pressure_load_vector

end module uniarc_frame_linear
