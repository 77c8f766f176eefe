!> Branch switching at a simple bifurcation (docs/theory.md §2.6), and the buckling mode there as
!> nodal displacements (the modes file, uniarc_modes_output).
!>
!> At a bifurcation located by re-solving (uniarc_path_locate), the converged state x_c nearest to it
!> and the least eigenvector φ of its tangent are kept: φ approximates the null vector of K_T at the
!> critical point — on the admissible cone at a lift-off (unilateral) bifurcation, where it is the
!> least mode of the tangent with the contacts that touch without force released (uniarc_path_stability).
!> The secondary branch leaves x_c along φ (Riks 1984, Int. J. Solids Struct. 20, 557–572; Wagner &
!> Wriggers 1988, Eng. Comput. 5, 103–109): the predictor is x_c + ξ φ at λ_c, with φ made orthogonal
!> to the primary path's tangent K⁻¹R (so that it does not lead back along the primary path) and ξ
!> the path's current step length; the corrector is Newton with the updated normal plane (Riks):
!> δλ = −Δuᵀδu_g / Δuᵀδu_t, which keeps the correction normal to the increment and so away from the
!> primary path, whose points lie at distance ξ in that plane. Then the usual arc length goes on.
module uniarc_path_branch
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_copy, only: reserve
   use uniarc_strings, only: real_to_string
   use uniarc_model, only: model_t, dofs_per_node, iteration_riks, analysis_options_t
   use uniarc_assembly, only: gather_nodal
   use uniarc_dof_map, only: dof_map_t, candidate_live, bed_deflection
   use uniarc_contact, only: candidate_gap
   use uniarc_path_state, only: path_state_t, path_system_t, step_trial_t, bifurcation_state_t, masked_dot, &
                                masked_norm, nodal_displacements, accept_trial
   use uniarc_path_newton, only: attempt_step
   use uniarc_path_state_copy, only: copy_state, move_state
   use uniarc_path_stability, only: commit_tangent
   use uniarc_path_point, only: describe_point
   use uniarc_path_contact_set, only: candidate_state, contact_units
   use uniarc_contact_lcp, only: contact_scales_t
   implicit none
   private
   public :: switch_branch, nodal_mode, mode_orientation

contains

   !> The buckling mode `mode` (n equations) as nodal displacements `nodal` (dofs_per_node, n_nodes),
   !> scaled so that the largest nodal translation sqrt(ux² + uy²) is 1 (a rotation-only mode: the
   !> largest rotation is 1) and signed by mode_orientation. Dimensionless shape.
   !> Errors: `nodal` refused by the system (error_analysis, out of memory, uniarc_memory).
   !> With `keep_sign` true (a lift-off mode, on the admissible cone: its sign opens the contacts that
   !> touch without force, docs/theory.md §2.6) the sign is kept.
   subroutine nodal_mode(model, map, mode, nodal, error, keep_sign)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: mode(:)
      real(dp), allocatable, intent(out) :: nodal(:, :)
      type(error_t), allocatable, intent(out) :: error
      logical, intent(in), optional :: keep_sign
      real(dp) :: largest
      integer :: status
      allocate (nodal(dofs_per_node, model%n_nodes), stat=status)
      call allocation_failure(status, 'the nodal buckling mode', 8.0_dp*dofs_per_node*model%n_nodes, &
                              error_analysis, error)
      if (allocated(error)) return
      call gather_nodal(map, mode, nodal)
      largest = maxval(sqrt(nodal(1, :)**2 + nodal(2, :)**2))
      if (.not. largest > 0.0_dp) largest = maxval(abs(nodal))
      if (.not. largest > 0.0_dp) return
      largest = largest*mode_orientation(nodal)
      if (present(keep_sign)) then
         if (keep_sign) largest = abs(largest)
      end if
      nodal(:, :) = nodal/largest
   end subroutine nodal_mode

   !> One step from the bifurcation kept in state%bifurcation onto the secondary branch: predictor
   !> x_c + ξφ at λ_c (φ orthogonal to the primary tangent, unit in the displacement norm; at a lift-off
   !> signed to open the contacts that touch without force, else by mode_orientation; ξ the
   !> current step length; orthogonal to the primary path's chord over the step that passed the
   !> bifurcation; at a lift-off the contacts it opens released from the first working set,
   !> release_opened), Riks' normal-plane corrections, the step halved on failure down to
   !> min_increment. The converged state is committed as the next step (point%switched set, its tangent
   !> factorised into state%system) and the arc length goes on from it along the new branch;
   !> state%bifurcation stays until the next step (the switch's row in STEM.crit).
   !> A converged step more than 60° from ξφ̂ (φ̂ᵀΔu < ‖Δu‖/2: on another branch, such as the primary
   !> one) is refused and halved like a failed one (docs/theory.md §2.6).
   !> `cuts` returns the halvings made. Errors (error_analysis): no bifurcation kept, a singular tangent
   !> at x_c, no convergence down to the smallest step, or every converged step off the mode's
   !> direction down to it ("no secondary branch found along the mode").
   subroutine switch_branch(model, state, error, cuts)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: cuts
      type(path_state_t) :: critical
      type(path_system_t), allocatable :: system
      type(step_trial_t) :: trial
      type(analysis_options_t) :: riks
      real(dp), allocatable :: phi(:), primary(:), start(:)
      real(dp) :: xi, t_norm, bytes, sign_of, along, size_increment
      integer :: step, status, off_mode
      cuts = 0
      off_mode = 0
      state%switch_due = .false.
      if (.not. allocated(state%bifurcation)) then
         call make_error(error, 'no bifurcation to switch branches at', error_analysis)
         return
      end if
      step = state%point%step
      call move_alloc(state%system, system)
      ! The step starts from the state at the bifurcation. Its tangent K⁻¹R is not used: K_T is
      ! singular there to the located precision, and K⁻¹R is dominated by the mode (noise / μ). The
      ! primary path's direction is the chord of the step that passed the bifurcation.
      call copy_state(state, critical, 'the state at the bifurcation', error)
      if (allocated(error)) then
         call move_alloc(system, state%system)
         return
      end if
      critical%u = state%bifurcation%u
      critical%active = state%bifurcation%active
      critical%lambda = state%bifurcation%lambda
      if (allocated(state%bifurcation%joint_plastic)) critical%joint_plastic = state%bifurcation%joint_plastic
      system%holds_committed = .false.
      system%holds_converged = .false.
      ! The vectors of the switch allocated with stat= (the assignments below then allocate nothing).
      bytes = 0.0_dp
      call reserve(primary, size(state%last_increment), status, bytes)
      if (status == 0) call reserve(phi, size(state%bifurcation%mode), status, bytes)
      if (status == 0) call reserve(start, size(state%bifurcation%mode), status, bytes)
      call allocation_failure(status, 'a vector of the branch switch', bytes, error_analysis, error)
      if (allocated(error)) then
         call move_alloc(system, state%system)
         return
      end if
      ! φ without reactions, orthogonal to the primary path, unit, signed.
      primary(:) = merge(state%last_increment, 0.0_dp, critical%map%metric > 0.0_dp)
      phi(:) = merge(state%bifurcation%mode, 0.0_dp, critical%map%metric > 0.0_dp)
      t_norm = masked_norm(critical%map, primary)
      if (t_norm > 0.0_dp) phi = phi - masked_dot(critical%map, phi, primary)/t_norm**2*primary
      if (.not. masked_norm(critical%map, phi) > 1.0e-3_dp*masked_norm(critical%map, state%bifurcation%mode)) then
         call move_alloc(system, state%system)
         call make_error(error, 'the buckling mode at the bifurcation is along the primary path: no branch '// &
                         'to switch to', error_analysis)
         return
      end if
      phi = phi/masked_norm(critical%map, phi)
      call mode_sign(model, critical, state%bifurcation%liftoff, phi, sign_of, error)
      if (allocated(error)) then
         call move_alloc(system, state%system)
         return
      end if
      phi = phi*sign_of
      ! At a lift-off the working set the corrections start with is the secondary branch's: the
      ! contacts that touch without force and that ξφ̂ opens are released (a rigid one would otherwise
      ! pull the structure back onto its obstacle in the first correction, its reaction unknown free
      ! to become any tension the arc length asks for).
      if (state%bifurcation%liftoff) then
         call release_opened(model, critical, phi, error)
         if (allocated(error)) then
            call move_alloc(system, state%system)
            return
         end if
      end if
      ! Riks' updated normal plane for the corrections of this step only (its options: no copy of the model).
      riks = model%analysis
      riks%iteration = iteration_riks
      xi = state%step_length
      do
         trial%length = xi
         start(:) = xi*phi
         call attempt_step(model, critical, system, trial, start=start, analysis=riks)
         if (allocated(trial%fatal)) then
            ! Out of memory (fail_attempt): no shorter step is tried; the run ends.
            call move_alloc(system, state%system)
            call move_alloc(trial%fatal, error)
            return
         end if
         if (trial%converged) then
            ! On the new branch: it leaves the bifurcation tangent to φ, so the converged increment
            ! keeps within 60° of ξφ̂ (cos ≥ 1/2; it tends to 0° as ξ → 0). A state further round
            ! is another branch — the primary one, or one reached through it — and is refused as a
            ! failed attempt: no silent return to the path the switch left (docs/theory.md §2.6).
            along = masked_dot(critical%map, trial%increment, phi)
            size_increment = masked_norm(critical%map, trial%increment)
            if (along >= 0.5_dp*size_increment) exit
            off_mode = off_mode + 1
            trial%reason = 'the converged state, at lambda = '//trim(real_to_string(critical%lambda + trial%dlambda, &
                           '(es12.5)'))//', lies '//trim(real_to_string(acos(max(-1.0_dp, min(1.0_dp, &
                           along/max(size_increment, tiny(1.0_dp)))))*45.0_dp/atan(1.0_dp), '(f6.1)'))// &
                           ' degrees off the mode: on another branch'
         end if
         xi = 0.5_dp*xi
         cuts = cuts + 1
         if (xi < model%analysis%min_increment*state%first_length .or. cuts > model%analysis%max_cuts) then
            call move_alloc(system, state%system)
            if (off_mode > 0) then
               call make_error(error, 'branch switching at lambda = '//real_to_string(critical%lambda, '(es12.5)')// &
                               ': no secondary branch found along the mode: every step that converged (the last: '// &
                               trial%reason//') left it for another branch, down to the smallest step; the '// &
                               'path does not go back to the branch it left', error_analysis)
            else
               call make_error(error, 'branch switching at lambda = '//real_to_string(critical%lambda, '(es12.5)')// &
                               ': no convergence ('//trial%reason//') down to the smallest step', error_analysis)
            end if
            return
         end if
      end do
      ! Commit: the first point of the secondary branch, numbered after the last one of the primary.
      call move_state(critical, state)
      call accept_trial(model, state, trial, error)
      if (allocated(error)) then
         call move_alloc(system, state%system)
         error%message = 'branch switching (converged state): '//error%message
         return
      end if
      state%step_length = xi
      state%taken_length = xi
      call commit_tangent(model, state, system, .false., error)
      if (allocated(error)) then
         call move_alloc(system, state%system)
         error%message = 'branch switching (converged state): '//error%message
         return
      end if
      call move_alloc(system, state%system)
      if (masked_dot(state%map, trial%increment, state%tangent_displacement) < 0.0_dp) then
         state%direction = -1
      else
         state%direction = 1
      end if
      call describe_point(model, state, step + 1, trial%iterations, trial%lcp_pivots, error)
      if (allocated(error)) return
      state%point%switched = .true.
      state%point%switch_lambda = critical%lambda
      state%point%limit_fraction = -1.0_dp
      state%point%bifurcation_fraction = -1.0_dp
      state%point%bifurcation_multiplicity = 0
      state%point%stability_by_contact = .false.
      state%point%stability_fraction = -1.0_dp
      state%point%limit_by_contact = .false.
   end subroutine switch_branch

   !> The working set of the first step along the secondary branch of a lift-off (docs/theory.md §2.6):
   !> the contacts of `state`'s working set that touch without force (reaction at most the
   !> displacement tolerance × the force unit, as the lift-off stability test finds them,
   !> uniarc_path_stability) and that the signed mode `phi` opens (a_cᵀφ + d_c(φ) above 1e-6 |a_c| of
   !> φ's largest displacement: below it is round-off of a motion along the surface, as in that test)
   !> leave state%active. Those in compression, the bilateral ones and those φ leaves in place stay.
   !> Without it the first correction starts with them closed: an elastic bed pulls the structure
   !> back by k ξ φ before the sign rule frees it, and a rigid contact's reaction unknown takes
   !> whatever tension returns the structure onto the obstacle, where the arc-length constraint can
   !> be met only by a huge Δλ (the strut on a rigid plane: λ = 8.9e4, 89° off the mode).
   !> Errors: the vectors of the test refused by the system (error_analysis, out of memory).
   subroutine release_opened(model, state, phi, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      real(dp), intent(in) :: phi(:)
      type(error_t), allocatable, intent(out) :: error
      type(contact_scales_t) :: units
      real(dp), allocatable :: nodal(:, :), shape(:, :), reaction(:), gap(:)
      real(dp) :: g, gradient(2), hessian(2, 2), opening, size_mode
      integer :: c, node, m, status
      m = size(state%active)
      if (m == 0) return
      call nodal_displacements(model, state, nodal, error)
      if (allocated(error)) return
      allocate (shape(dofs_per_node, model%n_nodes), reaction(m), gap(m), stat=status)
      call allocation_failure(status, 'the contacts a lift-off mode opens', &
                              8.0_dp*(dofs_per_node*model%n_nodes + 2*m), error_analysis, error)
      if (allocated(error)) return
      call gather_nodal(state%map, phi, shape)
      call candidate_state(model, state%map, state%u, nodal, state%active, reaction, gap, lambda=state%lambda)
      units = contact_units(state, state%u, reaction, state%active)
      size_mode = maxval(abs(state%map%metric*phi))
      do c = 1, m
         if (.not. state%active(c) .or. .not. candidate_live(state%map, c)) cycle
         if (model%contacts(c)%bilateral) cycle
         if (reaction(c) > model%analysis%displacement_tolerance*units%force) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, gradient, &
                            hessian, state%lambda)
         opening = dot_product(gradient, shape(1:2, node)) + bed_deflection(state%map, c, phi)
         if (opening > 1.0e-6_dp*norm2(gradient)*size_mode) state%active(c) = .false.
      end do
   end subroutine release_opened

   !> +1 or −1: the sign of the predictor along φ. At a state with contacts in the working set that
   !> touch without force (a lift-off), the sign that opens them (Σ a_cᵀφ ≥ 0 over the working set:
   !> the other sign presses into the medium, where it resists); else by mode_orientation.
   !> Errors: the nodal displacements of the state or of φ refused by the system (error_analysis, out
   !> of memory).
   subroutine mode_sign(model, state, liftoff, phi, sign_of, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      logical, intent(in) :: liftoff   !< the bifurcation is a lift-off (unilateral) one
      real(dp), intent(in) :: phi(:)
      real(dp), intent(out) :: sign_of
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), shape(:, :)
      real(dp) :: g, gradient(2), hessian(2, 2), opening
      integer :: c, node, status
      sign_of = 1.0_dp
      if (liftoff) then
         call nodal_displacements(model, state, nodal, error)
         if (allocated(error)) return
         allocate (shape(dofs_per_node, model%n_nodes), stat=status)
         call allocation_failure(status, 'the nodal displacements of the buckling mode', &
                                 8.0_dp*dofs_per_node*model%n_nodes, error_analysis, error)
         if (allocated(error)) return
         call gather_nodal(state%map, phi, shape)
         opening = 0.0_dp
         do c = 1, size(state%active)
            if (.not. state%active(c) .or. .not. candidate_live(state%map, c)) cycle
            node = model%contacts(c)%node
            call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, gradient, &
                               hessian, state%lambda)
            opening = opening + dot_product(gradient, shape(1:2, node)) + bed_deflection(state%map, c, phi)
         end do
         if (opening < 0.0_dp) sign_of = -1.0_dp
         return
      end if
      allocate (shape(dofs_per_node, model%n_nodes), stat=status)
      call allocation_failure(status, 'the nodal displacements of the buckling mode', &
                              8.0_dp*dofs_per_node*model%n_nodes, error_analysis, error)
      if (allocated(error)) return
      call gather_nodal(state%map, phi, shape)
      sign_of = mode_orientation(shape)
   end subroutine mode_sign

   !> +1 or −1: the sign that makes a mode `nodal` (dofs_per_node, n_nodes) point the project's way —
   !> its first significant translation, in the order of the nodes (ux before uy), positive; a
   !> translation is significant when its magnitude is at least 1e-3 of the largest (a mode without
   !> translations: the same with the rotations). Not "the largest component positive": the mode of a
   !> bifurcation of a symmetric structure is antisymmetric or symmetric, its largest components come
   !> in mirrored pairs of equal magnitude, and which of them round-off makes the larger would decide
   !> the sign — and the side of the secondary branch followed — differently on another machine.
   !> The 1e-3 margin is far above the mode's round-off (1e-10 of its norm at a bifurcation located to
   !> 1e-7) and far below the components that describe its shape.
   pure real(dp) function mode_orientation(nodal) result(sign_of)
      real(dp), intent(in) :: nodal(:, :)
      real(dp) :: largest
      integer :: node, d, first, last
      first = 1
      last = min(2, size(nodal, 1))
      largest = maxval(abs(nodal(first:last, :)))
      if (.not. largest > 0.0_dp) then
         first = min(3, size(nodal, 1))
         last = size(nodal, 1)
         largest = maxval(abs(nodal(first:last, :)))
      end if
      sign_of = 1.0_dp
      if (.not. largest > 0.0_dp) return
      do node = 1, size(nodal, 2)
         do d = first, last
            if (abs(nodal(d, node)) >= 1.0e-3_dp*largest) then
               if (nodal(d, node) < 0.0_dp) sign_of = -1.0_dp
               return
            end if
         end do
      end do
   end function mode_orientation

end module uniarc_path_branch
