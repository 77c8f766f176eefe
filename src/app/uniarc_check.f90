!> What is checked of a model before it is analysed, and the summary of `uniarc --check DECK`
!> (docs/contracts.md, "Checking a deck", "Memory"): the memory the analysis needs against the memory
!> available, and element stiffnesses that double precision can assemble. A model that fails either is
!> refused as bad input (exit code 2) before any result file or large array is made.
module uniarc_check
   use, intrinsic :: iso_fortran_env, only: output_unit
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_model, only: model_t, analysis_linear, control_load, control_displacement, dofs_per_node, &
                           element_kind_of, element_truss, element_length, load_pressure, foundation_pasternak, &
                           element_timoshenko, contact_candidate_t
   use uniarc_contact_law, only: chain_nodes
   use uniarc_dof_map, only: dof_map_t, build_dof_map, candidate_held_normal
   use uniarc_element, only: element_stiffness_scale, element_coordinates
   use uniarc_memory, only: model_memory_bytes, memory_shortfall, available_memory, memory_text, allocation_failure
   use uniarc_model, only: control_arclength, thermal_load_t, analysis_options_t, track_t
   use uniarc_builder_loads, only: thermal_excess
   use uniarc_band, only: band_matrix_t, band_factorize, band_solve
   use uniarc_assembly, only: assemble_reference_load
   use uniarc_path_mechanism, only: closed_linear_stiffness, find_mechanism
   implicit none
   private
   public :: model_memory_estimate, check_model, check_element_scales, print_model_summary, stiffness_bound
   public :: nearly_mechanism_warning, check_bed_ends, held_contact_warning, analysis_summary

   !> A linear response to the loads that moves a node by more than this many times the model's size
   !> is reported as a nearly singular model (nearly_mechanism_warning).
   real(dp), parameter :: response_bound = 1.0e3_dp

   !> The largest element stiffness times coordinate size (force) the analysis accepts: the round-off
   !> floor and the force scale of the convergence test sum squares of such products
   !> (uniarc_equilibrium), which must stay below the largest double, 1.8e308; 1e150 leaves a margin of
   !> 1e8 for the sums over elements.
   real(dp), parameter :: stiffness_bound = 1.0e150_dp
   !> The largest ratio of an element's axial to its bending stiffness, either way, the analysis
   !> accepts: 1e30 is the square of the 1e15 beyond which double precision (16 digits) loses the
   !> softer stiffness in the sums entirely, a margin for slender models (EA L²/EI of 1e8..1e12).
   real(dp), parameter :: ratio_bound = 1.0e30_dp
   !> Coordinates and element lengths the analysis accepts: lengths from 1e-100, coordinates within
   !> ±1e50. Then the products of lengths with stiffnesses from 1e-100 to 1e100 (EA, EI, a bed's k;
   !> uniarc_deck_mesh, uniarc_deck_contact) — k·L, EA/L — stay within 1e±200, and the moments of loads
   !> up to 1e100 per length over a span (q·L², the loads' work q·L³ in the arc-length constraint) stay
   !> below 1e250: coordinates of 1e100 (L = 1e100 in 41 decks of the extreme-parameter sweep) made
   !> those infinite, and the stiffness matrix's pivots NaN.
   real(dp), parameter :: coordinate_bound = 1.0e50_dp, length_floor = 1.0e-100_dp

contains

   !> Estimated peak memory (bytes) of the analysis of `model` (uniarc_memory: from the counts of
   !> nodes, elements, contact candidates, and the equations and half bandwidth of its DOF numbering).
   function model_memory_estimate(model, map) result(bytes)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp) :: bytes
      integer :: n_candidates
      n_candidates = 0
      if (allocated(model%contacts)) n_candidates = size(model%contacts)
      bytes = model_memory_bytes(real(model%n_nodes, dp), real(model%n_elements, dp), real(map%n_equations, dp), &
                                 real(map%half_bandwidth, dp), real(n_candidates, dp))
   end function model_memory_estimate

   !> The geometry and stiffness checks of a model, before its DOF numbering (which already forms
   !> stiffness scales): every coordinate within ±`coordinate_bound`, every element at least
   !> `length_floor` long, and every element's stiffness scale k_e (EA/L + 12 EI/L³, uniarc_element)
   !> times its size |x| (the larger of its coordinates and its length) at most `stiffness_bound`. k_e
   !> is compared through its logarithm, so that the check itself cannot overflow (EI = 1e100 over
   !> L = 1e-100 would). Errors (error_input, exit code 2): the first element that fails, named with
   !> its section, EA, EI and L.
   subroutine check_element_scales(model, error)
      type(model_t), intent(in) :: model
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: x(2, 2), length, size_x, log_k, t_axial, t_bending
      integer :: e, label
      character(len=:), allocatable :: what
      do e = 1, model%n_elements
         x = element_coordinates(model, e)
         what = ''
         if (.not. (maxval(abs(x)) <= coordinate_bound)) then
            what = 'a coordinate beyond 1e50 in magnitude'
         else
            length = norm2(x(:, 2) - x(:, 1))
            size_x = max(maxval(abs(x)), length)
            associate (section => model%sections(model%element_section(e)))
               if (.not. (length >= length_floor)) then
                  what = 'a length below 1e-100'
               else
                  t_axial = -huge(1.0_dp)
                  t_bending = -huge(1.0_dp)
                  if (section%ea > 0.0_dp) t_axial = log(section%ea) - log(length)
                  if (section%ei > 0.0_dp .and. element_kind_of(model, e) /= element_truss) &
                     t_bending = log(12.0_dp*section%ei) - 3.0_dp*log(length)
                  ! log(exp(a) + exp(b)) without forming either
                  log_k = max(t_axial, t_bending) + log(1.0_dp + exp(-abs(t_axial - t_bending)))
                  if (log_k + log(size_x) > log(stiffness_bound)) &
                     what = 'a stiffness EA/L + 12 EI/L^3 that times its size (coordinates, length) exceeds 1e150'
                  ! The ratio of its axial to its bending stiffness, (EA/L)/(12 EI/L^3): beyond
                  ! `ratio_bound` either way the softer one lies below the round-off of the stiffer in
                  ! every sum of the equations (double precision keeps 16 digits), the Newton iterates'
                  ! displacements along it are round-off amplified by the ratio, and their squares
                  ! overflowed (EI = 1e100 or EA = 1e-100 on beams of EA/L ~ 1e4: SIGFPE in Debug).
                  if (len(what) == 0 .and. t_axial > -huge(1.0_dp) .and. t_bending > -huge(1.0_dp)) then
                     if (abs(t_axial - t_bending) > log(ratio_bound)) &
                        what = 'a ratio of its axial to its bending stiffness, EA L^2/(12 EI), beyond 1e30 '// &
                               'or below 1e-30'
                  end if
               end if
            end associate
         end if
         if (len(what) == 0) cycle
         label = e
         if (allocated(model%element_label)) label = model%element_label(e)
         associate (section => model%sections(model%element_section(e)))
            call make_error(error, model%deck_path//': element '//integer_to_string(label)//' (section '// &
                            section%name//', EA = '//real_to_string(section%ea)//', EI = '// &
                            real_to_string(section%ei)//') has '//what//', beyond which the equations '// &
                            'overflow double precision; rescale the units of the deck', error_input)
         end associate
         return
      end do
      if (allocated(model%thermal_loads)) &
         call check_thermal_scales(model, model%thermal_loads, reachable_lambda(model%analysis), error)
      if (allocated(error) .or. .not. allocated(model%steps)) return
      do e = 1, size(model%steps)
         if (allocated(model%steps(e)%loads%thermal_loads)) &
            call check_thermal_scales(model, model%steps(e)%loads%thermal_loads, &
                                      reachable_lambda(model%steps(e)%analysis), error)
         if (allocated(error)) return
      end do
   end subroutine check_element_scales

   !> The largest |λ| an analysis scales its load pattern by that is known before it runs: 1 for the
   !> linear static analysis, `lambda_max` for a path that has one (its last step lands on it), 1 for
   !> a path without (it may go farther: its thermal deformation is then judged at the reference load
   !> only, docs/input.md *TEMPERATURE).
   pure real(dp) function reachable_lambda(options) result(lambda)
      type(analysis_options_t), intent(in) :: options
      lambda = 1.0_dp
      if (options%kind /= analysis_linear .and. options%lambda_max < huge(1.0_dp)) &
         lambda = max(1.0_dp, abs(options%lambda_max))
   end function reachable_lambda

   !> The free thermal deformations of the elements (uniarc_builder_loads, thermal_excess: the axial
   !> strain α ΔT at most 1 in magnitude, the free rotation α ΔT_d L/h at most π). A deck's *TEMPERATURE
   !> lines are checked as they are read (at their line and column); this guards a model built without
   !> a deck. Errors (error_input, exit code 2): the first element that fails, named with its values.
   subroutine check_thermal_scales(model, loads, lambda, error)
      type(model_t), intent(in) :: model
      type(thermal_load_t), intent(in) :: loads(:)
      real(dp), intent(in) :: lambda   !< the largest load factor the temperatures are scaled by (>= 1)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: x(2, 2)
      integer :: i, label
      character(len=:), allocatable :: what
      logical :: axial
      do i = 1, size(loads)
         associate (load => loads(i))
            x = element_coordinates(model, load%element)
            call thermal_excess(load%alpha, lambda*load%delta_t, lambda*load%difference, load%depth, &
                                norm2(x(:, 2) - x(:, 1)), what, axial)
            if (len(what) == 0) cycle
            label = load%element
            if (allocated(model%element_label)) label = model%element_label(load%element)
            if (lambda > 1.0_dp) what = what//' at the path''s lambda_max = '//real_to_string(lambda)// &
                                        ' (dT and dT_d scaled by it)'
            call make_error(error, model%deck_path//': element '//integer_to_string(label)//' has '//what// &
                            ' under *TEMPERATURE: its thermal deformation is beyond the element''s (a small '// &
                            'strain, a rotation against its chord) and overflows the equations; check the '// &
                            'units of alpha, dT, dT_d and h', error_input)
            return
         end associate
      end do
   end subroutine check_thermal_scales

   !> A Pasternak bed that goes on beyond an end of its set (`continues`, an end spring √(K G_p),
   !> docs/theory.md §3.10) where that end node is held as at a symmetry plane across the set: its
   !> rotation and its displacement along the set's tangent held, its displacement across free (XSYMM
   !> on a set along x, YSYMM on one along y). At a symmetry plane the bed's surface has w_b' = 0, no
   !> end spring (CONTINUES= naming the other end only); with the spring the results are those of a bed
   !> going on past the plane, silently wrong (a half infinite beam gave 0.63 of the whole beam's
   !> deflection). Errors (error_input, exit code 2): the first such foundation and end. An end held
   !> otherwise (pinned, clamped, free) is not judged: the bed may well go on there.
   subroutine check_bed_ends(model, error)
      type(model_t), intent(in) :: model
      type(error_t), allocatable, intent(out) :: error
      integer, allocatable :: nodes(:)
      integer :: f, end, node, neighbour, along, across, status
      real(dp) :: tangent(2)
      character(len=*), parameter :: end_name(2) = ['start', 'end  '], other(2) = ['END  ', 'START']
      if (.not. allocated(model%foundations)) return
      do f = 1, size(model%foundations)
         associate (bed => model%foundations(f))
            if (bed%law /= foundation_pasternak .or. .not. bed%shear_modulus > 0.0_dp) cycle
            call chain_nodes(model%n_nodes, model%connectivity, bed%elements, nodes, status)
            call allocation_failure(status, 'the nodes of foundation '''//bed%name//'''', 16.0_dp*model%n_nodes, &
                                    error_input, error)
            if (allocated(error)) return
            if (size(nodes) < 2) cycle
            do end = 1, 2
               if (.not. bed%continues(end)) cycle
               node = nodes(merge(1, size(nodes), end == 1))
               neighbour = nodes(merge(2, size(nodes) - 1, end == 1))
               tangent = model%coordinates(:, neighbour) - model%coordinates(:, node)
               tangent = tangent/norm2(tangent)
               ! a symmetry plane across a set running along x (XSYMM) or along y (YSYMM); the first
               ! element's chord on a curved set turns by half the element's angle from the tangent
               along = merge(1, 2, abs(tangent(1)) >= abs(tangent(2)))
               across = 3 - along
               if (.not. (model%fixed(3, node) .and. model%fixed(along, node) .and. .not. model%fixed(across, node))) cycle
               call make_error(error, model%deck_path//': foundation '''//bed%name//''' (TYPE=PASTERNAK) goes '// &
                               'on beyond the '//trim(end_name(end))//' of its set, node '// &
                               integer_to_string(model%node_label(node))//', held there as at a symmetry plane '// &
                               '(rotation and displacement along the set); expected CONTINUES='// &
                               trim(other(end))//' or NONE (no end spring at a symmetry plane, where w_b'' = 0)', error_input)
               return
            end do
         end associate
      end do
   end subroutine check_bed_ends

   !> The memory check of a model before its analysis (after its DOF numbering). Errors (error_input,
   !> exit code 2): the model has no free degree of freedom (every displacement and rotation held:
   !> there is no equation to solve, and the band solvers need at least one); the estimated memory
   !> exceeds what is available (the message gives both and what they count).
   subroutine check_model(model, map, error)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: shortfall
      if (map%n_equations == 0) then
         call make_error(error, model%deck_path//': the model has no free degree of freedom: every '// &
                         'displacement and rotation of its '//integer_to_string(model%n_nodes)// &
                         ' nodes is held (*BOUNDARY), so there is nothing to analyse; free at least one', &
                         error_input)
         return
      end if
      call memory_shortfall(model_memory_estimate(model, map), shortfall)
      if (allocated(shortfall)) then
         call make_error(error, model%deck_path//': the model does not fit in memory: its analysis ('// &
                         counts_text(model, map)//') would '//shortfall, error_input)
      end if
   end subroutine check_model

   !> Rigid contact candidates left out of the contact because their gap moves only along held DOFs
   !> (uniarc_dof_map: candidate_held_normal; docs/theory.md §3.1) on a node with a free translation —
   !> a rigid plane under a roller's held UY: `message` allocated, naming the nodes (labels, the first
   !> ten) and the obstacle of the first; the caller prints it and the analysis goes on. Such a
   !> candidate's reaction would act only on the support, which carries it. Candidates on nodes with
   !> both translations held are inert without a word, as they have always been.
   subroutine held_contact_warning(model, message)
      type(model_t), intent(in) :: model
      character(len=:), allocatable, intent(out) :: message
      character(len=:), allocatable :: nodes, obstacle
      integer :: c, shown, total, label
      if (.not. allocated(model%contacts)) return
      nodes = ''
      obstacle = ''
      shown = 0
      total = 0
      do c = 1, size(model%contacts)
         associate (candidate => model%contacts(c))
            if (model%fixed(1, candidate%node) .and. model%fixed(2, candidate%node)) cycle
            if (.not. candidate_held_normal(model, c)) cycle
            total = total + 1
            if (total == 1 .and. allocated(model%contact_groups) .and. candidate%group > 0) then
               if (candidate%group <= size(model%contact_groups)) then
                  if (allocated(model%contact_groups(candidate%group)%name)) &
                     obstacle = ' (of '//model%contact_groups(candidate%group)%name//')'
               end if
            end if
            if (shown == 10) cycle
            label = candidate%node
            if (allocated(model%node_label)) label = model%node_label(candidate%node)
            if (shown > 0) nodes = nodes//', '
            nodes = nodes//integer_to_string(label)
            shown = shown + 1
         end associate
      end do
      if (total == 0) return
      if (total > shown) nodes = nodes//' and '//integer_to_string(total - shown)//' more'
      message = 'the rigid contact at node '//nodes//obstacle//' is left out: the node can move only '// &
                'along the obstacle''s surface (its DOF along the normal is held by a support), so its gap '// &
                'never changes and the support carries what the contact would'
      if (total > 1) message = 'the rigid contacts at nodes '//message(len('the rigid contact at node ') + 1:)
      if (allocated(model%deck_path)) message = model%deck_path//': '//message
   end subroutine held_contact_warning

   !> A model held only by springs or contacts far softer than the structure (docs/contracts.md,
   !> "Nearly singular models"): not a mechanism — its stiffness is regular — but one whose rigid motion
   !> is nearly free, so that its displacements are that motion, beyond any structural meaning, and lose
   !> digits with the condition of the stiffness. Measured by the linear response u = K⁻¹R of the
   !> unloaded structure with every contact closed (closed_linear_stiffness) to the reference load R of
   !> the analysis — times the first increment of an arc-length or load-controlled *PATH, at λ = 1 for
   !> *STATIC — against the model's size (its largest extent in x or y): a node moving more than
   !> `response_bound` = 1000 times that size returns a warning (`message` allocated; the caller prints
   !> it and the analysis goes on). A deformation of a structure moves its nodes by at most about its
   !> size (a cantilever rolled into a ring, one length); only a rigid motion goes further, and one of a
   !> thousand sizes under the first increment is held by a stiffness ~1e-3 of what the load needs.
   !> Not measured: under displacement control (the step is a displacement), for decks with *STEP,
   !> when the stiffness is singular (a mechanism, which the analysis refuses) or the response is not
   !> finite (the analysis reports it).
   subroutine nearly_mechanism_warning(model, map, message)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      character(len=:), allocatable, intent(out) :: message
      type(band_matrix_t) :: stiffness
      type(error_t), allocatable :: failure
      real(dp), allocatable :: rhs(:, :)
      real(dp) :: size_model, scale, largest, ratio
      integer :: node, dof, worst_node, worst_dof, label, status
      if (map%n_equations == 0 .or. allocated(model%steps)) return
      if (model%analysis%kind == analysis_linear) then
         scale = 1.0_dp
      else if (model%analysis%control == control_arclength .or. model%analysis%control == control_load) then
         scale = abs(model%analysis%first_increment)
      else
         return
      end if
      size_model = max(maxval(model%coordinates(1, :)) - minval(model%coordinates(1, :)), &
                       maxval(model%coordinates(2, :)) - minval(model%coordinates(2, :)))
      if (.not. (size_model > 0.0_dp)) return
      call closed_linear_stiffness(model, map, stiffness, failure)
      if (allocated(failure)) return
      ! A mechanism is refused by the analysis with its own message.
      call find_mechanism(model, map, stiffness, failure)
      if (allocated(failure)) return
      ! Its load vector allocated with stat=: refused, no warning is measured (the analysis meets the
      ! shortage with its own message; docs/contracts.md, "Memory").
      allocate (rhs(map%n_equations, 1), stat=status)
      if (status /= 0) return
      call assemble_reference_load(model, map, .true., rhs(:, 1))
      call band_factorize(stiffness, failure)
      if (allocated(failure)) return
      call band_solve(stiffness, rhs, failure)
      if (allocated(failure)) return
      largest = 0.0_dp
      worst_node = 0
      worst_dof = 0
      do node = 1, model%n_nodes
         do dof = 1, 2
            if (map%equation(dof, node) == 0) cycle
            if (.not. (abs(scale*rhs(map%equation(dof, node), 1)) <= largest)) then
               largest = abs(scale*rhs(map%equation(dof, node), 1))
               worst_node = node
               worst_dof = dof
            end if
         end do
      end do
      ! A response that is not finite (loads that overflow the stiffness) is the analysis's to report.
      if (worst_node == 0 .or. .not. all(abs(rhs) <= huge(1.0_dp))) return
      ratio = largest/size_model
      if (.not. (ratio > response_bound)) return
      label = worst_node
      if (allocated(model%node_label)) label = model%node_label(worst_node)
      message = 'the model is nearly a mechanism: its linear response to the loads'// &
                trim(merge(' (at the first increment)', '                         ', &
                           model%analysis%kind /= analysis_linear))// &
                ' moves node '//integer_to_string(label)//' by '//trim(adjustl(real_to_string(largest, '(es10.3)')))// &
                ' in '//trim(merge('UX', 'UY', worst_dof == 1))//', '// &
                trim(adjustl(real_to_string(ratio, '(es10.3)')))//' times the model''s size '// &
                trim(adjustl(real_to_string(size_model, '(es10.3)')))//': a rigid motion is held only by '// &
                'springs or contacts far softer than the structure, and the displacements are that motion '// &
                '(with fewer significant digits as the stiffness is nearer singular); check the supports '// &
                'and the springs'' stiffnesses'
      if (allocated(model%deck_path)) message = model%deck_path//': '//message
   end subroutine nearly_mechanism_warning

   !> The summary of `uniarc --check` on stdout: counts, supports, loads and their totals, contact
   !> groups, the analysis and the memory estimate.
   subroutine print_model_summary(model, map)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      real(dp) :: total(dofs_per_node), distributed(2), available
      character(len=:), allocatable :: origin
      integer :: i, n_truss, held_nodes, held_dofs, loaded_nodes
      write (output_unit, '(a)') 'deck '//model%deck_path//': read and checked, not analysed'
      n_truss = 0
      do i = 1, model%n_elements
         if (element_kind_of(model, i) == element_truss) n_truss = n_truss + 1
      end do
      call line('nodes', integer_to_string(model%n_nodes))
      call line('elements', integer_to_string(model%n_elements)//' ('//integer_to_string(model%n_elements - n_truss)// &
                ' beam-columns, '//integer_to_string(n_truss)//' trusses)'//timoshenko_text())
      if (allocated(model%end_joints)) then
         if (any(model%end_joints%hinge .or. model%end_joints%compliance > 0.0_dp)) &
            call line('end releases', counted(count(model%end_joints%hinge), 'hinge')//', '// &
                      counted(count(.not. model%end_joints%hinge .and. model%end_joints%compliance > 0.0_dp), &
                              'rotational spring')//' (*RELEASE)')
      end if
      call line('node sets', integer_to_string(count_sets_nodes())//';  element sets '// &
                integer_to_string(count_sets_elements()))
      if (allocated(model%sections)) then
         call line('sections', integer_to_string(size(model%sections)))
         do i = 1, size(model%sections)
            if (model%sections(i)%gas > 0.0_dp) then
               call line('', model%sections(i)%name//': EA = '//real_to_string(model%sections(i)%ea)//', EI = '// &
                         real_to_string(model%sections(i)%ei)//', GAs = '//real_to_string(model%sections(i)%gas))
            else
               call line('', model%sections(i)%name//': EA = '//real_to_string(model%sections(i)%ea)//', EI = '// &
                         real_to_string(model%sections(i)%ei))
            end if
         end do
      end if
      held_nodes = 0
      held_dofs = 0
      if (allocated(model%fixed)) then
         held_nodes = count(any(model%fixed, dim=1))
         held_dofs = count(model%fixed)
      end if
      call line('supports', counted(held_nodes, 'node')//', '//counted(held_dofs, 'DOF')//' held')
      if (allocated(model%prescribed)) call line('prescribed', 'displacements of '// &
                                                 counted(count(model%prescribed /= 0.0_dp), 'held DOF')// &
                                                 ' (support settlements, times lambda)')
      total = 0.0_dp
      loaded_nodes = 0
      if (allocated(model%nodal_load)) then
         total = sum(model%nodal_load, dim=2)
         loaded_nodes = count(any(model%nodal_load /= 0.0_dp, dim=1))
      end if
      call line('nodal loads', 'on '//counted(loaded_nodes, 'node')//'; total FX = '//real_to_string(total(1))// &
                ', FY = '//real_to_string(total(2))//', MZ = '//real_to_string(total(3))//' (times lambda)')
      distributed = 0.0_dp
      if (allocated(model%distributed_loads)) then
         do i = 1, size(model%distributed_loads)
            associate (load => model%distributed_loads(i))
               if (load%kind /= load_pressure) distributed = distributed + [load%qx, load%qy]*element_length(model, load%element)
            end associate
         end do
         call line('distributed', integer_to_string(size(model%distributed_loads))//' element loads; total FX = '// &
                   real_to_string(distributed(1))//', FY = '//real_to_string(distributed(2))// &
                   ' (fixed-direction; pressures act along the normals)')
      end if
      if (allocated(model%contact_groups)) then
         ! a foundation's tangential springs (KT=) are candidates of its group but not contacts
         ! (docs/input.md *FOUNDATION): counted apart, with the law they act by
         call line('contact groups', integer_to_string(size(model%contact_groups))//', '// &
                   counted(count(.not. model%contacts%tangential), 'candidate')//tangential_text(model%contacts))
         do i = 1, size(model%contact_groups)
            call line('', model%contact_groups(i)%name//': '// &
                      counted(count(.not. model%contacts(model%contact_groups(i)%candidates)%tangential), &
                              'candidate')//tangential_text(model%contacts(model%contact_groups(i)%candidates)))
         end do
      else
         call line('contact groups', '0')
      end if
      if (allocated(model%tracks)) then
         call line('tracks', integer_to_string(size(model%tracks)))
      end if
      if (allocated(model%steps)) then
         call line('analysis', 'in '//integer_to_string(size(model%steps))//' analysis steps (below)')
      else
         call line('analysis', analysis_summary(model%analysis, model%tracks))
      end if
      call line('equations', integer_to_string(map%n_equations)//bed_text(map)//', half bandwidth '// &
                integer_to_string(map%half_bandwidth))
      call available_memory(available, origin)
      if (available >= 0.0_dp) then
         call line('memory', 'about '//memory_text(model_memory_estimate(model, map))//' estimated; '// &
                   memory_text(available)//' available ('//origin//')')
      else
         call line('memory', 'about '//memory_text(model_memory_estimate(model, map))//' estimated')
      end if
   contains
      !> ", N Timoshenko" when some of the beam-columns are shear-deformable (TYPE=TIMOSHENKO), else nothing.
      function timoshenko_text() result(text)
         character(len=:), allocatable :: text
         integer :: e, n_timoshenko
         n_timoshenko = 0
         do e = 1, model%n_elements
            if (element_kind_of(model, e) == element_timoshenko) n_timoshenko = n_timoshenko + 1
         end do
         text = ''
         if (n_timoshenko > 0) text = ', '//integer_to_string(n_timoshenko)//' of them Timoshenko (shear-deformable)'
      end function timoshenko_text
      subroutine line(label, text)
         character(len=*), intent(in) :: label, text
         character(len=16) :: padded
         padded = label
         write (output_unit, '(2x,a,a)') padded, text
      end subroutine line
      integer function count_sets_nodes()
         count_sets_nodes = 0
         if (allocated(model%node_sets)) count_sets_nodes = size(model%node_sets)
      end function count_sets_nodes
      integer function count_sets_elements()
         count_sets_elements = 0
         if (allocated(model%element_sets)) count_sets_elements = size(model%element_sets)
      end function count_sets_elements
   end subroutine print_model_summary

   !> The analysis options `analysis` in words, for the --check summary: its kind, control, first
   !> increment and stop rules (`tracks`: the model's, for the name of a stop track), e.g.
   !> 'path, arc length; first increment 0.1; stops at 200 steps, |lambda| >= 1'.
   pure function analysis_summary(analysis, tracks) result(text)
      type(analysis_options_t), intent(in) :: analysis
      type(track_t), allocatable, intent(in) :: tracks(:)   !< may be unallocated (no *TRACK)
      character(len=:), allocatable :: text
      if (analysis%kind == analysis_linear) then
         text = 'linear static (one load case, lambda = 1)'
         return
      end if
      select case (analysis%control)
      case (control_load)
         text = 'path, load control'
      case (control_displacement)
         text = 'path, displacement control'
      case default
         text = 'path, arc length'
      end select
      text = text//'; first increment '//real_to_string(analysis%first_increment)//'; stops at '// &
             integer_to_string(analysis%max_steps)//' steps'
      if (analysis%lambda_max < huge(1.0_dp)) text = text//', |lambda| >= '//real_to_string(analysis%lambda_max)
      if (.not. allocated(tracks)) return
      if (analysis%stop_track > 0 .and. analysis%stop_track <= size(tracks)) &
         text = text//', |'//tracks(analysis%stop_track)%name//'| >= '//real_to_string(analysis%stop_value)
   end function analysis_summary

   !> "1 node", "2 nodes": a count and its noun.
   pure function counted(n, noun) result(text)
      integer, intent(in) :: n
      character(len=*), intent(in) :: noun
      character(len=:), allocatable :: text
      text = integer_to_string(n)//' '//noun
      if (n /= 1) text = text//'s'
   end function counted

   !> ", with N tangential springs (in contact|bonded)" for the candidates `contacts` that have
   !> tangential springs (*FOUNDATION, KT=), else nothing.
   pure function tangential_text(contacts) result(text)
      type(contact_candidate_t), intent(in) :: contacts(:)
      character(len=:), allocatable :: text
      integer :: n_contact, n_bonded
      n_contact = count(contacts%tangential .and. contacts%partner > 0)
      n_bonded = count(contacts%tangential .and. contacts%partner == 0)
      text = ''
      if (n_contact > 0) text = text//', with '//counted(n_contact, 'tangential spring')//' acting in contact'
      if (n_bonded > 0) text = text//', with '//counted(n_bonded, 'tangential spring')//' bonded'
   end function tangential_text

   !> "N nodes, M elements, K contact candidates; E equations, half bandwidth B".
   function counts_text(model, map) result(text)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      character(len=:), allocatable :: text
      integer :: n_candidates
      n_candidates = 0
      if (allocated(model%contacts)) n_candidates = size(model%contacts)
      text = integer_to_string(model%n_nodes)//' nodes, '//integer_to_string(model%n_elements)//' elements, '// &
             integer_to_string(n_candidates)//' contact candidates; '//integer_to_string(map%n_equations)// &
             ' equations'//bed_text(map)//', half bandwidth '//integer_to_string(map%half_bandwidth)
   end function counts_text

   !> " (N of them the Pasternak beds' deflections)" when a bed has unknowns of its own (they
   !> are in the equations and the memory estimate), else nothing.
   pure function bed_text(map) result(text)
      type(dof_map_t), intent(in) :: map
      character(len=:), allocatable :: text
      integer :: n_bed
      text = ''
      n_bed = 0
      if (allocated(map%bed_equation)) n_bed = count(map%bed_equation > 0)
      if (n_bed > 0) text = ' ('//integer_to_string(n_bed)//' of them the Pasternak beds'' deflections)'
   end function bed_text

end module uniarc_check
