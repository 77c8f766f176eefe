!> Stability of a converged state of the path from its factorised tangent: the inertia (Sylvester's
!> law: negative pivots are negative eigenvalues) and the eigenvalue of least magnitude by inverse
!> iteration, which the critical-point detector (uniarc_critical_points) interpolates between steps.
module uniarc_path_stability
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t
   use uniarc_band, only: band_matrix_t, band_solve, band_inertia, band_inertia_from_factors
   implicit none
   private
   public :: structural_inertia, least_eigenvalue

contains

   !> Negative eigenvalues of the structure at a state whose augmented tangent is `assembled`
   !> (unfactorised) with band LU `factors`, and `n_active` the contact rows of the working set among
   !> them (active(c) and candidate_equation(c) > 0, per candidate). The inertia comes from the LU
   !> factors when they needed no row interchange, else by elimination without interchanges.
   subroutine structural_inertia(factors, assembled, active, candidate_equation, negative, n_active)
      type(band_matrix_t), intent(in) :: factors, assembled
      logical, intent(in) :: active(:)
      integer, intent(in) :: candidate_equation(:)
      integer, intent(out) :: negative, n_active
      logical :: singular, found
      call band_inertia_from_factors(factors, assembled, negative, singular, found)
      if (.not. found) call band_inertia(assembled, negative, singular)
      ! Each contact row of the working set adds one negative pivot to the saddle-point system
      ! (Haynsworth inertia additivity): what remains counts the unstable modes of the structure.
      n_active = count(active .and. candidate_equation > 0)
      negative = max(0, negative - n_active)
   end subroutine structural_inertia

   !> Eigenvalue of least magnitude of a factorised matrix by inverse iteration (Rayleigh quotient of
   !> K⁻¹); used only to place bifurcation points between steps, so a few digits suffice.
   !> `mode` (n) is the start vector and returns the last iterate: started from the mode of the last
   !> converged step, which changes little from step to step, the iteration settles in a few solves.
   !> Returns 0 for an empty matrix, a failed solve or an infinite quotient.
   function least_eigenvalue(matrix, mode) result(mu)
      type(band_matrix_t), intent(in) :: matrix
      real(dp), allocatable, intent(inout) :: mode(:)
      real(dp) :: mu
      real(dp), allocatable :: x(:, :), y(:)
      real(dp) :: nu, previous
      type(error_t), allocatable :: error
      integer :: k, i, first_check
      mu = 0.0_dp
      if (matrix%n == 0) return
      allocate (x(matrix%n, 1))
      ! No usable last mode (first step, another size, or a zero vector): a fixed generic start.
      if (allocated(mode)) then
         if (size(mode) /= matrix%n .or. .not. (norm2(mode) > 0.0_dp)) deallocate (mode)
      end if
      first_check = 1
      if (.not. allocated(mode)) then
         mode = [(1.0_dp + 0.1_dp*sin(real(i, dp)), i=1, matrix%n)]
         first_check = 2
      end if
      x(:, 1) = mode/norm2(mode)
      nu = 0.0_dp
      ! Stop when the Rayleigh quotient has settled to 1e-4 (it only places a bifurcation inside a
      ! step, by linear interpolation whose own error is of the order of the step). Near a critical
      ! point, where it matters, the least eigenvalue is well separated and a few solves do; where the
      ! low spectrum is clustered (a ring of 1e5 elements: ratios of neighbouring eigenvalues near 1)
      ! inverse iteration cannot separate them in any affordable number of solves, and the quotient
      ! after 8 — between the clustered eigenvalues, of their common sign — is what the detector
      ! needs. A warm start from the last mode needs two solves to compare quotients, a cold one three.
      do k = 1, 8
         y = x(:, 1)
         call band_solve(matrix, x, error)
         if (allocated(error)) return
         previous = nu
         nu = dot_product(y, x(:, 1))
         x = x/norm2(x)
         if (k > first_check .and. abs(nu - previous) <= 1.0e-4_dp*abs(nu)) exit
      end do
      if (all(abs(x(:, 1)) <= huge(1.0_dp))) mode = x(:, 1)
      if (abs(nu) > tiny(1.0_dp)) mu = 1.0_dp/nu
   end function least_eigenvalue

end module uniarc_path_stability
