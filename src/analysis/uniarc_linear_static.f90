!> Linear static analysis: K u = λ R_r with λ = 1 on the initial geometry.
module uniarc_linear_static
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, add_context, make_error, error_input
   use uniarc_model, only: model_t, dofs_per_node
   use uniarc_dof_map, only: dof_map_t, build_dof_map
   use uniarc_band, only: band_matrix_t, band_allocate, band_factorize, band_solve, band_inertia
   use uniarc_assembly, only: assemble_linear_stiffness, assemble_reference_load, gather_nodal
   implicit none
   private
   public :: solve_linear_static

contains

   !> Solve the linear problem; return nodal displacements (3, n_nodes) and the number of negative
   !> pivots of K (non-zero means the supports leave a mechanism or K is not positive definite).
   subroutine solve_linear_static(model, displacement, negative_pivots, error)
      type(model_t), intent(in) :: model
      real(dp), allocatable, intent(out) :: displacement(:, :)
      integer, intent(out) :: negative_pivots
      type(error_t), allocatable, intent(out) :: error
      type(dof_map_t) :: map
      type(band_matrix_t) :: stiffness
      real(dp), allocatable :: rhs(:, :)
      logical :: singular
      ! K here is the structure's alone: with a contact medium it would answer for the structure
      ! without it. Until the static contact LCP exists, the deck is refused (input: exit 2).
      if (allocated(model%contacts)) then
         if (size(model%contacts) > 0) then
            call make_error(error, 'linear static analysis: the model has a contact medium (*FOUNDATION, '// &
                            '*SPRING or *OBSTACLE), which *STATIC (the default analysis) does not include yet; '// &
                            'trace it with *PATH (CONTROL=LOAD up to lambda_max = 1 gives the geometrically nonlinear answer)', &
                            error_input)
            return
         end if
      end if
      call build_dof_map(model, map)
      call band_allocate(stiffness, map%n_equations, map%half_bandwidth, map%half_bandwidth, error)
      if (allocated(error)) return
      call assemble_linear_stiffness(model, map, stiffness)
      call band_inertia(stiffness, negative_pivots, singular)
      allocate (rhs(map%n_equations, 1))
      call assemble_reference_load(model, map, .true., rhs(:, 1))
      call band_factorize(stiffness, error)
      if (allocated(error)) then
         call add_context(error, 'linear static analysis (are the supports enough to hold the structure?)')
         return
      end if
      call band_solve(stiffness, rhs, error)
      if (allocated(error)) return
      allocate (displacement(dofs_per_node, model%n_nodes))
      call gather_nodal(map, rhs(:, 1), displacement)
   end subroutine solve_linear_static

end module uniarc_linear_static
