!> Benchmark of uniarc_lemke (issue 3): pivots and wall time of lemke_solve on random SPD
!> problems, n = 50 ... 1600, and the cost per pivot against n^2. Not a test: it prints, it does
!> not assert. Run the Release build:  build/bench_lemke [largest n, default 1600]
program bench_lemke
   use, intrinsic :: iso_fortran_env, only: output_unit
   use uniarc_kinds, only: dp, i8
   use uniarc_error, only: error_t
   use uniarc_lemke, only: lemke_options_t, lemke_report_t, lemke_solve, lemke_status_name
   implicit none

   integer, parameter :: sizes(6) = [50, 100, 200, 400, 800, 1600]
   real(dp), allocatable :: matrix(:, :), q(:), r(:), w(:)
   type(lemke_report_t) :: report
   type(error_t), allocatable :: error
   integer(i8) :: seed, start, finish, rate
   integer :: k, n, largest, status
   real(dp) :: seconds
   character(len=32) :: argument

   largest = sizes(size(sizes))
   if (command_argument_count() >= 1) then
      call get_command_argument(1, argument)
      read (argument, *, iostat=status) largest
      if (status /= 0) largest = sizes(size(sizes))
   end if

   write (output_unit, '(a)') '# Lemke on random SPD M = B B^T/n + 0.05 I, q uniform in (-1, 1)'
   write (output_unit, '(a)') '#     n  pivots  active     seconds  s/pivot/n^2   residual  status'
   seed = 271828_i8
   do k = 1, size(sizes)
      n = sizes(k)
      if (n > largest) exit
      allocate (matrix(n, n), q(n), r(n), w(n))
      call random_spd(seed, matrix)
      call random_uniform(seed, q)
      q = 2.0_dp*q - 1.0_dp
      call system_clock(start, rate)
      call lemke_solve(matrix, q, r, w, report, error)
      call system_clock(finish)
      if (allocated(error)) then
         write (output_unit, '(a)') 'error: '//error%message
         exit
      end if
      seconds = real(finish - start, dp)/real(rate, dp)
      write (output_unit, '(i7,2i8,f12.4,es13.3,es11.2,2x,a)') n, report%pivots, report%active, &
         seconds, seconds/max(report%pivots, 1)/real(n, dp)**2, report%residual, &
         lemke_status_name(report%status)
      deallocate (matrix, q, r, w)
   end do

contains

   !> Park-Miller minimal standard generator (CACM 31, 1988), uniform in (0, 1): reproducible
   !> and independent of the compiler's RNG.
   subroutine random_uniform(seed, values)
      integer(i8), intent(inout) :: seed
      real(dp), intent(out) :: values(:)
      integer(i8), parameter :: multiplier = 16807_i8, modulus = 2147483647_i8
      integer :: i
      do i = 1, size(values)
         seed = mod(multiplier*seed, modulus)
         values(i) = real(seed, dp)/real(modulus, dp)
      end do
   end subroutine random_uniform

   !> Random SPD matrix B B^T / n + 0.05 I with B uniform in (-1, 1).
   subroutine random_spd(seed, matrix)
      integer(i8), intent(inout) :: seed
      real(dp), intent(out) :: matrix(:, :)
      real(dp), allocatable :: b(:, :)
      integer :: j, n
      n = size(matrix, 1)
      allocate (b(n, n))
      do j = 1, n
         call random_uniform(seed, b(:, j))
      end do
      b = 2.0_dp*b - 1.0_dp
      matrix = matmul(b, transpose(b))/real(n, dp)
      do j = 1, n
         matrix(j, j) = matrix(j, j) + 0.05_dp
      end do
   end subroutine random_spd

end program bench_lemke
