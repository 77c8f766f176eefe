!> A linear complementarity problem given by what can be done with its matrix, not by the matrix.
!>
!>     find z, w:  w = q + M z,  w ≥ 0,  z ≥ 0,  wᵀz = 0        (M: m × m, never formed)
!>
!> The LCP is seen in a *frame*: a set F of indices whose input and output have been exchanged by a
!> principal pivot transform (PPT; Cottle, Pang & Stone 1992, §2.3; Tucker 1960). In the frame F the
!> LCP is (q_F, M_F) with, for the partition (F, N) of the indices,
!>
!>     M_F = [  M_FF⁻¹           −M_FF⁻¹ M_FN        ]     q_F = [ −M_FF⁻¹ q_F         ]
!>           [  M_NF M_FF⁻¹       M_NN − M_NF M_FF⁻¹ M_FN ]           [ q_N − M_NF M_FF⁻¹ q_F ]
!>
!> A PPT has the same solutions as the original (w_F and z_F trade places) and keeps P-matrix
!> properties. A solution of the LCP *is* a frame F with q_F ≥ 0: there z = 0 and w = q_F. This is what
!> the solvers of `uniarc_lcp_implicit` look for, and why an operator needs only:
!>
!> - `order`: m;
!> - `frame_q`: q_F of the current frame, computed afresh (for the contact LCP: from the residual of
!>   the nonlinear state, one banded solve — so every new frame is an iterative refinement);
!> - `scales`: for each output of the current frame, the size below which it is round-off (its unit);
!> - `apply`, `apply_transpose`: v = M_F y and v = M_Fᵀ y (for the contact LCP one banded solve each);
!> - `exchange`: F ← F Δ E for a set E (for the contact LCP: the rows of E change from "reaction
!>   free" to "gap closed" or back, and the banded tangent is refactorised). On failure (M_EE
!>   singular) the operator is left in the frame it had, and an error is returned.
!>
!> `dense_lcp_operator_t` is the operator of an explicit matrix (the PPT done on dense storage): the
!> reference in the unit tests and the way to run the implicit solvers on a small explicit LCP.
module uniarc_lcp_operator
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis, error_input
   use uniarc_foreign, only: dgetrf, dgetrs
   use uniarc_memory, only: allocation_failure
   implicit none
   private
   public :: lcp_operator_t, dense_lcp_operator_t, dense_operator

   !> The operations of an LCP in its current frame (see the module header).
   type, abstract :: lcp_operator_t
   contains
      procedure(order_interface), deferred :: order
      procedure(frame_q_interface), deferred :: frame_q
      procedure(scales_interface), deferred :: scales
      procedure(apply_interface), deferred :: apply
      procedure(apply_interface), deferred :: apply_transpose
      procedure(exchange_interface), deferred :: exchange
   end type lcp_operator_t

   abstract interface
      !> m, the number of complementary pairs.
      pure integer function order_interface(self)
         import :: lcp_operator_t
         class(lcp_operator_t), intent(in) :: self
      end function order_interface

      !> q_F (m) of the current frame.
      subroutine frame_q_interface(self, q, error)
         import :: lcp_operator_t, dp, error_t
         class(lcp_operator_t), intent(inout) :: self
         real(dp), intent(out) :: q(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine frame_q_interface

      !> Unit of each output w_i of the current frame (m, > 0): the acceptance test is relative to it.
      subroutine scales_interface(self, scale)
         import :: lcp_operator_t, dp
         class(lcp_operator_t), intent(in) :: self
         real(dp), intent(out) :: scale(:)
      end subroutine scales_interface

      !> v = M_F y (or M_Fᵀ y), y and v of size m.
      subroutine apply_interface(self, y, v, error)
         import :: lcp_operator_t, dp, error_t
         class(lcp_operator_t), intent(inout) :: self
         real(dp), intent(in) :: y(:)
         real(dp), intent(out) :: v(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine apply_interface

      !> F ← F Δ {i : flip(i)}; on error the frame is unchanged.
      subroutine exchange_interface(self, flip, error)
         import :: lcp_operator_t, error_t
         class(lcp_operator_t), intent(inout) :: self
         logical, intent(in) :: flip(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine exchange_interface
   end interface

   !> An explicit LCP (M, q) seen in a frame: the frame's matrix and vector are kept as dense arrays
   !> and recomputed by a PPT of the original at every exchange (O(m³); for tests and small LCPs).
   type, extends(lcp_operator_t) :: dense_lcp_operator_t
      real(dp), allocatable :: original_matrix(:, :)   !< M (m × m)
      real(dp), allocatable :: original_q(:)           !< q (m)
      logical, allocatable :: in_frame(:)              !< F: indices exchanged with respect to (M, q)
      real(dp), allocatable :: matrix(:, :)            !< M_F
      real(dp), allocatable :: q(:)                    !< q_F
      real(dp) :: unit = 1.0_dp                        !< output scale: ‖q‖∞ of the original
   contains
      procedure :: order => dense_order
      procedure :: frame_q => dense_frame_q
      procedure :: scales => dense_scales
      procedure :: apply => dense_apply
      procedure :: apply_transpose => dense_apply_transpose
      procedure :: exchange => dense_exchange
   end type dense_lcp_operator_t

contains

   !> The operator of the explicit LCP (M, q) in the frame F = ∅.
   !> Errors (category input): M not square or not matching q, non-finite data. Its copies refused by
   !> the system: out of memory (error_analysis, uniarc_memory).
   subroutine dense_operator(matrix, q, operator, error)
      real(dp), intent(in) :: matrix(:, :), q(:)
      type(dense_lcp_operator_t), intent(out) :: operator
      type(error_t), allocatable, intent(out) :: error
      integer :: m, status
      if (size(matrix, 1) /= size(q) .or. size(matrix, 2) /= size(q)) then
         call make_error(error, 'dense LCP operator: M must be m x m for q of size m', error_input)
         return
      end if
      if (.not. (all(abs(matrix) <= huge(1.0_dp)) .and. all(abs(q) <= huge(1.0_dp)))) then
         call make_error(error, 'dense LCP operator: M and q must be finite', error_input)
         return
      end if
      m = size(q)
      allocate (operator%original_matrix(m, m), operator%original_q(m), operator%matrix(m, m), operator%q(m), &
                operator%in_frame(m), stat=status)
      call allocation_failure(status, 'the dense LCP operator', 16.0_dp*m*m + 20.0_dp*m, error_analysis, error)
      if (allocated(error)) return
      operator%original_matrix(:, :) = matrix
      operator%original_q(:) = q
      operator%matrix(:, :) = matrix
      operator%q(:) = q
      operator%in_frame(:) = .false.
      operator%unit = 1.0_dp
      if (size(q) > 0) operator%unit = max(maxval(abs(q)), tiny(1.0_dp))
   end subroutine dense_operator

   pure integer function dense_order(self)
      class(dense_lcp_operator_t), intent(in) :: self
      dense_order = size(self%original_q)
   end function dense_order

   subroutine dense_frame_q(self, q, error)
      class(dense_lcp_operator_t), intent(inout) :: self
      real(dp), intent(out) :: q(:)
      type(error_t), allocatable, intent(out) :: error
      q = self%q
   end subroutine dense_frame_q

   !> One unit for every output: ‖q‖∞ of the original LCP (a PPT mixes the rows, so no finer unit is
   !> known for an explicit matrix).
   subroutine dense_scales(self, scale)
      class(dense_lcp_operator_t), intent(in) :: self
      real(dp), intent(out) :: scale(:)
      scale = self%unit
   end subroutine dense_scales

   subroutine dense_apply(self, y, v, error)
      class(dense_lcp_operator_t), intent(inout) :: self
      real(dp), intent(in) :: y(:)
      real(dp), intent(out) :: v(:)
      type(error_t), allocatable, intent(out) :: error
      v = matmul(self%matrix, y)
   end subroutine dense_apply

   subroutine dense_apply_transpose(self, y, v, error)
      class(dense_lcp_operator_t), intent(inout) :: self
      real(dp), intent(in) :: y(:)
      real(dp), intent(out) :: v(:)
      type(error_t), allocatable, intent(out) :: error
      v = matmul(y, self%matrix)
   end subroutine dense_apply_transpose

   !> F ← F Δ flip, and (M_F, q_F) recomputed from the original by the PPT formula of the module
   !> header. Error (category analysis) if M_FF is singular to working precision (LU pivot below
   !> m ε ‖M_FF‖); the frame is then unchanged. Its frame flags, index lists and factors refused by
   !> the system: out of memory (error_analysis), the frame unchanged.
   subroutine dense_exchange(self, flip, error)
      class(dense_lcp_operator_t), intent(inout) :: self
      logical, intent(in) :: flip(:)
      type(error_t), allocatable, intent(out) :: error
      logical, allocatable :: frame(:)
      integer, allocatable :: f(:), nf(:), pivots(:)
      real(dp), allocatable :: mff(:, :), rhs(:, :)
      integer :: m, p, info, i, status
      m = size(self%original_q)
      allocate (frame(m), stat=status)
      call allocation_failure(status, 'the frame flags of a dense LCP operator', 4.0_dp*m, error_analysis, error)
      if (allocated(error)) return
      frame(:) = self%in_frame .neqv. flip
      p = count(frame)
      allocate (f(p), nf(m - p), pivots(p), mff(p, p), stat=status)
      call allocation_failure(status, 'the principal block of a dense LCP operator', 8.0_dp*(m + p) + 8.0_dp*p*p, &
                              error_analysis, error)
      if (allocated(error)) return
      p = 0
      do i = 1, m
         if (frame(i)) then
            p = p + 1
            f(p) = i
         else
            nf(i - p) = i
         end if
      end do
      if (p == 0) then
         self%matrix = self%original_matrix
         self%q = self%original_q
         self%in_frame = frame
         return
      end if
      mff(:, :) = self%original_matrix(f, f)
      call dgetrf(p, p, mff, p, pivots, info)
      if (info /= 0) then
         call make_error(error, 'dense LCP operator: singular principal block in the exchange', error_analysis)
         return
      end if
      if (minval(abs([(mff(i, i), i=1, p)])) <= real(m, dp)*epsilon(1.0_dp)* &
          max(maxval(abs(self%original_matrix(f, f))), tiny(1.0_dp))) then
         call make_error(error, 'dense LCP operator: singular principal block in the exchange', error_analysis)
         return
      end if
      ! rhs = M_FF⁻¹ [I, M_FN, q_F]
      allocate (rhs(p, p + size(nf) + 1), stat=status)
      call allocation_failure(status, 'the exchange of a dense LCP operator', 8.0_dp*p*(m + 1), error_analysis, error)
      if (allocated(error)) return
      rhs = 0.0_dp
      do i = 1, p
         rhs(i, i) = 1.0_dp
      end do
      rhs(:, p + 1:p + size(nf)) = self%original_matrix(f, nf)
      rhs(:, p + size(nf) + 1) = self%original_q(f)
      call dgetrs('N', p, size(rhs, 2), mff, p, pivots, rhs, p, info)
      associate (inverse => rhs(:, 1:p), coupling => rhs(:, p + 1:p + size(nf)), qf => rhs(:, p + size(nf) + 1))
         self%matrix(f, f) = inverse
         self%matrix(f, nf) = -coupling
         self%matrix(nf, f) = matmul(self%original_matrix(nf, f), inverse)
         self%matrix(nf, nf) = self%original_matrix(nf, nf) - matmul(self%original_matrix(nf, f), coupling)
         self%q(f) = -qf
         self%q(nf) = self%original_q(nf) - matmul(self%original_matrix(nf, f), qf)
      end associate
      self%in_frame = frame
   end subroutine dense_exchange

end module uniarc_lcp_operator
