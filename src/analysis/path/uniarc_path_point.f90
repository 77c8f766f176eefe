!> The point record of a converged state (`path_point_t`): what the critical-point detector
!> (uniarc_critical_points) and the result files read there — the unit tangent of the path, the
!> complementarity residual, and per candidate whether it is in contact, its reaction or gap and the
!> rate of that value along the path.
module uniarc_path_point
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_copy, only: reserve
   use uniarc_model, only: model_t, control_displacement
   use uniarc_strings, only: integer_to_string
   use uniarc_dof_map, only: candidate_live, bed_deflection
   use uniarc_contact, only: candidate_gap
   use uniarc_path_state, only: path_state_t, masked_norm, nodal_displacements
   use uniarc_path_contact_set, only: candidate_state, violation
   use uniarc_path_integrator, only: degenerate_tangent
   implicit none
   private
   public :: describe_point

contains

   !> Fill the point record of the committed state (step number, Newton iterations and Lemke pivots of
   !> the step that reached it), and the committed reactions. The inertia and the least eigenvalue are
   !> the commit's (uniarc_path_stability). Errors: an array of the record refused by the system
   !> (error_analysis, out of memory; docs/contracts.md, "Memory").
   subroutine describe_point(model, state, step, iterations, lcp_pivots, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      integer, intent(in) :: step, iterations, lcp_pivots
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), reaction(:), gap(:)
      real(dp) :: norm, g, gradient(2), hessian(2, 2), rate, bytes, sense
      integer :: m, c, row, node, status
      ! The record's arrays allocated with stat= (the assignments below then allocate nothing).
      m = size(state%map%candidate_equation)
      bytes = 0.0_dp
      call reserve(state%point%rate, size(state%tangent_displacement), status, bytes)
      if (status == 0) call reserve(state%point%in_contact, m, status, bytes)
      if (status == 0) call reserve(state%point%contact_value, m, status, bytes)
      if (status == 0) call reserve(state%point%contact_rate, m, status, bytes)
      if (status == 0 .and. m > 0) call reserve(state%reactions, m, status, bytes)
      if (status == 0 .and. m > 0) call reserve(reaction, m, status, bytes)
      if (status == 0 .and. m > 0) call reserve(gap, m, status, bytes)
      call allocation_failure(status, 'an array of the point of step '//integer_to_string(step), bytes, &
                              error_analysis, error)
      if (allocated(error)) return
      state%point%step = step
      state%point%lambda = state%lambda
      state%point%iterations = iterations
      state%point%lcp_pivots = lcp_pivots
      ! Unit tangent of the path in (u, λ) with the arc-length metric ds² = ||du||² (cylindrical):
      ! du/ds = ±K⁻¹R/||K⁻¹R||, dλ/ds = ±1/||K⁻¹R||, signed by the direction of travel.
      norm = masked_norm(state%map, state%tangent_displacement)
      ! The sense of travel along ±(K⁻¹R, 1). Under displacement control `direction` is the sign of
      ! the controlled displacement's increment, Δλ = direction·Δw/(K⁻¹R)_w: the path goes along
      ! +(K⁻¹R, 1) where that component of K⁻¹R has direction's sign, along −(K⁻¹R, 1) where not (a
      ! load pointing down pushed down, Δw < 0: λ grows, dλ/ds > 0; docs/theory.md §2.1).
      sense = real(state%direction, dp)
      if (model%analysis%control == control_displacement .and. state%control_equation > 0) then
         if (state%tangent_displacement(state%control_equation) < 0.0_dp) sense = -sense
      end if
      if (degenerate_tangent(state, state%tangent_displacement)) then
         ! The contacts carry the whole reference load: the path goes in λ alone, measured by ψ
         ! (docs/theory.md §2.7): du/ds = 0, dλ/ds = ±1/ψ (±1 if ψ is 0: λ itself is the parameter),
         ! and the reactions grow at K⁻¹R's rate per unit s.
         norm = state%lambda_scale
         if (.not. (norm > 0.0_dp)) norm = 1.0_dp
         state%point%rate = 0.0_dp*state%tangent_displacement
      else
         state%point%rate = (sense/norm)*state%map%metric*state%tangent_displacement
      end if
      state%point%dlambda_ds = sense/norm
      state%point%lcp_residual = 0.0_dp
      state%point%in_contact = .false.
      state%point%contact_value = 0.0_dp
      state%point%contact_rate = 0.0_dp
      if (m > 0) then
         call nodal_displacements(model, state, nodal, error)
         if (allocated(error)) return
         call candidate_state(model, state%map, state%u, nodal, state%active, reaction, gap, state%slip, &
                              state%yielding, state%lambda)
         state%reactions = reaction
         state%point%lcp_residual = violation(model, state, state%u, reaction, gap, state%active, state%yielding)
         ! Reaction (in contact) or gap (free) of each candidate and its rate along the path, from the
         ! tangent: where a contact starts or ends between two steps is found from them.
         do c = 1, m
            row = state%map%candidate_equation(c)
            if (.not. candidate_live(state%map, c)) cycle
            node = model%contacts(c)%node
            call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, gradient, &
                               hessian, state%lambda, rate)
            g = gap(c)   ! with the plastic slip (docs/theory.md §3.9) and a Pasternak bed's surface
            state%point%in_contact(c) = state%active(c) .and. reaction(c) > 0.0_dp
            if (state%point%in_contact(c)) then
               state%point%contact_value(c) = reaction(c)
               if (yielding_at(c)) then
                  ! at its bearing limit: r = q, constant
                  state%point%contact_rate(c) = 0.0_dp
               else if (row > 0) then
                  state%point%contact_rate(c) = sense*state%tangent_displacement(row)/norm
               else
                  ! condensed: r = −g/t, dr/ds = −(a·du/ds)/t
                  state%point%contact_rate(c) = -sense*along(state%tangent_displacement)/norm/ &
                                                model%contacts(c)%flexibility
               end if
            else
               state%point%contact_value(c) = g
               state%point%contact_rate(c) = sense*along(state%tangent_displacement)/norm
               ! a moving obstacle closes the gap with λ too (docs/theory.md §3.11)
               if (rate /= 0.0_dp) state%point%contact_rate(c) = &
                  sense*(along(state%tangent_displacement) + rate)/norm
            end if
         end do
      end if

   contains

      !> Candidate c is at its bearing limit in the committed state.
      pure logical function yielding_at(c)
         integer, intent(in) :: c
         yielding_at = .false.
         if (allocated(state%yielding)) yielding_at = state%yielding(c)
      end function yielding_at

      !> a_cᵀ v at the candidate's node for an augmented vector v.
      pure real(dp) function along(v)
         real(dp), intent(in) :: v(:)
         integer :: i
         along = 0.0_dp
         do i = 1, 2
            if (state%map%equation(i, node) > 0) along = along + gradient(i)*v(state%map%equation(i, node))
         end do
         along = along + bed_deflection(state%map, c, v)
      end function along
   end subroutine describe_point

end module uniarc_path_point
