!> The analysis steps of a model (docs/input.md, *STEP; docs/theory.md §2.5): the model that each step
!> is analysed on.
!>
!> Step k applies its own load pattern F_k scaled by its λ on top of the loads of the steps before it,
!> held at the value they reached (dead loads): the external force of step k is
!>
!>     F_held + λ F_k,   F_held = Σ_{j<k} λ_j F_j,
!>
!> λ_j the load factor at which step j ended (as Abaqus and CalculiX keep the loads of earlier steps,
!> Abaqus Analysis User's Guide, "Defining an analysis"; CalculiX CrunchiX User's Manual, *STEP).
!> A deck without *STEP is one step, the model itself.
!>
!> Prescribed displacements (support settlements, *BOUNDARY with a value) are a pattern like the loads:
!> those of step k scale with its λ, those of the earlier steps are held at λ_j times theirs
!> (`prescribed_at`, docs/theory.md §2.9).
module uniarc_model_steps
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, load_pattern_t, analysis_step_t, analysis_linear, dofs_per_node, move_obstacles
   use uniarc_model_copy, only: copy_model, copy_pattern
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: integer_to_string
   implicit none
   private
   public :: n_analysis_steps, step_model
   public :: prescribed_at, has_prescribed

contains

   !> Number of analysis steps of the model: those of its *STEP cards, or 1 for a deck without *STEP.
   pure integer function n_analysis_steps(model) result(n)
      type(model_t), intent(in) :: model
      n = 1
      if (allocated(model%steps)) n = size(model%steps)
   end function n_analysis_steps

   !> The model that analysis step `k` (1 ≤ k ≤ n_analysis_steps) is analysed on: `model` with step k's
   !> loads as its reference loads (scaled by the step's λ) and step k's analysis options.
   !> `end_lambda(j)` (j < k; size ≥ k − 1) is the λ at which step j ended. A nonlinear step (*PATH)
   !> gets the patterns of steps 1..k−1 as `held`, pattern j with factor end_lambda(j), evaluated by the
   !> equilibrium on the current geometry like the step's own loads (follower pressure follows, a
   !> temperature change stays a natural strain). A linear static step (every step of such a deck is one,
   !> and each ends at λ = 1) gets them added to its own loads instead, times end_lambda(j): its solution
   !> is that of all the loads so far, as superposition requires.
   !> A model without steps is returned as it is (k = 1).
   !>
   !> Supports that change at step k (`model%steps(k)%fixed`, nonlinear steps; docs/theory.md §2.10):
   !> a DOF held from step k on is held where it was when the step began, `start_displacement`
   !> (dofs_per_node, n_nodes; every DOF's), a pattern held at factor 1; a DOF released at step k
   !> carries the force its support applied then, `start_reactions` (dofs_per_node, n_nodes,
   !> uniarc_support_reactions), as a load held at factor 1 and the same load reversed in the step's own
   !> pattern: the support's force is ramped down with λ and gone at λ = 1 (Abaqus Analysis User's
   !> Guide, "Boundary conditions": a removed boundary condition's reaction is ramped down over the
   !> step). The prescribed displacements of earlier steps at the released DOFs no longer act. Without
   !> the two arrays (the first step, or a caller that does not change supports) nothing changes.
   !> The stepped model has no steps of its own (`stepped%steps` unallocated): `model%steps` is moved
   !> out for the copy and back, so that a deck of many steps does not copy every step's patterns for
   !> every step (`model` is unchanged on return).
   subroutine step_model(model, k, end_lambda, stepped, error, start_displacement, start_reactions)
      type(model_t), intent(inout) :: model
      integer, intent(in) :: k
      real(dp), intent(in) :: end_lambda(:)
      type(model_t), intent(out) :: stepped
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(in), optional :: start_displacement(:, :), start_reactions(:, :)
      type(load_pattern_t), allocatable :: patterns(:)
      type(analysis_step_t), allocatable :: steps(:)
      type(load_pattern_t) :: own
      integer :: j, status
      real(dp) :: bytes
      call move_alloc(model%steps, steps)
      call copy_model(model, stepped, status, bytes)
      call move_alloc(steps, model%steps)
      call allocation_failure(status, 'an array of the model of analysis step '//integer_to_string(k), bytes, &
                              error_analysis, error)
      if (allocated(error)) return
      if (.not. allocated(model%steps)) return
      stepped%analysis = model%steps(k)%analysis
      if (allocated(model%steps(k)%fixed)) then
         call copy_logicals(model%steps(k)%fixed, stepped%fixed, status)
         call allocation_failure(status, 'the supports of analysis step '//integer_to_string(k), &
                                 4.0_dp*size(model%steps(k)%fixed), error_analysis, error)
         if (allocated(error)) return
      end if
      if (model%steps(k)%analysis%kind == analysis_linear) then
         allocate (patterns(k), stat=status)
         do j = 1, k
            if (status == 0) call copy_pattern(model%steps(j)%loads, patterns(j), status, bytes)
            if (j < k) patterns(j)%factor = end_lambda(j)
         end do
         if (status == 0) patterns(k)%factor = 1.0_dp
         if (status == 0) call merge_patterns(patterns, stepped, status, bytes)
         if (status == 0) call merge_prescribed(patterns, stepped, status, bytes)
         ! moved obstacles: every step's translation at its factor, in the gaps' offsets (superposition)
         if (status == 0) then
            do j = 1, k
               if (allocated(patterns(j)%moves)) call move_obstacles(stepped, patterns(j)%moves, patterns(j)%factor, &
                                                                     own=.false.)
            end do
         end if
         if (status == 0) allocate (stepped%held(0), stat=status)
      else
         if (allocated(stepped%prescribed)) deallocate (stepped%prescribed)
         call copy_pattern(model%steps(k)%loads, own, status, bytes)
         if (status == 0) then
            call move_alloc(own%nodal_load, stepped%nodal_load)
            call move_alloc(own%distributed_loads, stepped%distributed_loads)
            call move_alloc(own%thermal_loads, stepped%thermal_loads)
            if (allocated(own%prescribed)) then
               call move_alloc(own%prescribed, stepped%prescribed)
               where (.not. stepped%fixed) stepped%prescribed = 0.0_dp   ! released in the step
            end if
            allocate (stepped%held(k - 1), stat=status)
         end if
         do j = 1, k - 1
            if (status /= 0) exit
            call copy_pattern(model%steps(j)%loads, stepped%held(j), status, bytes)
            stepped%held(j)%factor = end_lambda(j)
            if (allocated(stepped%held(j)%prescribed)) &
               where (.not. stepped%fixed) stepped%held(j)%prescribed = 0.0_dp
            ! the obstacles moved in step j stay where that step left them (docs/theory.md §3.11)
            if (allocated(model%steps(j)%loads%moves)) &
               call move_obstacles(stepped, model%steps(j)%loads%moves, end_lambda(j), own=.false.)
         end do
         if (status == 0 .and. allocated(model%steps(k)%loads%moves)) &
            call move_obstacles(stepped, model%steps(k)%loads%moves, 1.0_dp, own=.true.)
         if (status == 0 .and. k > 1 .and. present(start_displacement) .and. present(start_reactions)) &
            call change_supports(model%steps(k - 1)%fixed, start_displacement, start_reactions, stepped, status, bytes)
      end if
      call allocation_failure(status, 'a load pattern of the model of analysis step '//integer_to_string(k), bytes, &
                              error_analysis, error)
   end subroutine step_model

   !> The supports of `stepped` against those of the step before, `before`: the held pattern of the
   !> DOFs added (held where they are, `start_displacement`) and of the DOFs released (their supports'
   !> forces `start_reactions`, held), and those forces reversed in the step's own loads (step_model).
   subroutine change_supports(before, start_displacement, start_reactions, stepped, status, bytes)
      logical, intent(in) :: before(:, :)
      real(dp), intent(in) :: start_displacement(:, :), start_reactions(:, :)
      type(model_t), intent(inout) :: stepped
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      type(load_pattern_t) :: change
      type(load_pattern_t), allocatable :: held(:)
      logical, allocatable :: added(:, :), released(:, :)
      integer :: j
      bytes = 4.0_dp*size(before)
      allocate (added(dofs_per_node, stepped%n_nodes), released(dofs_per_node, stepped%n_nodes), stat=status)
      if (status /= 0) return
      added = stepped%fixed .and. .not. before
      released = before .and. .not. stepped%fixed
      if (.not. (any(added) .or. any(released))) return
      change%factor = 1.0_dp
      bytes = 8.0_dp*size(before)
      allocate (change%nodal_load(dofs_per_node, stepped%n_nodes), change%distributed_loads(0), &
                change%thermal_loads(0), stat=status)
      if (status /= 0) return
      change%nodal_load = 0.0_dp
      where (released) change%nodal_load = start_reactions
      stepped%nodal_load = stepped%nodal_load - change%nodal_load
      if (any(added)) then
         allocate (change%prescribed(dofs_per_node, stepped%n_nodes), stat=status)
         if (status /= 0) return
         change%prescribed = 0.0_dp
         where (added) change%prescribed = start_displacement
      end if
      ! stepped%held extended by `change`, the patterns moved, not copied
      bytes = real(storage_size(change)/8, dp)*(size(stepped%held) + 1)
      allocate (held(size(stepped%held) + 1), stat=status)
      if (status /= 0) return
      do j = 1, size(stepped%held)
         call move_pattern(stepped%held(j), held(j))
      end do
      call move_pattern(change, held(size(held)))
      call move_alloc(held, stepped%held)
   end subroutine change_supports

   !> Pattern `from` moved into `to` (its arrays handed over, not copied).
   subroutine move_pattern(from, to)
      type(load_pattern_t), intent(inout) :: from, to
      to%factor = from%factor
      call move_alloc(from%nodal_load, to%nodal_load)
      call move_alloc(from%distributed_loads, to%distributed_loads)
      call move_alloc(from%thermal_loads, to%thermal_loads)
      call move_alloc(from%prescribed, to%prescribed)
   end subroutine move_pattern

   !> `dst` a copy of `src` (status: the stat= of its allocation).
   subroutine copy_logicals(src, dst, status)
      logical, intent(in) :: src(:, :)
      logical, allocatable, intent(inout) :: dst(:, :)
      integer, intent(out) :: status
      if (allocated(dst)) deallocate (dst)
      allocate (dst(size(src, 1), size(src, 2)), stat=status)
      if (status == 0) dst = src
   end subroutine copy_logicals

   !> The loads of `patterns`, each times its factor, as the reference loads of `stepped`: nodal loads
   !> summed, distributed loads and temperature changes listed one after another (the assembly sums
   !> the records of one element).
   subroutine merge_patterns(patterns, stepped, status, bytes)
      type(load_pattern_t), intent(in) :: patterns(:)
      type(model_t), intent(inout) :: stepped
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      integer :: j, i, n_dloads, n_thermal
      stepped%nodal_load = 0.0_dp*stepped%nodal_load
      n_dloads = 0
      n_thermal = 0
      do j = 1, size(patterns)
         stepped%nodal_load = stepped%nodal_load + patterns(j)%factor*patterns(j)%nodal_load
         n_dloads = n_dloads + size(patterns(j)%distributed_loads)
         n_thermal = n_thermal + size(patterns(j)%thermal_loads)
      end do
      if (allocated(stepped%distributed_loads)) deallocate (stepped%distributed_loads)
      if (allocated(stepped%thermal_loads)) deallocate (stepped%thermal_loads)
      bytes = real(storage_size(patterns(1)%distributed_loads)/8, dp)*n_dloads + &
              real(storage_size(patterns(1)%thermal_loads)/8, dp)*n_thermal
      allocate (stepped%distributed_loads(n_dloads), stepped%thermal_loads(n_thermal), stat=status)
      if (status /= 0) return
      n_dloads = 0
      n_thermal = 0
      do j = 1, size(patterns)
         associate (p => patterns(j))
            do i = 1, size(p%distributed_loads)
               n_dloads = n_dloads + 1
               stepped%distributed_loads(n_dloads) = p%distributed_loads(i)
               stepped%distributed_loads(n_dloads)%qx = p%factor*p%distributed_loads(i)%qx
               stepped%distributed_loads(n_dloads)%qy = p%factor*p%distributed_loads(i)%qy
               stepped%distributed_loads(n_dloads)%pressure = p%factor*p%distributed_loads(i)%pressure
            end do
            do i = 1, size(p%thermal_loads)
               n_thermal = n_thermal + 1
               stepped%thermal_loads(n_thermal) = p%thermal_loads(i)
               stepped%thermal_loads(n_thermal)%delta_t = p%factor*p%thermal_loads(i)%delta_t
               stepped%thermal_loads(n_thermal)%difference = p%factor*p%thermal_loads(i)%difference
            end do
         end associate
      end do
   end subroutine merge_patterns

   !> The prescribed displacements of the patterns, each times its factor, added to those of `stepped`
   !> (a linear static step: the settlements of every step so far, with those given before the steps).
   pure subroutine merge_prescribed(patterns, stepped, status, bytes)
      type(load_pattern_t), intent(in) :: patterns(:)
      type(model_t), intent(inout) :: stepped
      integer, intent(out) :: status
      real(dp), intent(inout) :: bytes
      integer :: j
      status = 0
      do j = 1, size(patterns)
         if (.not. allocated(patterns(j)%prescribed)) cycle
         if (.not. allocated(stepped%prescribed)) then
            bytes = 8.0_dp*dofs_per_node*stepped%n_nodes
            allocate (stepped%prescribed(dofs_per_node, stepped%n_nodes), stat=status)
            if (status /= 0) return
            stepped%prescribed = 0.0_dp
         end if
         stepped%prescribed = stepped%prescribed + patterns(j)%factor*patterns(j)%prescribed
      end do
   end subroutine merge_prescribed

   !> The model prescribes the displacement of some held DOF: its own pattern, a held one, or a step's.
   pure logical function has_prescribed(model)
      type(model_t), intent(in) :: model
      integer :: j
      has_prescribed = allocated(model%prescribed)
      if (allocated(model%held)) then
         do j = 1, size(model%held)
            has_prescribed = has_prescribed .or. allocated(model%held(j)%prescribed)
         end do
      end if
      if (allocated(model%steps)) then
         do j = 1, size(model%steps)
            has_prescribed = has_prescribed .or. allocated(model%steps(j)%loads%prescribed)
         end do
      end if
   end function has_prescribed

   !> The displacements (dofs_per_node, n_nodes) of the held DOFs at load factor λ: λ ū of the model's
   !> own pattern plus λ_j ū_j of each held one (zero where nothing is prescribed). The path following
   !> solves for the free DOFs; these are the others' (docs/theory.md §2.9).
   pure function prescribed_at(model, lambda) result(field)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: lambda
      real(dp) :: field(dofs_per_node, model%n_nodes)
      integer :: j
      field = 0.0_dp
      if (allocated(model%prescribed)) field = lambda*model%prescribed
      if (.not. allocated(model%held)) return
      do j = 1, size(model%held)
         if (allocated(model%held(j)%prescribed)) field = field + model%held(j)%factor*model%held(j)%prescribed
      end do
   end function prescribed_at

end module uniarc_model_steps
