!> The start of a path (or of an analysis step, or of a working set changed in place): the first step's
!> length, direction and force scale (size_first_step, docs/theory.md §2.1 and §2.7), ψ the displacement
!> a unit of λ moves (start_lambda_scale), and the floating motions a structure held only by its contacts
!> has at the unloaded state with the rigid approach to its first contact (find_floating,
!> approach_first_contact, §2.8). Moved out of uniarc_path_following, whose job is the step.
module uniarc_path_start
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_model, only: model_t, control_displacement, control_arclength, control_load, dofs_per_node
   use uniarc_dof_map, only: candidate_live
   use uniarc_band, only: band_allocate, band_factorize, band_solve
   use uniarc_path_state, only: path_state_t, path_system_t, masked_norm, nodal_displacements, equilibrium_at
   use uniarc_path_contact_set, only: touching_candidates
   use uniarc_path_mechanism, only: find_mechanism, floating_motions
   use uniarc_path_integrator, only: degenerate_tangent
   use uniarc_path_element_loads, only: element_load_norm, natural_deformation_scale
   use uniarc_contact_lcp, only: degenerate_fraction
   use uniarc_path_approach, only: rigid_approach
   implicit none
   private
   public :: size_first_step, find_floating, approach_first_contact

contains

   !> The first step length, direction and force scale of a path (or an analysis step) from the
   !> committed K⁻¹R and R and the controls of `model%analysis`.
   !> Errors (error_analysis): a zero first increment or reference load.
   subroutine size_first_step(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: element_norm
      associate (options => model%analysis)
         call start_lambda_scale(model, state, error)
         if (allocated(error)) return
         select case (options%control)
         case (control_arclength)
            state%first_length = abs(options%first_increment)*state%lambda_scale
         case default
            state%first_length = abs(options%first_increment)
         end select
         state%step_length = state%first_length
         state%direction = 1
         if (options%first_increment < 0.0_dp) state%direction = -1
         state%load_norm = abs(options%first_increment)*norm2(state%reference)
         if (options%control == control_displacement) state%load_norm = norm2(state%reference)
         call element_load_norm_at(model, state, element_norm, error)
         if (allocated(error)) return
         if (.not. (norm2(state%reference) > degenerate_fraction*element_norm)) then
            ! The supports take every equivalent nodal force of the element loads (a bar heated between
            ! two pins): the loads are sized by those forces, held DOFs included
            ! (uniarc_path_element_loads).
            state%load_norm = abs(options%first_increment)*element_norm
            if (options%control == control_displacement) state%load_norm = element_norm
         end if
         ! Obstacles that move but touch nothing yet (a punch above the structure): R is zero until one
         ! touches (docs/theory.md §3.11). Under load control λ (the motion) goes on all the same, the
         ! force scale that of their contact rows once in the set; an arc length has nothing to measure.
         if (.not. state%load_norm > 0.0_dp .and. moving_obstacles(model)) then
            if (options%control /= control_load) then
               call make_error(error, 'the moving obstacles touch nothing at the start of the step: their '// &
                               'motion moves nothing until they do, and the path has nothing to measure; '// &
                               'trace it with CONTROL=LOAD', error_analysis)
               return
            end if
            state%load_norm = abs(options%first_increment)*norm2(model%contacts%gap_rate)
            ! a moving curved obstacle: its rate −a·d is at most |d| (|a| = 1)
            if (any(model%contacts%motion(1) /= 0.0_dp) .or. any(model%contacts%motion(2) /= 0.0_dp)) &
               state%load_norm = abs(options%first_increment)*sqrt(sum(model%contacts%gap_rate**2) + &
                                                                    sum(model%contacts%motion(1)**2) + &
                                                                    sum(model%contacts%motion(2)**2))
         end if
         if (state%first_length <= 0.0_dp .or. state%load_norm <= 0.0_dp) then
            call make_error(error, 'the first increment or the reference load is zero: nothing to follow', &
                            error_analysis)
            return
         end if
      end associate
   end subroutine size_first_step

   !> The model has an obstacle that moves with λ in its step (*MOVE, contact_candidate_t%gap_rate).
   pure logical function moving_obstacles(model)
      type(model_t), intent(in) :: model
      moving_obstacles = .false.
      if (allocated(model%contacts)) moving_obstacles = any(model%contacts%gap_rate /= 0.0_dp) .or. &
                                                       any(model%contacts%motion(1) /= 0.0_dp) .or. &
                                                       any(model%contacts%motion(2) /= 0.0_dp)
   end function moving_obstacles

   !> The rigid motions that only the contacts can hold (a structure floating in a cavity until a
   !> contact touches, docs/theory.md §2.8): the stiffness at the unloaded state with the unilateral
   !> candidates and the springs with an uplift limit open (`system` is work space). Models without
   !> such candidates have none (a mechanism was refused before).
   subroutine find_floating(model, state, system, nodal, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(path_system_t), intent(inout) :: system
      real(dp), intent(in) :: nodal(:, :)
      type(error_t), allocatable, intent(out) :: error   !< out of memory (error_analysis)
      real(dp), allocatable :: internal(:), reference(:)
      logical, allocatable :: bonded(:)
      real(dp) :: element_scale
      logical :: unbonded
      integer :: c, status
      if (size(state%active) == 0) return
      allocate (bonded(size(state%active)), stat=status)
      call allocation_failure(status, 'the bonded candidates', 4.0_dp*size(state%active), error_analysis, error)
      if (allocated(error)) return
      ! a spring with an uplift limit (TU=) is bonded while elastic but holds nothing once it yields,
      ! at either limit: it is released here as a unilateral candidate is (docs/theory.md §3.9)
      ! a tangential spring that follows a radial partner is released with it (docs/theory.md §3.8)
      unbonded = .false.
      do c = 1, size(state%active)
         bonded(c) = candidate_live(state%map, c) .and. model%contacts(c)%bilateral .and. &
                     .not. model%contacts(c)%uplift_force > 0.0_dp .and. model%contacts(c)%partner == 0
         if (candidate_live(state%map, c) .and. .not. bonded(c)) unbonded = .true.
      end do
      if (.not. unbonded) return
      allocate (internal(state%map%n_equations), reference(state%map%n_equations), stat=status)
      call allocation_failure(status, 'the force vectors of the floating test', 16.0_dp*state%map%n_equations, &
                              error_analysis, error)
      if (allocated(error)) return
      call equilibrium_at(model, state, system, state%u, 0.0_dp, bonded, nodal, internal, reference, element_scale, &
                          error)
      if (allocated(error)) return
      call floating_motions(model, state%map, system%tangent, state%floating_motion, state%floating_equation, error)
   end subroutine find_floating

   !> A structure that floats across a gap and that the reference load pushes along a free rigid
   !> translation starts where that translation brings it to its first contact (docs/theory.md §2.8,
   !> uniarc_path_approach), at the start of the path and of every later analysis step (a step that
   !> ended with nothing pushing the structure onto its contacts, followed by one that does): state%u
   !> is translated, `nodal` updated and the working set is that of the translated state. The gaps of
   !> plastic media are those of their sunk surfaces (state%slip, §3.9). Untouched when there is no
   !> such translation (no floating motion, a self-equilibrated load, a contact holding it already).
   !> `system` is work space.
   !> Errors (error_input): no contact is ever met along the translation (rigid_approach).
   subroutine approach_first_contact(model, state, system, nodal, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(path_system_t), intent(inout) :: system
      real(dp), allocatable, intent(inout) :: nodal(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: internal(:), reference(:), shift(:)
      real(dp) :: element_scale
      integer :: contact, status
      if (.not. allocated(state%floating_equation)) return
      allocate (internal(state%map%n_equations), reference(state%map%n_equations), shift(state%map%n_equations), &
                stat=status)
      call allocation_failure(status, 'the force vectors of the rigid approach', 24.0_dp*state%map%n_equations, &
                              error_analysis, error)
      if (allocated(error)) return
      call equilibrium_at(model, state, system, state%u, 0.0_dp, state%active, nodal, internal, reference, &
                          element_scale, error)
      if (allocated(error)) return
      call rigid_approach(model, state%map, state%floating_motion, reference, nodal, state%length_scale, .false., &
                          shift, contact, error, state%slip)
      if (allocated(error) .or. contact == 0) return
      state%u = state%u + shift
      call nodal_displacements(model, state, nodal, error)
      if (allocated(error)) return
      call touching_candidates(model, state, nodal, state%active)
      ! (nothing of the set held the structure: none of the new set is at its limit)
      if (allocated(state%yielding)) state%yielding = state%yielding .and. state%active
   end subroutine approach_first_contact

   !> ψ (state%lambda_scale), the displacement norm a unit of λ moves at the unloaded state: ||K⁻¹R||;
   !> where the contacts touching at the start carry the whole reference load (K⁻¹R has no
   !> displacement: a heated bar against a rigid stop), the structure's own ||K⁻¹R|| with those contacts
   !> released (docs/theory.md §2.7). Errors (error_analysis): an arc length asked for where neither
   !> measures anything (the released structure is a mechanism).
   subroutine start_lambda_scale(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(inout) :: state
      type(error_t), allocatable, intent(out) :: error
      type(path_system_t) :: released
      type(error_t), allocatable :: singular
      real(dp), allocatable :: nodal(:, :), internal(:), reference(:), rhs(:, :)
      real(dp) :: element_scale, scale, natural
      character(len=:), allocatable :: place
      logical, allocatable :: bonded(:)
      integer :: c, status
      state%lambda_scale = masked_norm(state%map, state%tangent_displacement)
      natural = natural_deformation_scale(model)
      if (.not. any(state%active)) then
         call supports_carry_all(state, natural)
         return
      end if
      ! The touching unilateral contacts released (the bonded ones stay), in a system of its own:
      ! the committed factors stay for the first predictor.
      ! (allocated with stat= and filled in a loop: no array constructor of the candidates' length)
      allocate (bonded(size(state%active)), stat=status)
      call allocation_failure(status, 'the bonded contacts of the released structure', 4.0_dp*size(state%active), &
                              error_analysis, error)
      if (allocated(error)) return
      do c = 1, size(state%active)
         bonded(c) = state%active(c) .and. model%contacts(c)%bilateral .and. model%contacts(c)%partner == 0
      end do
      if (all(bonded .eqv. state%active)) then
         call supports_carry_all(state, natural)
         return
      end if
      call band_allocate(released%tangent, state%map%n_equations, state%map%half_bandwidth, &
                         state%map%half_bandwidth, error)
      if (allocated(error)) return
      allocate (internal(state%map%n_equations), reference(state%map%n_equations), rhs(state%map%n_equations, 1), &
                stat=status)
      call allocation_failure(status, 'the force vectors of the structure released from its contacts', &
                              24.0_dp*state%map%n_equations, error_analysis, error)
      if (allocated(error)) return
      call nodal_displacements(model, state, nodal, error)
      if (allocated(error)) return
      call equilibrium_at(model, state, released, state%u, 0.0_dp, bonded, nodal, internal, reference, element_scale, &
                          error)
      if (allocated(error)) return
      scale = 0.0_dp
      call find_mechanism(model, state%map, released%tangent, singular, error_analysis)
      if (allocated(singular)) then
         if (singular%out_of_memory) then
            call move_alloc(singular, error)
            return
         end if
      end if
      if (.not. allocated(singular)) call band_factorize(released%tangent, singular)
      if (.not. allocated(singular)) then
         rhs(:, 1) = reference
         call band_solve(released%tangent, rhs, singular)
         if (.not. allocated(singular)) scale = masked_norm(state%map, rhs(:, 1))
         if (.not. (scale < huge(1.0_dp))) scale = 0.0_dp
      end if
      ! Released from its contacts the structure is a mechanism or still moves nothing but round-off,
      ! and its held DOFs take the element loads (a heated bar pinned at its ends settled on a bed):
      ! ψ is the elements' free thermal deformation (supports_carry_all).
      if (natural > 0.0_dp .and. .not. (scale > degenerate_fraction*natural)) scale = natural
      state%lambda_scale = scale
      if (.not. degenerate_tangent(state, state%tangent_displacement)) then
         state%lambda_scale = masked_norm(state%map, state%tangent_displacement)
      else if (model%analysis%control == control_arclength .and. .not. (scale > 0.0_dp)) then
         ! the path's unloaded state, or the start of an analysis step after the first (its model
         ! holds the earlier steps' loads)
         place = 'unloaded state'
         if (allocated(model%held)) then
            if (size(model%held) > 0) place = 'start of the step'
         end if
         call make_error(error, place//': the contacts that touch at the start carry the whole reference '// &
                         'load, and without them the structure is a mechanism: an arc length has nothing '// &
                         'to measure; trace it with CONTROL=LOAD', error_analysis)
      end if
   end subroutine start_lambda_scale

   !> element_load_norm (uniarc_path_element_loads) at the committed displacements.
   !> Errors: its arrays refused by the system (error_analysis, out of memory, uniarc_memory).
   subroutine element_load_norm_at(model, state, norm, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      real(dp), intent(out) :: norm
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), total(:, :)
      integer :: status
      norm = 0.0_dp
      call nodal_displacements(model, state, nodal, error)
      if (allocated(error)) return
      allocate (total(dofs_per_node, model%n_nodes), stat=status)
      call allocation_failure(status, 'the nodal forces of the element loads', 8.0_dp*dofs_per_node*model%n_nodes, &
                              error_analysis, error)
      if (allocated(error)) return
      norm = element_load_norm(model, nodal, total)
   end subroutine element_load_norm_at

   !> ψ where K⁻¹R has no displacement and no contact to release: the supports take every equivalent
   !> nodal force of the step's temperature changes (a bar heated between two pins, a clamped beam
   !> under a gradient). The path goes in λ alone (docs/theory.md §2.7), measured by the elements'
   !> free thermal deformation per unit λ (uniarc_path_element_loads).
   subroutine supports_carry_all(state, natural)
      type(path_state_t), intent(inout) :: state
      real(dp), intent(in) :: natural
      if (.not. (natural > 0.0_dp)) return
      if (state%lambda_scale > degenerate_fraction*natural) return
      state%lambda_scale = natural
   end subroutine supports_carry_all

end module uniarc_path_start
