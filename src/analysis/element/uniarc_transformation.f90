!> Coordinate transformations of the two-node plane element: global displacements ↔ basic system.
!>
!> As OpenSees' CrdTransf, a transformation knows the element's geometry and kinematics, not its
!> material: it turns the six global end displacements u = (u_x1, u_y1, θ1, u_x2, u_y2, θ2) into the
!> basic deformations v = (e, θ̄1, θ̄2), and the basic forces q = (N, M1, M2) with their basic stiffness
!> Kb (from a basic element: uniarc_basic_beam, uniarc_basic_truss) into the global internal force and
!> tangent. Two transformations (docs/theory.md §1.2–1.4 and §1.8):
!>
!> - `transformation_linear`: small displacements on the initial chord, v = B0 u, f = B0ᵀ q,
!>   K = B0ᵀ Kb B0 (the linear static analysis);
!> - `transformation_corotational`: the frame of the current chord carries the rigid-body motion
!>   exactly (Crisfield 1991, vol. 1, ch. 7), v = (Ln − L0, θ1 − α, θ2 − α), f = Bᵀ q, and
!>   K = Bᵀ Kb B + N z zᵀ/Ln + (M1 + M2)/Ln² (r zᵀ + z rᵀ), B on the current chord.
!>
!> All routines are pure and allocation-free (called once per element per iteration).
module uniarc_transformation
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: chord_t, transformation_linear, transformation_corotational
   public :: transform_deformations, transform_to_global, transform_end_forces
   public :: compatibility_matrix, corotational_kinematics, outer

   !> The coordinate transformations.
   integer, parameter :: transformation_linear = 1       !< small displacements, initial chord
   integer, parameter :: transformation_corotational = 2 !< exact rigid-body motion, current chord

   !> The chord a transformation works on: initial length L0 (where the basic law is referred) and the
   !> length and direction of the chord that B is taken on (initial for linear, current for corotational).
   type :: chord_t
      real(dp) :: initial_length = 0.0_dp  !< L0
      real(dp) :: length = 0.0_dp          !< L0 (linear) or Ln (corotational)
      real(dp) :: c = 1.0_dp               !< cosine of that chord's angle from +x
      real(dp) :: s = 0.0_dp               !< sine of that chord's angle from +x
   end type chord_t

contains

   !> Basic deformations `deformation` = v = (e, θ̄1, θ̄2) (length, radians, radians) and the chord of
   !> the element with initial end coordinates x0(:, i) and total global displacements u (6), under
   !> `transformation` (transformation_linear or transformation_corotational; any other value is linear).
   pure subroutine transform_deformations(transformation, x0, u, chord, deformation)
      integer, intent(in) :: transformation
      real(dp), intent(in) :: x0(2, 2)
      real(dp), intent(in) :: u(6)
      type(chord_t), intent(out) :: chord
      real(dp), intent(out) :: deformation(3)
      real(dp) :: d(2), elongation, theta_bar(2)
      select case (transformation)
      case (transformation_corotational)
         call corotational_kinematics(x0, u, d, chord%initial_length, chord%length, chord%c, chord%s, &
                                      elongation, theta_bar)
         deformation = [elongation, theta_bar]
      case default
         ! Small displacements: v = B0 u on the initial chord (Crisfield 1991, vol. 1, §7.2).
         d = x0(:, 2) - x0(:, 1)
         chord%initial_length = norm2(d)
         chord%length = chord%initial_length
         chord%c = d(1)/chord%length
         chord%s = d(2)/chord%length
         deformation = matmul(compatibility_matrix(chord%c, chord%s, chord%length), u)
      end select
   end subroutine transform_deformations

   !> Global internal force f = Bᵀ q (6) and tangent k (6×6) from the basic forces `basic_force` = q
   !> (N, M1, M2) and the basic stiffness `basic_stiffness` = Kb (3×3) on `chord`. The corotational
   !> transformation adds the initial-stress matrix of the turning chord, Ks = N z zᵀ/Ln +
   !> (M1 + M2)/Ln² (r zᵀ + z rᵀ) with r = ∂Ln/∂u and z = Ln ∂β/∂u (docs/theory.md §1.4; the paper's
   !> Eq. 12); k is symmetric when Kb is.
   pure subroutine transform_to_global(transformation, chord, basic_force, basic_stiffness, f, k)
      integer, intent(in) :: transformation
      type(chord_t), intent(in) :: chord
      real(dp), intent(in) :: basic_force(3)
      real(dp), intent(in) :: basic_stiffness(3, 3)
      real(dp), intent(out) :: f(6)
      real(dp), intent(out) :: k(6, 6)
      real(dp) :: b(3, 6), r(6), z(6)
      b = compatibility_matrix(chord%c, chord%s, chord%length)
      f = matmul(transpose(b), basic_force)
      k = matmul(transpose(b), matmul(basic_stiffness, b))
      if (transformation /= transformation_corotational) return
      r = b(1, :)
      z = [chord%s, -chord%c, 0.0_dp, -chord%s, chord%c, 0.0_dp]
      k = k + (basic_force(1)/chord%length)*outer(z, z) &
          + ((basic_force(2) + basic_force(3))/chord%length**2)*(outer(r, z) + outer(z, r))
   end subroutine transform_to_global

   !> End forces for output from the basic forces q = (N, M1, M2) on `chord`: (N, V, M_start, M_end).
   !> N is the axial force (tension positive); M_start = −M1 and M_end = M2 are the bending moments at
   !> node 1 and node 2 in the beam convention M = EI κ (positive when the element bends towards its left
   !> normal: a uniform κ has θ̄1 = −κL/2, θ̄2 = κL/2, so M1 = −EIκ, M2 = EIκ); V = (M1 + M2)/L = dM/ds
   !> is the shear force of an element without load on its span, from the moment equilibrium of the
   !> element on the chord of the transformation (L = L0 linear, Ln corotational). Force units as q.
   pure function transform_end_forces(chord, basic_force) result(end_forces)
      type(chord_t), intent(in) :: chord
      real(dp), intent(in) :: basic_force(3)
      real(dp) :: end_forces(4)
      end_forces = [basic_force(1), (basic_force(2) + basic_force(3))/chord%length, -basic_force(2), &
                    basic_force(3)]
   end function transform_end_forces

   !> Compatibility matrix B (3×6): (de, dθ̄1, dθ̄2) = B du for a chord of direction (c, s) and length L.
   !> Row 1 is r = ∂L/∂u; rows 2–3 are the unit end rotations minus the chord rotation z/L.
   pure function compatibility_matrix(c, s, length) result(b)
      real(dp), intent(in) :: c, s, length
      real(dp) :: b(3, 6)
      b(1, :) = [-c, -s, 0.0_dp, c, s, 0.0_dp]
      b(2, :) = [-s/length, c/length, 1.0_dp, s/length, -c/length, 0.0_dp]
      b(3, :) = [-s/length, c/length, 0.0_dp, s/length, -c/length, 1.0_dp]
   end function compatibility_matrix

   !> Current chord and local deformations of the corotational element (Crisfield 1991, vol. 1, ch. 7).
   !>
   !> d, length, (c, s): current chord vector, length and direction; elongation e = Ln − L0, evaluated as
   !> (Ln² − L0²)/(Ln + L0) with Ln² − L0² = Δ·(2 d0 + Δ), Δ the relative end translation, so that small
   !> strains are not lost to cancellation between two nearly equal lengths. theta_bar(i) is the
   !> rotation of end i relative to the chord, θi − (β − β0), reduced to (−π, π] through atan2 of its
   !> sine and cosine: a rigid rotation of any size, including whole turns, gives zero to round-off.
   pure subroutine corotational_kinematics(x0, u, d, initial_length, length, c, s, elongation, theta_bar)
      real(dp), intent(in) :: x0(2, 2), u(6)
      real(dp), intent(out) :: d(2), initial_length, length, c, s, elongation, theta_bar(2)
      real(dp) :: d0(2), delta(2), c0, s0, cos_chord_turn, sin_chord_turn, theta
      integer :: i

      d0 = x0(:, 2) - x0(:, 1)
      initial_length = norm2(d0)
      delta = u(4:5) - u(1:2)
      d = d0 + delta
      length = norm2(d)
      c0 = d0(1)/initial_length
      s0 = d0(2)/initial_length
      if (length > epsilon(1.0_dp)*initial_length) then
         c = d(1)/length
         s = d(2)/length
      else
         ! A chord crushed to (nearly) a point has no direction: only a diverged Newton iterate gets
         ! here (its axial force is then about −EA, and the step is cut). Keep the initial direction
         ! and a length of one ulp of L0, so that the iterate stays finite and is rejected by the
         ! convergence test instead of dividing by zero.
         length = epsilon(1.0_dp)*initial_length
         c = c0
         s = s0
      end if
      elongation = dot_product(delta, 2.0_dp*d0 + delta)/(length + initial_length)

      ! Chord rotation β − β0 through its cosine and sine, never as an angle: no branch cut.
      cos_chord_turn = c0*c + s0*s
      sin_chord_turn = c0*s - s0*c
      do i = 1, 2
         theta = u(3*i)
         theta_bar(i) = atan2(sin(theta)*cos_chord_turn - cos(theta)*sin_chord_turn, &
                              cos(theta)*cos_chord_turn + sin(theta)*sin_chord_turn)
      end do
   end subroutine corotational_kinematics

   !> Outer product a bᵀ of two 6-vectors.
   pure function outer(a, b) result(m)
      real(dp), intent(in) :: a(6), b(6)
      real(dp) :: m(6, 6)
      integer :: j
      do j = 1, 6
         m(:, j) = a*b(j)
      end do
   end function outer

end module uniarc_transformation
