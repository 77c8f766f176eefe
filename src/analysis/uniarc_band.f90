!> Square matrices in LAPACK general band storage, assembled through DOF maps and factorised by band LU.
!>
!> Storage (LAPACK `dgbtrf` layout): A(i, j) lives in ab(kl + ku + 1 + i - j, j) for
!> max(1, j - ku) <= i <= min(n, j + kl); the first kl rows are room for the fill-in of row pivoting.
!> Memory and work are O(n·b) and O(n·b²) for half-bandwidth b: no dense n×n matrix anywhere.
!> A general (not Cholesky) factorisation is used because the tangent is indefinite past limit points.
module uniarc_band
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input
   use uniarc_strings, only: integer_to_string
   use uniarc_memory, only: allocation_failure
   use uniarc_foreign, only: dgbtrf, dgbtrs, lapack_check
   implicit none
   private
   public :: band_matrix_t
   public :: band_allocate, band_zero, band_add_element, band_add, band_get, band_multiply, band_product
   public :: band_factorize, band_solve, band_solve_transpose, band_inertia, band_set
   public :: band_copy, band_move, band_inertia_from_factors, band_weakest_pivot, &
             band_row_terms

   !> A square band matrix, its LU factors once factorised, and what the factorisation tells.
   type :: band_matrix_t
      integer :: n = 0          !< order
      integer :: kl = 0         !< sub-diagonals
      integer :: ku = 0         !< super-diagonals
      integer :: ldab = 1       !< leading dimension: 2 kl + ku + 1
      real(dp), allocatable :: ab(:, :)
      integer, allocatable :: pivots(:)
      logical :: factorized = .false.
      integer :: det_sign = 0   !< sign of the determinant after factorisation (0 if singular)
   end type band_matrix_t

contains

   !> Allocate an n×n band matrix with half-bandwidths kl, ku and set it to zero: (2 kl + ku + 1) n reals.
   !> With `error` present, an allocation the system refuses is returned (error_input, exit code 2:
   !> the model does not fit in memory) with the matrix's size, instead of ending the program.
   subroutine band_allocate(matrix, n, kl, ku, error, category)
      type(band_matrix_t), intent(out) :: matrix
      integer, intent(in) :: n, kl, ku
      type(error_t), allocatable, intent(out), optional :: error
      !> error_input (default: exit code 2) or error_analysis (exit code 1), as band_copy
      integer, intent(in), optional :: category
      integer :: status, error_category
      matrix%n = n
      matrix%kl = kl
      matrix%ku = ku
      matrix%ldab = 2*kl + ku + 1
      if (.not. present(error)) then
         allocate (matrix%ab(matrix%ldab, max(n, 1)), source=0.0_dp)
         allocate (matrix%pivots(max(n, 1)), source=0)
         return
      end if
      error_category = error_input
      if (present(category)) error_category = category
      allocate (matrix%ab(matrix%ldab, max(n, 1)), matrix%pivots(max(n, 1)), stat=status)
      call allocation_failure(status, 'the band matrix of '//integer_to_string(n)//' equations and half bandwidth '// &
                              integer_to_string(max(kl, ku)), 8.0_dp*real(matrix%ldab, dp)*real(max(n, 1), dp), &
                              error_category, error)
      if (allocated(error)) return
      matrix%ab = 0.0_dp
      matrix%pivots = 0
   end subroutine band_allocate

   !> target ← source, entries and factorisation state; the target's storage is reused when it has
   !> the shape already (no allocation per copy: a copy of a large band is a memory copy only).
   !> With `error` present, an allocation the system refuses is returned (error_input, exit code 2:
   !> the model does not fit in memory) with the copy's size, as band_allocate does; target is then
   !> left without storage. `category` (default error_input) is error_analysis for a copy made within
   !> an analysis step (exit code 1: the analysis ran out of memory).
   subroutine band_copy(source, target, error, category)
      type(band_matrix_t), intent(in) :: source
      type(band_matrix_t), intent(inout) :: target
      type(error_t), allocatable, intent(out), optional :: error
      integer, intent(in), optional :: category
      integer :: status, refusal_category
      if (allocated(target%ab)) then
         if (any(shape(target%ab) /= shape(source%ab))) deallocate (target%ab, target%pivots)
      end if
      if (.not. allocated(target%ab)) then
         if (present(error)) then
            allocate (target%ab(size(source%ab, 1), size(source%ab, 2)), target%pivots(size(source%pivots)), &
                      stat=status)
            if (status /= 0) then
               refusal_category = error_input
               if (present(category)) refusal_category = category
               if (allocated(target%ab)) deallocate (target%ab)
               if (allocated(target%pivots)) deallocate (target%pivots)
               call allocation_failure(status, 'a copy of the band matrix of '//integer_to_string(source%n)// &
                                       ' equations and half bandwidth '//integer_to_string(max(source%kl, source%ku)), &
                                       8.0_dp*real(size(source%ab, 1), dp)*real(size(source%ab, 2), dp), refusal_category, error)
               return
            end if
         else
            allocate (target%ab(size(source%ab, 1), size(source%ab, 2)), target%pivots(size(source%pivots)))
         end if
      end if
      target%ab(:, :) = source%ab
      target%pivots(:) = source%pivots
      call copy_description(source, target)
   end subroutine band_copy

   !> target ← source without copying the entries (their storage moves); source is left empty.
   subroutine band_move(source, target)
      type(band_matrix_t), intent(inout) :: source
      type(band_matrix_t), intent(inout) :: target
      if (allocated(target%ab)) deallocate (target%ab)
      if (allocated(target%pivots)) deallocate (target%pivots)
      call move_alloc(source%ab, target%ab)
      call move_alloc(source%pivots, target%pivots)
      call copy_description(source, target)
      source%factorized = .false.
   end subroutine band_move

   !> The scalar components (order, bandwidths, factorisation state) of source into target.
   pure subroutine copy_description(source, target)
      type(band_matrix_t), intent(in) :: source
      type(band_matrix_t), intent(inout) :: target
      target%n = source%n
      target%kl = source%kl
      target%ku = source%ku
      target%ldab = source%ldab
      target%factorized = source%factorized
      target%det_sign = source%det_sign
   end subroutine copy_description

   !> Zero the entries for a new assembly.
   subroutine band_zero(matrix)
      type(band_matrix_t), intent(inout) :: matrix
      matrix%ab = 0.0_dp
      matrix%factorized = .false.
      matrix%det_sign = 0
   end subroutine band_zero

   !> Add one entry A(i, j) += value (i, j inside the band).
   pure subroutine band_add(matrix, i, j, value)
      type(band_matrix_t), intent(inout) :: matrix
      integer, intent(in) :: i, j
      real(dp), intent(in) :: value
      integer :: row
      row = matrix%kl + matrix%ku + 1 + i - j
      matrix%ab(row, j) = matrix%ab(row, j) + value
   end subroutine band_add

   !> Set one entry A(i, j) = value (i, j inside the band) of an unfactorised matrix.
   pure subroutine band_set(matrix, i, j, value)
      type(band_matrix_t), intent(inout) :: matrix
      integer, intent(in) :: i, j
      real(dp), intent(in) :: value
      matrix%ab(matrix%kl + matrix%ku + 1 + i - j, j) = value
   end subroutine band_set

   !> Entry A(i, j) of an unfactorised matrix (zero outside the band).
   pure function band_get(matrix, i, j) result(value)
      type(band_matrix_t), intent(in) :: matrix
      integer, intent(in) :: i, j
      real(dp) :: value
      value = 0.0_dp
      if (i - j > matrix%kl .or. j - i > matrix%ku) return
      value = matrix%ab(matrix%kl + matrix%ku + 1 + i - j, j)
   end function band_get

   !> Scatter an element matrix through its steering vector: equation numbers, 0 for an eliminated DOF.
   pure subroutine band_add_element(matrix, equations, element_matrix)
      type(band_matrix_t), intent(inout) :: matrix
      integer, intent(in) :: equations(:)
      real(dp), intent(in) :: element_matrix(:, :)
      integer :: a, b, i, j, offset
      offset = matrix%kl + matrix%ku + 1
      do b = 1, size(equations)
         j = equations(b)
         if (j <= 0) cycle
         do a = 1, size(equations)
            i = equations(a)
            if (i <= 0) cycle
            matrix%ab(offset + i - j, j) = matrix%ab(offset + i - j, j) + element_matrix(a, b)
         end do
      end do
   end subroutine band_add_element

   !> y = A x for an unfactorised band matrix.
   pure function band_multiply(matrix, x) result(y)
      type(band_matrix_t), intent(in) :: matrix
      real(dp), intent(in) :: x(:)
      real(dp) :: y(size(x))
      call band_product(matrix, x, y)
   end function band_multiply

   !> y = A x (n) into the caller's `y`, as band_multiply: without the function's result, which the
   !> Release build allocates unchecked for a large n (docs/contracts.md, "Memory").
   pure subroutine band_product(matrix, x, y)
      type(band_matrix_t), intent(in) :: matrix
      real(dp), intent(in) :: x(:)
      real(dp), intent(out) :: y(:)   !< (size(x))
      integer :: i, j, offset
      offset = matrix%kl + matrix%ku + 1
      y = 0.0_dp
      do j = 1, matrix%n
         do i = max(1, j - matrix%ku), min(matrix%n, j + matrix%kl)
            y(i) = y(i) + matrix%ab(offset + i - j, j)*x(j)
         end do
      end do
   end subroutine band_product

   !> Factorise in place by band LU with partial pivoting (dgbtrf) and record the sign of det A.
   !> A zero pivot is reported as an error (category analysis): the caller cuts the step.
   subroutine band_factorize(matrix, error)
      type(band_matrix_t), intent(inout) :: matrix
      type(error_t), allocatable, intent(out) :: error
      integer :: info, i, sign_product
      matrix%factorized = .false.
      matrix%det_sign = 0
      if (matrix%n == 0) then
         matrix%factorized = .true.
         matrix%det_sign = 1
         return
      end if
      call dgbtrf(matrix%n, matrix%n, matrix%kl, matrix%ku, matrix%ab, matrix%ldab, matrix%pivots, info)
      call lapack_check('dgbtrf', info, error)
      if (allocated(error)) return
      ! det A = (-1)^(row interchanges) · Π U_ii; U's diagonal is row kl + ku + 1 of the factors.
      sign_product = 1
      do i = 1, matrix%n
         if (matrix%pivots(i) /= i) sign_product = -sign_product
         if (matrix%ab(matrix%kl + matrix%ku + 1, i) < 0.0_dp) sign_product = -sign_product
      end do
      matrix%det_sign = sign_product
      matrix%factorized = .true.
   end subroutine band_factorize

   !> Solve A X = B with the factors of band_factorize; B (n × nrhs) is overwritten by X.
   subroutine band_solve(matrix, rhs, error)
      type(band_matrix_t), intent(in) :: matrix
      real(dp), intent(inout) :: rhs(:, :)
      type(error_t), allocatable, intent(out) :: error
      call factored_solve(matrix, 'N', rhs, error)
   end subroutine band_solve

   !> Solve Aᵀ X = B with the factors of band_factorize; B (n × nrhs) is overwritten by X.
   subroutine band_solve_transpose(matrix, rhs, error)
      type(band_matrix_t), intent(in) :: matrix
      real(dp), intent(inout) :: rhs(:, :)
      type(error_t), allocatable, intent(out) :: error
      call factored_solve(matrix, 'T', rhs, error)
   end subroutine band_solve_transpose

   !> dgbtrs with the factors of band_factorize, for A (trans = 'N') or Aᵀ ('T').
   subroutine factored_solve(matrix, trans, rhs, error)
      type(band_matrix_t), intent(in) :: matrix
      character(len=1), intent(in) :: trans
      real(dp), intent(inout) :: rhs(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer :: info
      if (matrix%n == 0) return
      call dgbtrs(trans, matrix%n, matrix%kl, matrix%ku, size(rhs, 2), matrix%ab, matrix%ldab, &
                  matrix%pivots, rhs, size(rhs, 1), info)
      call lapack_check('dgbtrs', info, error)
   end subroutine factored_solve

   !> The inertia count of band_inertia read from the LU factors of band_factorize when they were
   !> obtained without a row interchange: the elimination was then the one band_inertia performs, and
   !> U's diagonal holds its pivots (round-off apart), so the second elimination is saved. `found` is
   !> false when an interchange happened (then call band_inertia on the unfactorised matrix).
   !> `original` is the unfactorised matrix: a pivot is zero when it is round-off of its own row.
   !> status (optional): the stat= of its row scales (nonzero: refused by the system, nothing counted
   !> and `found` false); without it a refusal stops the program.
   pure subroutine band_inertia_from_factors(factors, original, negative_pivots, singular, found, status)
      type(band_matrix_t), intent(in) :: factors, original
      integer, intent(out) :: negative_pivots
      logical, intent(out) :: singular, found
      integer, intent(out), optional :: status
      real(dp), allocatable :: row_scale(:)
      real(dp) :: pivot
      integer :: k
      negative_pivots = 0
      singular = .false.
      if (present(status)) status = 0
      found = factors%factorized
      if (.not. found) return
      do k = 1, factors%n
         if (factors%pivots(k) /= k) then
            found = .false.
            return
         end if
      end do
      call row_maxima(original, row_scale, status)
      if (.not. allocated(row_scale)) then
         found = .false.
         return
      end if
      do k = 1, factors%n
         pivot = factors%ab(factors%kl + factors%ku + 1, k)
         if (abs(pivot) <= epsilon(1.0_dp)*merge(row_scale(k), 1.0_dp, row_scale(k) > 0.0_dp)) then
            singular = .true.
            negative_pivots = negative_pivots + 1
         else if (pivot < 0.0_dp) then
            negative_pivots = negative_pivots + 1
         end if
      end do
   end subroutine band_inertia_from_factors

   !> The copy of a band's storage that band_inertia and band_weakest_pivot eliminate in. With `status`
   !> present it is allocated with stat= (nonzero: the system refused it, `work` unallocated); without
   !> it a refusal stops the program.
   pure subroutine elimination_copy(matrix, work, status)
      type(band_matrix_t), intent(in) :: matrix
      real(dp), allocatable, intent(out) :: work(:, :)
      integer, intent(out), optional :: status
      if (present(status)) then
         allocate (work, source=matrix%ab, stat=status)
      else
         allocate (work, source=matrix%ab)
      end if
   end subroutine elimination_copy

   !> Number of negative pivots of Gaussian elimination WITHOUT interchanges of an unfactorised matrix.
   !>
   !> For a symmetric matrix this is LDLᵀ, and by Sylvester's law of inertia the count equals the number
   !> of negative eigenvalues: 0 on stable equilibrium, +1 past each limit or bifurcation point. The
   !> row-pivoted LU of band_factorize gives only the sign of det A, not this count, hence the separate
   !> elimination (on a copy of the band, O(n·b²), done once per converged step). A pivot that vanishes
   !> and is coupled to the next row is eliminated with it as a 2×2 block (its inertia from the block's
   !> determinant and trace); one that vanishes otherwise is counted as negative (the matrix is singular
   !> there) and `singular` is set.
   !> status: that of the allocation of the copy (nonzero: the system refused it, nothing counted);
   !> without it a refusal stops the program.
   pure subroutine band_inertia(matrix, negative_pivots, singular, status)
      type(band_matrix_t), intent(in) :: matrix
      integer, intent(out) :: negative_pivots
      logical, intent(out) :: singular
      integer, intent(out), optional :: status
      real(dp), allocatable :: work(:, :), row_scale(:)
      real(dp) :: pivot, factor, scale, block(2, 2), det, inverse(2, 2), left(2)
      integer :: k, i, j, offset, last_row, last_col
      negative_pivots = 0
      singular = .false.
      if (present(status)) status = 0
      if (matrix%n == 0) return
      offset = matrix%kl + matrix%ku + 1
      call elimination_copy(matrix, work, status)
      if (.not. allocated(work)) return
      ! A pivot is zero when it is round-off of its own row: rows differ by many orders of magnitude
      ! (a contact row of a very soft spring has −1/k on its diagonal), so one scale for all rows would
      ! call the pivots of the structure zero beside it.
      call row_maxima(matrix, row_scale, status)
      if (.not. allocated(row_scale)) return
      k = 1
      do while (k <= matrix%n)
         pivot = work(offset, k)
         scale = row_scale(k)
         if (scale <= 0.0_dp) scale = 1.0_dp
         if (abs(pivot) <= epsilon(1.0_dp)*scale) then
            ! A zero pivot coupled to the next row (a rigid contact's reaction whose node is held,
            ! followed by the Pasternak bed's deflection under it, docs/theory.md §3.10): a 2×2 pivot
            ! block [0 b; b q] (Bunch & Kaufman 1977, Math. Comp. 31, 163–179), of inertia (1, 1)
            ! when b ≠ 0, eliminated as a block. Skipping the column instead would leave the next
            ! row free of the constraint the zero row states, and count the rest's inertia wrong.
            if (k < matrix%n .and. matrix%ku >= 1 .and. matrix%kl >= 1) then
               block = reshape([work(offset, k), work(offset + 1, k), work(offset - 1, k + 1), &
                                work(offset, k + 1)], [2, 2])
               det = block(1, 1)*block(2, 2) - block(1, 2)*block(2, 1)
               if (abs(block(1, 2)) > epsilon(1.0_dp)*scale .and. det /= 0.0_dp) then
                  if (det < 0.0_dp) then
                     negative_pivots = negative_pivots + 1
                  else if (block(1, 1) + block(2, 2) < 0.0_dp) then
                     negative_pivots = negative_pivots + 2
                  end if
                  ! A(i, j) −= [A(i, k) A(i, k+1)] block⁻¹ [A(k, j); A(k+1, j)] for i, j > k + 1 in the
                  ! band (block⁻¹ by its adjugate)
                  inverse = reshape([block(2, 2), -block(2, 1), -block(1, 2), block(1, 1)], [2, 2])/det
                  do i = k + 2, min(matrix%n, k + 1 + matrix%kl)
                     left = matmul([entry(i, k), entry(i, k + 1)], inverse)
                     do j = k + 2, min(matrix%n, k + 1 + matrix%ku)
                        work(offset + i - j, j) = work(offset + i - j, j) - left(1)*entry(k, j) - &
                                                  left(2)*entry(k + 1, j)
                     end do
                  end do
                  k = k + 2
                  cycle
               end if
            end if
            singular = .true.
            negative_pivots = negative_pivots + 1
            k = k + 1
            cycle
         end if
         if (pivot < 0.0_dp) negative_pivots = negative_pivots + 1
         last_row = min(matrix%n, k + matrix%kl)
         last_col = min(matrix%n, k + matrix%ku)
         do i = k + 1, last_row
            factor = work(offset + i - k, k)/pivot
            do j = k + 1, last_col
               work(offset + i - j, j) = work(offset + i - j, j) - factor*work(offset + k - j, j)
            end do
         end do
         k = k + 1
      end do

   contains

      !> A(i, j) of the working copy, 0 outside the band.
      pure real(dp) function entry(i, j)
         integer, intent(in) :: i, j
         entry = 0.0_dp
         if (i - j <= matrix%kl .and. j - i <= matrix%ku) entry = work(offset + i - j, j)
      end function entry

   end subroutine band_inertia

   !> The relative pivot test for a singular or near-singular matrix (a mechanism): Gaussian
   !> elimination without interchanges of an unfactorised matrix (on a copy, O(n·b²)), each pivot
   !> measured against the diagonal entry of its own row before elimination, |p_k| / |A_kk|. That
   !> ratio is the fraction of the row's own stiffness left once the rows before it are eliminated:
   !> about 1 where a DOF is held, round-off (1e-16·growth) where a DOF can move without
   !> deforming anything — unlike |p_k| / max|p|, which is tiny on any large, well-held model whose
   !> rows differ in stiffness. Rows with a zero diagonal (the contact rows of a rigid contact in
   !> an augmented saddle-point system) are measured against their largest entry instead, and the
   !> elimination skips a column whose pivot is exactly zero (as band_inertia does).
   !> `weakest`: the row with the smallest ratio (0 if n = 0); `ratio`: that ratio (huge if n = 0);
   !> `below`: the number of rows whose ratio is at most `tolerance`.
   !> Source: Golub & Van Loan (2013), Matrix Computations, §3.4 (LU pivots) and §4.2 (LDLᵀ of a
   !> semidefinite matrix: a zero pivot and the null vector).
   !> status: that of the allocation of the copy (nonzero: the system refused it, weakest 0);
   !> without it a refusal stops the program.
   pure subroutine band_weakest_pivot(matrix, tolerance, weakest, ratio, below, status)
      type(band_matrix_t), intent(in) :: matrix
      real(dp), intent(in) :: tolerance
      integer, intent(out) :: weakest, below
      real(dp), intent(out) :: ratio
      integer, intent(out), optional :: status
      real(dp), allocatable :: work(:, :), row_scale(:)
      real(dp) :: pivot, factor, scale, r
      integer :: k, i, j, offset, last_row, last_col
      weakest = 0
      below = 0
      ratio = huge(1.0_dp)
      if (present(status)) status = 0
      if (matrix%n == 0) return
      offset = matrix%kl + matrix%ku + 1
      call elimination_copy(matrix, work, status)
      if (.not. allocated(work)) return
      call row_maxima(matrix, row_scale, status)
      if (.not. allocated(row_scale)) return
      do k = 1, matrix%n
         scale = abs(matrix%ab(offset, k))
         if (scale <= 0.0_dp) scale = row_scale(k)
         pivot = work(offset, k)
         r = 0.0_dp
         if (scale > 0.0_dp) r = abs(pivot)/scale
         if (r < ratio) then
            ratio = r
            weakest = k
         end if
         if (r <= tolerance) below = below + 1
         if (pivot == 0.0_dp) cycle
         last_row = min(matrix%n, k + matrix%kl)
         last_col = min(matrix%n, k + matrix%ku)
         do i = k + 1, last_row
            factor = work(offset + i - k, k)/pivot
            do j = k + 1, last_col
               work(offset + i - j, j) = work(offset + i - j, j) - factor*work(offset + k - j, j)
            end do
         end do
      end do
   end subroutine band_weakest_pivot

   !> A x and the size of its terms, row by row, for an unfactorised matrix: product(i) = Σ_j A_ij x_j
   !> and magnitude(i) = Σ_j |A_ij x_j| (n each). Their ratio is the cancellation in row i: about ε
   !> where (A x)_i = 0 holds in exact arithmetic, as for a rigid-body motion of an unsupported
   !> structure (Higham 2002, Accuracy and Stability of Numerical Algorithms, §3.1: the error of a
   !> computed sum is at most about n ε Σ|terms|).
   pure subroutine band_row_terms(matrix, x, product, magnitude)
      type(band_matrix_t), intent(in) :: matrix
      real(dp), intent(in) :: x(:)
      real(dp), intent(out) :: product(:), magnitude(:)
      integer :: i, j, offset
      offset = matrix%kl + matrix%ku + 1
      product = 0.0_dp
      magnitude = 0.0_dp
      do j = 1, matrix%n
         do i = max(1, j - matrix%ku), min(matrix%n, j + matrix%kl)
            product(i) = product(i) + matrix%ab(offset + i - j, j)*x(j)
            magnitude(i) = magnitude(i) + abs(matrix%ab(offset + i - j, j)*x(j))
         end do
      end do
   end subroutine band_row_terms

   !> Largest |A(i, j)| of each row i of an unfactorised matrix (n), into `row_scale` (allocated here,
   !> not a function result: with `status` present with stat=, nonzero: refused by the system and
   !> `row_scale` unallocated; without it a refusal stops the program).
   pure subroutine row_maxima(matrix, row_scale, status)
      type(band_matrix_t), intent(in) :: matrix
      real(dp), allocatable, intent(out) :: row_scale(:)
      integer, intent(out), optional :: status
      integer :: i, j, offset
      if (present(status)) then
         allocate (row_scale(matrix%n), stat=status)
         if (status /= 0) return
      else
         allocate (row_scale(matrix%n))
      end if
      offset = matrix%kl + matrix%ku + 1
      row_scale = 0.0_dp
      do j = 1, matrix%n
         do i = max(1, j - matrix%ku), min(matrix%n, j + matrix%kl)
            row_scale(i) = max(row_scale(i), abs(matrix%ab(offset + i - j, j)))
         end do
      end do
   end subroutine row_maxima

end module uniarc_band
