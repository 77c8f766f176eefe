!> Solvers of an LCP  w = q + M z, w ≥ 0, z ≥ 0, wᵀz = 0  whose matrix is never formed: only the
!> operations of `uniarc_lcp_operator` (q of a frame, M y, Mᵀ y, exchange of a set) are used, so the
!> memory is that of the operator (for the contact LCP: the banded tangent, O(N·b)) plus O(m) vectors
!> and one dense block of O(p²) for p ≤ `complement_limit`, never O(m²) nor O(N·m).
!>
!> A solution is a frame F (a principal pivot transform, see `uniarc_lcp_operator`) with q_F ≥ 0.
!> Two phases reach it:
!>
!> 1. **Block principal pivoting** (Kostreva 1978; Júdice & Pires 1994): exchange at once every index
!>    whose output is negative in the current frame; one exchange (for the contact LCP: one banded
!>    refactorisation) moves many contacts. Júdice and Pires' safeguard counts the infeasibilities:
!>    when their number has not decreased for `block_backup` exchanges that move an index back (one
!>    the phase exchanged before) the phase stops. An exchange of indices the phase never moved is
!>    progress whatever the count: no frame can recur without an index going back, so there are at
!>    most m such exchanges (the edge of a contact region that creeps one candidate per exchange
!>    toward its place, docs/lemke.md). For a P-matrix it typically ends in a few exchanges; it is not
!>    finite in general (`block_steps` caps it), hence phase 2.
!> 2. **Lemke's complementary pivoting** (Lemke 1965; Cottle, Pang & Stone 1992, §4.4), started from
!>    the frame the first phase left: the scheme w = q + M z + d z0 with covering vector d = the unit
!>    of each infeasible output and 1e-6 of it for the others. Its basis is held as the operator's frame plus a dense Schur complement
!>    C = [M_RZ  d_R] of the p columns Z that entered since the last exchange (block-LU update of the
!>    basis: Bisschop & Meeraus 1977; Gill, Murray, Saunders & Wright 1984). A column of M costs one
!>    `apply`, a new row of C one `apply_transpose`, and the direction of all basic variables one
!>    more `apply` (O(N·b) each for the contact LCP). When p reaches `complement_limit`, Z is absorbed
!>    into the frame by one `exchange` (the covering vector is transformed with it, so Lemke's path
!>    goes on unchanged) and C shrinks to 1 × 1. Lemke is finite (with non-degenerate ratio tests) and
!>    is the safeguard of phase 1; its secondary ray proves infeasibility for copositive-plus M.
!>
!> Lemke's path moves one index per pivot; where a whole contact edge must move, block exchanges are
!> cheaper. In the first round Lemke therefore stops after `lemke_budget` pivots: the columns that
!> entered are exchanged into the frame (a principal pivot transform like any other) and the second
!> round starts from it with the block phase. Later rounds run Lemke to its end, so the solver keeps
!> Lemke's finiteness, and a round is left to verify its frame.
!>
!> Every phase ends in a frame whose q_F is computed afresh by the operator (an iterative refinement:
!> for the contact LCP a new banded solve from the nonlinear residual). It is accepted when
!> q_F(i) ≥ −tolerance · scale(i) for every output i, with scale(i) the operator's unit of that output
!> (the gap scale for a gap, the force scale for a reaction). An instance that cannot be brought to
!> that accuracy in `rounds` rounds is reported as a breakdown, never as solved.
module uniarc_lcp_implicit
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_foreign, only: dgetrf, dgetrs, interrupt_signal
   use uniarc_lcp_operator, only: lcp_operator_t
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_lemke, only: lemke_solved, lemke_ray_termination, lemke_pivot_limit, lemke_breakdown
   implicit none
   private
   public :: implicit_lcp_options_t, implicit_lcp_report_t, implicit_lcp_solve

   !> Options of `implicit_lcp_solve`; every component has a usable default.
   type :: implicit_lcp_options_t
      !> Acceptance: q_F(i) ≥ −tolerance · scale(i). 1e-9 is some 1e6 ε: room for the round-off of a
      !> banded solve with a condition number up to ~1e6 (the operator's q_F is computed afresh).
      real(dp) :: tolerance = 1.0e-9_dp
      !> Run the block principal pivoting phase first (off: Lemke alone, e.g. to test it).
      logical :: block_phase = .true.
      !> Júdice–Pires backup count: exchanges allowed without fewer infeasibilities that move an index
      !> back (exchanges of indices never moved before are progress, module header).
      integer :: block_backup = 3
      !> Most exchanges of the block phase in one round.
      integer :: block_steps = 50
      !> A block exchange is made only while more than this many outputs are infeasible; fewer are
      !> left to Lemke, whose pivot (two or three applications) costs far less than an exchange (one
      !> refactorisation) and which cannot cycle as a block exchange can at the edge of a contact
      !> region (measured in docs/benchmarks.md).
      integer :: block_threshold = 4
      !> Columns of the Schur complement before they are absorbed into the frame (≥ 1).
      integer :: complement_limit = 48
      !> Lemke pivots in one round; 0: automatic, max(1000, 20 m). Lemke's path can be O(m) long with a
      !> large constant: a lift-off front that travels the whole model takes 5–16 pivots per candidate
      !> (a long cantilever on a tensionless bed, docs/benchmarks.md §11; 4 m stopped it at n = 300). The
      !> same cap as the dense `lemke_solve` (20 n); for a P-matrix the path is finite without a cap.
      integer :: max_pivots = 0
      !> Verification rounds (a round = block phase, then Lemke if needed, then a fresh q_F).
      integer :: rounds = 4
      !> Lemke pivots before the first round hands over to the second round's block phase (module
      !> header; only with rounds > 2); 0: no budget.
      integer :: lemke_budget = 8
   end type implicit_lcp_options_t

   !> What `implicit_lcp_solve` did.
   type :: implicit_lcp_report_t
      !> lemke_solved, lemke_ray_termination, lemke_pivot_limit or lemke_breakdown.
      integer :: status = lemke_breakdown
      !> Principal pivots: indices exchanged by block steps plus Lemke's basis exchanges.
      integer :: pivots = 0
      integer :: block_steps = 0       !< exchanges of the block phase
      integer :: lemke_pivots = 0      !< basis exchanges of Lemke's phase (z0 entering included)
      integer :: exchanges = 0         !< frame changes (refactorisations of the contact operator)
      integer :: solves = 0            !< operator applications: frame_q, apply, apply_transpose
      integer :: largest_complement = 0  !< largest p of Lemke's Schur complement
      !> max_i max(0, −q_F(i)/scale(i)) at the returned frame (≤ tolerance when solved).
      real(dp) :: residual = 0.0_dp
      character(len=:), allocatable :: message
      !> An out-of-memory error of the solver or the operator (uniarc_error: out_of_memory), kept for
      !> implicit_lcp_solve to return: it ends the run instead of reading as an LCP without solution.
      type(error_t), allocatable :: fatal
   end type implicit_lcp_report_t

   !> Relative size below which a pivot entry is taken as the round-off of zero: 1e-12 of the largest
   !> entry of the same kind in the direction (about 1e4 ε, the error of a direction from one
   !> banded solve and one Schur solve).
   real(dp), parameter :: pivot_tolerance = 1.0e-12_dp

contains

   !> Solve the LCP of `operator` to the frame of a solution.
   !>
   !> In: the operator in its starting frame (for a warm start: the last solution's frame).
   !> Out: the operator in the solution's frame; w = q_F (m) there (z = 0); the report. An outcome
   !> other than solved is a status with a message; `error` is allocated only for misuse (options).
   subroutine implicit_lcp_solve(operator, w, report, error, options)
      class(lcp_operator_t), intent(inout) :: operator
      real(dp), intent(out) :: w(:)
      type(implicit_lcp_report_t), intent(out) :: report
      type(error_t), allocatable, intent(out) :: error
      type(implicit_lcp_options_t), intent(in), optional :: options
      type(implicit_lcp_options_t) :: opts
      real(dp), allocatable :: q(:), scale(:)
      type(error_t), allocatable :: failure
      integer :: m, round, status
      logical :: solved, broken
      if (present(options)) opts = options
      if (opts%block_backup < 0 .or. opts%block_steps < 0 .or. opts%block_threshold < 0 .or. opts%complement_limit < 1 .or. &
          opts%max_pivots < 0 .or. opts%lemke_budget < 0 .or. opts%rounds < 1 .or. .not. (opts%tolerance >= 0.0_dp)) then
         call make_error(error, 'implicit LCP solver: negative count, complement_limit < 1, rounds < 1 '// &
                         'or a negative tolerance in the options', error_input)
         return
      end if
      m = operator%order()
      if (size(w) /= m) then
         call make_error(error, 'implicit LCP solver: w must have the order of the operator', error_input)
         return
      end if
      if (opts%max_pivots == 0) opts%max_pivots = max(1000, 20*m)
      allocate (q(m), scale(m), stat=status)
      call allocation_failure(status, 'the vectors of the contact LCP''s solver', 16.0_dp*m, error_analysis, error)
      if (allocated(error)) return
      report%message = 'not solved to the stated accuracy'
      do round = 1, opts%rounds
         if (interrupted(report)) return
         call operator%frame_q(q, failure)
         report%solves = report%solves + 1
         if (allocated(failure)) then
            call breakdown(report, failure%message)
            call keep_fatal(report, failure)
            return
         end if
         call operator%scales(scale)
         if (.not. all(ieee_is_finite(q))) then
            call breakdown(report, 'the LCP vector q is not finite')
            return
         end if
         report%residual = infeasibility(q, scale)
         if (report%residual <= opts%tolerance) then
            w = q
            report%status = lemke_solved
            report%message = 'solved'
            return
         end if
         if (opts%block_phase) then
            call block_pivoting(operator, opts, q, scale, report, solved, broken)
            if (broken) return
            if (solved) then
               w = q
               report%residual = infeasibility(q, scale)
               report%status = lemke_solved
               report%message = 'solved'
               return
            end if
         end if
         call lemke_phase(operator, opts, q, scale, report, round == 1 .and. opts%rounds > 2)
         if (report%status /= lemke_solved) return
         ! Lemke ended in the solution's frame: the next round checks it with a fresh q_F.
         report%status = lemke_breakdown
      end do
      call breakdown(report, 'the contact LCP cannot be solved to the stated accuracy (relative '// &
                     'infeasibility '//real_to_string(report%residual)//' after '//integer_to_string(opts%rounds)//' rounds)')
   end subroutine implicit_lcp_solve

   !> Block principal pivoting with Júdice and Pires' safeguard; `q` and `scale` follow the frame.
   !> `broken`: the operator failed after an exchange (status breakdown, message set).
   subroutine block_pivoting(operator, opts, q, scale, report, solved, broken)
      class(lcp_operator_t), intent(inout) :: operator
      type(implicit_lcp_options_t), intent(in) :: opts
      real(dp), intent(inout) :: q(:), scale(:)
      type(implicit_lcp_report_t), intent(inout) :: report
      logical, intent(out) :: solved, broken
      logical, allocatable :: violated(:), moved(:)
      type(error_t), allocatable :: failure
      integer :: step, count_violated, fewest, backup, status
      solved = .false.
      broken = .false.
      allocate (violated(size(q)), moved(size(q)), stat=status)
      call allocation_failure(status, 'the block pivots of the contact LCP', 8.0_dp*size(q), error_analysis, failure)
      if (allocated(failure)) then
         call keep_fatal(report, failure)
         broken = .true.
         return
      end if
      fewest = size(q) + 1
      backup = opts%block_backup
      ! indices exchanged an odd number of times by this phase (the frame it started from: false)
      moved = .false.
      do step = 1, opts%block_steps + 1
         if (interrupted(report)) then
            broken = .true.
            return
         end if
         violated = q < -opts%tolerance*scale
         count_violated = count(violated)
         if (count_violated == 0) then
            solved = .true.
            return
         end if
         if (step > opts%block_steps .or. count_violated <= opts%block_threshold) return
         if (count_violated < fewest) then
            fewest = count_violated
            backup = opts%block_backup
         else if (any(violated .and. moved)) then
            ! No fewer infeasibilities and an index goes back: the exchanges may be cycling.
            if (backup > 0) then
               backup = backup - 1
            else
               return
            end if
         end if
         ! No fewer infeasibilities, but none of them moved by this phase before, is progress: no
         ! frame can recur without an index going back, and each such step moves a new index (at
         ! most m of them). The edges of contact regions that creep one candidate per exchange
         ! toward their place make these steps (docs/lemke.md, docs/benchmarks.md §9).
         call operator%exchange(violated, failure)
         report%exchanges = report%exchanges + 1
         ! A singular frame (the exchanged contacts would leave a mechanism): the operator kept the
         ! frame it had, and Lemke goes on from there (out of memory: the solve ends).
         if (allocated(failure)) then
            call keep_fatal(report, failure)
            broken = allocated(report%fatal)
            return
         end if
         moved = moved .neqv. violated
         report%block_steps = report%block_steps + 1
         report%pivots = report%pivots + count_violated
         call operator%frame_q(q, failure)
         report%solves = report%solves + 1
         if (allocated(failure)) then
            call breakdown(report, failure%message)
            call keep_fatal(report, failure)
            broken = .true.
            return
         end if
         call operator%scales(scale)
         if (.not. all(ieee_is_finite(q))) then
            call breakdown(report, 'the LCP vector q is not finite after a block exchange')
            broken = .true.
            return
         end if
      end do
   end subroutine block_pivoting

   !> Lemke's method from the current frame, the basis as frame + Schur complement (module header).
   !> Ends with status solved in the frame of the complementary solution, or another status.
   subroutine lemke_phase(operator, opts, q, scale, report, budgeted)
      class(lcp_operator_t), intent(inout) :: operator
      type(implicit_lcp_options_t), intent(in) :: opts
      real(dp), intent(inout) :: q(:), scale(:)
      type(implicit_lcp_report_t), intent(inout) :: report
      !> Stop after opts%lemke_budget pivots with Z exchanged into the frame (status solved: the caller
      !> checks the frame afresh and goes on from it).
      logical, intent(in) :: budgeted
      real(dp), allocatable :: d(:), z(:), wv(:), column(:), row(:), dz(:), dw(:), unit_vector(:)
      real(dp), allocatable :: entries(:, :), rhs(:), y(:)
      integer, allocatable :: rows(:), cols(:)
      logical, allocatable :: basic_w(:)
      type(error_t), allocatable :: failure
      real(dp) :: z0, dz0, t, best_ratio, best_slope, ratio, slope, largest_w, largest_z
      integer :: m, k, p, capacity, pivots, i, b, leave_kind, leave_index, position, status
      integer, parameter :: leave_none = 0, leave_z0 = 1, leave_w = 2, leave_z = 3
      logical :: entering_z, absorbed
      m = size(q)
      capacity = 2*opts%complement_limit + 2
      allocate (entries(capacity + 1, capacity), rows(capacity + 1), cols(capacity))
      allocate (z(m), unit_vector(m), column(m), row(m), dz(m), dw(m), d(m), wv(m), basic_w(m), stat=status)
      call allocation_failure(status, 'the vectors of Lemke''s method', 68.0_dp*m, error_analysis, failure)
      if (allocated(failure)) then
         call keep_fatal(report, failure)
         return
      end if
      z = 0.0_dp
      unit_vector = 0.0_dp
      allocate (rhs(capacity + 1), y(capacity + 1))
      ! Start: z0 enters at the most negative q_i/d_i. The covering vector is the unit of each output
      ! where the output is infeasible and 1e-6 of it elsewhere (any d > 0 is a valid covering vector,
      ! Cottle, Pang & Stone §4.4): the outputs that are already right hardly move with z0, so
      ! Lemke's path stays among the contacts that must change (pivots measured in
      ! docs/benchmarks.md).
      d = scale
      where (q >= 0.0_dp) d = 1.0e-6_dp*scale
      k = minloc(q/d, 1)
      z0 = -q(k)/d(k)
      wv = max(q + d*z0, 0.0_dp)
      wv(k) = 0.0_dp
      basic_w = .true.
      basic_w(k) = .false.
      p = 0
      rows(1) = k
      entering_z = .true.
      pivots = 1
      report%lemke_pivots = report%lemke_pivots + 1
      report%pivots = report%pivots + 1
      do
         if (interrupted(report)) return
         if (pivots >= opts%max_pivots) then
            report%status = lemke_pivot_limit
            report%message = 'Lemke: pivot limit ('//integer_to_string(opts%max_pivots)//') reached'
            return
         end if
         ! Right-hand side of the Schur system over the rows R = Z ∪ {k}.
         rhs(1:p + 1) = 0.0_dp
         if (entering_z) then
            unit_vector(k) = 1.0_dp
            call operator%apply(unit_vector, column, failure)
            unit_vector(k) = 0.0_dp
            report%solves = report%solves + 1
            if (allocated(failure)) then
               call breakdown(report, failure%message)
               call keep_fatal(report, failure)
               return
            end if
            rhs(1:p + 1) = -column(rows(1:p + 1))
         else
            position = findloc(rows(1:p + 1), k, 1)
            rhs(position) = 1.0_dp
         end if
         call schur_solve(entries(1:p + 1, 1:p), d(rows(1:p + 1)), rhs(1:p + 1), y(1:p + 1), failure)
         if (allocated(failure)) then
            call breakdown(report, 'Lemke: singular basis ('//failure%message//')')
            call keep_fatal(report, failure)
            return
         end if
         dz = 0.0_dp
         dz(cols(1:p)) = y(1:p)
         dz0 = y(p + 1)
         if (entering_z) dz(k) = 1.0_dp
         call operator%apply(dz, dw, failure)
         report%solves = report%solves + 1
         if (allocated(failure)) then
            call breakdown(report, failure%message)
            call keep_fatal(report, failure)
            return
         end if
         dw = dw + d*dz0
         if (.not. (all(ieee_is_finite(dw)) .and. ieee_is_finite(dz0) .and. all(ieee_is_finite(y(1:p + 1))))) then
            call breakdown(report, 'Lemke: non-finite direction')
            return
         end if
         ! Minimum ratio over the basic variables that decrease; ties (within 1e-9 relative) go to
         ! z0 (Lemke's rule: leave as soon as possible), then to the steepest relative slope.
         largest_w = maxval(abs(dw)/scale, mask=basic_w)
         if (.not. any(basic_w)) largest_w = 0.0_dp
         largest_z = 0.0_dp
         if (p > 0) largest_z = maxval(abs(y(1:p)))
         leave_kind = leave_none
         leave_index = 0
         best_ratio = huge(1.0_dp)
         best_slope = 0.0_dp
         if (dz0 < -pivot_tolerance) call consider(z0/(-dz0), huge(1.0_dp), leave_z0, 0)
         do b = 1, p
            if (y(b) < -pivot_tolerance*largest_z) call consider(z(cols(b))/(-y(b)), -y(b)/largest_z, leave_z, b)
         end do
         do i = 1, m
            if (.not. basic_w(i)) cycle
            if (dw(i) < -pivot_tolerance*largest_w*scale(i)) &
               call consider(wv(i)/(-dw(i)), -dw(i)/(scale(i)*largest_w), leave_w, i)
         end do
         if (leave_kind == leave_none) then
            report%status = lemke_ray_termination
            report%message = 'Lemke: ray termination (no blocking variable) -- no solution found'
            return
         end if
         t = max(best_ratio, 0.0_dp)
         ! Move along the direction.
         z0 = max(z0 + t*dz0, 0.0_dp)
         z(cols(1:p)) = max(z(cols(1:p)) + t*y(1:p), 0.0_dp)
         where (basic_w) wv = max(wv + t*dw, 0.0_dp)
         if (entering_z) then
            z(k) = t
         else
            wv(k) = t
            basic_w(k) = .true.
         end if
         pivots = pivots + 1
         report%lemke_pivots = report%lemke_pivots + 1
         report%pivots = report%pivots + 1
         select case (leave_kind)
         case (leave_z0)
            if (entering_z) then
               p = p + 1
               cols(p) = k
            end if
            call finish(failure)
            return
         case (leave_w)
            wv(leave_index) = 0.0_dp
            basic_w(leave_index) = .false.
            if (entering_z) then
               ! Z gains k, R gains leave_index: a new column and a new row of C.
               entries(1:p + 1, p + 1) = column(rows(1:p + 1))
               p = p + 1
               cols(p) = k
               rows(p + 1) = leave_index
            else
               ! R loses k and gains leave_index: the row of k is replaced.
               position = findloc(rows(1:p + 1), k, 1)
               rows(position) = leave_index
            end if
            call new_row(findloc(rows(1:p + 1), leave_index, 1), failure)
            if (allocated(failure)) then
               call breakdown(report, failure%message)
               call keep_fatal(report, failure)
               return
            end if
            k = leave_index
            entering_z = .true.
         case (leave_z)
            i = cols(leave_index)
            z(i) = 0.0_dp
            if (entering_z) then
               ! Z: k takes the place of i; R is unchanged as a set.
               cols(leave_index) = k
               entries(1:p + 1, leave_index) = column(rows(1:p + 1))
            else
               ! Z loses i, R loses k (R becomes the old Z).
               position = findloc(rows(1:p + 1), k, 1)
               rows(position) = rows(p + 1)
               entries(position, 1:p) = entries(p + 1, 1:p)
               cols(leave_index) = cols(p)
               entries(1:p, leave_index) = entries(1:p, p)
               p = p - 1
            end if
            k = i
            entering_z = .false.
         end select
         report%largest_complement = max(report%largest_complement, p)
         if (budgeted .and. opts%lemke_budget > 0 .and. pivots >= opts%lemke_budget .and. p > 0) then
            call finish(failure)
            return
         end if
         if (p >= opts%complement_limit) then
            call absorb(absorbed, failure)
            if (allocated(failure)) then
               call breakdown(report, failure%message)
               call keep_fatal(report, failure)
               return
            end if
            if (.not. absorbed .and. p >= capacity - 1) then
               call breakdown(report, 'Lemke: the Schur complement cannot be absorbed (singular block)')
               return
            end if
         end if
      end do

   contains

      !> Keep the blocking variable with the smallest ratio (ties: z0, then the steeper slope).
      subroutine consider(candidate_ratio, candidate_slope, kind, index)
         real(dp), intent(in) :: candidate_ratio, candidate_slope
         integer, intent(in) :: kind, index
         logical :: better
         ratio = max(candidate_ratio, 0.0_dp)
         slope = candidate_slope
         if (leave_kind == leave_none .or. ratio < best_ratio - 1.0e-9_dp*abs(best_ratio)) then
            better = .true.
         else if (ratio <= best_ratio + 1.0e-9_dp*abs(best_ratio)) then
            better = leave_kind /= leave_z0 .and. (kind == leave_z0 .or. slope > best_slope)
         else
            better = .false.
         end if
         if (.not. better) return
         if (leave_kind == leave_none) then
            best_ratio = ratio
         else
            best_ratio = min(ratio, best_ratio)
         end if
         best_slope = slope
         leave_kind = kind
         leave_index = index
      end subroutine consider

      !> Row `at` of C: M(rows(at), Z) from one transposed application.
      subroutine new_row(at, failure)
         integer, intent(in) :: at
         type(error_t), allocatable, intent(out) :: failure
         unit_vector(rows(at)) = 1.0_dp
         call operator%apply_transpose(unit_vector, row, failure)
         unit_vector(rows(at)) = 0.0_dp
         report%solves = report%solves + 1
         if (allocated(failure)) return
         entries(at, 1:p) = row(cols(1:p))
      end subroutine new_row

      !> z0 has left: exchange the basic z into the frame; the caller verifies the new q_F afresh.
      subroutine finish(failure)
         type(error_t), allocatable, intent(out) :: failure
         logical, allocatable :: flip(:)
         integer :: status
         allocate (flip(m), stat=status)
         call allocation_failure(status, 'the exchange of Lemke''s method', 4.0_dp*m, error_analysis, failure)
         if (allocated(failure)) then
            call keep_fatal(report, failure)
            return
         end if
         flip = .false.
         flip(cols(1:p)) = .true.
         if (p > 0) then
            call operator%exchange(flip, failure)
            report%exchanges = report%exchanges + 1
            if (allocated(failure)) then
               call breakdown(report, 'Lemke: the solution frame is singular ('//failure%message//')')
               call keep_fatal(report, failure)
               return
            end if
         end if
         report%status = lemke_solved
         report%message = 'solved'
      end subroutine finish

      !> Absorb Z into the frame: the covering vector transformed by the PPT on Z (d'_Z = −M_ZZ⁻¹ d_Z,
      !> d'_N = d_N + M_NZ d'_Z), q_F afresh, and the basic values recomputed from it (a refinement).
      !> `absorbed` is false (and nothing changed) when M_ZZ or the frame would be singular.
      subroutine absorb(absorbed, failure)
         logical, intent(out) :: absorbed
         type(error_t), allocatable, intent(out) :: failure
         real(dp), allocatable :: mzz(:, :), dzz(:, :), shift(:), new_d(:)
         integer, allocatable :: ipiv(:)
         logical, allocatable :: flip(:)
         integer :: a, info, status
         type(error_t), allocatable :: singular
         absorbed = .false.
         allocate (shift(m), new_d(m), flip(m), stat=status)
         call allocation_failure(status, 'the vectors of an absorption of Lemke''s method', 20.0_dp*m, &
                                 error_analysis, failure)
         if (allocated(failure)) then
            call keep_fatal(report, failure)
            return
         end if
         allocate (mzz(p, p), dzz(p, 1), ipiv(p))
         do a = 1, p
            mzz(a, :) = entries(findloc(rows(1:p + 1), cols(a), 1), 1:p)
         end do
         dzz(:, 1) = d(cols(1:p))
         call dgetrf(p, p, mzz, p, ipiv, info)
         if (info /= 0) return
         call dgetrs('N', p, 1, mzz, p, ipiv, dzz, p, info)
         dz = 0.0_dp
         dz(cols(1:p)) = -dzz(:, 1)
         call operator%apply(dz, shift, failure)
         report%solves = report%solves + 1
         if (allocated(failure)) return
         new_d = d + shift
         new_d(cols(1:p)) = -dzz(:, 1)
         flip = .false.
         flip(cols(1:p)) = .true.
         call operator%exchange(flip, singular)
         report%exchanges = report%exchanges + 1
         if (allocated(singular)) then
            call keep_fatal(report, singular)
            return
         end if
         absorbed = .true.
         d = new_d
         call operator%frame_q(q, failure)
         report%solves = report%solves + 1
         if (allocated(failure)) return
         call operator%scales(scale)
         if (.not. (abs(d(k)) > 0.0_dp)) then
            call make_error(failure, 'Lemke: zero covering entry after an absorption')
            return
         end if
         z0 = max(-q(k)/d(k), 0.0_dp)
         wv = max(q + d*z0, 0.0_dp)
         wv(k) = 0.0_dp
         basic_w = .true.
         basic_w(k) = .false.
         z = 0.0_dp
         p = 0
         rows(1) = k
      end subroutine absorb

   end subroutine lemke_phase

   !> Solve C y = rhs for C = [block  dcol] ((p+1) × (p+1)) by LU with one step of refinement.
   !> C mixes units (gap per reaction, reaction per gap, the covering vector), so it is equilibrated
   !> first (rows, then columns, by their largest entries): the singularity test — a pivot below
   !> (p+1) ε of the equilibrated matrix, whose entries are at most 1 — is then independent of units.
   subroutine schur_solve(block, dcol, rhs, y, failure)
      real(dp), intent(in) :: block(:, :), dcol(:), rhs(:)
      real(dp), intent(out) :: y(:)
      type(error_t), allocatable, intent(out) :: failure
      real(dp), allocatable :: c(:, :), lu(:, :), work(:, :), row_scale(:), column_scale(:)
      integer, allocatable :: ipiv(:)
      integer :: n, info, j
      real(dp) :: smallest
      n = size(rhs)
      allocate (c(n, n), ipiv(n), work(n, 1), row_scale(n), column_scale(n))
      if (n > 1) c(:, 1:n - 1) = block
      c(:, n) = dcol
      do j = 1, n
         row_scale(j) = maxval(abs(c(j, :)))
      end do
      if (.not. all(row_scale > 0.0_dp)) then
         call make_error(failure, 'a zero row')
         return
      end if
      do j = 1, n
         c(j, :) = c(j, :)/row_scale(j)
      end do
      do j = 1, n
         column_scale(j) = maxval(abs(c(:, j)))
      end do
      if (.not. all(column_scale > 0.0_dp)) then
         call make_error(failure, 'a zero column')
         return
      end if
      do j = 1, n
         c(:, j) = c(:, j)/column_scale(j)
      end do
      lu = c
      call dgetrf(n, n, lu, n, ipiv, info)
      smallest = minval([(abs(lu(j, j)), j=1, n)])
      if (info /= 0 .or. .not. (smallest > real(n, dp)*epsilon(1.0_dp))) then
         call make_error(failure, 'pivot '//real_to_string(smallest)//' of the equilibrated matrix')
         return
      end if
      work(:, 1) = rhs/row_scale
      call dgetrs('N', n, 1, lu, n, ipiv, work, n, info)
      y = work(:, 1)
      work(:, 1) = rhs/row_scale - matmul(c, y)
      call dgetrs('N', n, 1, lu, n, ipiv, work, n, info)
      y = (y + work(:, 1))/column_scale
   end subroutine schur_solve

   !> Largest relative infeasibility max_i max(0, −q_i/scale_i).
   pure real(dp) function infeasibility(q, scale)
      real(dp), intent(in) :: q(:), scale(:)
      infeasibility = 0.0_dp
      if (size(q) > 0) infeasibility = max(0.0_dp, maxval(-q/scale))
   end function infeasibility

   !> Keep `failure` in report%fatal when it is out of memory (the first one kept); nothing otherwise.
   subroutine keep_fatal(report, failure)
      type(implicit_lcp_report_t), intent(inout) :: report
      type(error_t), allocatable, intent(inout) :: failure
      if (.not. allocated(failure)) return
      if (.not. failure%out_of_memory .or. allocated(report%fatal)) return
      call move_alloc(failure, report%fatal)
      report%status = lemke_breakdown
      report%message = report%fatal%message
   end subroutine keep_fatal

   !> True when a SIGINT or SIGTERM has arrived (uniarc_foreign: interrupt_signal, polled once per
   !> pivot, exchange and round): the solve is abandoned as a breakdown whose message says so, and its
   !> caller's step does not converge (docs/contracts.md, "Interrupts").
   logical function interrupted(report)
      type(implicit_lcp_report_t), intent(inout) :: report
      interrupted = interrupt_signal() /= 0
      if (interrupted) call breakdown(report, 'interrupted by a signal')
   end function interrupted

   subroutine breakdown(report, message)
      type(implicit_lcp_report_t), intent(inout) :: report
      character(len=*), intent(in) :: message
      report%status = lemke_breakdown
      report%message = message
   end subroutine breakdown

end module uniarc_lcp_implicit
