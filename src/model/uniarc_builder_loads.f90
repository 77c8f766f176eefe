!> The loads of a model under construction (uniarc_model_builder): nodal forces, distributed loads
!> (fixed direction, pressure, follower pressure: one record per element and kind, summed), temperature
!> changes and prescribed displacements, all reference values scaled by λ; `take_loads` moves those
!> added so far into an analysis step's load pattern (*STEP).
module uniarc_builder_loads
   use uniarc_kinds, only: dp
   use uniarc_growth, only: grow_integers
   use uniarc_strings, only: real_to_string
   use uniarc_model, only: distributed_load_t, thermal_load_t, load_pattern_t, dofs_per_node, dof_ux, &
                           load_fixed_direction, load_pressure
   use uniarc_builder_type, only: model_builder_t, slot_fixed, slot_pressure, slot_follower
   implicit none
   private
   public :: add_nodal_load, add_line_load, add_pressure, add_thermal_load, thermal_excess
   public :: add_prescribed_displacement, has_prescribed_displacements, take_loads

contains

   !> Add the reference force (or moment, dof_rz) `value` on DOF `dof` of `node`; loads are summed.
   pure subroutine add_nodal_load(builder, node, dof, value)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: node, dof
      real(dp), intent(in) :: value
      builder%nodal_load(dof, node) = builder%nodal_load(dof, node) + value
   end subroutine add_nodal_load

   !> Add a reference force per unit initial length `value` in global direction `dof` (dof_ux: x, else y)
   !> on `element`; such loads on one element are summed into its one fixed-direction record.
   !> `status` (optional): nonzero, the stat= of the growth of the load records refused by the system
   !> (the load is then not added; without it a refusal stops the program with the runtime's message).
   pure subroutine add_line_load(builder, element, dof, value, status)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: element, dof
      real(dp), intent(in) :: value
      integer, intent(out), optional :: status
      integer :: record, grown
      call load_record(builder, element, slot_fixed, record, grown)
      if (present(status)) status = grown
      if (grown /= 0) return
      if (dof == dof_ux) then
         builder%loads(record)%qx = builder%loads(record)%qx + value
      else
         builder%loads(record)%qy = builder%loads(record)%qy + value
      end if
   end subroutine add_line_load

   !> Add a reference pressure per unit length `value` along the left normal of `element` (its tangent
   !> node1 → node2 turned by +90°), following the deformed normal if `follower`; summed per element
   !> into one pressure and one follower-pressure record.
   !> `status` (optional): as for add_line_load.
   pure subroutine add_pressure(builder, element, value, follower, status)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: element
      real(dp), intent(in) :: value
      logical, intent(in) :: follower
      integer, intent(out), optional :: status
      integer :: record, grown
      call load_record(builder, element, merge(slot_follower, slot_pressure, follower), record, grown)
      if (present(status)) status = grown
      if (grown /= 0) return
      builder%loads(record)%pressure = builder%loads(record)%pressure + value
   end subroutine add_pressure

   !> Add a temperature change of `element` (thermal_load_t: α, ΔT at the axis, ΔT_left − ΔT_right,
   !> depth h), a reference load scaled by λ; several on one element add up.
   !> `status` (optional): as for add_line_load (the list of temperature changes).
   pure subroutine add_thermal_load(builder, element, alpha, delta_t, difference, depth, status)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: element
      real(dp), intent(in) :: alpha, delta_t, difference, depth
      integer, intent(out), optional :: status
      type(thermal_load_t), allocatable :: grown(:)
      integer :: refused
      refused = 0
      if (.not. allocated(builder%thermal)) allocate (builder%thermal(8), stat=refused)
      if (present(status)) status = refused
      if (refused /= 0) return
      if (builder%n_thermal == size(builder%thermal)) then
         allocate (grown(2*size(builder%thermal)), stat=refused)
         if (present(status)) status = refused
         if (refused /= 0) return
         grown(1:builder%n_thermal) = builder%thermal(1:builder%n_thermal)
         call move_alloc(grown, builder%thermal)
      end if
      builder%n_thermal = builder%n_thermal + 1
      builder%thermal(builder%n_thermal) = thermal_load_t(element=element, alpha=alpha, delta_t=delta_t, &
                                                          difference=difference, depth=depth)
   end subroutine add_thermal_load

   !> What is wrong with a temperature change (α `alpha`, ΔT `delta_t` at the axis, ΔT_left − ΔT_right
   !> `difference` over the depth `depth`) on an element of length `length` (docs/theory.md §1.9), or ''
   !> when nothing is: the free axial strain α ΔT at most 1 in magnitude, and the free rotation of the
   !> element's ends against each other, α ΔT_d L / h, at most π. The corotational element takes its
   !> natural deformation as a small strain and a rotation against its chord; beyond these a deformation
   !> means nothing, and its products with the stiffnesses (EA α ΔT, EI κ, κ L² in the displacements)
   !> overflow double precision (ΔT_d = 1e300 or h = 1e-100: SIGFPE in the Debug build). The products
   !> are compared through logarithms, so that the test itself cannot overflow. `axial` is true when
   !> the strain is what fails (the rotation otherwise), for the message's column.
   pure subroutine thermal_excess(alpha, delta_t, difference, depth, length, what, axial)
      real(dp), intent(in) :: alpha, delta_t, difference, depth, length
      character(len=:), allocatable, intent(out) :: what
      logical, intent(out) :: axial
      real(dp), parameter :: pi = acos(-1.0_dp)
      what = ''
      axial = .false.
      if (alpha /= 0.0_dp .and. delta_t /= 0.0_dp) then
         if (log(abs(alpha)) + log(abs(delta_t)) > 0.0_dp) then
            what = 'a free thermal strain alpha dT beyond 1 in magnitude (alpha = '//real_to_string(alpha)// &
                   ', dT = '//real_to_string(delta_t)//')'
            axial = .true.
            return
         end if
      end if
      if (alpha /= 0.0_dp .and. difference /= 0.0_dp .and. depth > 0.0_dp .and. length > 0.0_dp) then
         if (log(abs(alpha)) + log(abs(difference)) + log(length) - log(depth) > log(pi)) &
            what = 'a free thermal rotation alpha dT_d L/h beyond pi (alpha = '//real_to_string(alpha)// &
                   ', dT_d = '//real_to_string(difference)//', h = '//real_to_string(depth)// &
                   ', L = '//real_to_string(length)//')'
      end if
   end subroutine thermal_excess

   !> Hold DOF `dof` of `node` and prescribe its displacement `value` (a support settlement), a reference
   !> value scaled by λ like the loads; values on one DOF add up.
   !> status: the stat= of the growth of the lists (nonzero: refused by the system, nothing added; for
   !> uniarc_memory, allocation_failure).
   pure subroutine add_prescribed_displacement(builder, node, dof, value, status)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: node, dof
      real(dp), intent(in) :: value
      integer, intent(out) :: status
      real(dp), allocatable :: grown(:)
      status = 0
      if (.not. allocated(builder%prescribed_node)) then
         allocate (builder%prescribed_node(8), builder%prescribed_dof(8), builder%prescribed_value(8), stat=status)
         if (status /= 0) return
      end if
      if (builder%n_prescribed == size(builder%prescribed_node)) then
         ! grown with stat= (a growth by an array constructor is not checked)
         call grow_integers(builder%prescribed_node, 2*builder%n_prescribed, status)
         if (status == 0) call grow_integers(builder%prescribed_dof, 2*builder%n_prescribed, status)
         if (status == 0) allocate (grown(2*builder%n_prescribed), stat=status)
         if (status /= 0) return
         grown(1:builder%n_prescribed) = builder%prescribed_value(1:builder%n_prescribed)
         grown(builder%n_prescribed + 1:) = 0.0_dp
         call move_alloc(grown, builder%prescribed_value)
      end if
      builder%n_prescribed = builder%n_prescribed + 1
      builder%prescribed_node(builder%n_prescribed) = node
      builder%prescribed_dof(builder%n_prescribed) = dof
      builder%prescribed_value(builder%n_prescribed) = value
      builder%fixed(dof, node) = .true.
   end subroutine add_prescribed_displacement

   !> True if some DOF has a prescribed displacement (add_prescribed_displacement).
   pure logical function has_prescribed_displacements(builder)
      type(model_builder_t), intent(in) :: builder
      has_prescribed_displacements = builder%n_prescribed > 0
   end function has_prescribed_displacements

   !> Move the loads added so far (nodal, distributed, temperature changes, prescribed displacements) into
   !> `pattern` (an analysis step's, *STEP) and start again without loads; the element's load records
   !> start afresh too. `status`: that of the pattern's allocations (nonzero: the system refused them,
   !> `pattern` incomplete and the builder's loads kept).
   subroutine take_loads(builder, pattern, status)
      type(model_builder_t), intent(inout) :: builder
      type(load_pattern_t), intent(out) :: pattern
      integer, intent(out) :: status
      integer :: i
      if (allocated(builder%nodal_load)) then
         allocate (pattern%nodal_load(dofs_per_node, builder%n_nodes), pattern%distributed_loads(builder%n_loads), &
                   pattern%thermal_loads(builder%n_thermal), stat=status)
      else
         allocate (pattern%nodal_load(dofs_per_node, 0), pattern%distributed_loads(builder%n_loads), &
                   pattern%thermal_loads(builder%n_thermal), stat=status)
      end if
      if (status == 0 .and. builder%n_prescribed > 0) &
         allocate (pattern%prescribed(dofs_per_node, builder%n_nodes), stat=status)
      if (status /= 0) return
      if (allocated(builder%nodal_load)) then
         pattern%nodal_load = builder%nodal_load(:, 1:builder%n_nodes)
         builder%nodal_load = 0.0_dp
      end if
      if (builder%n_loads > 0) pattern%distributed_loads = builder%loads(1:builder%n_loads)
      if (builder%n_thermal > 0) pattern%thermal_loads = builder%thermal(1:builder%n_thermal)
      builder%n_loads = 0
      builder%n_thermal = 0
      if (allocated(builder%load_index)) builder%load_index = 0
      if (builder%n_prescribed > 0) then
         pattern%prescribed = 0.0_dp
         do i = 1, builder%n_prescribed
            pattern%prescribed(builder%prescribed_dof(i), builder%prescribed_node(i)) = &
               pattern%prescribed(builder%prescribed_dof(i), builder%prescribed_node(i)) + builder%prescribed_value(i)
         end do
         builder%n_prescribed = 0
      end if
      if (allocated(builder%moves)) call move_alloc(builder%moves, pattern%moves)
   end subroutine take_loads

   !> The load record of `element` in `slot`, made if the element has none there yet.
   !> `status`: the stat= of the growth of the records (nonzero: refused by the system, no record made).
   pure subroutine load_record(builder, element, slot, record, status)
      type(model_builder_t), intent(inout) :: builder
      integer, intent(in) :: element, slot
      integer, intent(out) :: record, status
      type(distributed_load_t), allocatable :: grown(:)
      status = 0
      record = builder%load_index(slot, element)
      if (record > 0) return
      if (.not. allocated(builder%loads)) allocate (builder%loads(16), stat=status)
      if (status /= 0) return
      if (builder%n_loads == size(builder%loads)) then
         allocate (grown(2*size(builder%loads)), stat=status)
         if (status /= 0) return
         grown(1:builder%n_loads) = builder%loads(1:builder%n_loads)
         call move_alloc(grown, builder%loads)
      end if
      builder%n_loads = builder%n_loads + 1
      record = builder%n_loads
      builder%loads(record) = distributed_load_t(element=element, kind=merge(load_fixed_direction, &
                                                 load_pressure, slot == slot_fixed), follower=slot == slot_follower)
      builder%load_index(slot, element) = record
   end subroutine load_record

end module uniarc_builder_loads
