!> Copies of a model whose allocations are checked (docs/contracts.md, "Memory"): every allocatable
!> component allocated with stat=, so that a copy the system refuses is an error value, not a crash.
!>
!> An intrinsic assignment `copy = model` allocates each component unchecked: gfortran 12 copies a
!> refused component into a null pointer (SIGSEGV in memmove, measured under `ulimit -v` with the
!> Release build), and `allocate (copy, source=model, stat=)` checks the outer allocation only. Here
!> each record's scalars are copied by intrinsic assignment while its allocatable components are moved
!> aside (move_alloc, no allocation), then each component is allocated with stat= and copied.
!>
!> Every allocatable component of model_t and of its records must be handled below; one left out would
!> be copied by the intrinsic assignment (correct, but unchecked).
module uniarc_model_copy
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, section_t, node_set_t, element_set_t, track_t, contact_candidate_t, &
                           contact_group_t, foundation_t, load_pattern_t, output_options_t
   use uniarc_copy, only: copy_array, copy_text, move_text
   implicit none
   private
   public :: copy_model, copy_pattern

contains

   !> `dst` a copy of `src` without its analysis steps (`dst%steps` unallocated: the model of one step,
   !> uniarc_model_steps). `src` is unchanged on return (intent(inout): its components are moved aside
   !> while its scalars are copied). status: 0, or the stat= of the allocation that the system refused
   !> (`dst` then partly copied, to be discarded); bytes: the size of that array (for allocation_failure).
   subroutine copy_model(src, dst, status, bytes)
      type(model_t), intent(inout) :: src
      type(model_t), intent(out) :: dst
      integer, intent(out) :: status
      real(dp), intent(out) :: bytes
      type(model_t) :: aside
      integer :: i
      bytes = 0.0_dp
      call move_model_arrays(src, aside)
      dst = src
      call move_model_arrays(aside, src)
      call copy_text(src%deck_path, dst%deck_path, status, bytes)
      if (status == 0) call copy_text(src%title, dst%title, status, bytes)
      if (status == 0) call copy_array(src%coordinates, dst%coordinates, status, bytes)
      if (status == 0) call copy_array(src%node_label, dst%node_label, status, bytes)
      if (status == 0) call copy_array(src%connectivity, dst%connectivity, status, bytes)
      if (status == 0) call copy_array(src%element_label, dst%element_label, status, bytes)
      if (status == 0) call copy_array(src%element_section, dst%element_section, status, bytes)
      if (status == 0) call copy_array(src%element_kind, dst%element_kind, status, bytes)
      if (status == 0) call copy_array(src%fixed, dst%fixed, status, bytes)
      if (status == 0) call copy_array(src%nodal_load, dst%nodal_load, status, bytes)
      if (status == 0) call copy_array(src%prescribed, dst%prescribed, status, bytes)
      if (status /= 0) return
      if (allocated(src%end_joints)) then
         bytes = real(storage_size(src%end_joints)/8, dp)*size(src%end_joints)
         allocate (dst%end_joints(size(src%end_joints, 1), size(src%end_joints, 2)), stat=status)
         if (status /= 0) return
         dst%end_joints = src%end_joints   ! no allocatable component: no further allocation
      end if
      if (allocated(src%distributed_loads)) then
         bytes = real(storage_size(src%distributed_loads)/8, dp)*size(src%distributed_loads)
         allocate (dst%distributed_loads(size(src%distributed_loads)), stat=status)
         if (status /= 0) return
         dst%distributed_loads = src%distributed_loads
      end if
      if (allocated(src%thermal_loads)) then
         bytes = real(storage_size(src%thermal_loads)/8, dp)*size(src%thermal_loads)
         allocate (dst%thermal_loads(size(src%thermal_loads)), stat=status)
         if (status /= 0) return
         dst%thermal_loads = src%thermal_loads
      end if
      if (allocated(src%sections)) then
         bytes = real(storage_size(src%sections)/8, dp)*size(src%sections)
         allocate (dst%sections(size(src%sections)), stat=status)
         do i = 1, size(src%sections)
            if (status == 0) call copy_section(src%sections(i), dst%sections(i), status, bytes)
         end do
         if (status /= 0) return
      end if
      if (allocated(src%node_sets)) then
         bytes = real(storage_size(src%node_sets)/8, dp)*size(src%node_sets)
         allocate (dst%node_sets(size(src%node_sets)), stat=status)
         do i = 1, size(src%node_sets)
            if (status == 0) call copy_text(src%node_sets(i)%name, dst%node_sets(i)%name, status, bytes)
            if (status == 0) call copy_array(src%node_sets(i)%nodes, dst%node_sets(i)%nodes, status, bytes)
         end do
         if (status /= 0) return
      end if
      if (allocated(src%element_sets)) then
         bytes = real(storage_size(src%element_sets)/8, dp)*size(src%element_sets)
         allocate (dst%element_sets(size(src%element_sets)), stat=status)
         do i = 1, size(src%element_sets)
            if (status == 0) call copy_text(src%element_sets(i)%name, dst%element_sets(i)%name, status, bytes)
            if (status == 0) call copy_array(src%element_sets(i)%elements, dst%element_sets(i)%elements, status, bytes)
         end do
         if (status /= 0) return
      end if
      if (allocated(src%tracks)) then
         bytes = real(storage_size(src%tracks)/8, dp)*size(src%tracks)
         allocate (dst%tracks(size(src%tracks)), stat=status)
         do i = 1, size(src%tracks)
            if (status == 0) call copy_track(src%tracks(i), dst%tracks(i), status, bytes)
         end do
         if (status /= 0) return
      end if
      if (allocated(src%contacts)) then
         bytes = real(storage_size(src%contacts)/8, dp)*size(src%contacts)
         allocate (dst%contacts(size(src%contacts)), stat=status)
         do i = 1, size(src%contacts)
            if (status == 0) call copy_candidate(src%contacts(i), dst%contacts(i), status, bytes)
         end do
         if (status /= 0) return
      end if
      if (allocated(src%contact_groups)) then
         bytes = real(storage_size(src%contact_groups)/8, dp)*size(src%contact_groups)
         allocate (dst%contact_groups(size(src%contact_groups)), stat=status)
         do i = 1, size(src%contact_groups)
            if (status == 0) call copy_text(src%contact_groups(i)%name, dst%contact_groups(i)%name, status, bytes)
            if (status == 0) call copy_array(src%contact_groups(i)%candidates, dst%contact_groups(i)%candidates, &
                                             status, bytes)
         end do
         if (status /= 0) return
      end if
      if (allocated(src%foundations)) then
         bytes = real(storage_size(src%foundations)/8, dp)*size(src%foundations)
         allocate (dst%foundations(size(src%foundations)), stat=status)
         do i = 1, size(src%foundations)
            if (status == 0) call copy_foundation(src%foundations(i), dst%foundations(i), status, bytes)
         end do
         if (status /= 0) return
      end if
      if (allocated(src%held)) then
         bytes = real(storage_size(src%held)/8, dp)*size(src%held)
         allocate (dst%held(size(src%held)), stat=status)
         do i = 1, size(src%held)
            if (status == 0) call copy_pattern(src%held(i), dst%held(i), status, bytes)
         end do
         if (status /= 0) return
      end if
      call copy_output(src%output, dst%output, status, bytes)
   end subroutine copy_model

   !> Every allocatable component of the model moved from `from` to `to` (no copy, no allocation), the
   !> analysis steps included; `to`'s are replaced.
   subroutine move_model_arrays(from, to)
      type(model_t), intent(inout) :: from, to
      call move_text(from%deck_path, to%deck_path)
      call move_text(from%title, to%title)
      call move_alloc(from%coordinates, to%coordinates)
      call move_alloc(from%node_label, to%node_label)
      call move_alloc(from%connectivity, to%connectivity)
      call move_alloc(from%element_label, to%element_label)
      call move_alloc(from%element_section, to%element_section)
      call move_alloc(from%element_kind, to%element_kind)
      call move_alloc(from%end_joints, to%end_joints)
      call move_alloc(from%sections, to%sections)
      call move_alloc(from%node_sets, to%node_sets)
      call move_alloc(from%element_sets, to%element_sets)
      call move_alloc(from%fixed, to%fixed)
      call move_alloc(from%nodal_load, to%nodal_load)
      call move_alloc(from%distributed_loads, to%distributed_loads)
      call move_alloc(from%tracks, to%tracks)
      call move_alloc(from%contacts, to%contacts)
      call move_alloc(from%contact_groups, to%contact_groups)
      call move_alloc(from%foundations, to%foundations)
      call move_alloc(from%thermal_loads, to%thermal_loads)
      call move_alloc(from%prescribed, to%prescribed)
      call move_alloc(from%steps, to%steps)
      call move_alloc(from%held, to%held)
      if (allocated(to%output%forces_steps)) deallocate (to%output%forces_steps)
      if (allocated(from%output%forces_steps)) call move_alloc(from%output%forces_steps, to%output%forces_steps)
   end subroutine move_model_arrays

   !> `dst` a copy of the load pattern `src` (status, bytes as copy_model).
   subroutine copy_pattern(src, dst, status, bytes)
      type(load_pattern_t), intent(in) :: src
      type(load_pattern_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(out) :: bytes
      status = 0
      bytes = 0.0_dp
      dst%factor = src%factor
      call copy_array(src%nodal_load, dst%nodal_load, status, bytes)
      if (status == 0) call copy_array(src%prescribed, dst%prescribed, status, bytes)
      if (status == 0) call copy_array(src%moves, dst%moves, status, bytes)   ! obstacle translations (*MOVE)
      if (status /= 0) return
      if (allocated(dst%distributed_loads)) deallocate (dst%distributed_loads)
      if (allocated(src%distributed_loads)) then
         bytes = real(storage_size(src%distributed_loads)/8, dp)*size(src%distributed_loads)
         allocate (dst%distributed_loads(size(src%distributed_loads)), stat=status)
         if (status /= 0) return
         dst%distributed_loads = src%distributed_loads
      end if
      if (allocated(dst%thermal_loads)) deallocate (dst%thermal_loads)
      if (allocated(src%thermal_loads)) then
         bytes = real(storage_size(src%thermal_loads)/8, dp)*size(src%thermal_loads)
         allocate (dst%thermal_loads(size(src%thermal_loads)), stat=status)
         if (status /= 0) return
         dst%thermal_loads = src%thermal_loads
      end if
   end subroutine copy_pattern

   subroutine copy_section(src, dst, status, bytes)
      type(section_t), intent(inout) :: src
      type(section_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      character(len=:), allocatable :: name
      call move_text(src%name, name)
      dst = src
      call move_text(name, src%name)
      call copy_text(src%name, dst%name, status, bytes)
   end subroutine copy_section

   subroutine copy_track(src, dst, status, bytes)
      type(track_t), intent(inout) :: src
      type(track_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      character(len=:), allocatable :: name
      call move_text(src%name, name)
      dst = src
      call move_text(name, src%name)
      call copy_text(src%name, dst%name, status, bytes)
   end subroutine copy_track

   subroutine copy_candidate(src, dst, status, bytes)
      type(contact_candidate_t), intent(inout) :: src
      type(contact_candidate_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      real(dp), allocatable :: vertices(:, :)
      call move_alloc(src%vertices, vertices)
      dst = src
      call move_alloc(vertices, src%vertices)
      call copy_array(src%vertices, dst%vertices, status, bytes)
   end subroutine copy_candidate

   subroutine copy_foundation(src, dst, status, bytes)
      type(foundation_t), intent(inout) :: src
      type(foundation_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      character(len=:), allocatable :: name, element_set
      integer, allocatable :: elements(:)
      call move_text(src%name, name)
      call move_text(src%element_set, element_set)
      call move_alloc(src%elements, elements)
      dst = src
      call move_text(name, src%name)
      call move_text(element_set, src%element_set)
      call move_alloc(elements, src%elements)
      call copy_text(src%name, dst%name, status, bytes)
      if (status == 0) call copy_text(src%element_set, dst%element_set, status, bytes)
      if (status == 0) call copy_array(src%elements, dst%elements, status, bytes)
   end subroutine copy_foundation

   subroutine copy_output(src, dst, status, bytes)
      type(output_options_t), intent(in) :: src
      type(output_options_t), intent(inout) :: dst
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      call copy_array(src%forces_steps, dst%forces_steps, status, bytes)
   end subroutine copy_output

end module uniarc_model_copy
