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
   use uniarc_model, only: model_t, load_pattern_t, analysis_linear
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
   !> A model without steps is returned as it is (k = 1).
   function step_model(model, k, end_lambda) result(stepped)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      real(dp), intent(in) :: end_lambda(:)
      type(model_t) :: stepped
      type(load_pattern_t), allocatable :: patterns(:)
      integer :: j
      stepped = model
      if (.not. allocated(model%steps)) return
      stepped%analysis = model%steps(k)%analysis
      if (model%steps(k)%analysis%kind == analysis_linear) then
         allocate (patterns(k))
         do j = 1, k - 1
            patterns(j) = model%steps(j)%loads
            patterns(j)%factor = end_lambda(j)
         end do
         patterns(k) = model%steps(k)%loads
         patterns(k)%factor = 1.0_dp
         call merge_patterns(patterns, stepped)
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

   !> The loads of `patterns`, each times its factor, as the reference loads of `stepped`: nodal loads
   !> summed, distributed loads and temperature changes listed one after another (the assembly sums
   !> the records of one element).
   subroutine merge_patterns(patterns, stepped)
      type(load_pattern_t), intent(in) :: patterns(:)
      type(model_t), intent(inout) :: stepped
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
      allocate (stepped%distributed_loads(n_dloads), stepped%thermal_loads(n_thermal))
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

end module uniarc_model_steps
