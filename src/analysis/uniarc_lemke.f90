!> Lemke's complementary pivot algorithm for the linear complementarity problem (LCP)
!>
!>     find r, w:  w = q + M r,  w >= 0,  r >= 0,  w^T r = 0
!>
!> on dense real(dp) data (the paper's Eqs. 24-32: r the foundation reactions, w the gaps,
!> M = A K^-1 A^T + T). Lemke (1968), Cottle & Dantzig (1968); the presentation follows
!> Murty, *Linear Complementarity, Linear and Nonlinear Programming* (1988), Ch. 2, and
!> Cottle, Pang & Stone, *The Linear Complementarity Problem* (1992), Ch. 4 (scheme with a
!> covering vector d > 0 and the artificial variable z0:  w - M r - d z0 = q).
!>
!> The LCP outcomes (solved, ray termination, pivot limit, numerical breakdown) are statuses in
!> the report; `error` is allocated only for misuse (shape mismatch, bad options).
!>
!> Design choices (why):
!> - The basis is carried as an explicit inverse B^-1 (n x n) together with the basic values
!>   x_B = B^-1 q, updated by one Gauss-Jordan pivot per exchange. This is O(n^2) per pivot (the
!>   entering column B^-1 a_e costs one matrix-vector product, the update one rank-1 correction)
!>   and, unlike an LU factorisation with product-form updates, it hands the lexicographic ratio
!>   test the rows of B^-1 directly, which it needs at every degenerate tie. A full tableau with
!>   2n+1 columns would cost the same order but twice the memory and work.
!> - The problem is equilibrated first (Ruiz row/column scaling by powers of two, so the scaling
!>   itself is exact in floating point and exact ties stay exact). A positive diagonal scaling
!>   maps the LCP to an equivalent LCP and Lemke's path to the same path, so the tolerances can be
!>   absolute in the scaled problem: that is what makes them relative to the scale of M and q.
!> - After the last pivot the basic solution is improved by one step of iterative refinement
!>   against the original basis columns (O(n^2)); if the verification from the original M and q
!>   still fails, B^-1 is recomputed from scratch (O(n^3), only then) and the check repeated.
module uniarc_lemke
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input
   implicit none
   private
   public :: lemke_options_t, lemke_report_t, lemke_solve, lemke_status_name
   public :: lemke_solved, lemke_ray_termination, lemke_pivot_limit, lemke_breakdown

   !> Outcome: a solution was found and verified from the original M and q.
   integer, parameter :: lemke_solved = 0
   !> Outcome: secondary ray (no pivot row for the entering column) -- no solution found; for
   !> copositive-plus M (e.g. positive semidefinite) this proves the LCP infeasible.
   integer, parameter :: lemke_ray_termination = 1
   !> Outcome: the pivot cap was reached before z0 left the basis.
   integer, parameter :: lemke_pivot_limit = 2
   !> Outcome: numerical breakdown (singular basis, non-finite values, or failed verification).
   integer, parameter :: lemke_breakdown = 3

   !> Options of `lemke_solve`; every component has a usable default.
   type :: lemke_options_t
      !> Covering vector d > 0 of the artificial column (default: all ones).
      real(dp), allocatable :: covering(:)
      !> Pivot cap; 0 means automatic: max(10000, 20 n), enough for Murty's 2^n example to n = 13.
      integer :: max_pivots = 0
      !> Pivot entries below this fraction of the entering column's largest entry are not
      !> eligible (they would be round-off of exact zeros).
      real(dp) :: pivot_tolerance = 1.0e-11_dp
      !> Zero level in the equilibrated problem (where |q| <= 1 and M has unit row/column
      !> max-norms): basic values below it are flushed to zero, ratios within it relative are
      !> ties, and z0 below it times its first value counts as having left.
      real(dp) :: zero_tolerance = 1.0e-12_dp
      !> A solution is reported `lemke_solved` only if its verification residual (see
      !> `lemke_report_t%residual`) is at most this.
      real(dp) :: residual_tolerance = 1.0e-9_dp
      !> Recompute B^-1 from the basis columns every this many pivots (0: never; the final
      !> verification still recomputes it when needed). Costs O(n^3) each time.
      integer :: refactor_interval = 0
      !> Equilibrate M and q before pivoting (switch off only to study the plain algorithm).
      logical :: scaling = .true.
   end type lemke_options_t

   !> What `lemke_solve` did, with the solution verified from the original M and q.
   type :: lemke_report_t
      !> One of lemke_solved, lemke_ray_termination, lemke_pivot_limit, lemke_breakdown.
      integer :: status = lemke_breakdown
      !> Number of basis exchanges, the one that brings z0 in included.
      integer :: pivots = 0
      !> Number of components with r_i > 0.
      integer :: active = 0
      !> Verification residual max_i |min(r_i/|r|_inf, w_i/|q|_inf)| (dimensionless; 0 for an
      !> exact solution; it measures sign violations and complementarity alike).
      real(dp) :: residual = 0.0_dp
      !> |r^T w| with w recomputed as q + M r.
      real(dp) :: complementarity = 0.0_dp
      !> min_i r_i (0 for n = 0).
      real(dp) :: min_r = 0.0_dp
      !> min_i w_i with w recomputed as q + M r (0 for n = 0).
      real(dp) :: min_w = 0.0_dp
      !> Human-readable account of the outcome (for messages up the call chain).
      character(len=:), allocatable :: message
   end type lemke_report_t

contains

   !> Name of a status code, for messages.
   pure function lemke_status_name(status) result(name)
      integer, intent(in) :: status
      character(len=:), allocatable :: name
      select case (status)
      case (lemke_solved)
         name = 'solved'
      case (lemke_ray_termination)
         name = 'ray termination'
      case (lemke_pivot_limit)
         name = 'pivot limit'
      case (lemke_breakdown)
         name = 'numerical breakdown'
      case default
         name = 'unknown status'
      end select
   end function lemke_status_name

   !> Solve the LCP  w = q + M r, w >= 0, r >= 0, w^T r = 0  by Lemke's method (scheme with
   !> covering vector d and artificial variable z0; Murty 1988 Ch. 2, lexicographic
   !> minimum-ratio rule of the same chapter applied from the first pivot).
   !>
   !> In: M (n x n), q (n), options. Out: r, w (size n; w = q + M r recomputed from the original
   !> data), report (status, pivots, residuals). `error` is allocated only for misuse.
   subroutine lemke_solve(matrix, q, r, w, report, error, options)
      real(dp), intent(in) :: matrix(:, :)
      real(dp), intent(in) :: q(:)
      real(dp), intent(out) :: r(:)
      real(dp), intent(out) :: w(:)
      type(lemke_report_t), intent(out) :: report
      type(error_t), allocatable, intent(out) :: error
      type(lemke_options_t), intent(in), optional :: options

      type(lemke_options_t) :: opts
      integer :: n, max_pivots
      real(dp), allocatable :: row_scale(:), column_scale(:), scaled_matrix(:, :), scaled_q(:)
      real(dp), allocatable :: covering(:), inverse(:, :), basic(:), column(:)
      integer, allocatable :: basis(:), position(:)
      real(dp) :: q_scale, z0_first, z0_value
      integer :: entering, leaving_row, leaving, artificial, since_refactor, i
      logical :: finished, ok

      if (present(options)) opts = options
      n = size(q)
      call check_arguments(matrix, q, r, w, opts, error)
      if (allocated(error)) return

      report%pivots = 0
      if (n == 0) then
         report%status = lemke_solved
         report%message = 'empty problem'
         return
      end if
      r = 0.0_dp
      if (all(q >= 0.0_dp)) then
         ! r = 0 is a solution: w = q >= 0 and r^T w = 0 (no pivot needed).
         call verify(matrix, q, r, w, report)
         report%status = lemke_solved
         report%message = 'q >= 0: r = 0'
         return
      end if

      max_pivots = opts%max_pivots
      if (max_pivots <= 0) max_pivots = max(10000, 20*n)

      ! Equilibrate: scaled_matrix = D^-1 M S, scaled_q = D^-1 q / c, d~ = D^-1 d / |D^-1 d|;
      ! then r = c S r~ and w = c D w~ (the complementarity pairs are only rescaled).
      allocate (row_scale(n), column_scale(n))
      scaled_matrix = matrix
      if (opts%scaling) then
         call equilibrate(scaled_matrix, row_scale, column_scale)
      else
         row_scale = 1.0_dp
         column_scale = 1.0_dp
      end if
      scaled_q = q/row_scale
      q_scale = power_of_two(maxval(abs(scaled_q)))
      scaled_q = scaled_q/q_scale
      if (allocated(opts%covering)) then
         covering = opts%covering/row_scale
      else
         covering = 1.0_dp/row_scale
      end if
      covering = covering/power_of_two(maxval(covering))

      ! Variables: w_i is i, r_j is n + j, z0 is 2n + 1. Start from the basis of all w.
      artificial = 2*n + 1
      allocate (basis(n), position(2*n + 1), column(n), inverse(n, n))
      call identity(inverse)
      basis = [(i, i=1, n)]
      position = 0
      position(1:n) = basis
      basic = scaled_q

      ! First pivot: z0 enters, the row of the lexicographically smallest q_i/d_i leaves.
      column = -covering
      call select_row(basic, inverse, column, -1.0_dp, 0, opts, leaving_row)
      z0_first = -basic(leaving_row)/covering(leaving_row)
      entering = artificial
      finished = .false.
      since_refactor = 0
      report%status = lemke_breakdown
      report%message = 'not started'
      do
         leaving = basis(leaving_row)
         call pivot(inverse, basic, column, leaving_row)
         basis(leaving_row) = entering
         position(entering) = leaving_row
         position(leaving) = 0
         report%pivots = report%pivots + 1
         since_refactor = since_refactor + 1
         call flush_zeros(basic, opts%zero_tolerance)
         if (.not. all(ieee_is_finite(basic))) then
            report%status = lemke_breakdown
            report%message = 'non-finite basic values after a pivot'
            exit
         end if
         if (leaving == artificial) then
            finished = .true.
            report%message = 'z0 left the basis'
            exit
         end if
         z0_value = basic(position(artificial))
         if (z0_value <= opts%zero_tolerance*z0_first) then
            ! z0 is at zero although still basic: the current basic solution satisfies the LCP.
            finished = .true.
            report%message = 'z0 reached zero in the basis'
            exit
         end if
         if (opts%refactor_interval > 0 .and. since_refactor >= opts%refactor_interval) then
            call refactor(scaled_matrix, scaled_q, covering, basis, inverse, basic, ok)
            if (.not. ok) then
               report%status = lemke_breakdown
               report%message = 'singular basis at refactorisation'
               exit
            end if
            call flush_zeros(basic, opts%zero_tolerance)
            since_refactor = 0
         end if
         if (report%pivots >= max_pivots) then
            report%status = lemke_pivot_limit
            report%message = 'pivot limit reached'
            exit
         end if
         ! Complementary pivot rule: the partner of the variable that just left enters.
         entering = complement(leaving, n)
         call entering_column(scaled_matrix, covering, inverse, entering, n, column)
         call select_row(basic, inverse, column, 1.0_dp, position(artificial), opts, leaving_row)
         if (leaving_row == 0) then
            report%status = lemke_ray_termination
            report%message = 'secondary ray: no solution found'
            exit
         end if
      end do

      if (finished) then
         call refine(scaled_matrix, scaled_q, covering, basis, inverse, basic)
         call extract(basic, position, n, column_scale, q_scale, r)
         call verify(matrix, q, r, w, report)
         if (report%residual > opts%residual_tolerance) then
            ! Accumulated round-off in the updated inverse: recompute it and check again.
            call refactor(scaled_matrix, scaled_q, covering, basis, inverse, basic, ok)
            if (ok) then
               call extract(basic, position, n, column_scale, q_scale, r)
               call verify(matrix, q, r, w, report)
            end if
         end if
         if (report%residual <= opts%residual_tolerance) then
            report%status = lemke_solved
         else
            report%status = lemke_breakdown
            report%message = 'verification failed after the last pivot'
         end if
      else
         ! Return the current (infeasible or incomplete) point so the caller can inspect it.
         call extract(basic, position, n, column_scale, q_scale, r)
         call verify(matrix, q, r, w, report)
      end if
   end subroutine lemke_solve

   !> Misuse checks: shapes, covering vector, tolerances, finiteness of the data.
   subroutine check_arguments(matrix, q, r, w, opts, error)
      real(dp), intent(in) :: matrix(:, :), q(:), r(:), w(:)
      type(lemke_options_t), intent(in) :: opts
      type(error_t), allocatable, intent(out) :: error
      integer :: n
      character(len=120) :: text

      n = size(q)
      if (size(matrix, 1) /= n .or. size(matrix, 2) /= n .or. size(r) /= n .or. size(w) /= n) then
         write (text, '(a,i0,a,i0,a,i0,a,i0,a,i0)') 'shape mismatch: M is ', size(matrix, 1), &
            ' x ', size(matrix, 2), ', q has ', n, ', r has ', size(r), ', w has ', size(w)
         call make_error(error, 'lemke_solve: '//trim(text), error_input)
         return
      end if
      if (allocated(opts%covering)) then
         if (size(opts%covering) /= n) then
            call make_error(error, 'lemke_solve: covering vector has the wrong size', error_input)
            return
         end if
         if (n > 0) then
            if (.not. all(ieee_is_finite(opts%covering))) then
               call make_error(error, 'lemke_solve: covering vector must be finite', error_input)
               return
            end if
            if (.not. all(opts%covering > 0.0_dp)) then
               call make_error(error, 'lemke_solve: covering vector must be positive', &
                               error_input)
               return
            end if
         end if
      end if
      if (.not. (opts%pivot_tolerance > 0.0_dp .and. opts%zero_tolerance > 0.0_dp .and. &
                 opts%residual_tolerance > 0.0_dp)) then
         call make_error(error, 'lemke_solve: tolerances must be positive', error_input)
         return
      end if
      if (n > 0) then
         if (.not. (all(ieee_is_finite(matrix)) .and. all(ieee_is_finite(q)))) then
            call make_error(error, 'lemke_solve: M or q has non-finite entries', error_input)
            return
         end if
      end if
   end subroutine check_arguments

   !> The complementary partner of a variable: w_i <-> r_i.
   pure integer function complement(variable, n)
      integer, intent(in) :: variable, n
      if (variable <= n) then
         complement = variable + n
      else
         complement = variable - n
      end if
   end function complement

   !> The power of two nearest to x > 0 (1 for x = 0): scaling by it is exact in floating point.
   pure real(dp) function power_of_two(x)
      real(dp), intent(in) :: x
      if (x > 0.0_dp) then
         power_of_two = set_exponent(1.0_dp, exponent(x))
         if (x/power_of_two < sqrt(2.0_dp)/2.0_dp) power_of_two = power_of_two/2.0_dp
         if (x/power_of_two > sqrt(2.0_dp)) power_of_two = power_of_two*2.0_dp
      else
         power_of_two = 1.0_dp
      end if
   end function power_of_two

   !> Ruiz equilibration (Ruiz 2001, "A scaling algorithm to equilibrate both rows and columns
   !> norms in matrices"): repeatedly divide rows and columns by the square roots of their
   !> max-norms, rounded to powers of two, until all are within a factor 2 of one. On return
   !> matrix <- D^-1 M S with row_scale = D and column_scale = S.
   pure subroutine equilibrate(matrix, row_scale, column_scale)
      real(dp), intent(inout) :: matrix(:, :)
      real(dp), intent(out) :: row_scale(:), column_scale(:)
      integer :: sweep, i, j, n
      real(dp) :: row_norm(size(row_scale)), factor
      real(dp) :: column_factor(size(column_scale)), row_factor(size(row_scale))

      n = size(row_scale)
      row_scale = 1.0_dp
      column_scale = 1.0_dp
      do sweep = 1, 20
         row_norm = 0.0_dp
         do j = 1, n
            do i = 1, n
               row_norm(i) = max(row_norm(i), abs(matrix(i, j)))
            end do
         end do
         do i = 1, n
            row_factor(i) = power_of_two(sqrt(row_norm(i)))
         end do
         do j = 1, n
            column_factor(j) = power_of_two(sqrt(maxval(abs(matrix(:, j)))))
         end do
         ! The factors are powers of two, so "within 1/2 of one" means "exactly one".
         if (all(abs(row_factor - 1.0_dp) < 0.5_dp) .and. all(abs(column_factor - 1.0_dp) < 0.5_dp)) exit
         do j = 1, n
            factor = 1.0_dp/column_factor(j)
            matrix(:, j) = matrix(:, j)*factor/row_factor
         end do
         row_scale = row_scale*row_factor
         column_scale = column_scale/column_factor
      end do
   end subroutine equilibrate

   !> Set a square matrix to the identity.
   pure subroutine identity(matrix)
      real(dp), intent(out) :: matrix(:, :)
      integer :: i
      matrix = 0.0_dp
      do i = 1, size(matrix, 1)
         matrix(i, i) = 1.0_dp
      end do
   end subroutine identity

   !> Basic values whose magnitude is below the zero level are exact zeros made inexact by
   !> round-off; flushing them keeps degenerate ties exact for the ratio test.
   pure subroutine flush_zeros(basic, tolerance)
      real(dp), intent(inout) :: basic(:)
      real(dp), intent(in) :: tolerance
      where (abs(basic) <= tolerance) basic = 0.0_dp
   end subroutine flush_zeros

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

   !> Entering column B^-1 a_e; O(n^2) for an r variable, O(n) for a w variable (a unit column).
   pure subroutine entering_column(matrix, covering, inverse, variable, n, column)
      real(dp), intent(in) :: matrix(:, :), covering(:), inverse(:, :)
      integer, intent(in) :: variable, n
      real(dp), intent(out) :: column(:)
      if (variable <= n) then
         column = inverse(:, variable)
      else if (variable <= 2*n) then
         column = -matmul(inverse, matrix(:, variable - n))
      else
         column = -matmul(inverse, covering)
      end if
   end subroutine entering_column

   !> Lexicographic minimum-ratio test (Murty 1988, Ch. 2; Cottle, Pang & Stone 1992,
   !> Ch. 4). Candidate rows are those with sense*column(i) above the pivot tolerance; the
   !> leaving row minimises the row vector [x_i, (B^-1)_i.] / (sense*column(i)) lexicographically,
   !> which keeps every row of [x_B, B^-1] lexicographically positive and so rules out cycling.
   !> sense = -1 for the first pivot (z0 entering against all rows, ratios q_i/d_i), +1 after.
   !> If the row of z0 (artificial_row > 0) is among the ties of the first component it is chosen
   !> (the algorithm then ends). leaving_row = 0 when there is no candidate (secondary ray).
   pure subroutine select_row(basic, inverse, column, sense, artificial_row, opts, leaving_row)
      real(dp), intent(in) :: basic(:), inverse(:, :), column(:)
      real(dp), intent(in) :: sense
      integer, intent(in) :: artificial_row
      type(lemke_options_t), intent(in) :: opts
      integer, intent(out) :: leaving_row
      real(dp) :: threshold, ratio(size(basic)), best, spread, value
      logical :: tied(size(basic))
      integer :: i, k, n

      n = size(basic)
      leaving_row = 0
      ratio = 0.0_dp
      threshold = opts%pivot_tolerance*maxval(abs(column))
      tied = sense*column > threshold .and. threshold > 0.0_dp
      if (.not. any(tied)) return

      ! First component: the ratio x_i / a_i. After the first pivot x >= 0 in exact arithmetic,
      ! so a negative round-off value is read as zero.
      do i = 1, n
         if (tied(i)) then
            value = basic(i)
            if (sense > 0.0_dp) value = max(value, 0.0_dp)
            ratio(i) = value/(sense*column(i))
         end if
      end do
      best = minval(ratio, mask=tied)
      tied = tied .and. ratio <= best + opts%zero_tolerance*abs(best)
      if (artificial_row > 0) then
         if (tied(artificial_row)) then
            leaving_row = artificial_row
            return
         end if
      end if

      ! Further components: the rows of B^-1 divided by the pivot-column entry, until one row is
      ! left. Differences below the zero level relative to the column's spread count as ties.
      do k = 1, n
         if (count(tied) == 1) exit
         do i = 1, n
            if (tied(i)) ratio(i) = inverse(i, k)/(sense*column(i))
         end do
         best = minval(ratio, mask=tied)
         spread = maxval(abs(ratio), mask=tied)
         tied = tied .and. ratio <= best + opts%zero_tolerance*spread
      end do
      ! Rows of a nonsingular B^-1 are never proportional, so one row is left in exact
      ! arithmetic; if round-off leaves several, the largest pivot entry is the stable choice.
      value = -1.0_dp
      do i = 1, n
         if (tied(i)) then
            if (sense*column(i) > value) then
               value = sense*column(i)
               leaving_row = i
            end if
         end if
      end do
   end subroutine select_row

   !> Gauss-Jordan pivot on row t of [x_B | B^-1] with the entering column a = B^-1 a_e:
   !> row t /= a_t, row i -= a_i * (new row t). O(n^2), column by column for memory order.
   pure subroutine pivot(inverse, basic, column, row)
      real(dp), intent(inout) :: inverse(:, :), basic(:)
      real(dp), intent(in) :: column(:)
      integer, intent(in) :: row
      real(dp) :: factor(size(column)), pivot_row_value
      integer :: j

      factor = column/column(row)
      factor(row) = 0.0_dp
      do j = 1, size(inverse, 2)
         pivot_row_value = inverse(row, j)/column(row)
         inverse(:, j) = inverse(:, j) - factor*inverse(row, j)
         inverse(row, j) = pivot_row_value
      end do
      pivot_row_value = basic(row)/column(row)
      basic = basic - factor*basic(row)
      basic(row) = pivot_row_value
   end subroutine pivot

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

   !> One step of iterative refinement of x_B: x += B^-1 (q - B x), with B from the original
   !> columns (Golub & Van Loan, *Matrix Computations*, iterative improvement). O(n^2); it
   !> removes the drift that the updated inverse accumulates.
   pure subroutine refine(matrix, q, covering, basis, inverse, basic)
      real(dp), intent(in) :: matrix(:, :), q(:), covering(:)
      integer, intent(in) :: basis(:)
      real(dp), intent(in) :: inverse(:, :)
      real(dp), intent(inout) :: basic(:)
      real(dp) :: residual(size(q)), column(size(q))
      integer :: i, n
      n = size(q)
      residual = q
      do i = 1, n
         call original_column(matrix, covering, basis(i), n, column)
         residual = residual - column*basic(i)
      end do
      basic = basic + matmul(inverse, residual)
   end subroutine refine

   !> Recompute B^-1 and x_B = B^-1 q from scratch by Gauss-Jordan elimination with partial
   !> pivoting (Golub & Van Loan, *Matrix Computations*). O(n^3). ok = .false. if B is
   !> numerically singular.
   pure subroutine refactor(matrix, q, covering, basis, inverse, basic, ok)
      real(dp), intent(in) :: matrix(:, :), q(:), covering(:)
      integer, intent(in) :: basis(:)
      real(dp), intent(inout) :: inverse(:, :), basic(:)
      logical, intent(out) :: ok
      real(dp) :: b(size(q), size(q)), swap(size(q)), factor(size(q)), scale_b, pivot_value
      integer :: k, p, j, n

      n = size(q)
      call basis_matrix(matrix, covering, basis, b)
      call identity(inverse)
      scale_b = maxval(abs(b))
      ok = .false.
      do k = 1, n
         p = k - 1 + maxloc(abs(b(k:, k)), dim=1)
         if (abs(b(p, k)) <= epsilon(1.0_dp)*scale_b) return
         if (p /= k) then
            swap = b(k, :); b(k, :) = b(p, :); b(p, :) = swap
            swap = inverse(k, :); inverse(k, :) = inverse(p, :); inverse(p, :) = swap
         end if
         factor = b(:, k)/b(k, k)
         factor(k) = 0.0_dp
         do j = 1, n
            b(:, j) = b(:, j) - factor*b(k, j)
            inverse(:, j) = inverse(:, j) - factor*inverse(k, j)
         end do
         pivot_value = b(k, k)
         b(k, :) = b(k, :)/pivot_value
         inverse(k, :) = inverse(k, :)/pivot_value
      end do
      ! b is now the identity up to the row scaling done above; inverse holds B^-1.
      basic = matmul(inverse, q)
      ok = all(ieee_is_finite(basic))
   end subroutine refactor

   !> r from the basic values: r~_j where r_j is basic (negative round-off read as zero), then
   !> unscaled r = c S r~.
   pure subroutine extract(basic, position, n, column_scale, q_scale, r)
      real(dp), intent(in) :: basic(:)
      integer, intent(in) :: position(:), n
      real(dp), intent(in) :: column_scale(:), q_scale
      real(dp), intent(out) :: r(:)
      real(dp) :: rtilde(n)
      integer :: j
      rtilde = 0.0_dp
      do j = 1, n
         if (position(n + j) > 0) rtilde(j) = max(basic(position(n + j)), 0.0_dp)
      end do
      r = q_scale*column_scale*rtilde
   end subroutine extract

   !> Verification from the original data: w = q + M r and the residuals of the report.
   subroutine verify(matrix, q, r, w, report)
      real(dp), intent(in) :: matrix(:, :), q(:), r(:)
      real(dp), intent(out) :: w(:)
      type(lemke_report_t), intent(inout) :: report
      real(dp) :: r_scale, w_scale
      integer :: i

      w = q + matmul(matrix, r)
      report%min_r = minval(r)
      report%min_w = minval(w)
      report%complementarity = abs(dot_product(r, w))
      report%active = count(r > 0.0_dp)
      r_scale = maxval(abs(r))
      if (r_scale <= 0.0_dp) r_scale = 1.0_dp
      w_scale = maxval(abs(q))
      if (w_scale <= 0.0_dp) w_scale = 1.0_dp
      report%residual = 0.0_dp
      do i = 1, size(q)
         report%residual = max(report%residual, abs(min(r(i)/r_scale, w(i)/w_scale)))
      end do
   end subroutine verify

end module uniarc_lemke
