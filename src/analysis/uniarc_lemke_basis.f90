!> The basis of the dense Lemke solver (`uniarc_lemke`) as a linear system: the columns of the scaled
!> system w - M~ r - d~ z0 = q~ that its basic variables pick, the basis matrix B built from them,
!> iterative refinement of the basic values x_B against B, and a fresh LU factorisation of B by
!> LAPACK (dgetrf/dgetrs) from which B^-1 and x_B are recomputed. The pivoting itself (entering
!> column, lexicographic ratio test, Gauss-Jordan update of B^-1) stays in `uniarc_lemke`, which
!> calls these after its last pivot, every `refactor_interval` pivots and when the verification of
!> a point fails (docs/lemke.md).
!>
!> Variables are numbered as in `uniarc_lemke`: w_1..w_n are 1..n, r_1..r_n are n+1..2n, z0 is 2n+1.
!> Matrices and vectors are those of the equilibrated problem (`uniarc_lemke_scaling`).
module uniarc_lemke_basis
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use uniarc_kinds, only: dp
   use uniarc_foreign, only: dgetrf, dgetrs
   use uniarc_lemke_scaling, only: saturating_product
   implicit none
   private
   public :: value_limit, identity, original_column, refine, refactor

   !> Bound on |B^-1| entries and basic values in the equilibrated problem (2^960, about 1e289).
   !> Below it every sum of up to 2^31 such numbers times an equilibrated entry (<= 2) is finite;
   !> a pivot whose result would exceed it is a numerical breakdown, detected before computing.
   real(dp), parameter :: value_limit = 2.0_dp**960
   !> At most this many steps of iterative refinement: each step multiplies the residual by about
   !> cond(B) eps (Higham 2002, *Accuracy and Stability of Numerical Algorithms*, Ch. 12), so a
   !> few steps reach the rounding level whenever cond(B) eps < 1/10.
   integer, parameter :: max_refinement_steps = 5

contains

   !> Set a square matrix to the identity.
   pure subroutine identity(matrix)
      real(dp), intent(out) :: matrix(:, :)
      integer :: i
      matrix = 0.0_dp
      do i = 1, size(matrix, 1)
         matrix(i, i) = 1.0_dp
      end do
   end subroutine identity

   !> Column of the scaled system  w - M~ r - d~ z0 = q~  for one variable: e_i, -M~(:,j) or -d~.
   pure subroutine original_column(matrix, covering, variable, n, column)
      real(dp), intent(in) :: matrix(:, :), covering(:)
      integer, intent(in) :: variable, n
      real(dp), intent(out) :: column(:)
      if (variable <= n) then
         column = 0.0_dp
         column(variable) = 1.0_dp
      else if (variable <= 2*n) then
         column = -matrix(:, variable - n)
      else
         column = -covering
      end if
   end subroutine original_column

   !> The basis matrix B from the original (scaled) columns of its variables.
   pure subroutine basis_matrix(matrix, covering, basis, b)
      real(dp), intent(in) :: matrix(:, :), covering(:)
      integer, intent(in) :: basis(:)
      real(dp), intent(out) :: b(:, :)
      integer :: i, n
      n = size(basis)
      do i = 1, n
         call original_column(matrix, covering, basis(i), n, b(:, i))
      end do
   end subroutine basis_matrix

   !> Iterative refinement of x_B in working precision: x += B^-1 (q - B x), with B from the
   !> original columns and B^-1 applied either as the explicit inverse (O(n^2) per step) or by
   !> the LU factors of dgetrf (lu, pivots). Refinement in fixed precision reduces the residual
   !> q - B x (the backward error) to the rounding level even when the forward error cannot go
   !> below cond(B) eps (Higham 2002, Sec. 12.2), so a step is kept only if it reduces the residual
   !> and the iteration goes on only while each step at least halves it. Also stops when the
   !> correction could exceed value_limit (row_norm: 1-norms of the rows of B^-1).
   subroutine refine(matrix, q, covering, basis, basic, row_norm, inverse, lu, pivots)
      real(dp), intent(in) :: matrix(:, :), q(:), covering(:)
      integer, intent(in) :: basis(:)
      real(dp), intent(inout) :: basic(:)
      real(dp), intent(in) :: row_norm(:)
      real(dp), intent(in), optional :: inverse(:, :), lu(:, :)
      integer, intent(in), optional :: pivots(:)
      real(dp) :: residual(size(q)), correction(size(q)), trial(size(q)), size_now, size_trial
      integer :: n, step, info

      n = size(q)
      call basis_residual(matrix, q, covering, basis, basic, residual)
      size_now = maxval(abs(residual))
      do step = 1, max_refinement_steps
         if (.not. size_now > 0.0_dp) exit
         if (saturating_product(maxval(row_norm), size_now) > value_limit) exit
         correction = residual
         if (present(lu) .and. present(pivots)) then
            call dgetrs('N', n, 1, lu, n, pivots, correction, n, info)
            if (info /= 0) exit
         else if (present(inverse)) then
            correction = matmul(inverse, residual)
         else
            exit
         end if
         trial = basic + correction
         call basis_residual(matrix, q, covering, basis, trial, residual)
         size_trial = maxval(abs(residual))
         if (.not. size_trial < size_now) exit
         basic = trial
         if (.not. size_trial < size_now/2.0_dp) exit
         size_now = size_trial
      end do
   end subroutine refine

   !> residual = q - B x with B from the original (scaled) columns of the basis; O(n^2).
   pure subroutine basis_residual(matrix, q, covering, basis, basic, residual)
      real(dp), intent(in) :: matrix(:, :), q(:), covering(:), basic(:)
      integer, intent(in) :: basis(:)
      real(dp), intent(out) :: residual(:)
      real(dp) :: column(size(q))
      integer :: i, n
      n = size(q)
      residual = q
      do i = 1, n
         call original_column(matrix, covering, basis(i), n, column)
         residual = residual - column*basic(i)
      end do
   end subroutine basis_residual

   !> Factorise the basis afresh with LAPACK (dgetrf: LU with partial pivoting), then B^-1 from
   !> the factors (dgetrs on the identity; the explicit inverse is what the Gauss-Jordan updates
   !> and the lexicographic ratio test use) and x_B = B^-1 q by dgetrs, refined with the factors.
   !> O(n^3). ok = .false. if B is singular to working precision: a pivot of U at most
   !> n eps max|B| is within the backward error of the factorisation (Higham 2002, Thm. 9.3), so
   !> B^-1 computed from it would be meaningless (and could overflow).
   subroutine refactor(matrix, q, covering, basis, inverse, basic, row_norm, ok)
      real(dp), intent(in) :: matrix(:, :), q(:), covering(:)
      integer, intent(in) :: basis(:)
      real(dp), intent(inout) :: inverse(:, :), basic(:), row_norm(:)
      logical, intent(out) :: ok
      real(dp), allocatable :: b(:, :), lu(:, :)
      integer :: pivots(size(q)), k, n, info
      real(dp) :: singular_level

      n = size(q)
      ok = .false.
      allocate (b(n, n))
      call basis_matrix(matrix, covering, basis, b)
      lu = b
      call dgetrf(n, n, lu, n, pivots, info)
      if (info /= 0) return
      singular_level = real(n, dp)*epsilon(1.0_dp)*maxval(abs(b))
      do k = 1, n
         if (abs(lu(k, k)) <= singular_level) return
      end do
      call identity(inverse)
      call dgetrs('N', n, n, lu, n, pivots, inverse, n, info)
      if (info /= 0) return
      if (.not. all(ieee_is_finite(inverse))) return
      row_norm = sum(abs(inverse), dim=2)
      if (.not. maxval(row_norm) <= value_limit) return
      basic = q
      call dgetrs('N', n, 1, lu, n, pivots, basic, n, info)
      if (info /= 0) return
      call refine(matrix, q, covering, basis, basic, row_norm, lu=lu, pivots=pivots)
      ok = all(ieee_is_finite(basic))
   end subroutine refactor

end module uniarc_lemke_basis
