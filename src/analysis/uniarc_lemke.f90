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
!>   and hands the lexicographic ratio test the columns of B^-1 directly, which it reads at every
!>   degenerate tie. An LU factorisation alone would need either a factorisation update
!>   (Bartels-Golub / Forrest-Tomlin) or an O(n^3) refactorisation per pivot, plus one extra
!>   triangular solve per column the lexicographic test reads; so the explicit inverse is kept for
!>   the pivoting, and LAPACK's LU (dgetrf/dgetrs) is used where a basis is built from scratch.
!> - The problem is equilibrated first (Ruiz row/column scaling by powers of two, so the scaling
!>   itself is exact in floating point and exact ties stay exact). A positive diagonal scaling
!>   maps the LCP to an equivalent LCP and Lemke's path to the same path, so the tolerances can be
!>   absolute in the scaled problem: that is what makes them relative to the scale of M and q.
!>   The scale factors are kept as integer exponents and applied with `scale`, so data spanning
!>   the whole exponent range never overflow in the scaling (and a solution that does not fit in
!>   real(dp) is reported as a breakdown, never written as Inf).
!> - Every tolerance is relative to a round-off bound of the quantity it tests: a pivot entry
!>   (B^-1 a_e)_i to ||row i of B^-1||_1 ||a_e||_inf, a basic value produced by a pivot to the
!>   terms it was computed from. Entries and values that pass are never rejected for being small
!>   compared with the other rows (near-singular P-matrices have legitimately small pivots).
!> - After the last pivot the basic solution is improved by iterative refinement against the
!>   original basis columns (O(n^2) per step); if the verification from the original M and q still
!>   fails, the basis is factorised afresh by LAPACK's LU, the basic solution is solved and refined
!>   with the factors, and the check is repeated. The refinement and the LU refactorisation of the
!>   basis are in `uniarc_lemke_basis`; this module does the pivoting and the verification.
module uniarc_lemke
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use uniarc_kinds, only: dp
   use uniarc_foreign, only: interrupt_signal
   use uniarc_error, only: error_t, make_error, error_input
   use uniarc_lemke_scaling, only: equilibrate, scale_down, saturating_product, saturating_sum, safe_divide
   use uniarc_lemke_basis, only: value_limit, identity, original_column, refine, refactor
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
   !> Outcome: numerical breakdown (singular basis, values that would overflow, a solution that is
   !> not representable in real(dp), or failed verification).
   integer, parameter :: lemke_breakdown = 3

   !> Outcomes of the ratio test.
   integer, parameter :: select_found = 0, select_ray = 1, select_failed = 2
   !> Outcomes of the final extraction and verification of a point.
   integer, parameter :: point_verified = 0, point_inaccurate = 1, point_overflow = 2, &
                         point_not_finite = 3

   !> Options of `lemke_solve`; every component has a usable default.
   type :: lemke_options_t
      !> Covering vector d > 0 of the artificial column (default: all ones).
      real(dp), allocatable :: covering(:)
      !> Pivot cap, >= 0; 0 means automatic: max(10000, 20 n), enough for Murty's 2^n example to
      !> n = 13. A negative value is misuse (`error`).
      integer :: max_pivots = 0
      !> An entry a_i of the entering column a = B^-1 a_e is an eligible pivot only if
      !> sense*a_i > pivot_tolerance * ||(B^-1)_i.||_1 * ||a_e||_inf, with a_e the entering
      !> variable's column in the equilibrated problem. The right-hand side (without the factor)
      !> bounds the terms of the dot product that computes a_i, so its round-off is a small
      !> multiple of eps times it: gamma_n = n eps/2 for the product itself (Higham 2002, Sec. 3.1)
      !> plus the drift of the updated B^-1. 1e-13 (about 450 ulps) is above gamma_n up to
      !> n ~ 900 and above the typical sqrt(n) eps/2 for any n, yet below the 5e-13 relative size
      !> of the legitimate pivots of a P-matrix singular to 1e-12 (tests/unit/test_lemke.pf,
      !> test_near_singular_p_matrix). Every entry above this round-off level is eligible however
      !> small it is compared with the column's other entries, so a secondary ray is declared only
      !> when each positive entry is indistinguishable from round-off.
      real(dp) :: pivot_tolerance = 1.0e-13_dp
      !> Relative zero level (dimensionless): a basic value computed by a pivot as x_i - f_i x_t is
      !> set to zero when it is at most zero_tolerance * (|x_i| + |f_i x_t|) (cancellation down to
      !> round-off: an exact zero of a degenerate basis); ratios within it relative are ties of the
      !> lexicographic test; z0 below it times its first value counts as having left. 1e-14 (about
      !> 45 ulps) covers the 3 ulps of one update with margin for the drift of the operands, and
      !> resolves data that differ in the 13th digit (5e-13 relative in
      !> test_near_singular_p_matrix).
      real(dp) :: zero_tolerance = 1.0e-14_dp
      !> A solution is reported `lemke_solved` only if its verification residual (see
      !> `lemke_report_t%residual`) is at most this.
      real(dp) :: residual_tolerance = 1.0e-9_dp
      !> Refactorise the basis (LAPACK LU, B^-1 and x_B from the factors, x_B refined) every this
      !> many pivots, >= 0 (0: never; the final verification still refactorises when needed).
      !> Costs O(n^3) each time. A negative value is misuse (`error`).
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
      !> Verification residual (dimensionless; 0 for an exact solution):
      !>     max_i |min(r_i / s_r, w_i / s_w)|,  s_r = ||r||_inf,  s_w = ||M||_inf ||r||_inf + ||q||_inf
      !> (inf-norms; ||M||_inf the largest absolute row sum; a scale that is 0 is replaced by 1),
      !> with w = q + M r recomputed from the original data. s_w bounds every term of q + M r, so
      !> the round-off of w is a small multiple of eps s_w whatever the sizes of M, r and q: the
      !> residual is scale-aware and measures sign violations and complementarity alike.
      real(dp) :: residual = 0.0_dp
      !> |r^T w| with w recomputed as q + M r (saturated at huge(1.0_dp)).
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
   !> data), report (status, pivots, residuals). `error` is allocated only for misuse. On an outcome
   !> other than `lemke_solved`, r and w are the last point reached, or r = 0 and w = q when that
   !> point is not representable in real(dp); they are always finite.
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
      real(dp), allocatable :: scaled_matrix(:, :), scaled_q(:), covering(:), inverse(:, :)
      real(dp), allocatable :: basic(:), column(:), row_norm(:)
      integer, allocatable :: basis(:), position(:), row_exp(:), column_exp(:)
      real(dp) :: z0_first, z0_value, column_norm
      integer :: q_exp, covering_exp, entering, leaving_row, leaving, artificial, since_refactor, i
      integer :: outcome, point
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
         call verify(matrix, q, r, w, report, ok)
         report%status = lemke_solved
         report%message = 'q >= 0: r = 0'
         return
      end if

      max_pivots = opts%max_pivots
      if (max_pivots == 0) max_pivots = max(10000, 20*n)

      ! Equilibrate: scaled_matrix = D^-1 M S, scaled_q = D^-1 q / c, d~ = D^-1 d / c_d, with
      ! D = 2^row_exp, S = 2^column_exp, c = 2^q_exp; then r = c S r~ and w = c D w~ (the
      ! complementarity pairs are only rescaled). Only exponents are added, so nothing overflows.
      allocate (row_exp(n), column_exp(n), scaled_q(n), covering(n))
      scaled_matrix = matrix
      if (opts%scaling) then
         call equilibrate(scaled_matrix, row_exp, column_exp)
      else
         row_exp = 0
         column_exp = 0
      end if
      call scale_down(q, row_exp, scaled_q, q_exp)
      if (allocated(opts%covering)) then
         call scale_down(opts%covering, row_exp, covering, covering_exp)
      else
         call scale_down([(1.0_dp, i=1, n)], row_exp, covering, covering_exp)
      end if

      ! Variables: w_i is i, r_j is n + j, z0 is 2n + 1. Start from the basis of all w.
      artificial = 2*n + 1
      allocate (basis(n), position(2*n + 1), column(n), inverse(n, n), row_norm(n))
      call identity(inverse)
      row_norm = 1.0_dp
      basis = [(i, i=1, n)]
      position = 0
      position(1:n) = basis
      basic = scaled_q

      report%status = lemke_breakdown
      report%message = 'not started'
      finished = .false.
      z0_first = 0.0_dp
      since_refactor = 0
      if (.not. all(covering > 0.0_dp)) then
         ! d_i / max d below the smallest subnormal: that row could not take part in the first
         ! ratio test, and Lemke's path would start from an infeasible basis.
         report%message = 'covering vector spread beyond the exponent range (an entry underflows '// &
                          'after scaling)'
         call conclude(matrix, q, basic, position, column_exp, q_exp, opts, r, w, report, point)
         return
      end if

      ! First pivot: z0 enters, the row of the lexicographically smallest q_i/d_i leaves. Its
      ! column -d~ is exact data (B = I), so every d~_i > 0 is eligible: column_norm = 0.
      column = -covering
      call select_row(basic, inverse, column, row_norm, 0.0_dp, -1.0_dp, 0, opts, leaving_row, &
                      outcome)
      if (outcome /= select_found) then
         ! Every d~_i > 0 is eligible, so this is not reached; kept so that no index 0 is used.
         report%message = 'no pivot row for z0'
         call conclude(matrix, q, basic, position, column_exp, q_exp, opts, r, w, report, point)
         return
      end if
      entering = artificial
      do
         leaving = basis(leaving_row)
         call pivot(inverse, basic, column, leaving_row, row_norm, opts%zero_tolerance, ok)
         if (.not. ok) then
            report%status = lemke_breakdown
            report%message = 'basis numerically singular: the pivot would make B^-1 overflow'
            exit
         end if
         basis(leaving_row) = entering
         position(entering) = leaving_row
         position(leaving) = 0
         report%pivots = report%pivots + 1
         since_refactor = since_refactor + 1
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
         ! z0 is basic here (it entered at the first pivot and has not left): position > 0.
         z0_value = basic(position(artificial))
         if (report%pivots == 1) z0_first = z0_value
         if (z0_value <= opts%zero_tolerance*z0_first) then
            ! z0 is at zero although still basic: the current basic solution satisfies the LCP.
            finished = .true.
            report%message = 'z0 reached zero in the basis'
            exit
         end if
         if (opts%refactor_interval > 0 .and. since_refactor >= opts%refactor_interval) then
            call refactor(scaled_matrix, scaled_q, covering, basis, inverse, basic, row_norm, ok)
            if (.not. ok) then
               report%status = lemke_breakdown
               report%message = 'singular basis at refactorisation'
               exit
            end if
            call flush_roundoff(basic, row_norm, maxval(abs(scaled_q)), opts%zero_tolerance)
            since_refactor = 0
         end if
         if (report%pivots >= max_pivots) then
            report%status = lemke_pivot_limit
            report%message = 'pivot limit reached'
            exit
         end if
         ! A SIGINT or SIGTERM abandons the solve (docs/contracts.md, "Interrupts").
         if (interrupt_signal() /= 0) then
            report%status = lemke_breakdown
            report%message = 'interrupted by a signal'
            exit
         end if
         ! Complementary pivot rule: the partner of the variable that just left enters.
         entering = complement(leaving, n)
         call entering_column(scaled_matrix, covering, inverse, entering, n, column, column_norm)
         if (.not. all(ieee_is_finite(column))) then
            report%status = lemke_breakdown
            report%message = 'non-finite entering column'
            exit
         end if
         call select_row(basic, inverse, column, row_norm, column_norm, 1.0_dp, &
                         position(artificial), opts, leaving_row, outcome)
         if (outcome == select_ray) then
            report%status = lemke_ray_termination
            report%message = 'secondary ray: no solution found'
            exit
         else if (outcome /= select_found) then
            report%status = lemke_breakdown
            report%message = 'the ratio test found no row (non-finite ratios)'
            exit
         end if
      end do

      if (finished) then
         call refine(scaled_matrix, scaled_q, covering, basis, basic, row_norm, inverse=inverse)
         call conclude(matrix, q, basic, position, column_exp, q_exp, opts, r, w, report, point)
         if (point == point_inaccurate) then
            ! Accumulated round-off in the updated inverse: factorise the basis afresh.
            call refactor(scaled_matrix, scaled_q, covering, basis, inverse, basic, row_norm, ok)
            if (ok) then
               call conclude(matrix, q, basic, position, column_exp, q_exp, opts, r, w, report, &
                             point)
            end if
         end if
         select case (point)
         case (point_verified)
            report%status = lemke_solved
         case (point_inaccurate)
            report%status = lemke_breakdown
            report%message = 'verification failed after the last pivot'
         case default
            ! conclude has set the message (overflow or non-finite values).
            report%status = lemke_breakdown
         end select
      else
         ! Return the current (infeasible or incomplete) point so the caller can inspect it.
         call conclude(matrix, q, basic, position, column_exp, q_exp, opts, r, w, report, point)
      end if
   end subroutine lemke_solve

   !> Misuse checks: shapes, covering vector, tolerances, counts, finiteness of the data.
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
      if (opts%max_pivots < 0) then
         write (text, '(a,i0)') 'max_pivots must be >= 0 (0: automatic), got ', opts%max_pivots
         call make_error(error, 'lemke_solve: '//trim(text), error_input)
         return
      end if
      if (opts%refactor_interval < 0) then
         write (text, '(a,i0)') 'refactor_interval must be >= 0 (0: never), got ', &
            opts%refactor_interval
         call make_error(error, 'lemke_solve: '//trim(text), error_input)
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

   !> Basic values fresh from a refactorisation: x_i = (B^-1 q)_i is computed from terms bounded by
   !> ||(B^-1)_i.||_1 ||q||_inf, so a value below zero_tolerance times that is an exact zero made
   !> inexact by round-off; flushing it keeps degenerate ties exact for the ratio test.
   pure subroutine flush_roundoff(basic, row_norm, q_norm, zero_tolerance)
      real(dp), intent(inout) :: basic(:)
      real(dp), intent(in) :: row_norm(:), q_norm, zero_tolerance
      where (abs(basic) <= zero_tolerance*row_norm*q_norm) basic = 0.0_dp
   end subroutine flush_roundoff

   !> Entering column B^-1 a_e; O(n^2) for an r variable or z0, O(n) for a w variable (a unit
   !> column). column_norm = ||a_e||_inf, the scale of the column in the equilibrated problem.
   pure subroutine entering_column(matrix, covering, inverse, variable, n, column, column_norm)
      real(dp), intent(in) :: matrix(:, :), covering(:), inverse(:, :)
      integer, intent(in) :: variable, n
      real(dp), intent(out) :: column(:), column_norm
      if (variable <= n) then
         column = inverse(:, variable)
         column_norm = 1.0_dp
      else if (variable <= 2*n) then
         column = -matmul(inverse, matrix(:, variable - n))
         column_norm = maxval(abs(matrix(:, variable - n)))
      else
         column = -matmul(inverse, covering)
         column_norm = maxval(abs(covering))
      end if
   end subroutine entering_column

   !> Lexicographic minimum-ratio test (Murty 1988, Ch. 2; Cottle, Pang & Stone 1992,
   !> Ch. 4). Candidate rows are those with sense*column(i) above its round-off level
   !> pivot_tolerance * row_norm(i) * column_norm (row_norm: 1-norms of the rows of B^-1;
   !> column_norm: ||a_e||_inf, or 0 for exact data). The leaving row minimises the row vector
   !> [x_i, (B^-1)_i.] / (sense*column(i)) lexicographically, which keeps every row of [x_B, B^-1]
   !> lexicographically positive and so rules out cycling. sense = -1 for the first pivot (z0
   !> entering against all rows, ratios q_i/d_i), +1 after. If the row of z0 (artificial_row > 0) is
   !> among the ties of the first component it is chosen (the algorithm then ends).
   !> outcome: select_found (leaving_row > 0), select_ray (no candidate: secondary ray) or
   !> select_failed (no row left, which finite data cannot produce; leaving_row = 0 is never
   !> returned with select_found).
   pure subroutine select_row(basic, inverse, column, row_norm, column_norm, sense, artificial_row, &
                              opts, leaving_row, outcome)
      real(dp), intent(in) :: basic(:), inverse(:, :), column(:), row_norm(:)
      real(dp), intent(in) :: column_norm, sense
      integer, intent(in) :: artificial_row
      type(lemke_options_t), intent(in) :: opts
      integer, intent(out) :: leaving_row, outcome
      real(dp) :: ratio(size(basic)), best, spread, value
      logical :: tied(size(basic))
      integer :: i, k, n

      n = size(basic)
      leaving_row = 0
      outcome = select_failed
      ratio = 0.0_dp
      tied = sense*column > opts%pivot_tolerance*row_norm*column_norm
      if (.not. any(tied)) then
         outcome = select_ray
         return
      end if

      ! First component: the ratio x_i / a_i. After the first pivot x >= 0 in exact arithmetic,
      ! so a negative round-off value is read as zero.
      do i = 1, n
         if (tied(i)) then
            value = basic(i)
            if (sense > 0.0_dp) value = max(value, 0.0_dp)
            ratio(i) = safe_divide(value, sense*column(i))
         end if
      end do
      best = minval(ratio, mask=tied)
      tied = tied .and. ratio <= best + opts%zero_tolerance*abs(best)
      if (artificial_row > 0) then
         if (tied(artificial_row)) then
            leaving_row = artificial_row
            outcome = select_found
            return
         end if
      end if

      ! Further components: the rows of B^-1 divided by the pivot-column entry, until one row is
      ! left. Differences below the zero level relative to the column's spread count as ties.
      do k = 1, n
         if (count(tied) <= 1) exit
         do i = 1, n
            if (tied(i)) ratio(i) = safe_divide(inverse(i, k), sense*column(i))
         end do
         best = minval(ratio, mask=tied)
         spread = maxval(abs(ratio), mask=tied)
         tied = tied .and. ratio <= best + opts%zero_tolerance*spread
      end do
      ! Rows of a nonsingular B^-1 are never proportional, so one row is left in exact
      ! arithmetic; if round-off leaves several, the largest pivot entry is the stable choice.
      value = 0.0_dp
      do i = 1, n
         if (tied(i)) then
            if (sense*column(i) > value) then
               value = sense*column(i)
               leaving_row = i
            end if
         end if
      end do
      if (leaving_row > 0) outcome = select_found
   end subroutine select_row

   !> Gauss-Jordan pivot on row t of [x_B | B^-1] with the entering column a = B^-1 a_e:
   !> row t /= a_t, row i -= a_i * (new row t). O(n^2), column by column for memory order; the row
   !> 1-norms of the new B^-1 are accumulated on the way (row_norm). A new basic value that is
   !> round-off of a cancellation (|x_i - f_i x_t| <= zero_tolerance (|x_i| + |f_i x_t|)) is set to
   !> an exact zero. ok = .false. (and nothing changed) if the result could exceed value_limit:
   !> the bound is checked before anything is computed, so no operation overflows.
   pure subroutine pivot(inverse, basic, column, row, row_norm, zero_tolerance, ok)
      real(dp), intent(inout) :: inverse(:, :), basic(:), row_norm(:)
      real(dp), intent(in) :: column(:), zero_tolerance
      integer, intent(in) :: row
      logical, intent(out) :: ok
      real(dp) :: factor(size(column)), pivot_value, pivot_row_value, pivot_row_norm, row_max
      real(dp) :: growth, bound, term, value, old
      integer :: i, j

      pivot_value = column(row)
      ! New pivot row: (old row) / a_t, at most row_max / |a_t|; other rows: old - (a_i / a_t) *
      ! (old pivot row), at most max(old) + growth * row_max with growth = max|a| / |a_t|.
      row_max = max(maxval(abs(inverse(row, :))), abs(basic(row)))
      growth = safe_divide(maxval(abs(column)), abs(pivot_value))
      bound = saturating_sum(max(maxval(row_norm), maxval(abs(basic))), &
                             saturating_product(growth, row_max))
      ok = bound <= value_limit .and. safe_divide(row_max, abs(pivot_value)) <= value_limit
      if (.not. ok) return

      factor = column/pivot_value
      factor(row) = 0.0_dp
      ! One sweep updates B^-1 and sums the new row norms; row t's entries are overwritten after
      ! the sweep and its norm is exactly the old one over |a_t|.
      pivot_row_norm = row_norm(row)/abs(pivot_value)
      row_norm = 0.0_dp
      do j = 1, size(inverse, 2)
         old = inverse(row, j)
         do i = 1, size(inverse, 1)
            value = inverse(i, j) - factor(i)*old
            inverse(i, j) = value
            row_norm(i) = row_norm(i) + abs(value)
         end do
         inverse(row, j) = old/pivot_value
      end do
      row_norm(row) = pivot_row_norm
      pivot_row_value = basic(row)/pivot_value
      do i = 1, size(basic)
         if (i == row) cycle
         old = basic(i)
         term = factor(i)*basic(row)
         value = old - term
         if (abs(value) <= zero_tolerance*(abs(old) + abs(term))) value = 0.0_dp
         basic(i) = value
      end do
      basic(row) = pivot_row_value
   end subroutine pivot

   !> r from the basic values: r~_j where r_j is basic (negative round-off read as zero), then
   !> unscaled r_j = 2^(q_exp + column_exp(j)) r~_j. representable = .false. (and r = 0) if some
   !> r_j exceeds huge(1.0_dp), checked on the exponents before scaling, or is not finite.
   pure subroutine extract(basic, position, column_exp, q_exp, r, representable)
      real(dp), intent(in) :: basic(:)
      integer, intent(in) :: position(:), column_exp(:), q_exp
      real(dp), intent(out) :: r(:)
      logical, intent(out) :: representable
      real(dp) :: value
      integer :: j, n
      n = size(r)
      r = 0.0_dp
      representable = .true.
      do j = 1, n
         if (position(n + j) == 0) cycle
         if (.not. ieee_is_finite(basic(position(n + j)))) then
            representable = .false.
            cycle
         end if
         value = max(basic(position(n + j)), 0.0_dp)
         if (.not. value > 0.0_dp) cycle
         ! value = f 2^e with f < 1, so value 2^k < 2^(e + k) is finite when e + k <= maxexponent.
         if (exponent(value) + q_exp + column_exp(j) > maxexponent(value)) then
            representable = .false.
         else
            r(j) = scale(value, q_exp + column_exp(j))
         end if
      end do
      if (.not. representable) r = 0.0_dp
   end subroutine extract

   !> ||M||_inf (largest absolute row sum), saturated at huge(1.0_dp); computed relative to the
   !> largest entry, so no partial sum overflows.
   pure real(dp) function inf_norm(matrix)
      real(dp), intent(in) :: matrix(:, :)
      real(dp) :: largest, row_sum(size(matrix, 1))
      integer :: j
      largest = maxval(abs(matrix))
      inf_norm = 0.0_dp
      if (.not. largest > 0.0_dp) return
      row_sum = 0.0_dp
      do j = 1, size(matrix, 2)
         row_sum = row_sum + abs(matrix(:, j))/largest
      end do
      inf_norm = saturating_product(largest, maxval(row_sum))
   end function inf_norm

   !> Verification from the original data: w = q + M r and the residuals of the report (see
   !> `lemke_report_t%residual`). representable = .false. (w = q, report untouched) when
   !> ||M|| ||r|| + ||q|| exceeds huge/2: w could then overflow, and is not computed.
   subroutine verify(matrix, q, r, w, report, representable)
      real(dp), intent(in) :: matrix(:, :), q(:), r(:)
      real(dp), intent(out) :: w(:)
      type(lemke_report_t), intent(inout) :: report
      logical, intent(out) :: representable
      real(dp) :: r_scale, w_scale, w_max
      integer :: i

      r_scale = maxval(abs(r))
      w_scale = saturating_sum(saturating_product(inf_norm(matrix), r_scale), maxval(abs(q)))
      representable = w_scale <= huge(1.0_dp)/2.0_dp
      if (.not. representable) then
         w = q
         return
      end if
      w = q + matmul(matrix, r)
      report%min_r = minval(r)
      report%min_w = minval(w)
      report%active = count(r > 0.0_dp)
      if (r_scale <= 0.0_dp) r_scale = 1.0_dp
      if (w_scale <= 0.0_dp) w_scale = 1.0_dp
      w_max = maxval(abs(w))
      report%complementarity = 0.0_dp
      if (w_max > 0.0_dp) then
         report%complementarity = saturating_product(saturating_product(r_scale, w_max), &
                                                     abs(dot_product(r/r_scale, w/w_max)))
      end if
      report%residual = 0.0_dp
      do i = 1, size(q)
         report%residual = max(report%residual, abs(min(r(i)/r_scale, w(i)/w_scale)))
      end do
   end subroutine verify

   !> Extract r from the basic values, verify it, and classify the point: point_verified (finite,
   !> residual within tolerance), point_inaccurate (finite, residual too large), point_overflow
   !> (r or w not representable: r = 0, w = q returned) or point_not_finite (a non-finite value
   !> slipped through: r = 0, w = q returned). Overflow and non-finite values set the message.
   subroutine conclude(matrix, q, basic, position, column_exp, q_exp, opts, r, w, report, point)
      real(dp), intent(in) :: matrix(:, :), q(:), basic(:)
      integer, intent(in) :: position(:), column_exp(:), q_exp
      type(lemke_options_t), intent(in) :: opts
      real(dp), intent(out) :: r(:), w(:)
      type(lemke_report_t), intent(inout) :: report
      integer, intent(out) :: point
      logical :: representable, fits

      call extract(basic, position, column_exp, q_exp, r, representable)
      if (.not. representable) then
         point = point_overflow
         report%message = report%message//'; the point reached overflows: r exceeds huge, '// &
                          'r = 0 returned'
      else
         call verify(matrix, q, r, w, report, fits)
         if (.not. fits) then
            point = point_overflow
            report%message = report%message//'; w = q + M r would overflow, r = 0 returned'
         else if (.not. (all(ieee_is_finite(r)) .and. all(ieee_is_finite(w)) .and. &
                         ieee_is_finite(report%residual))) then
            point = point_not_finite
            report%message = report%message//'; non-finite r or w, r = 0 returned'
         else if (report%residual <= opts%residual_tolerance) then
            point = point_verified
            return
         else
            point = point_inaccurate
            return
         end if
      end if
      ! r = 0 always fits: ||M|| ||r|| + ||q|| = ||q||.
      r = 0.0_dp
      call verify(matrix, q, r, w, report, fits)
   end subroutine conclude

end module uniarc_lemke
