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
module uniarc_model_steps
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, analysis_step_t, analysis_linear
   implicit none
   private
   public :: n_analysis_steps, step_model

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
   !> A model without steps is returned as it is (k = 1). The stepped model has no steps of its own
   !> (`stepped%steps` unallocated): they are each a load pattern of (3, n_nodes) reals, and a copy of
   !> all of them for every step made a deck of many steps take O(steps² × nodes) time and twice their
   !> memory (10 000 nodes, 600 static steps: 580 MB, docs/contracts.md "Memory"). `model%steps` is
   !> moved out for the copy and back: `model` is unchanged on return.
   function step_model(model, k, end_lambda) result(stepped)
      type(model_t), intent(inout) :: model
      integer, intent(in) :: k
      real(dp), intent(in) :: end_lambda(:)
      type(model_t) :: stepped
      type(analysis_step_t), allocatable :: steps(:)
      real(dp), allocatable :: factors(:)
      integer :: j
      if (.not. allocated(model%steps)) then
         stepped = model
         return
      end if
      call move_alloc(model%steps, steps)
      stepped = model
      call move_alloc(steps, model%steps)
      stepped%analysis = model%steps(k)%analysis
      if (model%steps(k)%analysis%kind == analysis_linear) then
         allocate (factors(k))
         factors(1:k - 1) = end_lambda(1:k - 1)
         factors(k) = 1.0_dp
         call merge_patterns(model%steps(1:k), factors, stepped)
         allocate (stepped%held(0))
      else
         stepped%nodal_load = model%steps(k)%loads%nodal_load
         stepped%distributed_loads = model%steps(k)%loads%distributed_loads
         stepped%thermal_loads = model%steps(k)%loads%thermal_loads
         allocate (stepped%held(k - 1))
         do j = 1, k - 1
            stepped%held(j) = model%steps(j)%loads
            stepped%held(j)%factor = end_lambda(j)
         end do
      end if
   end function step_model

   !> The loads of `steps`, each times its factor (`factors`, one per step), as the reference loads of
   !> `stepped`: nodal loads summed, distributed loads and temperature changes listed one after another
   !> (the assembly sums the records of one element). The patterns are read where they are, not copied.
   subroutine merge_patterns(steps, factors, stepped)
      type(analysis_step_t), intent(in) :: steps(:)
      real(dp), intent(in) :: factors(:)
      type(model_t), intent(inout) :: stepped
      integer :: j, i, n_dloads, n_thermal
      stepped%nodal_load = 0.0_dp*stepped%nodal_load
      n_dloads = 0
      n_thermal = 0
      do j = 1, size(steps)
         stepped%nodal_load = stepped%nodal_load + factors(j)*steps(j)%loads%nodal_load
         n_dloads = n_dloads + size(steps(j)%loads%distributed_loads)
         n_thermal = n_thermal + size(steps(j)%loads%thermal_loads)
      end do
      if (allocated(stepped%distributed_loads)) deallocate (stepped%distributed_loads)
      if (allocated(stepped%thermal_loads)) deallocate (stepped%thermal_loads)
      allocate (stepped%distributed_loads(n_dloads), stepped%thermal_loads(n_thermal))
      n_dloads = 0
      n_thermal = 0
      do j = 1, size(steps)
         associate (p => steps(j)%loads, factor => factors(j))
            do i = 1, size(p%distributed_loads)
               n_dloads = n_dloads + 1
               stepped%distributed_loads(n_dloads) = p%distributed_loads(i)
               stepped%distributed_loads(n_dloads)%qx = factor*p%distributed_loads(i)%qx
               stepped%distributed_loads(n_dloads)%qy = factor*p%distributed_loads(i)%qy
               stepped%distributed_loads(n_dloads)%pressure = factor*p%distributed_loads(i)%pressure
            end do
            do i = 1, size(p%thermal_loads)
               n_thermal = n_thermal + 1
               stepped%thermal_loads(n_thermal) = p%thermal_loads(i)
               stepped%thermal_loads(n_thermal)%delta_t = factor*p%thermal_loads(i)%delta_t
               stepped%thermal_loads(n_thermal)%difference = factor*p%thermal_loads(i)%difference
            end do
         end associate
      end do
   end subroutine merge_patterns

end module uniarc_model_steps
