!> The floating motions of a structure held only by its contacts, as a subspace (docs/theory.md §2.8):
!> the rigid motions F (n, k ≤ 3) that the supports leave free (uniarc_path_mechanism, floating_motions)
!> and, for a working set S of contacts, the part of their span that no contact of S holds — the null
!> space of B = N_S F, N_S the unit normals of the contacts of S at their nodes. One motion at a time
!> is not enough: with F = {v₁, v₂} a contact may see v₁ and v₂ and still leave v₁ − c v₂ free (a ring
!> in a cavity resting on its invert, x held at its crown: the invert sees the vertical translation and
!> any mixture of it with the rotation about the crown, not that rotation itself).
!>
!> The null space is found by the singular value decomposition of B (one-sided Jacobi, Hestenes 1958;
!> Demmel & Veselić 1992, SIAM J. Matrix Anal. Appl. 13, 1204–1245: it resolves small singular values
!> to high relative accuracy), a rank-revealing test, not a zero pivot.
module uniarc_floating_subspace
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t
   use uniarc_dof_map, only: dof_map_t, candidate_live
   use uniarc_contact_law, only: candidate_gap
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   implicit none
   private
   public :: orthonormal_motions, unheld_motions, spring_equations, remove_unheld

   !> A direction v of the span is held by no contact of the set when the normals' components along it
   !> have a 2-norm (its singular value in B) of at most this fraction of max|v|: for one motion and
   !> one contact this is the path's test (uniarc_path_state, sees_floating: |a_cᵀv| ≤ 1e-6 |a_c|
   !> max|v|). Round-off leaves ~1e-15 of max|v| along an unheld motion; a contact that holds one sees
   !> it at the angle of its normal, 4e-5 rad for the tilted first contact of §2.8, far above.
   real(dp), parameter :: floating_tolerance = 1.0e-6_dp
   !> Jacobi sweeps: k ≤ 3 columns converge quadratically in two or three; the bound is for safety.
   integer, parameter :: max_sweeps = 30

contains

   !> `basis` (n, k): the columns of `motions` (n, k) orthonormal in the displacement metric
   !> (map%metric: reactions weigh nothing), modified Gram–Schmidt. A column dependent on the previous
   !> ones (none is: floating_motions holds each before looking for the next) is left out.
   !> Errors (error_analysis, out of memory): the work copy or `basis` refused by the system.
   subroutine orthonormal_motions(map, motions, basis, error)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: motions(:, :)
      real(dp), allocatable, intent(out) :: basis(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: work(:, :)
      real(dp) :: d
      integer :: k, j, kept, status
      allocate (work(size(motions, 1), size(motions, 2)), stat=status)
      call allocation_failure(status, 'the orthonormal floating motions', 8.0_dp*size(motions), error_analysis, error)
      if (allocated(error)) return
      work(:, :) = motions
      kept = 0
      do k = 1, size(motions, 2)
         do j = 1, kept
            work(:, k) = work(:, k) - sum(map%metric*work(:, j)*work(:, k))*work(:, j)
         end do
         d = sqrt(sum(map%metric*work(:, k)**2))
         if (.not. d > epsilon(1.0_dp)*sqrt(sum(map%metric*motions(:, k)**2))) cycle
         kept = kept + 1
         work(:, kept) = work(:, k)/d
      end do
      allocate (basis(size(motions, 1), kept), stat=status)
      call allocation_failure(status, 'the orthonormal floating motions', 8.0_dp*size(motions, 1)*kept, &
                              error_analysis, error)
      if (allocated(error)) return
      basis(:, :) = work(:, 1:kept)
   end subroutine orthonormal_motions

   !> `unheld` (n, p ≤ k): an orthonormal basis (metric) of the motions of span(`basis`) that no contact
   !> of `set` holds — the right singular vectors of B = N_S F (rows: the unit normals a_c/|a_c| at u = 0
   !> of the set's live, non-tangential candidates applied to each motion's displacement at their node;
   !> columns: `basis`, orthonormal in the metric) whose singular value is at most floating_tolerance of
   !> the motion's largest component. p = 0: the set holds every floating motion.
   !> `tangential` (optional, default false): the set's tangential springs count too, each by its
   !> direction along its node's tangent (the path's tangent holds with them: a ring on a bed with
   !> shear springs has its rotation held by them).
   !> Errors (error_analysis, out of memory): B, its rotations, the motions or `unheld` refused by the
   !> system (each allocated with stat=, no array constructor of the set's length).
   subroutine unheld_motions(model, map, set, basis, unheld, error, tangential)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      logical, intent(in) :: set(:)
      real(dp), intent(in) :: basis(:, :)
      real(dp), allocatable, intent(out) :: unheld(:, :)
      type(error_t), allocatable, intent(out) :: error
      logical, intent(in), optional :: tangential
      real(dp), allocatable :: b(:, :), z(:, :), v(:, :)
      real(dp) :: gap, gradient(2), hessian(2, 2), sigma
      logical, allocatable :: free(:)
      logical :: with_tangential
      integer :: c, node, i, m, k, kept, status
      with_tangential = .false.
      if (present(tangential)) with_tangential = tangential
      k = size(basis, 2)
      m = 0
      do c = 1, size(set)
         if (set(c) .and. candidate_live(map, c) .and. (with_tangential .or. .not. model%contacts(c)%tangential)) &
            m = m + 1
      end do
      allocate (b(m, k), source=0.0_dp, stat=status)
      call allocation_failure(status, 'the contact normals on the floating motions', 8.0_dp*m*k, error_analysis, error)
      if (allocated(error)) return
      m = 0
      do c = 1, size(set)
         if (.not. (set(c) .and. candidate_live(map, c))) cycle
         if (model%contacts(c)%tangential .and. .not. with_tangential) cycle
         m = m + 1
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), [0.0_dp, 0.0_dp], gap, gradient, hessian)
         if (.not. norm2(gradient) > 0.0_dp) cycle
         gradient = gradient/norm2(gradient)
         do i = 1, 2
            if (map%equation(i, node) > 0) b(m, :) = b(m, :) + gradient(i)*basis(map%equation(i, node), :)
         end do
      end do
      call jacobi_svd(b, z, status)
      call allocation_failure(status, 'the rotations of the floating motions'' singular value decomposition', &
                              8.0_dp*(m + 2*k + k*k), error_analysis, error)
      if (allocated(error)) return
      allocate (v(size(basis, 1), k), free(k), stat=status)
      call allocation_failure(status, 'the rotated floating motions', 8.0_dp*size(basis, 1)*k + 4.0_dp*k, &
                              error_analysis, error)
      if (allocated(error)) return
      v(:, :) = matmul(basis, z)
      do i = 1, k
         sigma = norm2(b(:, i))
         free(i) = sigma <= floating_tolerance*maxval(abs(v(:, i)))
      end do
      allocate (unheld(size(basis, 1), count(free)), stat=status)
      call allocation_failure(status, 'the floating motions no contact holds', 8.0_dp*size(basis, 1)*count(free), &
                              error_analysis, error)
      if (allocated(error)) return
      kept = 0
      do i = 1, k
         if (.not. free(i)) cycle
         kept = kept + 1
         unheld(:, kept) = v(:, i)
      end do
   end subroutine unheld_motions

   !> One-sided Jacobi SVD of b (m, k): on return the columns of b are mutually orthogonal (b·z of the
   !> input, their norms the singular values) and z (k, k) is the orthogonal matrix of the rotations
   !> (its columns the right singular vectors). Hestenes 1958; Demmel & Veselić 1992, Algorithm 4.1.
   !> `status`: the stat= of z and of the column work vectors (nonzero: refused, b untouched).
   pure subroutine jacobi_svd(b, z, status)
      real(dp), intent(inout) :: b(:, :)
      real(dp), allocatable, intent(out) :: z(:, :)
      integer, intent(out) :: status
      real(dp) :: alpha, beta, gamma, zeta, t, cs, sn
      real(dp), allocatable :: column(:), zcolumn(:)
      integer :: k, p, q, sweep, i
      logical :: rotated
      k = size(b, 2)
      allocate (z(k, k), source=0.0_dp, stat=status)
      if (status /= 0) return
      allocate (column(size(b, 1)), zcolumn(k), stat=status)
      if (status /= 0) return
      do i = 1, k
         z(i, i) = 1.0_dp
      end do
      do sweep = 1, max_sweeps
         rotated = .false.
         do p = 1, k - 1
            do q = p + 1, k
               alpha = sum(b(:, p)**2)
               beta = sum(b(:, q)**2)
               gamma = sum(b(:, p)*b(:, q))
               ! (a column of zero length — its squares underflow to 0 while its products with
               ! another are subnormal round-off — needs no rotation: ζ would overflow)
               if (.not. abs(gamma) > epsilon(1.0_dp)*sqrt(alpha)*sqrt(beta)) cycle
               if (.not. min(alpha, beta) > tiny(1.0_dp)) cycle
               rotated = .true.
               zeta = (beta - alpha)/(2.0_dp*gamma)
               ! t = 1/(2ζ) where ζ² would overflow or 1 + ζ² rounds to ζ² (|ζ| > 1/√ε): the same t to
               ! a relative O(1/ζ²) below ε (Golub & Van Loan 2013, §8.5.2, the symmetric Schur rotation)
               if (abs(zeta) > 1.0_dp/sqrt(epsilon(1.0_dp))) then
                  t = 0.5_dp/zeta
               else
                  t = sign(1.0_dp, zeta)/(abs(zeta) + sqrt(1.0_dp + zeta**2))
               end if
               cs = 1.0_dp/sqrt(1.0_dp + t**2)
               sn = cs*t
               column(:) = b(:, p)
               b(:, p) = cs*column - sn*b(:, q)
               b(:, q) = sn*column + cs*b(:, q)
               zcolumn(:) = z(:, p)
               z(:, p) = cs*zcolumn - sn*z(:, q)
               z(:, q) = sn*zcolumn + cs*z(:, q)
            end do
         end do
         if (.not. rotated) exit
      end do
   end subroutine jacobi_svd

   !> The equations (p) at which springs hold the motions `unheld` (n, p): Gaussian elimination with
   !> complete pivoting on their displacements (metric), so that the p × p matrix of the motions at
   !> those equations is regular and the springs leave no combination of them free.
   !> Errors (error_analysis, out of memory): the work copy of the motions or `equations` refused.
   subroutine spring_equations(map, unheld, equations, error)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: unheld(:, :)
      integer, allocatable, intent(out) :: equations(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: w(:, :)
      logical, allocatable :: done(:)
      real(dp) :: best
      integer :: p, i, l, j, column, row, status
      p = size(unheld, 2)
      allocate (equations(p), source=0, stat=status)
      if (status == 0) allocate (done(p), source=.false., stat=status)
      if (status == 0) allocate (w(size(unheld, 1), p), stat=status)
      call allocation_failure(status, 'the spring equations of the floating motions', 8.0_dp*size(unheld) + 8.0_dp*p, &
                              error_analysis, error)
      if (allocated(error)) return
      w(:, :) = unheld
      do i = 1, p
         w(:, i) = map%metric*w(:, i)
      end do
      do i = 1, p
         best = -1.0_dp
         column = 0
         row = 0
         do l = 1, p
            if (done(l)) cycle
            j = maxloc(abs(w(:, l)), 1)
            if (abs(w(j, l)) > best) then
               best = abs(w(j, l))
               column = l
               row = j
            end if
         end do
         equations(i) = row
         done(column) = .true.
         if (.not. best > 0.0_dp) cycle
         do l = 1, p
            if (done(l)) cycle
            w(:, l) = w(:, l) - (w(row, l)/w(row, column))*w(:, column)
         end do
      end do
   end subroutine spring_equations

   !> x (n) less its components along `unheld` (n, p, orthonormal in the metric): the solution of a
   !> set that leaves those motions free is defined up to them (they deform nothing and no contact of
   !> the set sees them), and the one with none of them, x ⟂ unheld in the metric, is the minimum-norm
   !> one: the same whatever equations the springs held and whatever round-off the solve left along
   !> them (a symmetric structure under a symmetric load keeps its symmetric solution).
   pure subroutine remove_unheld(map, unheld, x)
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: unheld(:, :)
      real(dp), intent(inout) :: x(:)
      integer :: i
      do i = 1, size(unheld, 2)
         x = x - sum(map%metric*unheld(:, i)*x)*unheld(:, i)
      end do
   end subroutine remove_unheld

end module uniarc_floating_subspace
