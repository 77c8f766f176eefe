!> The integrator of the path following: how the step is constrained and how the load factor moves
!> (OpenSees' StaticIntegrator: LoadControl, DisplacementControl, ArcLength), for the three controls of
!> *PATH (load, displacement, arc length) and the three arc-length iteration strategies (Crisfield
!> 1991 ch. 9): Chan's (1988) minimum residual displacement (the paper's choice), Crisfield's (1981)
!> cylindrical arc length, Riks/Ramm's (1981) updated normal plane.
!>
!> Dot products and norms are over the displacement unknowns only (the metric of the equation
!> numbering masks the reactions out). The committed state is read, never written.
module uniarc_path_integrator
   use uniarc_kinds, only: dp
   use uniarc_model, only: analysis_options_t, control_load, control_displacement, control_arclength, &
                           iteration_chan, iteration_cylindrical, iteration_riks
   use uniarc_dof_map, only: dof_map_t
   use uniarc_contact_lcp, only: path_constraint_t, constraint_arclength, constraint_load, constraint_displacement, &
                                 degenerate_fraction
   use uniarc_path_state, only: path_state_t, masked_dot, masked_norm
   implicit none
   private
   public :: predictor_dlambda, step_constraint, correction_constraint, iteration_dlambda, degenerate_tangent


contains

   !> Whether the tangent ut = K⁻¹R (n) of a working set has no displacement: the contacts of the set
   !> carry the whole reference load (a rigid obstacle under the loaded node, a heated bar against a
   !> rigid stop). The arc length ||Δu|| cannot measure such a step; it is taken in λ (a load step).
   pure logical function degenerate_tangent(state, ut)
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: ut(:)
      degenerate_tangent = .not. (masked_norm(state%map, ut) > degenerate_fraction*state%lambda_scale)
   end function degenerate_tangent

   !> Load increment of the predictor along the tangent ut (n) for a step of the given length.
   !> For arc length the sign follows the direction of travel: positive angle with the last increment
   !> (the committed `direction` was chosen so for the committed tangent; a predictor tangent computed
   !> with another contact set may point the other way, so the angle is taken again).
   pure real(dp) function predictor_dlambda(options, state, ut, length) result(dlambda)
      type(analysis_options_t), intent(in) :: options
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: ut(:), length
      real(dp) :: cosine
      select case (options%control)
      case (control_arclength)
         if (degenerate_tangent(state, ut)) then
            ! The reference load moves nothing: a load step, Δλ = Δl/ψ (docs/theory.md §2.7).
            dlambda = state%direction*length/state%lambda_scale
            return
         end if
         dlambda = state%direction*length/masked_norm(state%map, ut)
         cosine = masked_dot(state%map, state%last_increment, ut)
         if (cosine*dlambda < 0.0_dp) dlambda = -dlambda
      case (control_displacement)
         ! A controlled displacement that the reference load does not move (the contacts carry the
         ! load) gives no Δλ: the iteration says why (iteration_dlambda).
         dlambda = 0.0_dp
         if (abs(ut(state%control_equation)) > 0.0_dp) dlambda = state%direction*length/ut(state%control_equation)
      case default
         dlambda = state%direction*length
      end select
   end function predictor_dlambda

   !> The constraint of the predictor LCP: the linearised step (normal plane to the tangent at distance
   !> Δl for arc length, the load or displacement increment otherwise).
   !> A load step (`load_step`, docs/theory.md §2.7) is constrained by its Δλ under any control.
   pure subroutine step_constraint(options, state, ut, dlambda, constraint, load_step)
      type(analysis_options_t), intent(in) :: options
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: ut(:), dlambda
      type(path_constraint_t), intent(out) :: constraint
      logical, intent(in), optional :: load_step
      select case (control_of(options, load_step))
      case (control_arclength)
         constraint%kind = constraint_arclength
         constraint%lambda_scale = state%lambda_scale
         constraint%t = state%map%metric*ut*dlambda
         constraint%target = masked_dot(state%map, constraint%t, ut*dlambda)
      case (control_displacement)
         constraint%kind = constraint_displacement
         constraint%equation = state%control_equation
         constraint%target = dlambda*ut(state%control_equation)
      case default
         constraint%kind = constraint_load
         constraint%target = dlambda
      end select
   end subroutine step_constraint

   !> The constraint of a corrector LCP inside a step: stay on the step (normal plane to the current
   !> increment, or the same load or controlled displacement).
   pure subroutine correction_constraint(options, state, increment, constraint, load_step)
      type(analysis_options_t), intent(in) :: options
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: increment(:)
      type(path_constraint_t), intent(out) :: constraint
      logical, intent(in), optional :: load_step
      select case (control_of(options, load_step))
      case (control_arclength)
         constraint%kind = constraint_arclength
         constraint%lambda_scale = state%lambda_scale
         constraint%t = state%map%metric*increment
      case (control_displacement)
         constraint%kind = constraint_displacement
         constraint%equation = state%control_equation
      case default
         constraint%kind = constraint_load
      end select
      constraint%target = 0.0_dp
   end subroutine correction_constraint

   !> Load correction δλ of a Newton iteration by the control: none under load control; the one that
   !> keeps the controlled displacement under displacement control; the iteration strategy's under arc
   !> length. du_residual = K⁻¹g and du_tangent = K⁻¹R (n) are this iteration's solutions, increment
   !> (n) the step so far, length the step's Δl. `reason` is empty on success, else why δλ has none.
   !> A load step (`load_step`) has δλ = 0 under any control.
   pure subroutine iteration_dlambda(options, state, increment, du_residual, du_tangent, length, dl, reason, &
                                     load_step)
      type(analysis_options_t), intent(in) :: options
      type(path_state_t), intent(in) :: state
      real(dp), intent(in) :: increment(:), du_residual(:), du_tangent(:), length
      real(dp), intent(out) :: dl
      character(len=:), allocatable, intent(out) :: reason
      logical, intent(in), optional :: load_step
      reason = ''
      select case (control_of(options, load_step))
      case (control_load)
         dl = 0.0_dp
      case (control_displacement)
         if (.not. (abs(du_tangent(state%control_equation)) > 0.0_dp)) then
            dl = 0.0_dp
            reason = 'the reference load does not move the controlled displacement with this contact set '// &
                     '(its contacts and the supports carry it): trace it with CONTROL=ARCLENGTH or CONTROL=LOAD'
            return
         end if
         dl = -du_residual(state%control_equation)/du_tangent(state%control_equation)
      case default
         call load_correction(options, state%map, increment, du_residual, du_tangent, length, dl, reason)
      end select
   end subroutine iteration_dlambda

   !> The control a step is constrained by: the deck's, or load control for a load step.
   pure integer function control_of(options, load_step) result(control)
      type(analysis_options_t), intent(in) :: options
      logical, intent(in), optional :: load_step
      control = options%control
      if (present(load_step)) then
         if (load_step) control = control_load
      end if
   end function control_of

   !> Load correction δλ of an arc-length iteration; `reason` is empty on success.
   pure subroutine load_correction(options, map, increment, du_residual, du_tangent, length, dl, reason)
      type(analysis_options_t), intent(in) :: options
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: increment(:), du_residual(:), du_tangent(:), length
      real(dp), intent(out) :: dl
      character(len=:), allocatable, intent(out) :: reason
      real(dp) :: a, b, c, discriminant, root(2), cosine(2)
      integer :: k
      reason = ''
      dl = 0.0_dp
      ! With the contacts of the working set carrying the whole reference load, K⁻¹R has no
      ! displacement part and no arc-length strategy can fix δλ (a rigid obstacle under the load).
      if (.not. (masked_dot(map, du_tangent, du_tangent) > 0.0_dp)) then
         reason = 'the reference load moves no displacement with this contact set (its contacts and the '// &
                  'supports carry it)'
         return
      end if
      select case (options%iteration)
      case (iteration_chan)
         ! Minimum residual displacement (Chan 1988): δλ minimises ||δu_g + δλ δu_t||.
         dl = -masked_dot(map, du_tangent, du_residual)/masked_dot(map, du_tangent, du_tangent)
      case (iteration_riks)
         ! Updated normal plane (Ramm 1981): the correction is orthogonal to the current increment.
         if (.not. (abs(masked_dot(map, increment, du_tangent)) > 0.0_dp)) then
            reason = 'the tangent is orthogonal to the increment (updated normal plane)'
            return
         end if
         dl = -masked_dot(map, increment, du_residual)/masked_dot(map, increment, du_tangent)
      case (iteration_cylindrical)
         ! ||Δu + δu_g + δλ δu_t|| = Δl (Crisfield 1981): the root closer in angle to the increment.
         a = masked_dot(map, du_tangent, du_tangent)
         b = 2.0_dp*masked_dot(map, du_tangent, increment + du_residual)
         c = masked_dot(map, increment + du_residual, increment + du_residual) - length**2
         discriminant = b**2 - 4.0_dp*a*c
         if (discriminant < 0.0_dp) then
            reason = 'the arc-length constraint has no real root'
            dl = 0.0_dp
            return
         end if
         root(1) = (-b + sqrt(discriminant))/(2.0_dp*a)
         root(2) = (-b - sqrt(discriminant))/(2.0_dp*a)
         do k = 1, 2
            cosine(k) = masked_dot(map, increment, increment + du_residual + root(k)*du_tangent)
         end do
         dl = root(maxloc(cosine, 1))
      case default
         dl = 0.0_dp
         reason = 'unknown iteration strategy'
      end select
   end subroutine load_correction

end module uniarc_path_integrator
