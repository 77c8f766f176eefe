!> The elastic–perfectly plastic law of a compression-only medium (`*FOUNDATION` or `*SPRING` with
!> QU=; docs/theory.md §3.9): the bearing and the plastic slip of a soil spring as pipeline soil-spring
!> guidelines specify them (ASCE/ALA 2001, "Guidelines for the design of buried steel pipe", bilinear
!> bearing springs).
!>
!> A plastic candidate c (contact_candidate_t%plastic) has the bearing limit q_c = yield_force and a
!> plastic slip s_c (length, along the penetration −a_c; ≥ 0 without an uplift limit): the medium's
!> surface has sunk by s_c, so that its gap is g_c + s_c. Over a step from the committed slip s_n, with Δs_c = s_c − s_n:
!>
!>     w_c = g_c + s_n + Δs_c + t_c r_c ≥ 0,   r_c ≥ 0,   w_c r_c = 0      (contact, the gap with slip)
!>     y_c = q_c − r_c ≥ 0,   Δs_c ≥ 0,   y_c Δs_c = 0                     (bearing limit, the slip)
!>
!> both linear in (u, r, Δs) at fixed geometry: an LCP of one more pair per plastic candidate (Maier
!> 1970; Cottle, Pang & Stone 1992, §1.2). A candidate is open (r = 0), elastic (w = 0, Δs = 0,
!> 0 ≤ r ≤ q) or yielding (r = q, Δs = −(g + s_n + t q) ≥ 0, w = 0). The analysis keeps a yielding
!> candidate in the working set with the equation r = q (`yielding`), and the yield pairs are exchanged
!> by the block rule of `yield_rule` (Júdice & Pires 1994; Hintermüller, Ito & Kunisch 2002 for bound
!> constraints) while the contact pairs of the frame are the contact LCP's (Lemke, block pivoting).
!> The slip is history: `commit_slip` moves it on with a converged step only.
!>
!> With an uplift limit (TU=, contact_candidate_t%uplift_force = T_c > 0) the spring is bonded while
!> elastic and yields in tension too, r ≥ −T_c, with the same slip s (ASCE/ALA 2001, bilinear bearing
!> and uplift springs): two yield pairs per candidate, the contact pair gone (t_c the flexibility),
!>
!>     w_c = g_c + s_n + Δs⁺ − Δs⁻ + t_c r_c = 0                      (bonded, the gap with slip)
!>     q_c − r_c ≥ 0,  Δs⁺ ≥ 0,  (q_c − r_c) Δs⁺ = 0                  (bearing limit)
!>     T_c + r_c ≥ 0,  Δs⁻ ≥ 0,  (T_c + r_c) Δs⁻ = 0                  (uplift limit)
!>
!> At most one of the two pairs is pivoted (r = q and r = −T exclude each other); which one is read
!> off the sign of the reaction (`limit_force`), which the yield rule finds beyond q or below −T when it
!> pivots the pair and the row r = q or r = −T then keeps (docs/theory.md §3.9). A yielding
!> candidate's row is r = limit_force.
!>
!> With its own uplift stiffness (KU=, contact_candidate_t%uplift_flexibility = 1/k_u > 0) the elastic
!> law is bilinear at δ = −(g + s) = 0: r = k δ in compression, r = k_u δ in tension. Its kink is one
!> more complementarity pair (docs/theory.md §3.9, "Two stiffnesses"), exchanged as the yield pairs
!> are, at every Newton state: the branch is the sign of the candidate's force there
!> (`branch_flexibility`), so that the row is g + s + t(r) r = 0 with t(r) = 1/k for r ≥ 0 and 1/k_u
!> for r < 0, continuous in r.
module uniarc_contact_plastic
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, contact_candidate_t
   use uniarc_dof_map, only: dof_map_t, candidate_live
   use uniarc_contact_law, only: candidate_gap
   implicit none
   private
   public :: has_plastic, slip_shift, shifts_gap, yield_rule, plastic_violation, commit_slip, slip_increment, limit_force
   public :: branch_flexibility, branch_changed

contains

   !> Whether the model has a candidate with a bearing limit.
   pure logical function has_plastic(model)
      type(model_t), intent(in) :: model
      has_plastic = .false.
      if (allocated(model%contacts)) has_plastic = any(model%contacts%plastic)
   end function has_plastic

   !> The slip that shifts candidate c's gap: slip(c) for a plastic candidate, and for a tangential
   !> spring that follows a radial partner (contact_candidate_t%partner) its anchor −a_c along a path
   !> (the gap t·u − a_c: the spring is stress-free where its contact last closed, docs/theory.md
   !> §3.8); 0 otherwise or when no slip is given (so that the gaps of elastic media are the contact
   !> law's, bit for bit).
   pure real(dp) function slip_shift(model, c, slip) result(shift)
      type(model_t), intent(in) :: model
      integer, intent(in) :: c
      real(dp), intent(in), optional :: slip(:)
      shift = 0.0_dp
      if (.not. present(slip)) return
      if ((model%contacts(c)%plastic .or. model%contacts(c)%partner > 0) .and. c <= size(slip)) shift = slip(c)
   end function slip_shift

   !> Whether candidate c's gap is shifted by its slip (slip_shift): every plastic candidate, and a
   !> tangential spring that follows a partner when a slip (its anchor, along a path) is given.
   pure logical function shifts_gap(model, c, with_slip)
      type(model_t), intent(in) :: model
      integer, intent(in) :: c
      logical, intent(in) :: with_slip   !< a slip array is given
      shifts_gap = model%contacts(c)%plastic .or. (model%contacts(c)%partner > 0 .and. with_slip)
   end function shifts_gap

   !> The limit force a yielding candidate holds: its bearing limit q (force, ≥ 0, pushing); with an
   !> uplift limit t (TU=) and a negative `force`, −t (pulling). `force` tells the side: the reaction
   !> unknown of a candidate with a reaction row (at its limit it keeps that limit's sign from one
   !> Newton iterate to the next), the elastic force −(g + s_n)/t of a condensed spring.
   pure real(dp) function limit_force(candidate, force) result(limit)
      type(contact_candidate_t), intent(in) :: candidate
      real(dp), intent(in) :: force
      limit = candidate%yield_force
      if (candidate%uplift_force > 0.0_dp .and. force < 0.0_dp) limit = -candidate%uplift_force
   end function limit_force

   !> The flexibility of candidate c's elastic branch at the force `force`: 1/k_u (uplift_flexibility)
   !> where the candidate has its own uplift stiffness and force < 0 (tension), else 1/k (flexibility).
   !> `force` tells the branch: the reaction unknown of a candidate with a reaction row, the elastic
   !> deformation δ = −(g + s) of a condensed spring (its force has the sign of δ on either branch).
   !> The kink pair z ≥ 0, z − δ ≥ 0, z (z − δ) = 0 (z = max(δ, 0)) of docs/theory.md §3.9 is complementary
   !> on the branch this names.
   pure real(dp) function branch_flexibility(candidate, force) result(flexibility)
      type(contact_candidate_t), intent(in) :: candidate
      real(dp), intent(in) :: force
      flexibility = candidate%flexibility
      if (candidate%uplift_flexibility > 0.0_dp .and. force < 0.0_dp) flexibility = candidate%uplift_flexibility
   end function branch_flexibility

   !> Whether a candidate with its own uplift stiffness (KU=) is on another branch of its elastic law at
   !> the unknowns `after` than at `before` (both (n), with the committed slip `slip`): the sign of its
   !> force (its reaction unknown, or δ = −(g + s) of a condensed spring) changed. The tangent of such a
   !> step jumps from k to k_u (or back) within it, so its corrector is O(Δl) from a predictor of the
   !> tangent at its start, as a step whose working set changed (docs/theory.md §3.9, "Two stiffnesses").
   pure logical function branch_changed(model, map, before, after, slip)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: before(:), after(:)
      real(dp), intent(in), optional :: slip(:)
      integer :: c
      branch_changed = .false.
      if (.not. allocated(model%contacts)) return
      do c = 1, size(model%contacts)
         if (.not. (model%contacts(c)%uplift_flexibility > 0.0_dp .and. candidate_live(map, c))) cycle
         if ((elastic_side(c, before) < 0.0_dp) .neqv. (elastic_side(c, after) < 0.0_dp)) then
            branch_changed = .true.
            return
         end if
      end do

   contains

      !> A number of the sign of candidate c's elastic force at the unknowns x.
      pure real(dp) function elastic_side(c, x) result(side)
         integer, intent(in) :: c
         real(dp), intent(in) :: x(:)
         real(dp) :: u(2), gap, gradient(2), hessian(2, 2)
         integer :: node, k
         if (map%candidate_equation(c) > 0) then
            side = x(map%candidate_equation(c))
            return
         end if
         node = model%contacts(c)%node
         u = 0.0_dp
         do k = 1, 2
            if (map%equation(k, node) > 0) u(k) = x(map%equation(k, node))
         end do
         call candidate_gap(model%contacts(c), model%coordinates(:, node), u, gap, gradient, hessian)
         side = -(gap + slip_shift(model, c, slip))
      end function elastic_side
   end function branch_changed

   !> Δs = −(g + t r_y) of a yielding candidate whose gap with the committed slip is `gap` (g + s_n),
   !> r_y = limit_force(candidate, force): the signed slip increment that keeps w = 0 at r = r_y,
   !> non-negative in bearing and non-positive in uplift while the candidate still yields.
   pure real(dp) function slip_increment(candidate, gap, force) result(increment)
      type(contact_candidate_t), intent(in) :: candidate
      real(dp), intent(in) :: gap, force
      real(dp) :: limit
      limit = limit_force(candidate, force)
      ! t of the branch the limit lies on: at r = −t_u the uplift one (1/k_u)
      increment = -(gap + branch_flexibility(candidate, limit)*limit)
   end function slip_increment

   !> The multiplier of the pivoted yield pair: Δs⁺ = Δs in bearing, Δs⁻ = −Δs in uplift (≥ 0 while
   !> the candidate yields).
   pure real(dp) function slip_multiplier(candidate, gap, force) result(multiplier)
      type(contact_candidate_t), intent(in) :: candidate
      real(dp), intent(in) :: gap, force
      multiplier = slip_increment(candidate, gap, force)
      if (limit_force(candidate, force) < 0.0_dp) multiplier = -multiplier
   end function slip_multiplier

   !> The larger violation of the elastic range −t ≤ r ≤ q (force; only r − q without an uplift limit).
   pure real(dp) function elastic_excess(candidate, reaction) result(excess)
      type(contact_candidate_t), intent(in) :: candidate
      real(dp), intent(in) :: reaction
      excess = reaction - candidate%yield_force
      if (candidate%uplift_force > 0.0_dp) excess = max(excess, -candidate%uplift_force - reaction)
   end function elastic_excess

   !> The block exchange of the yield pairs at a state in equilibrium: an elastic candidate of the
   !> working set whose reaction exceeds its limit starts to yield (r > q, or r < −t with an uplift
   !> limit: y < 0), a yielding one whose slip multiplier would be negative unloads elastically
   !> (Δs⁺ < 0 in bearing, Δs⁻ < 0 in uplift), each beyond `tolerance` × the
   !> force and gap units. Only candidates of the set `active` yield.
   !> reaction, gap (per candidate): reactions (r = q when yielding) and gaps with the committed slip.
   pure subroutine yield_rule(model, map, reaction, gap, active, yielding, force_unit, gap_unit, tolerance, &
                              new_yielding)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: reaction(:), gap(:)
      logical, intent(in) :: active(:), yielding(:)
      real(dp), intent(in) :: force_unit, gap_unit, tolerance
      logical, intent(out) :: new_yielding(:)
      integer :: c
      new_yielding = yielding .and. active
      do c = 1, size(yielding)
         if (.not. (model%contacts(c)%plastic .and. candidate_live(map, c) .and. active(c))) cycle
         if (yielding(c)) then
            if (-slip_multiplier(model%contacts(c), gap(c), reaction(c))/gap_unit > tolerance) new_yielding(c) = .false.
         else
            if (elastic_excess(model%contacts(c), reaction(c))/force_unit > tolerance) new_yielding(c) = .true.
         end if
      end do
   end subroutine yield_rule

   !> Largest relative violation of the yield pairs: (r − q)/r_scale (and (−t − r)/r_scale with an uplift
   !> limit) for an elastic candidate of the set, −Δs⁺/g_scale or −Δs⁻/g_scale for a yielding one (0
   !> when there is no plastic candidate).
   pure real(dp) function plastic_violation(model, map, reaction, gap, active, yielding, r_scale, g_scale) &
      result(worst)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: reaction(:), gap(:)
      logical, intent(in) :: active(:), yielding(:)
      real(dp), intent(in) :: r_scale, g_scale
      integer :: c
      worst = 0.0_dp
      do c = 1, size(yielding)
         if (.not. (model%contacts(c)%plastic .and. candidate_live(map, c) .and. active(c))) cycle
         if (yielding(c)) then
            worst = max(worst, -slip_multiplier(model%contacts(c), gap(c), reaction(c))/g_scale)
         else
            worst = max(worst, elastic_excess(model%contacts(c), reaction(c))/r_scale)
         end if
      end do
   end function plastic_violation

   !> Commit a converged step: the slip of every yielding candidate moves on by its increment
   !> Δs = −(g + s_n + t r_y) at the converged unknowns x (their nodal displacements `nodal` (3,
   !> n_nodes)), r_y = q (Δs ≥ 0) or −t in uplift (Δs ≤ 0), the side that of the reaction (its unknown,
   !> or −(g + s_n)/t of a condensed spring); the others keep theirs (the slip stays after unloading).
   pure subroutine commit_slip(model, map, x, nodal, yielding, slip)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: x(:), nodal(:, :)
      logical, intent(in) :: yielding(:)
      real(dp), intent(inout) :: slip(:)
      real(dp) :: gap, gradient(2), hessian(2, 2), force
      integer :: c, node
      do c = 1, size(yielding)
         if (.not. (yielding(c) .and. model%contacts(c)%plastic .and. candidate_live(map, c))) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, gradient, hessian)
         if (map%candidate_equation(c) > 0) then
            force = x(map%candidate_equation(c))
         else
            ! the elastic force's sign is that of δ = −(g + s_n) on either branch
            force = -(gap + slip(c))/branch_flexibility(model%contacts(c), -(gap + slip(c)))
         end if
         if (limit_force(model%contacts(c), force) < 0.0_dp) then
            slip(c) = slip(c) + min(0.0_dp, slip_increment(model%contacts(c), gap + slip(c), force))
         else
            slip(c) = slip(c) + max(0.0_dp, slip_increment(model%contacts(c), gap + slip(c), force))
         end if
      end do
   end subroutine commit_slip

end module uniarc_contact_plastic
