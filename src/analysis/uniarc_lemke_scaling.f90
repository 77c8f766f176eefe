!> Equilibration by powers of two and overflow-safe arithmetic for the dense Lemke solver
!> (`uniarc_lemke`): the scaling makes its tolerances relative to the scale of M and q while staying
!> exact in floating point (a power of two changes no digit, so exact ties stay exact), and the
!> saturating operations bound every intermediate of the ratio test and of the verification.
module uniarc_lemke_scaling
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: equilibrate, scale_down, saturating_product, saturating_sum, safe_divide

   !> Ratios of the ratio test are saturated at this magnitude, so differences and relative ties
   !> of two ratios stay finite.
   real(dp), parameter :: ratio_cap = huge(1.0_dp)/8.0_dp

contains

   !> The exponent k of the power of two nearest to x > 0 in ratio: x / 2^k in [1/sqrt(2), sqrt(2)].
   pure integer function nearest_exponent(x)
      real(dp), intent(in) :: x
      ! x = f 2^e with f in [1/2, 1): x / 2^(e-1) = 2 f in [1, 2).
      nearest_exponent = exponent(x) - 1
      if (2.0_dp*fraction(x) > sqrt(2.0_dp)) nearest_exponent = nearest_exponent + 1
   end function nearest_exponent

   !> Ruiz equilibration (Ruiz 2001, "A scaling algorithm to equilibrate both rows and columns
   !> norms in matrices"): repeatedly divide rows and columns by the square roots of their
   !> max-norms, rounded to powers of two, until all are within a factor 2 of one. On return
   !> matrix <- D^-1 M S with D = diag(2^row_exp), S = diag(2^column_exp). Entries never grow
   !> beyond 2 (|m_ij| <= sqrt(row norm * column norm)), so the scaling cannot overflow.
   pure subroutine equilibrate(matrix, row_exp, column_exp)
      real(dp), intent(inout) :: matrix(:, :)
      integer, intent(out) :: row_exp(:), column_exp(:)
      integer :: sweep, i, j, n
      real(dp) :: row_norm(size(row_exp)), norm
      integer :: row_step(size(row_exp)), column_step(size(column_exp))

      n = size(row_exp)
      row_exp = 0
      column_exp = 0
      do sweep = 1, 20
         row_norm = 0.0_dp
         do j = 1, n
            do i = 1, n
               row_norm(i) = max(row_norm(i), abs(matrix(i, j)))
            end do
         end do
         do i = 1, n
            row_step(i) = half_exponent(row_norm(i))
         end do
         do j = 1, n
            norm = maxval(abs(matrix(:, j)))
            column_step(j) = half_exponent(norm)
         end do
         ! The factors are powers of two, so "within a factor sqrt(2) of one" means "exactly one".
         if (all(row_step == 0) .and. all(column_step == 0)) exit
         do j = 1, n
            do i = 1, n
               matrix(i, j) = scale(matrix(i, j), -row_step(i) - column_step(j))
            end do
         end do
         row_exp = row_exp + row_step
         column_exp = column_exp - column_step
      end do
   contains
      !> Exponent of the power of two nearest to sqrt(norm); 0 for an empty row or column.
      pure integer function half_exponent(norm)
         real(dp), intent(in) :: norm
         if (norm > 0.0_dp) then
            half_exponent = nearest_exponent(sqrt(norm))
         else
            half_exponent = 0
         end if
      end function half_exponent
   end subroutine equilibrate

   !> scaled = D^-1 v / 2^p with D = diag(2^row_exp) and p the exponent of the power of two nearest
   !> to max_i |v_i / D_i|, so |scaled| <= sqrt(2). Computed on exponents (the quotients v_i / D_i
   !> themselves may not be representable); p = 0 for v = 0. Entries far below the largest may
   !> underflow to zero, which is their value at the working precision of the scaled problem.
   pure subroutine scale_down(v, row_exp, scaled, p)
      real(dp), intent(in) :: v(:)
      integer, intent(in) :: row_exp(:)
      real(dp), intent(out) :: scaled(:)
      integer, intent(out) :: p
      integer :: i, top
      logical :: any_nonzero

      any_nonzero = .false.
      top = 0
      do i = 1, size(v)
         if (abs(v(i)) > 0.0_dp) then
            if (any_nonzero) then
               top = max(top, exponent(v(i)) - row_exp(i))
            else
               top = exponent(v(i)) - row_exp(i)
               any_nonzero = .true.
            end if
         end if
      end do
      p = 0
      scaled = 0.0_dp
      if (.not. any_nonzero) return
      ! Every |v_i| / D_i is below 2^top: after scaling by 2^-top all lie in [0, 1), the largest
      ! in [1/2, 1), whose nearest power of two is 2^0 or 2^-1.
      do i = 1, size(v)
         scaled(i) = scale(v(i), -row_exp(i) - top)
      end do
      p = top + nearest_exponent(maxval(abs(scaled)))
      do i = 1, size(v)
         scaled(i) = scale(v(i), -row_exp(i) - p)
      end do
   end subroutine scale_down

   !> x * y for x, y >= 0, saturated at huge(1.0_dp) instead of overflowing.
   pure real(dp) function saturating_product(x, y)
      real(dp), intent(in) :: x, y
      if (x <= 1.0_dp) then
         saturating_product = x*y
      else if (y <= huge(1.0_dp)/x) then
         saturating_product = x*y
      else
         saturating_product = huge(1.0_dp)
      end if
   end function saturating_product

   !> x + y for x, y >= 0, saturated at huge(1.0_dp) instead of overflowing.
   pure real(dp) function saturating_sum(x, y)
      real(dp), intent(in) :: x, y
      if (x <= huge(1.0_dp) - y) then
         saturating_sum = x + y
      else
         saturating_sum = huge(1.0_dp)
      end if
   end function saturating_sum

   !> x / y for finite x and y > 0, saturated at +-ratio_cap instead of overflowing.
   pure real(dp) function safe_divide(x, y)
      real(dp), intent(in) :: x, y
      if (y >= 1.0_dp) then
         safe_divide = sign(min(abs(x)/y, ratio_cap), x)
      else if (abs(x) <= ratio_cap*y) then
         safe_divide = x/y
      else
         safe_divide = sign(ratio_cap, x)
      end if
   end function safe_divide

end module uniarc_lemke_scaling
