!> The contact LCP of a step (paper Eqs. 26–32), solved on the banded tangent without ever forming
!> its matrix (docs/theory.md §3.3, docs/lemke.md).
!>
!> The paper condenses the structure on the candidates, M = A K⁻¹ Aᵀ + T, a dense m × m matrix that
!> needs K positive definite. uniarc keeps the LCP implicit: its matrix is the operator of the
!> augmented tangent K_S of a working set S (candidates in contact enforced as equalities, the others
!> free), bordered with the linearised path constraint that fixes δλ. In the LCP unknowns this is the
!> principal pivot transform (PPT) of the paper's LCP with respect to S: for c ∉ S the input is the
!> reaction r_c and the output the gap w_c; for c ∈ S the roles are exchanged. A PPT has the same
!> solutions and keeps P-matrix properties (Cottle, Pang & Stone 1992, §2.3), and K_S is regular where
!> K alone is not (a ring resting in a cavity; a path constraint bordering a limit point).
!>
!> `contact_lcp_operator_t` is that LCP as an `lcp_operator_t`: a column or row of M is one banded
!> solve (with K_S or K_Sᵀ), an exchange of candidates is an edit of their rows of K_S and one banded
!> refactorisation, and q of a frame comes afresh from the nonlinear residual. Memory: two band
!> matrices and O(N) vectors, nothing of size m² or N·m. The solver is `uniarc_lcp_implicit`.
module uniarc_contact_lcp
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_copy, only: reserve
   use uniarc_model, only: model_t
   use uniarc_dof_map, only: dof_map_t, candidate_live, bed_deflection
   use uniarc_band, only: band_matrix_t, band_factorize, band_solve, band_solve_transpose, band_copy, &
                          band_move, band_product
   use uniarc_contact, only: candidate_gap, set_membership, in_set, carried_by_support, grazing
   use uniarc_lcp_operator, only: lcp_operator_t
   use uniarc_lcp_implicit, only: implicit_lcp_solve, implicit_lcp_report_t, implicit_lcp_options_t
   use uniarc_lemke, only: lemke_solved, lemke_ray_termination
   implicit none
   private
   public :: path_constraint_t, contact_scales_t, contact_linearization_t, contact_selection_t, select_contact_set
   public :: constraint_arclength, constraint_load, constraint_displacement, degenerate_fraction

   !> A response to the reference load whose displacement is at most this fraction of ψ (the
   !> displacement a unit of λ moves at the unloaded state, path_constraint_t%lambda_scale) moves
   !> nothing: the contacts carry the whole load. A rigid contact under the load leaves round-off of
   !> the solve only; a structure that merely stiffens stays far above (docs/theory.md §2.7).
   real(dp), parameter :: degenerate_fraction = 1.0e-12_dp

   integer, parameter :: constraint_arclength = 1     !< tᵀδu = target (δu the displacement part)
   integer, parameter :: constraint_load = 2          !< δλ = target
   integer, parameter :: constraint_displacement = 3  !< δu(equation) = target

   !> The linearised path constraint that fixes δλ in the LCP.
   type :: path_constraint_t
      integer :: kind = constraint_load
      real(dp), allocatable :: t(:)   !< arc length: direction in displacement space (masked)
      real(dp) :: target = 0.0_dp
      integer :: equation = 0         !< displacement control
      !> arc length: ψ, the displacement norm a unit of λ moves at the start (0: not known); a frame
      !> whose K_S⁻¹R moves at most degenerate_fraction of it along t is degenerate
      real(dp) :: lambda_scale = 0.0_dp
   end type path_constraint_t

   !> Units of the contact quantities: a gap (length) and a reaction (force) are round-off below
   !> `tolerance` times these (the LCP's acceptance test, docs/lemke.md).
   type :: contact_scales_t
      real(dp) :: gap = 1.0_dp
      real(dp) :: force = 1.0_dp
   end type contact_scales_t

   !> The state the contact LCP is linearised at, for the working set it is posed in (n equations).
   type :: contact_linearization_t
      real(dp), allocatable :: x(:)            !< (n) unknowns: displacements and reactions
      real(dp), allocatable :: nodal(:, :)     !< (3, n_nodes) nodal displacements of x
      real(dp), allocatable :: residual(:)     !< (n) g = λR − F_aug for the set
      real(dp), allocatable :: reference(:)    !< (n) R
      real(dp), allocatable :: du_residual(:)  !< (n) K_S⁻¹ g
      real(dp), allocatable :: du_tangent(:)   !< (n) K_S⁻¹ R
      type(path_constraint_t) :: constraint    !< the linearised path constraint that fixes δλ
      type(contact_scales_t) :: units          !< units of gaps and forces (lower bounds)
      !> plastic media (docs/theory.md §3.9), when allocated: the committed slip of every candidate (it
      !> shifts the gaps of the plastic ones) and the candidates at their bearing limit, whose rows
      !> r = q are part of K_S and no variable of this LCP (their yield pairs are exchanged outside it)
      real(dp), allocatable :: slip(:)
      logical, allocatable :: yielding(:)
      !> λ of the state: the gap of a moving obstacle is g(u) + λ ∂g/∂λ (gap_rate, docs/theory.md §3.11)
      real(dp) :: lambda = 0.0_dp
   end type contact_linearization_t

   !> What the contact LCP selects.
   type :: contact_selection_t
      logical, allocatable :: active(:)          !< (candidates) the new working set
      type(implicit_lcp_report_t) :: report      !< pivots, exchanges, solves, status
      !> true if the caller's `tangent` holds on return the band LU of K_S for the new set (the frame
      !> the LCP ended in), with du_tangent = K_S⁻¹R for it: no assembly or factorisation is needed.
      logical :: kept = .false.
      real(dp), allocatable :: du_tangent(:)     !< (n) when kept
      !> the LCP failed in a frame where the path constraint does not fix δλ (its contacts carry the
      !> whole reference load): the caller may pose it again with the load constraint
      logical :: degenerate = .false.
   end type contact_selection_t

   !> The contact LCP at a state, in the frame of a working set (module header).
   type, extends(lcp_operator_t) :: contact_lcp_operator_t
      integer :: m = 0
      integer, allocatable :: row(:)          !< (m) equation of the candidate's reaction (0: condensed)
      integer, allocatable :: eq(:, :)        !< (2, m) equations of its node's translations (0: held)
      !> (m) equation of the Pasternak bed's deflection d under it (0: none); its gap is g + d, so a_c
      !> has a 1 there (docs/theory.md §3.10)
      integer, allocatable :: bed(:)
      real(dp), allocatable :: gradient(:, :) !< (2, m) a_c = ∂g/∂u at the state
      real(dp), allocatable :: hessian(:, :, :)  !< (2, 2, m) ∂a_c/∂u at the state
      real(dp), allocatable :: flexibility(:) !< (m) t_c = 1/k_c (0: rigid)
      real(dp), allocatable :: gap(:)         !< (m) g_c at the state
      !> (m) ∂g_c/∂λ of a moving obstacle (contact_candidate_t%gap_rate; 0 for the others): R of the row
      !> in the set, and the δλ term of the gap of a candidate out of it (docs/theory.md §3.11)
      real(dp), allocatable :: rate(:)
      real(dp), allocatable :: reaction(:)    !< (m) r_c, the unknown at the state
      logical, allocatable :: active(:)       !< (m) the frame: in the working set
      type(band_matrix_t) :: matrix           !< K_S assembled (unfactorised) for the frame
      type(band_matrix_t) :: factors          !< its band LU
      real(dp), allocatable :: residual(:)    !< (n) augmented residual g of the frame
      real(dp), allocatable :: reference(:)   !< (n) reference load R
      real(dp), allocatable :: du_residual(:), du_tangent(:)  !< (n) K_S⁻¹ g, K_S⁻¹ R
      real(dp), allocatable :: border(:)      !< (n) c of the bordering projector P = I − K_S⁻¹R cᵀ
      real(dp), allocatable :: correction(:, :)  !< (n, 2) last refinement corrections of K_S⁻¹g, K_S⁻¹R
      real(dp), allocatable :: round_off(:)   !< (m) estimated round-off of each q_c of the frame
      real(dp) :: tolerance = 1.0e-9_dp       !< the solver's acceptance tolerance (for the units)
      logical :: degenerate = .false.         !< the path constraint does not fix δλ in this frame
      type(path_constraint_t) :: constraint
      type(contact_scales_t) :: units         !< the caller's units (lower bounds)
      type(contact_scales_t) :: frame_units   !< units of the current frame (set by frame_q)
      real(dp), allocatable :: work(:, :)     !< (n, 1) solve buffer
   contains
      procedure :: order => contact_order
      procedure :: frame_q => contact_frame_q
      procedure :: scales => contact_scales
      procedure :: apply => contact_apply
      procedure :: apply_transpose => contact_apply_transpose
      procedure :: exchange => contact_exchange
   end type contact_lcp_operator_t

contains

   !> Solve the contact LCP linearised at the current state and return the new working set.
   !>
   !> In: the `linearization` (unknowns x and nodal displacements, residual g = λR − F_aug and
   !> reference R for the set `active`, K_S⁻¹g and K_S⁻¹R, the path constraint, the units of gaps
   !> and forces); `assembled`, the augmented tangent K_S for `active` (unfactorised), and `tangent`,
   !> its band LU — both workspace: their storage is lent to the LCP and given back with other
   !> contents (unless `selection%kept`, the caller assembles and factorises again for the new set).
   !> Out: `selection` (the new set, the report: pivots, exchanges, solves; whether `tangent` holds
   !> the new set's factors). An LCP that is not solved to the
   !> stated accuracy is an error (category analysis): the caller cuts the step rather than accept a
   !> contact set that is not a solution. When the working set is already right (q ≥ 0, the usual case
   !> along a path) nothing is factorised and no matrix is copied: the step costs what it would
   !> without contact.
   subroutine select_contact_set(model, map, linearization, active, assembled, tangent, selection, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(contact_linearization_t), intent(in) :: linearization
      logical, intent(in) :: active(:)
      type(band_matrix_t), intent(inout) :: assembled, tangent
      type(contact_selection_t), intent(out) :: selection
      type(error_t), allocatable, intent(out) :: error
      type(contact_lcp_operator_t) :: lcp
      integer, allocatable :: unilateral(:)
      real(dp), allocatable :: q(:), w(:), scale(:), reaction(:), gap(:)
      type(implicit_lcp_options_t) :: options
      real(dp) :: r_scale, w_scale
      integer :: c, j, m, status
      real(dp) :: bytes
      logical :: partner_changed
      ! a grazing candidate of `active` left the set: its row is closed in every frame of this LCP, so
      ! no frame's factors are the new set's (selection%kept stays false)
      logical :: dropped

      ! Every array of the model's length allocated with stat= (docs/contracts.md, "Memory"): a
      ! refusal is an out-of-memory error, which ends the run (uniarc_path_state: fail_attempt).
      bytes = 0.0_dp
      call reserve(selection%active, size(active), status, bytes)
      call allocation_failure(status, 'the working set of the contact LCP', bytes, error_analysis, error)
      if (allocated(error)) return
      selection%active(:) = active
      selection%kept = .false.
      dropped = .false.
      ! A rigid candidate whose gap moves only along held DOFs at this state is carried by its node's
      ! support (uniarc_contact, held_by_support): its column of M is zero, it is no variable of the LCP
      ! and leaves the set (its row of K_S is the identity, r = 0, in or out of it). One that grazes its
      ! obstacle (uniarc_contact, grazing) is none either: it leaves the set and keeps its row.
      do c = 1, size(map%candidate_equation)
         if (selection%active(c) .and. .not. model%contacts(c)%bilateral) then
            if (carried_by_support(model, map, c, linearization%nodal, linearization%lambda)) &
               selection%active(c) = .false.
            if (grazes(c)) then
               selection%active(c) = .false.
               dropped = .true.
            end if
         end if
      end do
      ! The unilateral candidates: live, not bilateral, not yielding, not carried by a support.
      m = 0
      do c = 1, size(map%candidate_equation)
         if (unilateral_candidate(c)) m = m + 1
      end do
      allocate (unilateral(m), stat=status)
      call allocation_failure(status, 'the candidates of the contact LCP', 4.0_dp*m, error_analysis, error)
      if (allocated(error)) return
      m = 0
      do c = 1, size(map%candidate_equation)
         if (.not. unilateral_candidate(c)) cycle
         m = m + 1
         unilateral(m) = c
      end do
      call candidate_data(model, map, linearization%x, linearization%nodal, unilateral, active, linearization%lambda, &
                          lcp, error)
      if (allocated(error)) return
      if (allocated(linearization%slip)) then
         do j = 1, lcp%m
            c = unilateral(j)
            if (model%contacts(c)%plastic) then
               lcp%gap(j) = lcp%gap(j) + linearization%slip(c)
               if (lcp%row(j) == 0 .and. lcp%active(j)) lcp%reaction(j) = -lcp%gap(j)/lcp%flexibility(j)
            end if
         end do
      end if
      selection%report%status = lemke_solved
      selection%report%message = 'solved'
      if (lcp%m == 0) return
      ! allocate (..., source=) rather than assignment to the unallocated components: gfortran 12's
      ! reallocation on assignment reads the bounds of the unallocated descriptor first (GCC bug
      ! 77504, an integer overflow under -fsanitize=undefined; docs/testing.md, "Sanitizers").
      bytes = 8.0_dp*size(linearization%du_residual)
      allocate (lcp%du_residual, source=linearization%du_residual, stat=status)
      if (status == 0) allocate (lcp%du_tangent, source=linearization%du_tangent, stat=status)
      if (status == 0) allocate (lcp%border(size(linearization%du_tangent)), stat=status)
      call allocation_failure(status, 'a vector of the contact LCP', bytes, error_analysis, error)
      if (allocated(error)) return
      lcp%constraint = linearization%constraint
      lcp%units = linearization%units
      lcp%tolerance = options%tolerance
      call border_vector(lcp)

      ! q first: when the working set is already right (q ≥ 0 within round-off) the LCP's answer is
      ! the frame itself and nothing more is needed (the warm start that the paper's form cannot have).
      allocate (q(lcp%m), scale(lcp%m), w(lcp%m), lcp%round_off(lcp%m), stat=status)
      call allocation_failure(status, 'the vectors of the contact LCP', 32.0_dp*lcp%m, error_analysis, error)
      if (allocated(error)) return
      call lcp%frame_q(q, error)
      selection%degenerate = lcp%degenerate
      if (allocated(error)) return
      call lcp%scales(scale)
      if (all(q >= -options%tolerance*scale)) then
         selection%report%solves = 1
         return
      end if

      call band_move(assembled, lcp%matrix)
      call band_move(tangent, lcp%factors)
      bytes = 8.0_dp*size(linearization%x)
      allocate (lcp%residual, source=linearization%residual, stat=status)
      if (status == 0) allocate (lcp%reference, source=linearization%reference, stat=status)
      if (status == 0) allocate (lcp%work(size(linearization%x), 1), stat=status)
      if (status /= 0) then
         call band_move(lcp%matrix, assembled)
         call band_move(lcp%factors, tangent)
      end if
      call allocation_failure(status, 'a vector of the contact LCP', bytes, error_analysis, error)
      if (allocated(error)) return
      call implicit_lcp_solve(lcp, w, selection%report, error, options)
      call band_move(lcp%matrix, assembled)
      call band_move(lcp%factors, tangent)
      tangent%factorized = .false.
      ! out of memory within the solver: the run ends (not an LCP without solution)
      if (.not. allocated(error) .and. allocated(selection%report%fatal)) &
         call move_alloc(selection%report%fatal, error)
      ! Under an arc-length constraint a ray is the same degeneracy seen from a frame without the
      ! contacts that would carry the load: the bordered M of those candidates is singular (its
      ! determinant is that of the bordered K_S of the frame with them, a Schur complement; Cottle,
      ! Pang & Stone 1992, §2.3), and the step is longer than the displacement left to reach them.
      selection%degenerate = lcp%degenerate .or. (lcp%constraint%kind == constraint_arclength .and. &
                                                  selection%report%status == lemke_ray_termination)
      if (allocated(error)) return
      if (selection%report%status /= lemke_solved) then
         ! The report's message names the outcome (a ray, the pivot cap, a breakdown) and its cause.
         call make_error(error, 'contact LCP not solved: '//selection%report%message, error_analysis)
         return
      end if

      ! The solution's frame: reactions (outputs of candidates in the set) and gaps (of the others);
      ! in contact where the reaction dominates its complement.
      allocate (reaction(lcp%m), gap(lcp%m), stat=status)
      call allocation_failure(status, 'the reactions and gaps of the contact LCP', 16.0_dp*lcp%m, error_analysis, error)
      if (allocated(error)) return
      do j = 1, lcp%m
         if (lcp%active(j)) then
            reaction(j) = w(j)
            gap(j) = 0.0_dp
         else
            reaction(j) = 0.0_dp
            gap(j) = w(j)
         end if
      end do
      r_scale = max(maxval(abs(reaction)), tiny(1.0_dp))
      w_scale = max(maxval(abs(gap)), tiny(1.0_dp))
      do j = 1, lcp%m
         selection%active(unilateral(j)) = reaction(j)/r_scale > gap(j)/w_scale
      end do
      ! The factors of the final frame serve the caller when the new set is that frame (and no
      ! tangential spring follows a partner that changed: the frames keep them as they were).
      partner_changed = .false.
      do c = 1, size(active)
         if (model%contacts(c)%partner > 0 .and. &
             (in_set(model, selection%active, c) .neqv. in_set(model, active, c))) partner_changed = .true.
      end do
      if (all(selection%active(unilateral) .eqv. lcp%active) .and. .not. partner_changed .and. .not. dropped) then
         tangent%factorized = .true.
         call move_alloc(lcp%du_tangent, selection%du_tangent)   ! the operator's last use of it
         selection%kept = .true.
      end if

   contains

      !> Candidate c is a variable of the LCP: live, not bilateral, not yielding.
      logical function unilateral_candidate(c)
         integer, intent(in) :: c
         unilateral_candidate = candidate_live(map, c) .and. .not. model%contacts(c)%bilateral
         if (unilateral_candidate .and. allocated(linearization%yielding)) &
            unilateral_candidate = .not. linearization%yielding(c)
         if (unilateral_candidate) unilateral_candidate = &
            .not. carried_by_support(model, map, c, linearization%nodal, linearization%lambda)
         if (unilateral_candidate) unilateral_candidate = .not. grazes(c)
      end function unilateral_candidate

      !> Candidate c grazes its obstacle at the linearisation (uniarc_contact, grazing), within the gap
      !> tolerance of the path's complementarity check (uniarc_path_contact_set, violation): its gap
      !> cannot fall below zero along its node's free motion, so it is no variable and not in the set.
      logical function grazes(c)
         integer, intent(in) :: c
         grazes = grazing(model, map, c, linearization%nodal, linearization%lambda, &
                          model%analysis%displacement_tolerance*linearization%units%gap)
      end function grazes
   end subroutine select_contact_set

   !> The per-candidate data of the operator for the unilateral candidates `unilateral`.
   !> Errors: the arrays refused by the system (error_analysis, out of memory).
   subroutine candidate_data(model, map, x, nodal, unilateral, active, lambda, lcp, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: x(:), nodal(:, :)
      integer, intent(in) :: unilateral(:)
      logical, intent(in) :: active(:)
      real(dp), intent(in) :: lambda   !< of the state (moving obstacles)
      type(contact_lcp_operator_t), intent(inout) :: lcp
      type(error_t), allocatable, intent(out) :: error
      integer :: j, c, node, status
      lcp%m = size(unilateral)
      allocate (lcp%row(lcp%m), lcp%eq(2, lcp%m), lcp%bed(lcp%m), lcp%gradient(2, lcp%m), lcp%hessian(2, 2, lcp%m), &
                lcp%flexibility(lcp%m), lcp%gap(lcp%m), lcp%reaction(lcp%m), lcp%active(lcp%m), lcp%rate(lcp%m), &
                stat=status)
      call allocation_failure(status, 'the candidate data of the contact LCP', 124.0_dp*lcp%m, error_analysis, error)
      if (allocated(error)) return
      do j = 1, lcp%m
         c = unilateral(j)
         node = model%contacts(c)%node
         lcp%row(j) = map%candidate_equation(c)
         lcp%eq(:, j) = map%equation(1:2, node)
         lcp%bed(j) = map%bed_equation(c)
         lcp%flexibility(j) = model%contacts(c)%flexibility
         lcp%active(j) = active(c)
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), lcp%gap(j), &
                            lcp%gradient(:, j), lcp%hessian(:, :, j), lambda, lcp%rate(j))
         lcp%gap(j) = lcp%gap(j) + bed_deflection(map, c, x)
         ! a plane's λ ∂g/∂λ (a moving curved obstacle's gap is exact in λ already: candidate_gap)
         if (model%contacts(c)%gap_rate /= 0.0_dp) lcp%gap(j) = lcp%gap(j) + lambda*lcp%rate(j)
         if (lcp%row(j) > 0) then
            lcp%reaction(j) = x(lcp%row(j))
         else if (lcp%active(j)) then
            lcp%reaction(j) = -lcp%gap(j)/lcp%flexibility(j)   ! a condensed spring in contact
         else
            lcp%reaction(j) = 0.0_dp
         end if
      end do
   end subroutine candidate_data

   pure integer function contact_order(self)
      class(contact_lcp_operator_t), intent(in) :: self
      contact_order = self%m
   end function contact_order

   !> q of the frame: with the particular solution p = K_S⁻¹g + δλ K_S⁻¹R (δλ from the constraint),
   !> q_c = g_c + a_cᵀp + t_c (r_c + p_r) (the linearised gap) for c ∉ S, r_c + p_r for c ∈ S.
   !> Also the frame's units: a gap is compared with the largest displacement of the linearised step
   !> (the round-off of q is relative to it, not to the committed displacements, which are 0 at the
   !> first step), a reaction with the largest predicted reaction; the caller's units are lower bounds.
   subroutine contact_frame_q(self, q, error)
      class(contact_lcp_operator_t), intent(inout) :: self
      real(dp), intent(out) :: q(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: particular(:)
      real(dp) :: dlambda, largest_displacement, largest_reaction
      integer :: j, i, status
      if (self%degenerate) then
         q = 0.0_dp
         call make_error(error, 'the path constraint does not fix the load increment with this contact '// &
                         'set (its contacts and the supports carry the whole reference load; load or '// &
                         'displacement control of another node can pass here)', error_analysis)
         return
      end if
      dlambda = bordered_dlambda(self%constraint, self%du_residual, self%du_tangent, self%constraint%target)
      allocate (particular(size(self%du_residual)), stat=status)
      call allocation_failure(status, 'a vector of the contact LCP', 8.0_dp*size(self%du_residual), &
                              error_analysis, error)
      if (allocated(error)) return
      particular(:) = self%du_residual + dlambda*self%du_tangent
      largest_displacement = 0.0_dp
      largest_reaction = 0.0_dp
      do j = 1, self%m
         do i = 1, 2
            if (self%eq(i, j) > 0) largest_displacement = max(largest_displacement, abs(particular(self%eq(i, j))))
         end do
         if (self%bed(j) > 0) largest_displacement = max(largest_displacement, abs(particular(self%bed(j))))
         if (self%row(j) == 0) then
            ! condensed spring: r = −(g + a·p)/t in the set, the gap g + a·p out of it
            if (self%active(j)) then
               q(j) = -(self%gap(j) + along(self, j, particular))/self%flexibility(j)
               largest_reaction = max(largest_reaction, abs(q(j)))
            else
               q(j) = self%gap(j) + along(self, j, particular) + dlambda*self%rate(j)
            end if
         else if (self%active(j)) then
            q(j) = self%reaction(j) + particular(self%row(j))
            largest_reaction = max(largest_reaction, abs(q(j)))
         else
            ! a moving obstacle's gap changes with λ too: + δλ ∂g/∂λ (docs/theory.md §3.11)
            q(j) = self%gap(j) + along(self, j, particular) + dlambda*self%rate(j) + &
                   self%flexibility(j)*(self%reaction(j) + particular(self%row(j)))
         end if
      end do
      self%frame_units%gap = max(self%units%gap, largest_displacement)
      self%frame_units%force = max(self%units%force, largest_reaction)
      ! Round-off of q: what the last refinement corrected (an upper estimate of the error left after
      ! it, Higham 2002, §12.1), carried through the same formulas; zero before any refactorisation.
      ! (round_off is allocated, with its status checked, where the operator is built.)
      self%round_off = 0.0_dp
      if (allocated(self%correction)) then
         particular = abs(self%correction(:, 1)) + abs(dlambda*self%correction(:, 2))
         do j = 1, self%m
            if (self%row(j) == 0) then
               self%round_off(j) = abs(along(self, j, particular))
               do i = 1, 2
                  if (self%eq(i, j) > 0) self%round_off(j) = max(self%round_off(j), &
                                                                 abs(self%gradient(i, j))*particular(self%eq(i, j)))
               end do
               if (self%active(j)) self%round_off(j) = self%round_off(j)/self%flexibility(j)
            else if (self%active(j)) then
               self%round_off(j) = particular(self%row(j))
            else
               self%round_off(j) = abs(along(self, j, particular)) + self%flexibility(j)*particular(self%row(j))
               do i = 1, 2
                  if (self%eq(i, j) > 0) self%round_off(j) = max(self%round_off(j), &
                                                                 abs(self%gradient(i, j))*particular(self%eq(i, j)))
               end do
               if (self%bed(j) > 0) self%round_off(j) = max(self%round_off(j), particular(self%bed(j)))
            end if
         end do
      end if
   end subroutine contact_frame_q

   !> A gap is measured against the gap unit, a reaction against the force unit (of the last frame_q);
   !> where the estimated round-off of q_c is larger than the tolerance times that unit, the unit is
   !> raised so that the solver's acceptance (q_c ≥ −tolerance · unit, docs/lemke.md) never asks for
   !> digits that the band LU of an ill-conditioned tangent cannot give: such a q_c is zero to working
   !> precision.
   subroutine contact_scales(self, scale)
      class(contact_lcp_operator_t), intent(in) :: self
      real(dp), intent(out) :: scale(:)
      where (self%active)
         scale = self%frame_units%force
      elsewhere
         scale = self%frame_units%gap
      end where
      if (allocated(self%round_off) .and. self%tolerance > 0.0_dp) scale = max(scale, self%round_off/self%tolerance)
   end subroutine contact_scales

   !> v = M_S y: unit inputs (a reaction for c ∉ S, a gap opening for c ∈ S) weighted by y, one
   !> banded solve, the bordering projection, then the outputs (gap or reaction).
   subroutine contact_apply(self, y, v, error)
      class(contact_lcp_operator_t), intent(inout) :: self
      real(dp), intent(in) :: y(:)
      real(dp), intent(out) :: v(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: j
      real(dp) :: dlambda
      self%work = 0.0_dp
      do j = 1, self%m
         if (self%row(j) == 0) then
            ! condensed spring: a force a y (out of the set, y a reaction) or a y/t (in it, y a gap)
            if (self%active(j)) then
               call add_along(self, j, y(j)/self%flexibility(j), self%work(:, 1))
            else
               call add_along(self, j, y(j), self%work(:, 1))
            end if
         else if (self%active(j)) then
            self%work(self%row(j), 1) = -y(j)
         else
            self%work(self%row(j), 1) = y(j)
         end if
      end do
      call band_solve(self%factors, self%work, error)
      if (allocated(error)) return
      ! δλ of the response (the bordering); a moving obstacle's gap out of the set changes by δλ ∂g/∂λ
      dlambda = -dot_product(self%border, self%work(:, 1))
      self%work(:, 1) = self%work(:, 1) + self%du_tangent*dlambda
      do j = 1, self%m
         if (self%row(j) == 0) then
            if (self%active(j)) then
               v(j) = (y(j) - along(self, j, self%work(:, 1)))/self%flexibility(j)
            else
               v(j) = along(self, j, self%work(:, 1)) + self%flexibility(j)*y(j)
            end if
         else if (self%active(j)) then
            v(j) = self%work(self%row(j), 1)
         else
            v(j) = along(self, j, self%work(:, 1)) + self%flexibility(j)*self%work(self%row(j), 1) + &
                   dlambda*self%rate(j)
         end if
      end do
   end subroutine contact_apply

   !> v = M_Sᵀ y: the output functionals weighted by y, the transposed projection, one solve with
   !> K_Sᵀ, then the input entries.
   subroutine contact_apply_transpose(self, y, v, error)
      class(contact_lcp_operator_t), intent(inout) :: self
      real(dp), intent(in) :: y(:)
      real(dp), intent(out) :: v(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: j, i
      self%work = 0.0_dp
      do j = 1, self%m
         if (self%row(j) == 0) then
            ! condensed spring: the output functional −aᵀ/t (in the set) or aᵀ (out of it)
            if (self%active(j)) then
               call add_along(self, j, -y(j)/self%flexibility(j), self%work(:, 1))
            else
               call add_along(self, j, y(j), self%work(:, 1))
            end if
         else if (self%active(j)) then
            self%work(self%row(j), 1) = self%work(self%row(j), 1) + y(j)
         else
            do i = 1, 2
               if (self%eq(i, j) > 0) self%work(self%eq(i, j), 1) = self%work(self%eq(i, j), 1) + &
                                                                     y(j)*self%gradient(i, j)
            end do
            if (self%bed(j) > 0) self%work(self%bed(j), 1) = self%work(self%bed(j), 1) + y(j)
            self%work(self%row(j), 1) = self%work(self%row(j), 1) + y(j)*self%flexibility(j)
         end if
      end do
      self%work(:, 1) = self%work(:, 1) - self%border*dot_product(self%du_tangent, self%work(:, 1))
      ! the transpose of the δλ term of contact_apply: −c Σ_{j∉S} y_j ∂g_j/∂λ (rows out of the set)
      if (any(self%rate /= 0.0_dp)) self%work(:, 1) = self%work(:, 1) - &
                                    self%border*sum(y*self%rate, mask=.not. self%active .and. self%row > 0)
      call band_solve_transpose(self%factors, self%work, error)
      if (allocated(error)) return
      do j = 1, self%m
         if (self%row(j) == 0) then
            ! the input column (a/t in the set, a out of it) and the direct term (1/t, t)
            if (self%active(j)) then
               v(j) = (along(self, j, self%work(:, 1)) + y(j))/self%flexibility(j)
            else
               v(j) = along(self, j, self%work(:, 1)) + self%flexibility(j)*y(j)
            end if
         else if (self%active(j)) then
            v(j) = -self%work(self%row(j), 1)
         else
            v(j) = self%work(self%row(j), 1)
         end if
      end do
   end subroutine contact_apply_transpose

   !> Move the flipped candidates in or out of the working set: their rows of K_S and of the residual
   !> change (module uniarc_contact: a_cᵀ, t_c and g_c + t_c r_c in the set; the identity and −r_c out
   !> of it), K_S is refactorised and K_S⁻¹g, K_S⁻¹R are solved again. On a singular K_S the rows are
   !> restored and refactorised, and the error returned.
   subroutine contact_exchange(self, flip, error)
      class(contact_lcp_operator_t), intent(inout) :: self
      logical, intent(in) :: flip(:)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: restore_error
      call toggle(self, flip)
      call refactorize(self, error)
      if (.not. allocated(error)) return
      call toggle(self, flip)
      call refactorize(self, restore_error)
      if (allocated(restore_error)) error%message = error%message//'; restoring the frame: '//restore_error%message
   end subroutine contact_exchange

   !> Toggle the working-set membership of the flipped candidates in the matrix and the residual.
   subroutine toggle(self, flip)
      type(contact_lcp_operator_t), intent(inout) :: self
      logical, intent(in) :: flip(:)
      integer :: j
      do j = 1, self%m
         if (.not. flip(j)) cycle
         self%active(j) = .not. self%active(j)
         call set_membership(self%row(j), self%eq(:, j), self%gap(j), self%gradient(:, j), self%hessian(:, :, j), &
                             self%flexibility(j), self%reaction(j), self%active(j), self%matrix, self%residual, &
                             self%bed(j))
         ! a moving obstacle's row has R = ∂g/∂λ in the set, 0 out of it (uniarc_contact, assemble_contact)
         if (self%row(j) > 0 .and. self%rate(j) /= 0.0_dp) &
            self%reference(self%row(j)) = merge(self%rate(j), 0.0_dp, self%active(j))
      end do
   end subroutine toggle

   !> Factorise the frame's matrix and solve for K_S⁻¹g and K_S⁻¹R, each with one step of iterative
   !> refinement against the unfactorised matrix (Higham 2002, §12.1): q of the new frame is then as
   !> accurate as the band LU allows, whatever the pivots that led to the frame.
   subroutine refactorize(self, error)
      type(contact_lcp_operator_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: rhs(:, :), correction(:, :), product(:)
      integer :: k, status
      call band_copy(self%matrix, self%factors, error, error_analysis)
      if (allocated(error)) return
      call band_factorize(self%factors, error)
      if (allocated(error)) return
      allocate (rhs(size(self%residual), 2), correction(size(self%residual), 2), product(size(self%residual)), &
                stat=status)
      call allocation_failure(status, 'the vectors of a refactorisation of the contact LCP', &
                              40.0_dp*size(self%residual), error_analysis, error)
      if (allocated(error)) return
      rhs(:, 1) = self%residual
      rhs(:, 2) = self%reference
      call band_solve(self%factors, rhs, error)
      if (allocated(error)) return
      call band_product(self%matrix, rhs(:, 1), product)
      correction(:, 1) = self%residual - product
      call band_product(self%matrix, rhs(:, 2), product)
      correction(:, 2) = self%reference - product
      call band_solve(self%factors, correction, error)
      if (allocated(error)) return
      do k = 1, 2
         rhs(:, k) = rhs(:, k) + correction(:, k)
      end do
      call move_alloc(correction, self%correction)
      self%du_residual = rhs(:, 1)
      self%du_tangent = rhs(:, 2)
      call border_vector(self)
   end subroutine refactorize

   !> c of the bordering: a response v = K_S⁻¹b is projected to v − K_S⁻¹R (cᵀv) so that it keeps the
   !> linearised path constraint (δλ = −cᵀv).
   subroutine border_vector(self)
      type(contact_lcp_operator_t), intent(inout) :: self
      real(dp) :: denominator, magnitude
      ! (border is allocated, with its status checked, where the operator is built.)
      self%border = 0.0_dp
      ! The constraint fixes δλ only where it sees the response to the reference load: tᵀK_S⁻¹R (or the
      ! controlled component of K_S⁻¹R) must not vanish. It does when the contacts of the frame carry
      ! the whole reference load (a rigid obstacle under the loaded node).
      select case (self%constraint%kind)
      case (constraint_arclength)
         denominator = dot_product(self%constraint%t, self%du_tangent)
         magnitude = norm2(self%constraint%t)*norm2(self%du_tangent)
         ! Measured against ψ too: K_S⁻¹R of a frame whose contacts carry the load is round-off,
         ! and so is its own norm (docs/theory.md §2.7).
         if (.not. (abs(denominator) > degenerate_fraction*norm2(self%constraint%t)*self%constraint%lambda_scale)) &
            denominator = 0.0_dp
      case (constraint_displacement)
         denominator = self%du_tangent(self%constraint%equation)
         magnitude = maxval(abs(self%du_tangent))
      case default
         self%degenerate = .false.
         return
      end select
      self%degenerate = .not. (abs(denominator) > 1.0e3_dp*epsilon(1.0_dp)*magnitude)
      if (self%degenerate) return
      select case (self%constraint%kind)
      case (constraint_arclength)
         self%border = self%constraint%t/denominator
      case (constraint_displacement)
         self%border(self%constraint%equation) = 1.0_dp/denominator
      end select
   end subroutine border_vector

   !> a_cᵀ v at candidate j's node for an augmented vector v (with the bed's deflection under a Pasternak
   !> bed point).
   pure real(dp) function along(self, j, v)
      type(contact_lcp_operator_t), intent(in) :: self
      integer, intent(in) :: j
      real(dp), intent(in) :: v(:)
      integer :: i
      along = 0.0_dp
      do i = 1, 2
         if (self%eq(i, j) > 0) along = along + self%gradient(i, j)*v(self%eq(i, j))
      end do
      if (self%bed(j) > 0) along = along + v(self%bed(j))
   end function along

   !> v ← v + s a_c at candidate j's node (an augmented vector v).
   pure subroutine add_along(self, j, s, v)
      type(contact_lcp_operator_t), intent(in) :: self
      integer, intent(in) :: j
      real(dp), intent(in) :: s
      real(dp), intent(inout) :: v(:)
      integer :: i
      do i = 1, 2
         if (self%eq(i, j) > 0) v(self%eq(i, j)) = v(self%eq(i, j)) + s*self%gradient(i, j)
      end do
      if (self%bed(j) > 0) v(self%bed(j)) = v(self%bed(j)) + s
   end subroutine add_along

   !> δλ of the bordered system for a response v = K_S⁻¹(·): the constraint with the given target.
   pure real(dp) function bordered_dlambda(constraint, v, du_tangent, target) result(dlambda)
      type(path_constraint_t), intent(in) :: constraint
      real(dp), intent(in) :: v(:), du_tangent(:), target
      select case (constraint%kind)
      case (constraint_arclength)
         dlambda = (target - dot_product(constraint%t, v))/dot_product(constraint%t, du_tangent)
      case (constraint_displacement)
         dlambda = (target - v(constraint%equation))/du_tangent(constraint%equation)
      case default
         ! Load control: δλ is the target itself for the particular solution, 0 for a response.
         dlambda = target
      end select
   end function bordered_dlambda

end module uniarc_contact_lcp
