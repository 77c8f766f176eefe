!> The rigid approach of a structure that floats across an initial gap (docs/theory.md §2.8): a free
!> body under a load whose resultant has a component along a rigid translation its supports leave
!> free is in equilibrium at no λ > 0 until a contact holds it, so the load moves it at λ → 0⁺ until
!> the first contact touches. This module finds that translation: the free translations among the
!> floating motions (uniarc_path_mechanism, floating_motions), the reference load's resultant along
!> them, and the smallest distance s along that direction e at which a unilateral candidate's gap
!> closes. The path (uniarc_path_following) and the linear analysis (uniarc_linear_static) start
!> from the structure translated by s e, whose strains and stresses are those of the unloaded state
!> (a translation deforms nothing), with the touching contacts in the first working set.
!>
!> A rotation alone (a structure pinned at a point, floating about it) is not approached: the
!> structure keeps the behaviour of §2.8.
module uniarc_path_approach
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: real_to_string
   use uniarc_model, only: model_t, gap_fixed_direction
   use uniarc_dof_map, only: dof_map_t, candidate_live
   use uniarc_contact_law, only: candidate_gap
   use uniarc_contact_plastic, only: slip_shift
   implicit none
   private
   public :: rigid_approach

   !> A translation is free when its part outside the floating motions' span is at most this fraction
   !> of it (a free translation is a combination of the motions to round-off, ~1e-15 of it; one that
   !> a support holds differs from every combination by the held nodes' share, ≥ 1/n_nodes).
   real(dp), parameter :: span_tolerance = 1.0e-8_dp
   !> The load pushes along the free translations when its resultant there exceeds this fraction of
   !> the sum of the magnitudes of its nodal forces: a self-equilibrated load (a pressure on a closed
   !> ring, whose nodal forces cancel exactly in exact arithmetic) leaves round-off, ~1e-16 of it.
   real(dp), parameter :: push_tolerance = 1.0e-9_dp
   !> A gap at most this fraction of the model's size is closed (the tolerance of the first working
   !> set, uniarc_path_contact_set touching_candidates).
   real(dp), parameter :: touch_fraction = 1.0e-9_dp
   !> A contact whose gap the translation changes by less than this fraction of the translation
   !> neither holds nor is met by it (the slope of a fixed-direction gap across e, round-off).
   real(dp), parameter :: slope_tolerance = 1.0e-12_dp
   !> Steps of the march along e toward a curved obstacle (sphere tracing: each step is the current
   !> gap, a signed distance, so it cannot pass the surface); a ray that meets nothing in these many
   !> steps, or beyond `reach_factor` model sizes, meets nothing.
   integer, parameter :: max_march = 10000
   real(dp), parameter :: reach_factor = 1.0e6_dp

contains

   !> The rigid translation `shift` (n_equations: s e on the translational equations of every node,
   !> 0 elsewhere) that brings the structure from the displacements `nodal` (dofs_per_node, n_nodes)
   !> to its first contact, or zero when there is none to make: no floating motion, no free
   !> translation, a load with no resultant along the free translations, or a contact that touches
   !> and already holds that translation (bonded ones included).
   !> `motions` (n_equations, k ≤ 3): the floating motions; `reference` (n_equations) the reference
   !> load R; `length_scale` the model's size. `linearised`: the gaps are g + a·u, linearised at
   !> `nodal` (those of the linear analysis) instead of the exact ones (the path's: a translation is
   !> exact in it). `contact` returns the candidate met (0: none). `slip` (optional, one per candidate):
   !> the committed plastic slip, by which a plastic candidate's medium has sunk (its gap is g + s,
   !> uniarc_contact_plastic): a later analysis step of a structure that floats over the hollow its
   !> load left meets the medium where it now is.
   !> Errors (error_input): the load pushes the structure along a free translation on which no contact
   !> is ever met (a mechanism under its loads); (error_analysis, out of memory): the work copies of the
   !> motions' basis and of the uniform translations refused by the system.
   subroutine rigid_approach(model, map, motions, reference, nodal, length_scale, linearised, shift, contact, error, &
                            slip)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: motions(:, :), reference(:), nodal(:, :), length_scale
      logical, intent(in) :: linearised
      real(dp), intent(out) :: shift(:)
      integer, intent(out) :: contact
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(in), optional :: slip(:)
      real(dp) :: free(2, 2), force(2), push(2), e(2), total, s, s_best, gap, gradient(2), hessian(2, 2), slope
      real(dp) :: offset
      character(len=:), allocatable :: deck
      integer :: n_free, c, i, node, status
      real(dp) :: bytes
      shift = 0.0_dp
      contact = 0
      call free_translations(model, map, motions, free, n_free, status, bytes)
      call allocation_failure(status, 'the translations of the rigid approach', bytes, error_analysis, error)
      if (allocated(error)) return
      if (n_free == 0) return
      ! The resultant of R (its translational part: the free DOFs' forces) along the free translations.
      force = 0.0_dp
      total = 0.0_dp
      do node = 1, model%n_nodes
         do i = 1, 2
            if (map%equation(i, node) > 0) then
               force(i) = force(i) + reference(map%equation(i, node))
               total = total + abs(reference(map%equation(i, node)))
            end if
         end do
      end do
      push = 0.0_dp
      do i = 1, n_free
         push = push + dot_product(force, free(:, i))*free(:, i)
      end do
      if (.not. norm2(push) > push_tolerance*total) return
      e = push/norm2(push)
      s_best = huge(1.0_dp)
      do c = 1, size(model%contacts)
         if (.not. candidate_live(map, c) .or. model%contacts(c)%tangential) cycle
         node = model%contacts(c)%node
         call candidate_gap(model%contacts(c), model%coordinates(:, node), nodal(1:2, node), gap, gradient, hessian)
         offset = 0.0_dp
         if (model%contacts(c)%plastic) offset = slip_shift(model, c, slip)
         gap = gap + offset
         slope = dot_product(gradient, e)
         if (model%contacts(c)%bilateral) then
            ! a bonded candidate (a spring with an uplift limit too) holds the translation it sees
            if (abs(slope) > slope_tolerance) return
            cycle
         end if
         if (gap <= touch_fraction*length_scale) then
            if (slope < -slope_tolerance) return   ! touching and closing: held at the start
            cycle
         end if
         if (linearised .or. model%contacts(c)%gap_kind == gap_fixed_direction) then
            if (slope < -slope_tolerance) then
               s = gap/(-slope)
            else
               cycle
            end if
         else
            call march(model, c, nodal(1:2, node), e, gap, min(s_best, reach_factor*length_scale), &
                       touch_fraction*length_scale, offset, s)
         end if
         if (s < s_best) then
            s_best = s
            contact = c
         end if
      end do
      if (contact == 0) then
         deck = 'the model'
         if (allocated(model%deck_path)) deck = model%deck_path//': the model'
         call make_error(error, deck//' is a mechanism under its loads: held only by its contacts, it is '// &
                         'pushed by the reference load along the rigid translation ('// &
                         trim(real_to_string(e(1), '(f8.5)'))//', '//trim(real_to_string(e(2), '(f8.5)'))// &
                         '), which its supports leave free, and no contact is ever met that way (docs/theory.md '// &
                         '§2.8); check the direction of the loads and the gaps', error_input)
         return
      end if
      do node = 1, model%n_nodes
         do i = 1, 2
            if (map%equation(i, node) > 0) shift(map%equation(i, node)) = s_best*e(i)
         end do
      end do
   end subroutine rigid_approach

   !> The plane translations (unit columns of `free`, n_free of them) that lie in the span of the
   !> floating motions: the component of the uniform translations (1, 0) and (0, 1) of every free
   !> translational DOF outside that span (in the displacement metric) is formed for each, and the
   !> directions where their 2 × 2 Gram matrix vanishes (relative to the translations' own size) are
   !> free. `status`: the stat= of the basis' and the translations' work arrays, of `bytes` together
   !> (nonzero: refused, n_free = 0).
   subroutine free_translations(model, map, motions, free, n_free, status, bytes)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp), intent(in) :: motions(:, :)
      real(dp), intent(out) :: free(2, 2)
      integer, intent(out) :: n_free, status
      real(dp), intent(out) :: bytes
      real(dp), allocatable :: basis(:, :), translation(:, :)
      real(dp) :: gram(2, 2), size2, eigen(2), vector(2, 2), half_trace, radius, a, b, d
      integer :: k, j, i, node
      free = 0.0_dp
      n_free = 0
      status = 0
      bytes = 8.0_dp*size(motions, 1)*(size(motions, 2) + 2)
      if (size(motions, 2) == 0) return
      ! an orthonormal basis of the motions' span in the metric (modified Gram–Schmidt); its work
      ! arrays allocated with stat= (an assignment that allocates is not checked)
      allocate (basis(size(motions, 1), size(motions, 2)), translation(size(motions, 1), 2), stat=status)
      if (status /= 0) return
      basis(:, :) = motions
      do k = 1, size(basis, 2)
         do j = 1, k - 1
            basis(:, k) = basis(:, k) - sum(map%metric*basis(:, j)*basis(:, k))*basis(:, j)
         end do
         d = sqrt(sum(map%metric*basis(:, k)**2))
         if (.not. d > 0.0_dp) return
         basis(:, k) = basis(:, k)/d
      end do
      translation(:, :) = 0.0_dp
      do node = 1, model%n_nodes
         do i = 1, 2
            if (map%equation(i, node) > 0) translation(map%equation(i, node), i) = 1.0_dp
         end do
      end do
      size2 = max(sum(translation(:, 1)**2), sum(translation(:, 2)**2))
      if (.not. size2 > 0.0_dp) return
      do i = 1, 2
         do k = 1, size(basis, 2)
            translation(:, i) = translation(:, i) - sum(map%metric*basis(:, k)*translation(:, i))*basis(:, k)
         end do
      end do
      do i = 1, 2
         do j = 1, 2
            gram(i, j) = sum(map%metric*translation(:, i)*translation(:, j))/size2
         end do
      end do
      ! eigenpairs of the symmetric 2 × 2 Gram matrix
      a = gram(1, 1)
      b = gram(1, 2)
      d = gram(2, 2)
      half_trace = 0.5_dp*(a + d)
      radius = hypot(0.5_dp*(a - d), b)
      eigen = [half_trace - radius, half_trace + radius]
      if (abs(b) > 0.0_dp) then
         vector(:, 1) = [b, eigen(1) - a]
         vector(:, 2) = [-vector(2, 1), vector(1, 1)]
         vector(:, 1) = vector(:, 1)/norm2(vector(:, 1))
         vector(:, 2) = vector(:, 2)/norm2(vector(:, 2))
      else if (a <= d) then
         vector = reshape([1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [2, 2])
         eigen = [a, d]
      else
         vector = reshape([0.0_dp, 1.0_dp, 1.0_dp, 0.0_dp], [2, 2])
         eigen = [d, a]
      end if
      do k = 1, 2
         if (eigen(k) <= span_tolerance**2) then
            n_free = n_free + 1
            free(:, n_free) = vector(:, k)
         end if
      end do
   end subroutine free_translations

   !> The distance s ≤ limit along the unit direction e at which the exact gap of candidate c, its
   !> node displaced by u, closes (to `tolerance`), marching by the gap itself (a signed distance to
   !> the obstacle, 1-Lipschitz in the position: a step never passes the surface; Hart 1996, sphere
   !> tracing, The Visual Computer 12:527–545). `gap` is the gap at s = 0 (> tolerance), `offset`
   !> included.
   !> s = huge when the surface is not met before `limit`.
   subroutine march(model, c, u, e, gap, limit, tolerance, offset, s)
      type(model_t), intent(in) :: model
      integer, intent(in) :: c
      real(dp), intent(in) :: u(2), e(2), gap, limit, tolerance
      real(dp), intent(in) :: offset   !< added to the obstacle's gap (a plastic slip; 0 otherwise)
      real(dp), intent(out) :: s
      real(dp) :: g, gradient(2), hessian(2, 2)
      integer :: k, node
      node = model%contacts(c)%node
      s = 0.0_dp
      g = gap
      do k = 1, max_march
         s = s + g
         if (s > limit) exit
         call candidate_gap(model%contacts(c), model%coordinates(:, node), u + s*e, g, gradient, hessian)
         g = g + offset
         if (g <= tolerance) return
      end do
      s = huge(1.0_dp)
   end subroutine march

end module uniarc_path_approach
