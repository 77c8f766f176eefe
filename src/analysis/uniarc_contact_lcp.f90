!> The contact LCP of a step (paper Eqs. 26–32), in a form that stays solvable where K_T is singular or
!> indefinite (docs/theory.md §3.3).
!>
!> The paper condenses the structure on the candidates, M = A K⁻¹ Aᵀ + T, which needs K positive
!> definite. uniarc condenses instead with the factorised augmented tangent K_S of the current working
!> set S (candidates in contact enforced as equalities, the others free), bordered with the linearised
!> path constraint that fixes δλ. In the LCP unknowns this is a principal pivot transform of the
!> paper's LCP with respect to S: for c ∉ S the input is the reaction r_c and the output the gap w_c,
!> for c ∈ S the roles are exchanged. A principal pivot transform has the same solutions and keeps
!> P-matrix properties (Cottle, Pang & Stone 1992, §2.3), and K_S is regular where K alone is not:
!> when the contacts of S hold a rigid-body mode (a ring resting in a cavity) or the path constraint
!> borders a limit point. When S is already the right set, q ≥ 0 and Lemke returns at once.
module uniarc_contact_lcp
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis
   use uniarc_model, only: model_t
   use uniarc_dof_map, only: dof_map_t
   use uniarc_band, only: band_matrix_t, band_solve
   use uniarc_contact, only: candidate_gap
   use uniarc_lemke, only: lemke_solve, lemke_report_t, lemke_solved, lemke_status_name
   implicit none
   private
   public :: path_constraint_t, select_contact_set
   public :: constraint_arclength, constraint_load, constraint_displacement

   integer, parameter :: constraint_arclength = 1     !< tᵀδu = target (δu the displacement part)
   integer, parameter :: constraint_load = 2          !< δλ = target
   integer, parameter :: constraint_displacement = 3  !< δu(equation) = target

   !> The linearised path constraint that fixes δλ in the LCP.
   type :: path_constraint_t
      integer :: kind = constraint_load
      real(dp), allocatable :: t(:)   !< arc length: direction in displacement space (masked)
      real(dp) :: target = 0.0_dp
      integer :: equation = 0         !< displacement control
   end type path_constraint_t

contains

   !> Solve the contact LCP linearised at the current state and return the new working set.
   !>
   !> In: the augmented tangent K_S factorised for the set `active`; x the current unknowns
   !> (displacements and reactions); nodal the current nodal displacements; du_residual = K_S⁻¹ g
   !> (g the augmented residual) and du_tangent = K_S⁻¹ R; the path constraint.
   !> Out: `new_active`, the Lemke report. A Lemke outcome other than solved is an error (category
   !> analysis): the caller cuts the step rather than accept a contact set that is not a solution.
   subroutine select_contact_set(model, map, tangent, x, nodal, du_residual, du_tangent, constraint, &
                                 active, new_active, report, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(band_matrix_t), intent(in) :: tangent
      real(dp), intent(in) :: x(:), nodal(:, :), du_residual(:), du_tangent(:)
      type(path_constraint_t), intent(in) :: constraint
      logical, intent(in) :: active(:)
      logical, intent(out) :: new_active(:)
      type(lemke_report_t), intent(out) :: report
      type(error_t), allocatable, intent(out) :: error
      integer, allocatable :: unilateral(:)
      real(dp), allocatable :: responses(:, :), particular(:), matrix(:, :), q(:), r_in(:), w_out(:)
      real(dp), allocatable :: reaction(:), gap(:)
      real(dp) :: dlambda, g, gradient(2), hessian(2, 2), r_scale, w_scale
      integer :: m, j, k, c, row, node
      type(error_t), allocatable :: solve_error

      new_active = active
      unilateral = pack([(c, c=1, size(map%candidate_equation))], &
                        [(map%candidate_equation(c) > 0 .and. .not. model%contacts(c)%bilateral, &
                          c=1, size(map%candidate_equation))])
      m = size(unilateral)
      if (m == 0) return

      ! Particular solution: the current residual and the constraint's own target.
      dlambda = bordered_dlambda(constraint, du_residual, du_tangent, constraint%target)
      particular = du_residual + dlambda*du_tangent

      ! q first: when the working set is already right (q >= 0, the usual case along a path) the LCP's
      ! answer is r' = 0 and the matrix is never needed, so a step costs O(N) as without contact. This
      ! is the warm start that the paper's form cannot have.
      allocate (matrix(m, m), q(m), r_in(m), w_out(m))
      do j = 1, m
         c = unilateral(j)
         row = map%candidate_equation(c)
         node = model%contacts(c)%node
         if (active(c)) then
            q(j) = x(row) + particular(row)
         else
            call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, &
                               gradient, hessian)
            q(j) = g + displacement_along(particular) + model%contacts(c)%flexibility*(x(row) + particular(row))
         end if
      end do
      if (all(q >= 0.0_dp)) then
         report%status = lemke_solved
         report%pivots = 0
         return
      end if

      ! One response per LCP input: a unit reaction (c ∉ S) or a unit gap opening (c ∈ S).
      allocate (responses(size(x), m), source=0.0_dp)
      do k = 1, m
         row = map%candidate_equation(unilateral(k))
         if (active(unilateral(k))) then
            responses(row, k) = -1.0_dp
         else
            responses(row, k) = 1.0_dp
         end if
      end do
      call band_solve(tangent, responses, solve_error)
      if (allocated(solve_error)) then
         call move_alloc(solve_error, error)
         return
      end if
      do k = 1, m
         dlambda = bordered_dlambda(constraint, responses(:, k), du_tangent, 0.0_dp)
         responses(:, k) = responses(:, k) + dlambda*du_tangent
      end do

      ! Outputs: the gap w_c (c ∉ S) or the reaction r_c (c ∈ S), affine in the inputs.
      do j = 1, m
         c = unilateral(j)
         row = map%candidate_equation(c)
         node = model%contacts(c)%node
         if (active(c)) then
            matrix(j, :) = responses(row, :)
         else
            call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), g, &
                               gradient, hessian)
            do k = 1, m
               matrix(j, k) = displacement_along(responses(:, k)) + model%contacts(c)%flexibility*responses(row, k)
            end do
         end if
      end do

      call lemke_solve(matrix, q, r_in, w_out, report, error)
      if (allocated(error)) return
      if (report%status /= lemke_solved) then
         call make_error(error, 'the contact LCP has no solution found by Lemke ('// &
                         lemke_status_name(report%status)//')', error_analysis)
         return
      end if

      ! Back to reactions and gaps; in contact where the reaction dominates its complement.
      allocate (reaction(m), gap(m))
      do j = 1, m
         if (active(unilateral(j))) then
            reaction(j) = w_out(j)
            gap(j) = r_in(j)
         else
            reaction(j) = r_in(j)
            gap(j) = w_out(j)
         end if
      end do
      r_scale = max(maxval(abs(reaction)), tiny(1.0_dp))
      w_scale = max(maxval(abs(gap)), tiny(1.0_dp))
      do j = 1, m
         new_active(unilateral(j)) = reaction(j)/r_scale > gap(j)/w_scale
      end do

   contains

      !> a_cᵀ δu at candidate c's node for an augmented vector v.
      pure real(dp) function displacement_along(v)
         real(dp), intent(in) :: v(:)
         integer :: i
         displacement_along = 0.0_dp
         do i = 1, 2
            if (map%equation(i, node) > 0) displacement_along = displacement_along + gradient(i)*v(map%equation(i, node))
         end do
      end function displacement_along

   end subroutine select_contact_set

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
