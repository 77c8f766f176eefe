!> Unilateral contact of the structure with foundations and obstacles: the contact rows of the augmented
!> system (docs/theory.md §3; the path file's contact columns are uniarc_contact_summary's). The gaps and
!> their derivatives are the contact law's (uniarc_contact_law).
!>
!> Every candidate c has a gap g_c(u) ≥ 0 (positive = open), a reaction r_c ≥ 0 acting on its node along
!> a_c = ∂g_c/∂u (the direction in which the gap opens), and a flexibility t_c (1/k; 0 = rigid), with
!> the complementarity conditions of the paper (Eqs. 25, 32):
!>     w_c = g_c + t_c r_c ≥ 0,   r_c ≥ 0,   w_c r_c = 0.
!> For a given working set S (the candidates taken in contact) the equations are smooth: the reactions
!> are unknowns of an augmented system, numbered with their nodes so that it stays banded:
!>     [ K_T − Σ r_c ∂a_c/∂u   −a_c ] [δu]   [ λR − F + Σ a_c r_c ]
!>     [ −a_cᵀ                 −t_c ] [δr] = [ g_c + t_c r_c      ]   for c ∈ S (w_c = 0 enforced)
!>     [ 0                      1   ]        [ −r_c               ]   for c ∉ S (r_c = 0)
!> The −a_c columns of inactive candidates are kept: they are how a reaction acts when the LCP asks.
!>
!> A foundation's tangential spring that follows its radial partner (contact_candidate_t%partner) is
!> never a variable of the LCP. In the static analysis it is in the set only with its partner
!> (`in_set`), switched with it; along a path its own flag is history, set at each commit from its
!> partner's committed status, and its gap is shifted by its anchor (docs/theory.md §3.8).
!>
!> A point of a Pasternak bed (docs/theory.md §3.10) is a rigid contact with the bed's surface, whose
!> deflection d_c (into the bed) is an unknown of its own (dof_map_t%bed_equation): its gap is
!> g_c + d_c, so the row in the set reads −a_cᵀδu − δd_c = g_c + d_c, and the bed's row is its
!> equilibrium Σ_j K_b(c, j) d_j − r_c = 0 (F_aug = K_b d − r there, tangent K_b and −1 at r_c).
!>
!> A rigid candidate whose gap gradient a_c has no component on its node's free translations at the
!> state (`held_by_support`: the normal of a curved obstacle along a held DOF — the vertex of an ellipse
!> beside a node held in x, a polyline's face parallel to the line a roller lets its node move on) has a
!> row −a_cᵀ = 0 and a column −a_c = 0: in the set the augmented matrix would be singular, though the
!> structure is not a mechanism. Its gap does not change with the free DOFs (to first order) and its
!> reaction would act on the support alone, which carries it: the candidate keeps the row of a free
!> one (r_c = 0) wherever the working set puts it, the LCP leaves it out and the path's sign rule takes
!> it out of the set (docs/theory.md §3.1). A rigid plane with such a normal never has a row at all
!> (uniarc_dof_map: candidate_held_normal); a curved obstacle's normal turns with the node, so the
!> test is made at every state.
!>
!> A rigid candidate that touches a curved obstacle where the gap, along its node's free translations,
!> has a minimum of (within a tolerance) zero is `grazing`: the tip of a bar held in y pushed in x over
!> the top of a circle. The gap there never goes negative whatever the free DOFs do, so the constraint
!> g ≥ 0 is not binding and its reaction is zero. Closed, it would have to balance the push with r a_f,
!> a_f its free gradient, which tends to 0 at the tangency: Newton converges a hair before it (a_f ~
!> 1e-8) with r ~ 1e7 times the load, a stop that does not exist. The path's sign rule, its
!> complementarity check and the contact LCP take a grazing candidate out of the set (uniarc_path_contact_set,
!> uniarc_contact_lcp); it keeps its row and re-enters if the node later penetrates. The test is of
!> second order (docs/theory.md §3.1): with a_f, H_f the gap's gradient and Hessian on the free
!> translations at the state, H_f positive definite, the gap's quadratic model has its minimum
!>     g_min = g − ½ a_fᵀ H_f⁻¹ a_f          (Newton's step to it: δ = −H_f⁻¹ a_f),
!> and the candidate grazes where g ≤ τ and g_min ≥ −τ, τ the gap tolerance of the complementarity
!> check. Both bounds together keep |δ| ≤ √(4τ/h_min), where the quadratic model is exact to
!> O(|δ|³): the test is local. A node with both translations free beside a circle or an ellipse
!> has H_f singular along the normal (its gap falls linearly there): never grazing.
!>
!> A spring no stiffer than the structure at its node is condensed (uniarc_dof_map): it has no row;
!> in the set its reaction is r_c = −g_c/t_c, a function of u, which adds −a_c r_c to F and
!> a_c a_cᵀ/t_c − r_c ∂a_c/∂u to the tangent (the row above eliminated); out of the set it adds nothing.
module uniarc_contact
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, contact_candidate_t, analysis_linear, gap_fixed_direction
   use uniarc_contact_law, only: candidate_gap
   use uniarc_contact_plastic, only: slip_shift, shifts_gap, limit_force, branch_flexibility
   use uniarc_dof_map, only: dof_map_t
   use uniarc_band, only: band_matrix_t, band_add, band_set
   implicit none
   private
   ! candidate_gap is the contact law's (uniarc_contact_law), made public here too for the solvers that
   ! take it from this module.
   public :: candidate_gap, assemble_contact, toggle_contacts, set_membership
   public :: in_set, held_by_support, carried_by_support, grazing

   !> A gap gradient whose components on the node's free translations are at most this fraction of its
   !> length moves only along held DOFs (held_by_support): the round-off of a unit normal's component
   !> across an axis (cos 90° = 6e-17) is far below, and a component this small makes the reaction's row
   !> of K_S a pivot of 1e-12 of its neighbours, a reaction a million million times the load it carries.
   !> The tolerance of the rigid planes' candidate_held_normal (uniarc_dof_map), the same test.
   real(dp), parameter :: held_gradient_tolerance = 1.0e-12_dp

contains


   !> Add the contact rows and columns of the augmented system at nodal displacements u (3, n) and
   !> reactions r (one per candidate) for the working set `active`; `internal` receives the contact
   !> part of F_aug so that the residual is λR − F_aug (see the module header for the rows).
   !> With plastic candidates (uniarc_contact_plastic): `slip` (one per candidate) shifts their gaps,
   !> and a `yielding` candidate of the set has the row r = q (augmented) or the constant force q along
   !> a_c without stiffness (condensed), its bearing limit q (docs/theory.md §3.9).
   !> `deflections` (one per candidate, default 0): the Pasternak bed's surface deflections d_c.
   !> `lambda` (default 0): the load factor of the state, where a moving curved obstacle stands
   !> (contact_candidate_t%motion; docs/theory.md §3.11).
   subroutine assemble_contact(model, map, displacement, reactions, active, tangent, internal, slip, yielding, &
                               deflections, reference, lambda)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: displacement(:, :)
      real(dp), intent(in) :: reactions(:)
      logical, intent(in) :: active(:)
      type(band_matrix_t), intent(inout) :: tangent
      real(dp), intent(inout) :: internal(:)
      real(dp), intent(in), optional :: slip(:)
      logical, intent(in), optional :: yielding(:)
      real(dp), intent(in), optional :: deflections(:)
      !> R (n): a moving obstacle's row in the set gets ∂g/∂λ (contact_candidate_t%gap_rate), so that the
      !> residual λR − F_aug of the row is its gap g(u) + λ ∂g/∂λ + t r (docs/theory.md §3.11)
      !> a moving curved obstacle's gap is exact in λ (candidate_gap), so its rows keep
      !> λR − F_aug = g(u, λ) + t r with R = ∂g/∂λ at the state, and its equilibrium rows get the
      !> λ-derivative of −a r in R likewise (the residual unchanged, the tangent exact)
      real(dp), intent(in), optional :: lambda
      real(dp), intent(inout), optional :: reference(:)
      real(dp) :: gap, gradient(2), hessian(2, 2), rate, at, swing(2), flexibility
      integer :: c, i, j, row, node, eq(2), bed
      logical :: yields, curved, carried
      ! no copy of `deflections` (a hot path): read where present, 0 otherwise (add_bed_row, d_c below)
      at = 0.0_dp
      if (present(lambda)) at = lambda
      do c = 1, size(map%candidate_equation)
         bed = map%bed_equation(c)
         if (bed > 0) call add_bed_row(model%contacts(c), map, c, reactions(c), tangent, internal, deflections)
         row = map%candidate_equation(c)
         yields = .false.
         if (present(yielding)) yields = yielding(c) .and. model%contacts(c)%plastic
         if (map%condensed(c)) then
            if (in_set(model, active, c)) call add_condensed_spring(model%contacts(c), model%coordinates(:, model%contacts(c)%node), &
                                                     displacement(1:2, model%contacts(c)%node), &
                                                     map%equation(1:2, model%contacts(c)%node), tangent, internal, &
                                                     slip_shift(model, c, slip), yields, &
                                                     shifts_gap(model, c, present(slip)))
            cycle
         end if
         if (row == 0) cycle
         associate (candidate => model%contacts(c))
            node = candidate%node
            eq = map%equation(1:2, node)
            call candidate_gap(candidate, model%coordinates(:, node), displacement(1:2, node), gap, &
                               gradient, hessian, at, rate)
            curved = any(candidate%motion /= 0.0_dp)
            carried = held_by_support(row, eq, gradient, candidate%flexibility, bed)
            if (shifts_gap(model, c, present(slip))) gap = gap + slip_shift(model, c, slip)
            if (present(deflections)) then
               gap = gap + deflections(c)
            else
               gap = gap + 0.0_dp   ! as with d_c = 0 before: a gap of −0 becomes +0
            end if
            ! a moving curved obstacle: ∂(a r)/∂λ = −r h d, moved from F_aug into R (module header)
            swing = 0.0_dp
            if (curved .and. present(reference)) swing = -reactions(c)*matmul(hessian, candidate%motion)
            do i = 1, 2
               if (eq(i) == 0) cycle
               ! Equilibrium rows: −a_c r_c in F_aug; its derivative −r ∂a/∂u in the tangent.
               internal(eq(i)) = internal(eq(i)) - gradient(i)*reactions(c)
               if (curved .and. present(reference)) then
                  internal(eq(i)) = internal(eq(i)) + at*swing(i)
                  reference(eq(i)) = reference(eq(i)) + swing(i)
               end if
               call band_add(tangent, eq(i), row, -gradient(i))
               do j = 1, 2
                  if (eq(j) > 0) call band_add(tangent, eq(i), eq(j), -reactions(c)*hessian(i, j))
               end do
            end do
            if (in_set(model, active, c) .and. yields) then
               ! at the bearing limit: r = q (or at the uplift limit, r = −t: limit_force)
               internal(row) = reactions(c) - limit_force(candidate, reactions(c))
               call band_add(tangent, row, row, 1.0_dp)
            else if (in_set(model, active, c) .and. .not. carried) then
               ! t of the branch the reaction is on (1/k_u in tension with KU=; docs/theory.md §3.9):
               ! g + t(r) r is continuous and piecewise linear in r, its derivative t(r)
               flexibility = branch_flexibility(candidate, reactions(c))
               internal(row) = -(gap + flexibility*reactions(c))
               do i = 1, 2
                  if (eq(i) > 0) call band_add(tangent, row, eq(i), -gradient(i))
               end do
               call band_add(tangent, row, row, -flexibility)
               if (bed > 0) call band_add(tangent, row, bed, -1.0_dp)
               if (present(reference) .and. candidate%gap_rate /= 0.0_dp) reference(row) = candidate%gap_rate
               if (present(reference) .and. curved) then
                  ! g(u, λ) is in F_aug whole: R = ∂g/∂λ there, and λR taken back out of F_aug
                  reference(row) = rate
                  internal(row) = internal(row) + at*rate
               end if
            else
               ! out of the set, or carried by its node's support (module header): r = 0
               internal(row) = reactions(c)
               call band_add(tangent, row, row, 1.0_dp)
            end if
         end associate
      end do
   end subroutine assemble_contact

   !> Move the candidates `flip` in or out of the working set in an assembled augmented tangent and
   !> its residual λR − F_aug (n) at nodal displacements (3, n_nodes) and reactions (one per
   !> candidate); `active` is the new set. Tangential springs whose radial partner flips move with it. The same result as assembling again with the new set
   !> (assemble_contact; round-off apart), at the cost of the flipped candidates only.
   !> `slip` (optional, one per candidate) shifts the gaps of plastic candidates (assemble_contact); a
   !> yielding candidate is never flipped (uniarc_path_contact_set, sign_rule).
   !> `deflections` (one per candidate, default 0): the Pasternak bed's surface deflections d_c.
   subroutine toggle_contacts(model, map, displacement, reactions, flip, active, tangent, residual, slip, &
                              deflections, lambda, reference)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: displacement(:, :), reactions(:)
      logical, intent(in) :: flip(:), active(:)
      type(band_matrix_t), intent(inout) :: tangent
      real(dp), intent(inout) :: residual(:)
      real(dp), intent(in), optional :: slip(:)
      real(dp), intent(in), optional :: deflections(:)
      !> λ of the state and its R (n): a moving obstacle's gap is g(u) + λ ∂g/∂λ, and its row of R is
      !> ∂g/∂λ in the set, 0 out of it (assemble_contact)
      real(dp), intent(in), optional :: lambda
      real(dp), intent(inout), optional :: reference(:)
      real(dp) :: gap, gradient(2), hessian(2, 2), rate
      logical :: entering
      integer :: c, row, node
      do c = 1, size(flip)
         ! a tangential spring moves with its radial partner (in_set); the set before is active Δ flip,
         ! read where needed (no copy of the set's length)
         entering = in_set(model, active, c)
         if (entering .eqv. in_set_before(c)) cycle
         row = map%candidate_equation(c)
         if (row == 0 .and. .not. map%condensed(c)) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), displacement(1:2, node), gap, &
                            gradient, hessian, lambda, rate)
         if (shifts_gap(model, c, present(slip))) gap = gap + slip_shift(model, c, slip)
         if (present(deflections)) gap = gap + deflections(c)
         if (model%contacts(c)%gap_rate /= 0.0_dp .and. present(lambda)) gap = gap + lambda*model%contacts(c)%gap_rate
         call set_membership(row, map%equation(1:2, node), gap, gradient, hessian, model%contacts(c)%flexibility, &
                             reactions(c), entering, tangent, residual, map%bed_equation(c))
         ! ∂g/∂λ: a plane's gap_rate, a curved obstacle's −a·d at the state (candidate_gap)
         if (rate /= 0.0_dp .and. present(reference) .and. row > 0) reference(row) = &
            merge(rate, 0.0_dp, entering .and. .not. held_by_support(row, map%equation(1:2, node), gradient, &
                                                                     model%contacts(c)%flexibility, map%bed_equation(c)))
      end do

   contains

      !> in_set of candidate i in the set before the flip, active Δ flip.
      pure logical function in_set_before(i)
         integer, intent(in) :: i
         integer :: partner
         in_set_before = active(i) .neqv. flip(i)
         partner = model%contacts(i)%partner
         if (partner > 0 .and. model%analysis%kind == analysis_linear) &
            in_set_before = in_set_before .and. (active(partner) .neqv. flip(partner))
      end function in_set_before

   end subroutine toggle_contacts

   !> Whether candidate c acts in the working set `active` (one flag per candidate): its own flag; and
   !> in the static analysis (*STATIC), for a tangential spring that follows a radial partner
   !> (contact_candidate_t%partner), the partner's too, so that it acts only where the radial contact
   !> is closed. Along a path (*PATH) the tangential spring's own flag is its status, history taken
   !> from its partner's committed status at each commit (uniarc_path_state, commit_tangential;
   !> docs/theory.md §3.8), so that a step's equations do not jump where a radial contact opens.
   pure logical function in_set(model, active, c)
      type(model_t), intent(in) :: model
      logical, intent(in) :: active(:)
      integer, intent(in) :: c
      in_set = active(c)
      if (model%contacts(c)%partner > 0 .and. model%analysis%kind == analysis_linear) &
         in_set = in_set .and. active(model%contacts(c)%partner)
   end function in_set

   !> One candidate entering (`entering`) or leaving the working set, in an assembled augmented tangent
   !> and its residual λR − F_aug: the one place that knows what membership means (module header).
   !> row: its reaction equation (0: a condensed spring); eq (2): its node's translations (0: held);
   !> gap, gradient (2), hessian (2, 2): g, a = ∂g/∂u, ∂a/∂u at the state; flexibility t; reaction: its
   !> unknown's value at the state (augmented rows only).
   !> - condensed spring: a aᵀ/t − r ∂a/∂u with r = −g/t is added (entering) or removed, and its force
   !>   a r moves into or out of the residual of the equilibrium rows;
   !> - augmented row: entering, the row −aᵀ, −t with residual g + t r (w = 0 enforced); leaving, the
   !>   identity row with residual −r (r = 0 enforced).
   !> - a Pasternak bed point (`bed` > 0, its deflection's equation; `gap` then g + d): the row has −1
   !>   at d in the set, 0 out of it.
   !> - a rigid candidate whose gradient moves only along held DOFs (held_by_support) gets the identity
   !>   row entering too: the support carries its reaction (module header).
   subroutine set_membership(row, eq, gap, gradient, hessian, flexibility, reaction, entering, tangent, residual, bed)
      integer, intent(in) :: row, eq(2)
      real(dp), intent(in) :: gap, gradient(2), hessian(2, 2), flexibility, reaction
      logical, intent(in) :: entering
      type(band_matrix_t), intent(inout) :: tangent
      real(dp), intent(inout) :: residual(:)
      integer, intent(in), optional :: bed
      real(dp) :: sign, spring_reaction
      integer :: i, j, bed_row
      bed_row = 0
      if (present(bed)) bed_row = bed
      if (row == 0) then
         sign = -1.0_dp
         if (entering) sign = 1.0_dp
         spring_reaction = -gap/flexibility
         do i = 1, 2
            if (eq(i) == 0) cycle
            residual(eq(i)) = residual(eq(i)) + sign*gradient(i)*spring_reaction
            do j = 1, 2
               if (eq(j) > 0) call band_add(tangent, eq(i), eq(j), &
                                            sign*(gradient(i)*gradient(j)/flexibility - spring_reaction*hessian(i, j)))
            end do
         end do
      else if (entering .and. .not. held_by_support(row, eq, gradient, flexibility, bed_row)) then
         do i = 1, 2
            if (eq(i) > 0) call band_set(tangent, row, eq(i), -gradient(i))
         end do
         call band_set(tangent, row, row, -flexibility)
         if (present(bed)) then
            if (bed > 0) call band_set(tangent, row, bed, -1.0_dp)
         end if
         residual(row) = gap + flexibility*reaction
      else
         do i = 1, 2
            if (eq(i) > 0) call band_set(tangent, row, eq(i), 0.0_dp)
         end do
         call band_set(tangent, row, row, 1.0_dp)
         if (present(bed)) then
            if (bed > 0) call band_set(tangent, row, bed, 0.0_dp)
         end if
         residual(row) = -reaction
      end if
   end subroutine set_membership

   !> Whether a candidate with reaction equation `row` (0: none), node equations eq (2, 0 where held),
   !> gap gradient a = `gradient` (2), flexibility t and Pasternak deflection equation `bed` (0: none)
   !> is carried by its node's support at this state (module header): rigid (t = 0, no bed) with an
   !> augmented row, and no component of a on a free translation above held_gradient_tolerance of |a|.
   pure logical function held_by_support(row, eq, gradient, flexibility, bed) result(held)
      integer, intent(in) :: row, eq(2), bed
      real(dp), intent(in) :: gradient(2), flexibility
      real(dp) :: length
      integer :: k
      held = .false.
      if (row == 0 .or. flexibility /= 0.0_dp .or. bed /= 0) return
      length = norm2(gradient)
      do k = 1, 2
         if (eq(k) > 0 .and. abs(gradient(k)) > held_gradient_tolerance*length) return
      end do
      held = .true.
   end function held_by_support

   !> held_by_support for candidate c of `model` at nodal displacements `nodal` (3, n_nodes) and load
   !> factor `lambda` (a moving obstacle's position; default 0), its gradient from the contact law.
   pure logical function carried_by_support(model, map, c, nodal, lambda) result(held)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      integer, intent(in) :: c
      real(dp), intent(in) :: nodal(:, :)
      real(dp), intent(in), optional :: lambda
      real(dp) :: gap, gradient(2), hessian(2, 2), at
      integer :: node
      held = .false.
      if (map%candidate_equation(c) == 0) return
      if (model%contacts(c)%flexibility /= 0.0_dp .or. map%bed_equation(c) /= 0) return
      ! a fixed direction never turns: one along held DOFs has no row (uniarc_dof_map,
      ! candidate_held_normal, the same test), so a plane with a row is never carried
      if (model%contacts(c)%gap_kind == gap_fixed_direction) return
      at = 0.0_dp
      if (present(lambda)) at = lambda
      node = model%contacts(c)%node
      call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, gradient, hessian, at)
      held = held_by_support(map%candidate_equation(c), map%equation(1:2, node), gradient, &
                             model%contacts(c)%flexibility, map%bed_equation(c))
   end function carried_by_support

   !> Whether candidate c of `model` grazes its obstacle at nodal displacements `nodal` (3, n_nodes) and
   !> load factor `lambda` (a moving obstacle's position) with gap tolerance `tolerance` (absolute, a
   !> length): a rigid, elastic, unbonded candidate with an augmented row and a curved gap, touching
   !> (g ≤ τ), whose gap along its node's free translations has a strict local minimum g_min ≥ −τ
   !> (module header: g_min = g − ½ a_fᵀ H_f⁻¹ a_f). A candidate with no free translation is
   !> carried_by_support's, not this test's.
   pure logical function grazing(model, map, c, nodal, lambda, tolerance) result(grazes)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      integer, intent(in) :: c
      real(dp), intent(in) :: nodal(:, :)
      real(dp), intent(in) :: lambda
      real(dp), intent(in) :: tolerance
      real(dp) :: gap, gradient(2), hessian(2, 2), determinant, lowest
      integer :: node, eq(2), k
      grazes = .false.
      if (map%candidate_equation(c) == 0 .or. map%bed_equation(c) /= 0) return
      associate (candidate => model%contacts(c))
         if (candidate%flexibility /= 0.0_dp .or. candidate%bilateral .or. candidate%plastic) return
         if (candidate%gap_kind == gap_fixed_direction) return   ! a plane's gap is linear: no minimum
         node = candidate%node
         eq = map%equation(1:2, node)
         if (all(eq == 0)) return
         call candidate_gap(candidate, model%coordinates(:, node), nodal(1:2, node), gap, gradient, hessian, lambda)
      end associate
      if (gap > tolerance) return
      if (all(eq > 0)) then
         ! both free: H_f = H must be positive definite (Sylvester), g_min by Cramer's rule
         determinant = hessian(1, 1)*hessian(2, 2) - hessian(1, 2)*hessian(2, 1)
         if (hessian(1, 1) <= 0.0_dp .or. determinant <= 0.0_dp) return
         lowest = gap - 0.5_dp*(hessian(2, 2)*gradient(1)**2 - (hessian(1, 2) + hessian(2, 1))*gradient(1)*gradient(2) &
                                + hessian(1, 1)*gradient(2)**2)/determinant
      else
         k = merge(1, 2, eq(1) > 0)
         if (hessian(k, k) <= 0.0_dp) return
         lowest = gap - 0.5_dp*gradient(k)**2/hessian(k, k)
      end if
      grazes = lowest >= -tolerance
   end function grazing

   !> The row of Pasternak bed point c (module header): F_aug = Σ_j K_b(c, j) d_j − r_c on its deflection's
   !> equation, the tangent K_b(c, ·) on the deflections of c and its neighbours and −1 at its reaction.
   pure subroutine add_bed_row(candidate, map, c, reaction, tangent, internal, deflections)
      type(contact_candidate_t), intent(in) :: candidate
      type(dof_map_t), intent(in) :: map
      integer, intent(in) :: c
      real(dp), intent(in) :: reaction          !< r_c
      type(band_matrix_t), intent(inout) :: tangent
      real(dp), intent(inout) :: internal(:)
      real(dp), intent(in), optional :: deflections(:)    !< (n_contacts) d of every candidate (default 0)
      real(dp) :: d
      integer :: bed, k, neighbours(3)
      bed = map%bed_equation(c)
      neighbours = [candidate%bed_previous, c, candidate%bed_next]
      internal(bed) = -reaction
      do k = 1, 3
         if (neighbours(k) == 0) cycle
         d = 0.0_dp
         if (present(deflections)) d = deflections(neighbours(k))
         internal(bed) = internal(bed) + candidate%bed_stiffness(k)*d
         call band_add(tangent, bed, map%bed_equation(neighbours(k)), candidate%bed_stiffness(k))
      end do
      if (map%candidate_equation(c) > 0) call band_add(tangent, bed, map%candidate_equation(c), -1.0_dp)
   end subroutine add_bed_row

   !> A condensed spring in contact at its node's displacement u (2): reaction r = −g/t on the node
   !> along a = ∂g/∂u (F gets −a r) and its tangent a aᵀ/t − r ∂a/∂u, on the node's equations eq (2).
   !> A plastic one: its gap shifted by its slip `shift`; when `yields`, r = q (its bearing limit) and
   !> the tangent −q ∂a/∂u only (no spring stiffness at the limit); at an uplift limit r = −t likewise.
   !> With its own uplift stiffness (KU=) t is 1/k_u where the spring is stretched (g > 0).
   pure subroutine add_condensed_spring(candidate, x0, u, eq, tangent, internal, shift, yields, shifted)
      type(contact_candidate_t), intent(in) :: candidate
      real(dp), intent(in) :: x0(2), u(2)
      integer, intent(in) :: eq(2)
      type(band_matrix_t), intent(inout) :: tangent
      real(dp), intent(inout) :: internal(:)
      real(dp), intent(in) :: shift
      logical, intent(in) :: yields
      logical, intent(in) :: shifted   !< whether `shift` moves the gap (uniarc_contact_plastic, shifts_gap)
      real(dp) :: gap, gradient(2), hessian(2, 2), reaction, elastic, flexibility
      integer :: i, j
      call candidate_gap(candidate, x0, u, gap, gradient, hessian)
      if (shifted) gap = gap + shift
      ! the branch of the bilinear law (KU=) is the sign of δ = −g (docs/theory.md §3.9)
      flexibility = branch_flexibility(candidate, -gap)
      reaction = -gap/flexibility
      elastic = 1.0_dp
      if (yields) then
         reaction = limit_force(candidate, reaction)   ! the side: the elastic force −g/t
         elastic = 0.0_dp
      end if
      do i = 1, 2
         if (eq(i) == 0) cycle
         internal(eq(i)) = internal(eq(i)) - gradient(i)*reaction
         do j = 1, 2
            if (eq(j) > 0) call band_add(tangent, eq(i), eq(j), &
                                         elastic*(gradient(i)*gradient(j)/flexibility) - &
                                         reaction*hessian(i, j))
         end do
      end do
   end subroutine add_condensed_spring

end module uniarc_contact
