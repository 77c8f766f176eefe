!> The equilibrium check of the linear static analysis (docs/contracts.md, docs/theory.md §3.4): before
!> a result is written, the structure as a whole must be in equilibrium under the loads, the supports'
!> reactions and the contact forces of the media — the resultant force (x, y) and the resultant moment
!> of all of them vanish to round-off:
!>     Σ_i (P_i + S_i + C_i) = 0,   Σ_i (x_i × (P_i + S_i + C_i) + m_i) = 0,
!> P the applied loads (every DOF, held or free), S the supports' reactions (uniarc_support_reactions:
!> the elements' forces of their deformations minus the loads at each held DOF, so that a contact force
!> there is counted in S), C the contact forces a_c r_c of the candidates in contact at free DOFs (the
!> reactions of beds, springs, obstacles and tangential springs, on the initial geometry as the linear
!> analysis takes them). A Pasternak bed acts on the structure through its contact points only, so its
!> shear layer and end springs are inside C. The check measures the resultant against the sum of the
!> magnitudes of the forces in it; a linear solve that leaves more than balance_tolerance of them
!> unbalanced is an analysis error (exit 1) and nothing is written.
module uniarc_static_balance
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_model, only: model_t, dofs_per_node
   use uniarc_contact, only: candidate_gap, in_set
   use uniarc_support_reactions, only: support_reactions
   use uniarc_strings, only: real_to_string
   implicit none
   private
   public :: check_static_balance, static_imbalance, balance_tolerance

   !> The balance asked of a linear result: that of a converged state of the path, whose residual is
   !> at most the force tolerance (default 1e-8) of the force scale and whose floating structure
   !> balances as a whole to it (docs/theory.md §3.4): *STATIC is held to no stricter standard than
   !> *PATH, CONTROL=LOAD on the same model. Round-off: the refined solve (uniarc_linear_static,
   !> refine_solution) leaves a residual of order ε Σ_j |K_ij u_j| per row (componentwise backward
   !> stability after one refinement step, Higham 2002, *Accuracy and Stability of Numerical
   !> Algorithms*, §12.2), so the resultant over a floating motion's rows grows with the ratio of the
   !> element terms to the springs that hold the motion (its condition): measured 3.9e-9 of the forces
   !> for a footing (EI = 1e5, 200 elements) on a bed of modulus 1, a ratio 1.2e14, whose result is
   !> right to that (the relative error of the rigid motion is the relative imbalance; *PATH accepts it).
   !> A solution that is wrong leaves orders more: 1.2e-3 (a cantilever of 10 000 elements, condition
   !> 1e16), 1.4e-2 (a footing EI = 1e9 on 20 elements), 1e-5 to 2e-3 unrefined. 1e-9 refused the first.
   real(dp), parameter :: balance_tolerance = 1.0e-8_dp

contains

   !> An error (analysis) when the state `displacement` (dofs_per_node, n_nodes; with the prescribed
   !> displacements) and contact `reactions` (one per candidate) with the working set `active` of the
   !> linear analysis of `model` at λ = 1 leave an imbalance above balance_tolerance (static_imbalance).
   subroutine check_static_balance(model, displacement, reactions, active, error)
      type(model_t), intent(inout) :: model   !< unchanged (inout for support_reactions' copy_model)
      real(dp), intent(in) :: displacement(:, :)
      real(dp), intent(in) :: reactions(:)
      logical, intent(in) :: active(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: imbalance
      call static_imbalance(model, displacement, reactions, active, imbalance, error)
      if (allocated(error)) return
      if (imbalance <= balance_tolerance) return
      call make_error(error, 'linear static analysis: the solution is not in equilibrium: the loads, the '// &
                      'supports'' reactions and the contact forces leave a resultant of '// &
                      real_to_string(imbalance)//' of their sum (at most '//real_to_string(balance_tolerance)// &
                      ' accepted): the stiffness matrix is too badly conditioned for the solve (a member far '// &
                      'stiffer than what holds it, or a slender member cut into very many short elements); '// &
                      'no result file written', error_analysis)
   end subroutine check_static_balance

   !> The relative imbalance of a linear static state (module header): max(|ΣF_x|, |ΣF_y|, |ΣM|/ℓ)
   !> over Σ|F| + Σ|m|/ℓ (the magnitudes of the forces' components and couples), ℓ the largest distance of a node from the
   !> nodes' centroid (the moments' point). Errors: an allocation of the supports' reactions.
   subroutine static_imbalance(model, displacement, reactions, active, imbalance, error)
      type(model_t), intent(inout) :: model   !< unchanged (inout for support_reactions' copy_model)
      real(dp), intent(in) :: displacement(:, :)
      real(dp), intent(in) :: reactions(:)
      logical, intent(in) :: active(:)
      real(dp), intent(out) :: imbalance
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: supports(:, :), loads(:, :), nodal(:, :)
      real(dp) :: gap, gradient(2), hessian(2, 2), force(2), moment, centre(2), arm(2), scale, length
      integer :: c, i, node
      imbalance = 0.0_dp
      call support_reactions(model, displacement, 1.0_dp, .true., supports, error=error, loads=loads)
      if (allocated(error)) return
      nodal = loads + supports
      scale = sum(abs(loads(1:2, :))) + sum(abs(supports(1:2, :)))
      do c = 1, min(size(reactions), size(model%contacts))
         if (.not. in_set(model, active, c)) cycle
         node = model%contacts(c)%node
         ! the reaction along the normal at the state: a plane's is constant; a curved or polyline
         ! obstacle's is the one the linear analysis re-linearised its gap at (uniarc_linear_static)
         call candidate_gap(model%contacts(c), model%coordinates(:, node), displacement(1:2, node), gap, gradient, &
                            hessian)
         do i = 1, 2
            if (model%fixed(i, node)) cycle   ! carried by the support, counted in its reaction
            nodal(i, node) = nodal(i, node) + gradient(i)*reactions(c)
            scale = scale + abs(gradient(i)*reactions(c))
         end do
      end do
      if (model%n_nodes == 0 .or. scale <= 0.0_dp) return
      centre = sum(model%coordinates, dim=2)/model%n_nodes
      length = tiny(1.0_dp)
      force = 0.0_dp
      moment = 0.0_dp
      do i = 1, model%n_nodes
         arm = model%coordinates(:, i) - centre
         length = max(length, norm2(arm))
         force = force + nodal(1:2, i)
         moment = moment + arm(1)*nodal(2, i) - arm(2)*nodal(1, i) + nodal(3, i)
      end do
      scale = scale + (sum(abs(loads(3, :))) + sum(abs(supports(3, :))))/length
      imbalance = max(abs(force(1)), abs(force(2)), abs(moment)/length)/scale
   end subroutine static_imbalance

end module uniarc_static_balance
