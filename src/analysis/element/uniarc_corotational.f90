!> Nonlinear 2-D corotational Euler–Bernoulli beam-column and its displacement-dependent loads.
!>
!> The element follows Crisfield (1991, vol. 1, ch. 7): a frame that moves with the chord between the
!> two current end nodes carries the rigid-body motion exactly, and in that frame the element is the
!> small-strain Euler–Bernoulli basic element. `corotational_response` is that composition — the
!> corotational transformation (uniarc_transformation) around the basic beam (uniarc_basic_beam) — for
!> one element given by its coordinates and section, as the element layer (uniarc_element) computes it
!> for a model's beam-column. The equations are derived in docs/theory.md, section "Beam-column element".
!>
!> DOF order of an element vector: (u_x1, u_y1, θ1, u_x2, u_y2, θ2) in global axes, total (not
!> incremental) displacements from the stress-free straight configuration x0. Rotations are
!> counter-clockwise positive and may reach any size (several turns): only the rotation of each end
!> relative to the current chord must stay below π in magnitude, which a well-meshed model guarantees.
!>
!> All kernels are pure and allocation-free: the assembly calls them once per element per iteration.
module uniarc_corotational
   use uniarc_kinds, only: dp
   use uniarc_frame_linear, only: pressure_load_vector
   use uniarc_transformation, only: chord_t, transformation_corotational, transform_deformations, &
                                    transform_to_global, corotational_kinematics, outer
   use uniarc_basic_beam, only: beam_basic_response
   implicit none
   private
   public :: corotational_response, follower_pressure

contains

   !> Internal force, tangent stiffness and basic forces of the corotational beam-column.
   !>
   !> In:  x0(:, i) initial coordinates of end i; u total global displacements; ea, ei stiffnesses.
   !> Out: f_int = Bᵀ q, the global internal force (6), zero to round-off under any rigid-body motion;
   !>      k_t = ∂f_int/∂u (6×6, symmetric) = KL + Ks where
   !>        KL = Bᵀ Kb B on the current chord — the paper's small-displacement matrix (its Eq. 11); the
   !>             paper's large-displacement matrix KNL (Eq. 13) is carried by evaluating B on the
   !>             current chord rather than the initial one;
   !>        Ks = N z zᵀ/Ln + (M1 + M2)/Ln² (r zᵀ + z rᵀ) — the initial-stress (geometric) matrix of the
   !>             paper's Eq. (12), from the change of B with the chord direction and length;
   !>      basic_force = q = (N, M1, M2) = Kb (e, θ̄1, θ̄2), N positive in tension, end moments
   !>        counter-clockwise positive.
   !> r = (−c, −s, 0, c, s, 0) = ∂Ln/∂u and z = (s, −c, 0, −s, c, 0) = Ln ∂β/∂u, β the chord angle; see
   !> docs/theory.md for the derivation (Crisfield 1991, vol. 1, ch. 7).
   pure subroutine corotational_response(x0, u, ea, ei, f_int, k_t, basic_force)
      real(dp), intent(in) :: x0(2, 2)
      real(dp), intent(in) :: u(6)
      real(dp), intent(in) :: ea, ei
      real(dp), intent(out) :: f_int(6)
      real(dp), intent(out) :: k_t(6, 6)
      real(dp), intent(out) :: basic_force(3)
      type(chord_t) :: chord
      real(dp) :: deformation(3), kb(3, 3)

      call transform_deformations(transformation_corotational, x0, u, chord, deformation)
      ! The constitutive law lives in the corotated frame, referred to the initial length (small
      ! strains): the same Kb as the linear element.
      call beam_basic_response(chord%initial_length, ea, ei, deformation, basic_force, kb)
      call transform_to_global(transformation_corotational, chord, basic_force, kb, f_int, k_t)
   end subroutine corotational_response

   !> Consistent nodal loads of a uniform pressure on the current (deformed) element and their load
   !> stiffness.
   !>
   !> In:  x0 initial end coordinates; u total global displacements; pressure p per unit current length,
   !>      acting along the current left normal (the chord direction node 1 → node 2 turned by +90°).
   !> Out: f = the work-conjugate nodal loads of p on the element's corotational cubic shape:
   !>        f = pressure_load_vector(x current, p) + p Ln (θ̄1 − θ̄2)/6 · r,
   !>      the first term from the chord, the second from the area between chord and cubic,
   !>      Ln²(θ̄1 − θ̄2)/12 (zero at u = 0, so f(0) equals uniarc_frame_linear's pressure_load_vector);
   !>      k_load = −∂f/∂u, so that the assembled tangent is K_T = K_int + k_load (with f and k_load both
   !>      scaled by the load factor). k_load is not symmetric: the chord part has the antisymmetric end
   !>      terms of a follower pressure (Schweizerhof & Ramm 1984, Comput. Struct. 18:1099), which cancel
   !>      on a closed ring or at supported ends, where the total is the symmetric Hessian of −p × area.
   pure subroutine follower_pressure(x0, u, pressure, f, k_load)
      real(dp), intent(in) :: x0(2, 2)
      real(dp), intent(in) :: u(6)
      real(dp), intent(in) :: pressure
      real(dp), intent(out) :: f(6)
      real(dp), intent(out) :: k_load(6, 6)
      real(dp), parameter :: e_x(6) = [-1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp]  ! ∂dx/∂u
      real(dp), parameter :: e_y(6) = [0.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp]  ! ∂dy/∂u
      real(dp), parameter :: e_t(6) = [0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, -1.0_dp] ! ∂(θ̄1−θ̄2)/∂u
      real(dp), parameter :: s_x(6) = [1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp]
      real(dp), parameter :: s_y(6) = [0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp]
      real(dp) :: d(2), initial_length, length, c, s, elongation, theta_bar(2), x(2, 2), v(6)
      real(dp) :: relative_turn

      call corotational_kinematics(x0, u, d, initial_length, length, c, s, elongation, theta_bar)
      x(:, 1) = x0(:, 1) + u(1:2)
      x(:, 2) = x0(:, 2) + u(4:5)
      relative_turn = theta_bar(1) - theta_bar(2)
      v = [-d(1), -d(2), 0.0_dp, d(1), d(2), 0.0_dp]    ! Ln r = ∂(Ln²/2)/∂u

      f = pressure_load_vector(x, pressure) + (pressure*relative_turn/6.0_dp)*v

      ! −∂f/∂u term by term: chord forces p/2 (−dy, dx) at both ends; end moments ±p Ln²/12; the
      ! area correction p (θ̄1 − θ̄2) Ln r/6 (the chord rotation cancels in θ̄1 − θ̄2).
      k_load = -(0.5_dp*pressure)*(outer(s_y, e_x) - outer(s_x, e_y)) &
               - (pressure/6.0_dp)*(outer(e_t, v) + outer(v, e_t)) &
               - (pressure*relative_turn/6.0_dp)*(outer(e_x, e_x) + outer(e_y, e_y))
   end subroutine follower_pressure

end module uniarc_corotational
