!> What a step that no cut-back converges says about itself (docs/contracts.md, exit code 1): the
!> hints added to its error — joints at their moment limit, contacts at their bearing limit
!> (docs/theory.md §1.11, §3.9), a node at the crest of a moving curved obstacle (§3.11), a node at a
!> concave corner of a polyline, a node passing close by a convex one — and the lift-off test of a
!> load that no contact can hold (§3.12).
!> Used by the path following (uniarc_path_following, path_advance) only.
module uniarc_path_failure
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_model, only: model_t, dofs_per_node, gap_polyline
   use uniarc_contact_law, only: candidate_gap
   use uniarc_obstacle_shapes, only: polyline_concave_corner
   use uniarc_dof_map, only: candidate_live
   use uniarc_assembly, only: gather_nodal
   use uniarc_path_state, only: path_state_t, path_system_t, equilibrium_at, yielded_joints
   use uniarc_lift_off, only: describe_lift_off
   implicit none
   private
   public :: add_crest_hint, add_mechanism_hint, lift_off_error, at_bearing_limit, add_concave_corner_hint
   public :: add_convex_corner_hint, add_unstable_branch_hint

   !> How a real is written in these messages (λ): 6 digits suffice, as in uniarc_path_following.
   character(len=*), parameter :: message_edit = '(es12.5)'

contains

   !> A path that goes back along itself (docs/theory.md §2.3, "back along the path") from an unstable
   !> state (`neg_pivots` > 0) past a bifurcation it passed without switching (`bifurcations` > 0,
   !> `switch_bifurcation` 0): the branch traced is one the structure does not take, and a loop of its
   !> branches led the path back onto itself. The message says so and names the way onto the branch
   !> that leaves the first bifurcation (*PATH, SWITCH=1; the circular liner in its host, whose perfect
   !> ring bifurcates into its oval mode at 3.0 before it touches the host, collapses at 35.04 along
   !> that branch, as the oval liners do along their paths).
   subroutine add_unstable_branch_hint(neg_pivots, bifurcations, switch_bifurcation, error)
      integer, intent(in) :: neg_pivots, bifurcations, switch_bifurcation
      type(error_t), intent(inout) :: error
      if (neg_pivots <= 0 .or. bifurcations <= 0 .or. switch_bifurcation /= 0) return
      error%message = error%message//'; the path is on an unstable branch ('// &
                      integer_to_string(neg_pivots)//' negative pivots) past '// &
                      integer_to_string(bifurcations)//' bifurcation(s) it did not switch at: '// &
                      '*PATH, SWITCH=1 follows the branch that leaves the first (docs/input.md, *PATH)'
   end subroutine add_unstable_branch_hint

   !> A step that fails where a moving curved obstacle (contact_candidate_t%motion) carries a node in
   !> contact over its crest: there ∂g/∂λ = −a·d vanishes (|a·d| below 2 % of |d|), so the motion pushes
   !> nothing and du/dλ turns, which the branch checks in displacement take for a reversal and the arc
   !> length cannot measure (docs/theory.md §3.11). The message names the node; the path is not traced past
   !> the crest. Its nodal displacements refused by the system: no hint.
   subroutine add_crest_hint(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(error_t), intent(inout) :: error
      real(dp), allocatable :: nodal(:, :)
      real(dp) :: gap, gradient(2), hessian(2, 2), rate
      integer :: c, node, status
      if (.not. allocated(model%contacts) .or. .not. allocated(state%u) .or. .not. allocated(state%active)) return
      if (all(model%contacts%motion(1) == 0.0_dp) .and. all(model%contacts%motion(2) == 0.0_dp)) return
      ! refused by the system: no hint (the step's own error stands; docs/contracts.md, "Memory")
      allocate (nodal(dofs_per_node, model%n_nodes), stat=status)
      if (status /= 0) return
      call gather_nodal(state%map, state%u, nodal)
      do c = 1, size(model%contacts)
         if (all(model%contacts(c)%motion == 0.0_dp) .or. .not. state%active(c)) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, gradient, hessian, &
                            state%lambda, rate)
         if (abs(rate) >= 0.02_dp*norm2(model%contacts(c)%motion)) cycle
         error%message = error%message//'; node '//integer_to_string(model%node_label(node))// &
                         ' is at the crest of the moving obstacle '''//group_name(model, c)//''' (its motion '// &
                         'no longer pushes it: dg/dlambda = '//real_to_string(rate, message_edit)//'), where '// &
                         'the path in the displacements turns, which the path following does not pass (its '// &
                         'steps are measured in the displacements): end the step before the crest '// &
                         '(docs/theory.md 3.11)'
         return
      end do
   end subroutine add_crest_hint

   !> A step that fails from a state whose joints are at their moment limit (`*RELEASE, MY=`): with them
   !> as hinges the structure may be a mechanism — a plastic collapse, past which no equilibrium holds
   !> a higher load (docs/theory.md §1.11). The message names them, and the contact points at their
   !> bearing limit QU (not as a collapse: that is the certificate's, uniarc_path_collapse).
   subroutine add_mechanism_hint(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(error_t), intent(inout) :: error
      character(len=:), allocatable :: labels
      integer :: count, c
      call yielded_joints(model, state, count, labels)
      if (count > 0) error%message = error%message//'; '//integer_to_string(count)// &
                                     ' joint(s) at the moment limit MY ('//labels//'): with them as hinges the '// &
                                     'structure may be a mechanism (plastic collapse at lambda = '// &
                                     real_to_string(state%lambda, message_edit)//')'
      ! Beds and springs at their bearing limit (QU=, docs/theory.md §3.9): named, not called a collapse
      ! (the path driver adds what the collapse certificate found: uniarc_path_collapse).
      if (.not. (allocated(state%yielding) .and. allocated(state%active))) return
      count = 0
      labels = ''
      do c = 1, size(state%yielding)
         if (.not. (state%yielding(c) .and. state%active(c))) cycle
         count = count + 1
         if (len(labels) > 60) cycle
         if (len(labels) > 0) labels = labels//', '
         labels = labels//integer_to_string(model%node_label(model%contacts(c)%node))
         if (len(labels) > 60) labels = labels//', ...'
      end do
      if (count == 0) return
      error%message = error%message//'; '//integer_to_string(count)//' contact point(s) of beds or springs at '// &
                      'their bearing limit QU (nodes '//labels//') at lambda = '// &
                      real_to_string(state%lambda, message_edit)
   end subroutine add_mechanism_hint


   !> A step that no cut-back converges, tested for lift-off (uniarc_lift_off, docs/theory.md §3.12):
   !> with the state's free rigid motions (those only the unilateral contacts hold, find_floating),
   !> the unbalanced load at λ + dlambda (the load step's smallest attempt) with those contacts open, at
   !> the step's starting displacements. `error` allocated (error_analysis): the load lifts the
   !> structure off, at that λ. `system` is work space (its tangent is overwritten).
   subroutine lift_off_error(model, state, system, dlambda, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(path_system_t), intent(inout) :: system
      real(dp), intent(in) :: dlambda
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal(:, :), internal(:), reference(:)
      logical, allocatable :: bonded(:)
      character(len=:), allocatable :: text
      real(dp) :: element_scale, lambda
      integer :: c, status
      if (.not. allocated(state%floating_motion) .or. dlambda == 0.0_dp) return
      if (size(state%floating_motion, 2) == 0) return
      allocate (nodal(dofs_per_node, model%n_nodes), internal(state%map%n_equations), &
                reference(state%map%n_equations), bonded(size(state%active)), stat=status)
      call allocation_failure(status, 'the force vectors of the lift-off test', &
                              8.0_dp*(dofs_per_node*model%n_nodes + 2*state%map%n_equations), error_analysis, error)
      if (allocated(error)) return
      call gather_nodal(state%map, state%u, nodal)
      do c = 1, size(state%active)
         bonded(c) = candidate_live(state%map, c) .and. model%contacts(c)%bilateral .and. &
                     .not. model%contacts(c)%uplift_force > 0.0_dp .and. model%contacts(c)%partner == 0
      end do
      lambda = state%lambda + dlambda
      call equilibrium_at(model, state, system, state%u, lambda, bonded, nodal, internal, reference, element_scale, &
                          error)
      if (allocated(error)) return
      ! the tangent now holds this assembly, neither the committed nor a converged one
      system%holds_committed = .false.
      system%holds_converged = .false.
      call describe_lift_off(model, state%map, state%floating_motion, nodal, lambda*reference - internal, text)
      if (.not. allocated(text)) return
      call make_error(error, text//' (at lambda = '//real_to_string(lambda, message_edit)//')', error_analysis)
   end subroutine lift_off_error

   !> Whether a contact of the working set of `state` is at its bearing (or uplift) limit.
   logical function at_bearing_limit(state) result(at_limit)
      type(path_state_t), intent(in) :: state
      at_limit = .false.
      if (.not. (allocated(state%yielding) .and. allocated(state%active))) return
      if (size(state%yielding) /= size(state%active)) return
      at_limit = any(state%yielding .and. state%active)
   end function at_bearing_limit

   !> A step that does not converge with a node of a polyline obstacle at a concave corner of it
   !> (within 1e-3 of the model's size, in contact or about to be: its gap below that too): the cause
   !> is the corner, not a limit point. The node's gap is the distance to the nearer face, which is
   !> not differentiable where the two faces are equally near (uniarc_obstacle_shapes,
   !> polyline_concave_corner), so Newton's iterates switch faces and do not settle
   !> (docs/input.md, *OBSTACLE). The message names the node, the obstacle and the corner, and the
   !> workaround: the two faces as two obstacles.
   subroutine add_concave_corner_hint(model, state, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      type(error_t), intent(inout) :: error
      real(dp), allocatable :: nodal(:, :)
      real(dp) :: reach, x(2), gap, gradient(2), hessian(2, 2)
      integer :: c, node, corner, status
      if (.not. allocated(model%contacts) .or. .not. allocated(state%u)) return
      if (.not. any(model%contacts%gap_kind == gap_polyline)) return
      ! refused, no hint: the step's own error stands (as for the mechanism and crest hints)
      allocate (nodal(dofs_per_node, model%n_nodes), stat=status)
      if (status /= 0) return
      call gather_nodal(state%map, state%u, nodal)
      reach = 1.0e-3_dp*norm2(maxval(model%coordinates, dim=2) - minval(model%coordinates, dim=2))
      do c = 1, size(model%contacts)
         if (model%contacts(c)%gap_kind /= gap_polyline) cycle
         node = model%contacts(c)%node
         ! a moving polyline stands translated by λ d (docs/theory.md §3.11): the node against it at rest
         x = model%coordinates(:, node) + nodal(1:2, node) - state%lambda*model%contacts(c)%motion
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, gradient, hessian, &
                            state%lambda)
         if (gap > reach) cycle
         corner = polyline_concave_corner(model%contacts(c)%vertices, x, reach)
         if (corner == 0) cycle
         error%message = error%message//'; node '//integer_to_string(model%node_label(node))// &
                         ' is in contact at a concave corner ('// &
                         real_to_string(model%contacts(c)%vertices(1, corner), message_edit)//', '// &
                         real_to_string(model%contacts(c)%vertices(2, corner), message_edit)// &
                         ') of the polyline obstacle '''//group_name(model, c)//''': its gap there is the '// &
                         'distance to the nearer face, which is not differentiable where the two faces are '// &
                         'equally near, so the iterations switch faces and do not settle (a polyline does not '// &
                         'hold a node in a concave corner): give the two faces as two obstacles on the node set '// &
                         '(docs/input.md, *OBSTACLE)'
         return
      end do
   end subroutine add_concave_corner_hint

   !> A step that does not converge with a node of a polyline obstacle whose nearest feature is a convex
   !> corner at a distance d (0 < d ≤ 1e-3 of the model's size): the corner's gap is |x − v|, a circle
   !> of radius d (uniarc_obstacle_shapes), whose linearisation a·Δu holds only for motions well below d.
   !> A step that moves the node more than d past it predicts a contact that the exact gap never makes
   !> (a node held 1e-6 beside the corner, sliding past it: the linearised gap closes after 2e-6 of
   !> travel, the exact one stays ≥ 1e-6), and the corrector, free of it, lands far from that predictor
   !> (uniarc_path_acceptance, far_from_predictor): every cut is refused until a step moves the node
   !> less than about d. The path there is right once the step is that short, so the message says how
   !> short: `smallest` is the smallest attempt over the first step; under load control the
   !> displacement of the first step at the node (first_length × K⁻¹R) gives the min_increment and
   !> max_cuts (*PATH) that reach d/10.
   subroutine add_convex_corner_hint(model, state, control_load, smallest, error)
      type(model_t), intent(in) :: model
      type(path_state_t), intent(in) :: state
      logical, intent(in) :: control_load
      real(dp), intent(in) :: smallest
      type(error_t), intent(inout) :: error
      real(dp), allocatable :: nodal(:, :)
      real(dp) :: reach, gap, gradient(2), hessian(2, 2), distance, travel, ratio
      integer :: c, node, status, k, cuts
      if (.not. allocated(model%contacts) .or. .not. allocated(state%u)) return
      if (.not. any(model%contacts%gap_kind == gap_polyline)) return
      ! refused, no hint: the step's own error stands (as for the other hints)
      allocate (nodal(dofs_per_node, model%n_nodes), stat=status)
      if (status /= 0) return
      call gather_nodal(state%map, state%u, nodal)
      reach = 1.0e-3_dp*norm2(maxval(model%coordinates, dim=2) - minval(model%coordinates, dim=2))
      do c = 1, size(model%contacts)
         if (model%contacts(c)%gap_kind /= gap_polyline .or. .not. candidate_live(state%map, c)) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, gradient, hessian, &
                            state%lambda)
         ! only a vertex has a Hessian, ±(I − e eᵀ)/d, trace ±1/d: positive on the free side of a convex corner
         if (.not. (hessian(1, 1) + hessian(2, 2) > 0.0_dp)) cycle
         distance = 1.0_dp/(hessian(1, 1) + hessian(2, 2))
         if (distance > reach) cycle
         error%message = error%message//'; node '//integer_to_string(model%node_label(node))//' passes '// &
                         trim(adjustl(real_to_string(distance, '(es9.2)')))//' from a convex corner of the '// &
                         'polyline obstacle '''//group_name(model, c)//''', whose gap turns through the corner''s '// &
                         'angle within that distance: a step that moves the node farther sees a contact that is '// &
                         'not there (the linearised gap closes, the exact one does not) and is refused'
         travel = 0.0_dp
         if (control_load .and. allocated(state%tangent_displacement)) then
            do k = 1, 2
               if (state%map%equation(k, node) > 0) travel = max(travel, &
                  abs(state%first_length*state%tangent_displacement(state%map%equation(k, node))))
            end do
         end if
         if (travel > 0.0_dp) then
            ratio = 0.1_dp*distance/travel
            cuts = ceiling(log(1.0_dp/ratio)/log(2.0_dp))
            error%message = error%message//'; the smallest step moved it about '// &
                            trim(adjustl(real_to_string(smallest*travel, '(es9.2)')))//': let the step be cut '// &
                            'below '//trim(adjustl(real_to_string(0.1_dp*distance, '(es9.2)')))//' (*PATH, '// &
                            'min_increment = '//trim(adjustl(real_to_string(ratio, '(es9.2)')))// &
                            ', max_cuts = '//integer_to_string(cuts)//') or place the node farther from the corner'
         else
            error%message = error%message//'; let the step be cut until it moves the node less than that '// &
                            '(min_increment and max_cuts of *PATH) or place the node farther from the corner'
         end if
         return
      end do
   end subroutine add_convex_corner_hint

   !> The name of the contact group of candidate c.
   function group_name(model, c) result(name)
      type(model_t), intent(in) :: model
      integer, intent(in) :: c
      character(len=:), allocatable :: name
      name = 'unnamed'
      if (.not. allocated(model%contact_groups)) return
      if (model%contacts(c)%group < 1 .or. model%contacts(c)%group > size(model%contact_groups)) return
      if (allocated(model%contact_groups(model%contacts(c)%group)%name)) &
         name = model%contact_groups(model%contacts(c)%group)%name
   end function group_name

end module uniarc_path_failure
