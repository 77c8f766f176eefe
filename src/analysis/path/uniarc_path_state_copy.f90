!> Copies of a path state whose allocations are checked (docs/contracts.md, "Memory"): the state at the
!> start of a step (the critical-point locator's and a rejection's), the state a probe restores and
!> the state of a bifurcation that a branch switch starts from.
!>
!> As in uniarc_model_copy: an intrinsic assignment `copy = state` allocates every component unchecked
!> (gfortran 12 crashes in memmove when one is refused), so the record's scalars are copied by an
!> intrinsic assignment while its allocatable components are moved aside (move_alloc), then each
!> component is allocated with stat= and copied. Every allocatable component of path_state_t and of the
!> records it holds must be handled below; one left out would be copied, but unchecked.
module uniarc_path_state_copy
   use uniarc_kinds, only: dp
   use uniarc_copy, only: copy_array
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_dof_map, only: dof_map_t
   use uniarc_band, only: band_matrix_t
   use uniarc_path_state, only: path_state_t, path_point_t, path_system_t, bifurcation_state_t, step_trial_t
   implicit none
   private
   public :: copy_state, move_state, copy_point_record, move_point, move_trial, move_map

contains

   !> `dst` a copy of `src` (its system too, if it has one). `src` is unchanged on return (intent(inout):
   !> its arrays are moved aside while its scalars are copied). error: out of memory (error_analysis,
   !> flagged out_of_memory: it ends the run) naming `what` (the copy, as a noun phrase) and the size of
   !> the array that was refused; `dst` is then to be discarded.
   subroutine copy_state(src, dst, what, error)
      type(path_state_t), intent(inout) :: src
      type(path_state_t), intent(inout) :: dst
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      type(path_state_t) :: aside
      integer :: status
      real(dp) :: bytes
      bytes = 0.0_dp
      call move_state_arrays(src, aside)
      dst = src
      call move_state_arrays(aside, src)
      call copy_map(src%map, dst%map, status, bytes)
      if (status == 0) call copy_array(src%committed_residual, dst%committed_residual, status, bytes)
      if (status == 0) call copy_array(src%eigenvector, dst%eigenvector, status, bytes)
      if (status == 0) call copy_array(src%liftoff_mode, dst%liftoff_mode, status, bytes)
      if (status == 0) call copy_array(src%u, dst%u, status, bytes)
      if (status == 0) call copy_array(src%active, dst%active, status, bytes)
      if (status == 0) call copy_array(src%reactions, dst%reactions, status, bytes)
      if (status == 0) call copy_array(src%joint_plastic, dst%joint_plastic, status, bytes)
      if (status == 0) call copy_array(src%slip, dst%slip, status, bytes)
      if (status == 0) call copy_array(src%yielding, dst%yielding, status, bytes)
      if (status == 0) call copy_array(src%fixed_load, dst%fixed_load, status, bytes)
      if (status == 0) call copy_array(src%reference, dst%reference, status, bytes)
      if (status == 0) call copy_array(src%tangent_displacement, dst%tangent_displacement, status, bytes)
      if (status == 0) call copy_array(src%last_increment, dst%last_increment, status, bytes)
      if (status == 0) call copy_array(src%floating_motion, dst%floating_motion, status, bytes)
      if (status == 0) call copy_array(src%floating_equation, dst%floating_equation, status, bytes)
      if (status == 0) call copy_point(src%point, dst%point, status, bytes)
      if (status == 0) call copy_array(src%contact_start_u, dst%contact_start_u, status, bytes)
      if (status == 0 .and. allocated(src%bifurcation)) then
         bytes = real(storage_size(src%bifurcation)/8, dp)
         allocate (dst%bifurcation, stat=status)
         if (status == 0) call copy_bifurcation(src%bifurcation, dst%bifurcation, status, bytes)
      end if
      if (status == 0 .and. allocated(src%system)) then
         bytes = real(storage_size(src%system)/8, dp)
         allocate (dst%system, stat=status)
         if (status == 0) call copy_system(src%system, dst%system, status, bytes)
      end if
      call allocation_failure(status, 'an array of '//what, bytes, error_analysis, error)
   end subroutine copy_state

   !> `from` moved into `to` (its arrays handed over, not copied; `from` left without them).
   subroutine move_state(from, to)
      type(path_state_t), intent(inout) :: from, to
      type(path_state_t) :: aside
      call move_state_arrays(from, aside)
      to = from
      call move_state_arrays(aside, to)
   end subroutine move_state

   !> Attempt `from` moved into `to` (its arrays handed over, not copied; `from` left without them): what
   !> `to = from` does without allocating, so without an allocation that could be refused.
   subroutine move_trial(from, to)
      type(step_trial_t), intent(inout) :: from, to
      type(step_trial_t) :: aside
      call move_trial_arrays(from, aside)
      to = from
      call move_trial_arrays(aside, to)
   end subroutine move_trial

   !> Numbering `from` moved into `to` (its arrays handed over, not copied): `to = from` without an
   !> allocation.
   subroutine move_map(from, to)
      type(dof_map_t), intent(inout) :: from, to
      type(dof_map_t) :: aside
      call move_map_arrays(from, aside)
      to = from
      call move_map_arrays(aside, to)
   end subroutine move_map

   subroutine move_map_arrays(from, to)
      type(dof_map_t), intent(inout) :: from, to
      call move_alloc(from%equation, to%equation)
      call move_alloc(from%node_order, to%node_order)
      call move_alloc(from%candidate_equation, to%candidate_equation)
      call move_alloc(from%condensed, to%condensed)
      call move_alloc(from%bed_equation, to%bed_equation)
      call move_alloc(from%metric, to%metric)
   end subroutine move_map_arrays

   !> Every allocatable component of the attempt moved from `from` to `to`; `to`'s are replaced.
   subroutine move_trial_arrays(from, to)
      type(step_trial_t), intent(inout) :: from, to
      call move_alloc(from%increment, to%increment)
      call move_alloc(from%predictor, to%predictor)
      call move_alloc(from%active, to%active)
      call move_alloc(from%yielding, to%yielding)
      if (allocated(to%reason)) deallocate (to%reason)
      if (allocated(from%reason)) call move_alloc(from%reason, to%reason)
      if (allocated(to%fatal)) deallocate (to%fatal)
      if (allocated(from%fatal)) call move_alloc(from%fatal, to%fatal)
   end subroutine move_trial_arrays

   !> Every allocatable component of the state (and of its map and point) moved from `from` to `to`:
   !> no copy, no allocation; `to`'s are replaced.
   subroutine move_state_arrays(from, to)
      type(path_state_t), intent(inout) :: from, to
      call move_alloc(from%map%equation, to%map%equation)
      call move_alloc(from%map%node_order, to%map%node_order)
      call move_alloc(from%map%candidate_equation, to%map%candidate_equation)
      call move_alloc(from%map%condensed, to%map%condensed)
      call move_alloc(from%map%bed_equation, to%map%bed_equation)
      call move_alloc(from%map%metric, to%map%metric)
      call move_alloc(from%system, to%system)
      call move_alloc(from%committed_residual, to%committed_residual)
      call move_alloc(from%eigenvector, to%eigenvector)
      call move_alloc(from%liftoff_mode, to%liftoff_mode)
      call move_alloc(from%u, to%u)
      call move_alloc(from%active, to%active)
      call move_alloc(from%reactions, to%reactions)
      call move_alloc(from%joint_plastic, to%joint_plastic)
      call move_alloc(from%slip, to%slip)
      call move_alloc(from%yielding, to%yielding)
      call move_alloc(from%fixed_load, to%fixed_load)
      call move_alloc(from%reference, to%reference)
      call move_alloc(from%tangent_displacement, to%tangent_displacement)
      call move_alloc(from%last_increment, to%last_increment)
      call move_alloc(from%floating_motion, to%floating_motion)
      call move_alloc(from%floating_equation, to%floating_equation)
      call move_alloc(from%point%rate, to%point%rate)
      call move_alloc(from%point%in_contact, to%point%in_contact)
      call move_alloc(from%point%contact_value, to%point%contact_value)
      call move_alloc(from%point%contact_rate, to%point%contact_rate)
      call move_alloc(from%bifurcation, to%bifurcation)
      call move_alloc(from%contact_start_u, to%contact_start_u)
   end subroutine move_state_arrays

   !> `dst` a copy of the point record `src` (scalars and arrays; `src` unchanged, inout for the move
   !> aside). error: as copy_state.
   subroutine copy_point_record(src, dst, what, error)
      type(path_point_t), intent(inout) :: src
      type(path_point_t), intent(inout) :: dst
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      type(path_point_t) :: aside
      integer :: status
      real(dp) :: bytes
      bytes = 0.0_dp
      call move_point_arrays(src, aside)
      dst = src
      call move_point_arrays(aside, src)
      call copy_point(src, dst, status, bytes)
      call allocation_failure(status, 'an array of '//what, bytes, error_analysis, error)
   end subroutine copy_point_record

   !> Point record `from` moved into `to` (its arrays handed over, not copied; `from` left without them).
   subroutine move_point(from, to)
      type(path_point_t), intent(inout) :: from, to
      type(path_point_t) :: aside
      call move_point_arrays(from, aside)
      to = from
      call move_point_arrays(aside, to)
   end subroutine move_point

   subroutine move_point_arrays(from, to)
      type(path_point_t), intent(inout) :: from, to
      call move_alloc(from%rate, to%rate)
      call move_alloc(from%in_contact, to%in_contact)
      call move_alloc(from%contact_value, to%contact_value)
      call move_alloc(from%contact_rate, to%contact_rate)
   end subroutine move_point_arrays

   subroutine copy_map(src, dst, status, bytes)
      type(dof_map_t), intent(in) :: src
      type(dof_map_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      call copy_array(src%equation, dst%equation, status, bytes)
      if (status == 0) call copy_array(src%node_order, dst%node_order, status, bytes)
      if (status == 0) call copy_array(src%candidate_equation, dst%candidate_equation, status, bytes)
      if (status == 0) call copy_array(src%condensed, dst%condensed, status, bytes)
      if (status == 0) call copy_array(src%bed_equation, dst%bed_equation, status, bytes)
      if (status == 0) call copy_array(src%metric, dst%metric, status, bytes)
   end subroutine copy_map

   subroutine copy_point(src, dst, status, bytes)
      type(path_point_t), intent(in) :: src
      type(path_point_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      call copy_array(src%rate, dst%rate, status, bytes)
      if (status == 0) call copy_array(src%in_contact, dst%in_contact, status, bytes)
      if (status == 0) call copy_array(src%contact_value, dst%contact_value, status, bytes)
      if (status == 0) call copy_array(src%contact_rate, dst%contact_rate, status, bytes)
   end subroutine copy_point

   subroutine copy_bifurcation(src, dst, status, bytes)
      type(bifurcation_state_t), intent(inout) :: src
      type(bifurcation_state_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      type(bifurcation_state_t) :: aside
      call move_alloc(src%u, aside%u)
      call move_alloc(src%active, aside%active)
      call move_alloc(src%mode, aside%mode)
      call move_alloc(src%joint_plastic, aside%joint_plastic)
      dst = src
      call move_alloc(aside%u, src%u)
      call move_alloc(aside%active, src%active)
      call move_alloc(aside%mode, src%mode)
      call move_alloc(aside%joint_plastic, src%joint_plastic)
      call copy_array(src%u, dst%u, status, bytes)
      if (status == 0) call copy_array(src%active, dst%active, status, bytes)
      if (status == 0) call copy_array(src%mode, dst%mode, status, bytes)
      if (status == 0) call copy_array(src%joint_plastic, dst%joint_plastic, status, bytes)
   end subroutine copy_bifurcation

   subroutine copy_system(src, dst, status, bytes)
      type(path_system_t), intent(inout) :: src
      type(path_system_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      type(path_system_t) :: aside
      call move_system_arrays(src, aside)
      dst = src
      call move_system_arrays(aside, src)
      call copy_band(src%tangent, dst%tangent, status, bytes)
      if (status == 0) call copy_band(src%assembled, dst%assembled, status, bytes)
      if (status == 0) call copy_array(src%converged_internal, dst%converged_internal, status, bytes)
      if (status == 0) call copy_array(src%converged_reference, dst%converged_reference, status, bytes)
   end subroutine copy_system

   subroutine move_system_arrays(from, to)
      type(path_system_t), intent(inout) :: from, to
      call move_alloc(from%tangent%ab, to%tangent%ab)
      call move_alloc(from%tangent%pivots, to%tangent%pivots)
      call move_alloc(from%assembled%ab, to%assembled%ab)
      call move_alloc(from%assembled%pivots, to%assembled%pivots)
      call move_alloc(from%converged_internal, to%converged_internal)
      call move_alloc(from%converged_reference, to%converged_reference)
   end subroutine move_system_arrays

   !> The band arrays of `src` copied into `dst` (its scalars already copied with its record).
   subroutine copy_band(src, dst, status, bytes)
      type(band_matrix_t), intent(in) :: src
      type(band_matrix_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      call copy_array(src%ab, dst%ab, status, bytes)
      if (status == 0) call copy_array(src%pivots, dst%pivots, status, bytes)
   end subroutine copy_band

end module uniarc_path_state_copy
