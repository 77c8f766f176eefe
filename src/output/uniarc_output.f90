!> Result files of docs/contracts.md: the path file `STEM.path`, critical points `STEM.crit`, shapes
!> `STEM.shape`, the surfaces of the contact media `STEM.surface` (when the model has any), the
!> internal forces `STEM.forces` and contact pressures `STEM.contact` (`*OUTPUT, FORCES`; their
!> values are uniarc_output_forces'), and with `--csv` the same tables as comma-separated
!> `STEM.path.csv`, ... for spreadsheets.
!>
!> Every table starts with one line of column names (no comment sign: numpy's genfromtxt(names=True),
!> pandas' read_csv and gnuplot's columnheader take it as it is), then the provenance of the run as
!> `#` comment lines (uniarc_provenance), which those readers skip, then the rows. Counts are written
!> as integers, every other number in one ES format.
!>
!> The files are written in the run's work directory and moved to their final names by the run's
!> commit (uniarc_result_directory), so a crash never leaves a half file under a final name. Rows are
!> written whole and flushed, so an analysis that fails part-way keeps every converged step
!> (docs/contracts.md: exit code 1, complete rows only). Every write, flush and close is checked
!> (uniarc_text_file): a failure is returned as an error naming the file and the system's words.
module uniarc_output
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_model, only: model_t, tracked_values, gap_fixed_direction
   use uniarc_text_file, only: text_file_t, create_text_file, put_line, flush_text_file, close_text_file, &
                               discard_text_file
   use uniarc_result_directory, only: result_directory_t, work_path, final_path, add_result_file
   use uniarc_provenance, only: provenance_t, provenance_lines
   use uniarc_contact_summary, only: contact_summary_t
   use uniarc_model_steps, only: has_prescribed
   use uniarc_output_forces, only: element_end_forces, candidate_gaps, candidate_lengths, tangential_springs
   implicit none
   private
   public :: step_record_t, output_files_t, move_record
   public :: open_outputs, write_path_row, write_crit_row, write_shape, close_outputs, discard_outputs
   public :: path_header, format_number, nodal_reactions, surface_point
   public :: forces_due, write_forces, medium_name

   !> What a converged step reports (one row of the path file).
   type :: step_record_t
      integer :: step = 0
      real(dp) :: lambda = 0.0_dp
      real(dp), allocatable :: displacement(:, :)   !< (3, n_nodes) total nodal displacements
      real(dp), allocatable :: reactions(:)         !< (n_contacts) reaction of every contact candidate
      !> (n_contacts) the Pasternak beds' surface deflection under every candidate (0 for the others;
      !> unallocated: none), which the contact table's gap includes (the gap with the bed's surface)
      real(dp), allocatable :: bed_deflections(:)
      integer :: n_contact = 0            !< candidates in contact
      integer :: contact_regions = 0      !< number of contiguous contact regions
      real(dp) :: s_contact(2) = 0.0_dp   !< ends of the first contact region
      real(dp) :: reaction_max = 0.0_dp
      real(dp) :: reaction_sum = 0.0_dp
      real(dp) :: lcp_residual = 0.0_dp   !< complementarity residual, relative to the scale
      integer :: lcp_pivots = 0
      integer :: iterations = 0
      integer :: neg_pivots = 0
      integer :: analysis_step = 0        !< the analysis step (*STEP) of the row; written when the deck has steps
      !> the force of the prescribed displacements along their motion (uniarc_support_reactions,
      !> prescribed_force); written when the deck prescribes displacements
      real(dp) :: prescribed_force = 0.0_dp
      !> (n_groups) the contact columns of each contact group (uniarc_contact_summary, summarize_groups);
      !> written as the group's own path columns when the model has more than one group
      type(contact_summary_t), allocatable :: groups(:)
      !> (2, n_elements) committed plastic rotations of the joints with a moment limit (`*RELEASE, MY=`);
      !> unallocated without such joints
      real(dp), allocatable :: joint_plastic(:, :)
      !> plastic media (*FOUNDATION or *SPRING with QU=): the plastic slip of every candidate (length) and
      !> whether it is at its bearing limit, for STEM.contact (unallocated: none)
      real(dp), allocatable :: slip(:)
      logical, allocatable :: yielding(:)
   end type step_record_t

   !> One table: its blank-separated file and, with --csv, its comma-separated twin.
   type :: table_t
      type(text_file_t) :: text, csv
      logical :: with_csv = .false.
   end type table_t

   !> The result files of one run.
   type :: output_files_t
      type(table_t) :: path, crit, shape
      type(table_t) :: forces, contact      !< *OUTPUT, FORCES: STEM.forces, STEM.contact (with candidates)
      logical :: with_forces = .false.      !< the forces tables are open
      logical :: with_contact = .false.     !< STEM.contact is open
      integer :: forces_last = -1           !< the step last written to them, −1 before any
      logical :: step_column = .false.      !< a deck with analysis steps: rows end with `analysis_step`
   end type output_files_t

   !> Number format of every real: ES with 13 significant digits (docs/contracts.md).
   character(len=*), parameter :: number_format = '(es21.12e3)'

contains

   !> Record `from` moved into `to` (its arrays handed over, not copied; `from` left without them): what
   !> `to = from` does without allocating, so without an allocation that could be refused
   !> (docs/contracts.md, "Memory").
   subroutine move_record(from, to)
      type(step_record_t), intent(inout) :: from, to
      type(step_record_t) :: aside
      call move_record_arrays(from, aside)
      to = from
      call move_record_arrays(aside, to)
   end subroutine move_record

   !> Every allocatable component of a record moved from `from` to `to`; `to`'s are replaced.
   subroutine move_record_arrays(from, to)
      type(step_record_t), intent(inout) :: from, to
      call move_alloc(from%displacement, to%displacement)
      call move_alloc(from%reactions, to%reactions)
      call move_alloc(from%bed_deflections, to%bed_deflections)
      call move_alloc(from%groups, to%groups)
      call move_alloc(from%joint_plastic, to%joint_plastic)
      call move_alloc(from%slip, to%slip)
      call move_alloc(from%yielding, to%yielding)
   end subroutine move_record_arrays

   !> Start `STEM.path|crit|shape` in the run's work directory (and their `.csv` twins when `csv`)
   !> with their header and provenance lines, and write `STEM.surface` whole when the model has contact
   !> candidates.
   subroutine open_outputs(model, results, provenance, csv, files, error)
      type(model_t), intent(in) :: model
      type(result_directory_t), intent(inout) :: results
      type(provenance_t), intent(in) :: provenance
      logical, intent(in) :: csv
      type(output_files_t), intent(out) :: files
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: comments(:)
      comments = provenance_lines(provenance)
      call open_table(results, files%path, results%stem//'.path', path_header(model), comments, csv, error)
      if (allocated(error)) return
      ! a deck with steps: the event's analysis step by number and by name (docs/contracts.md)
      call open_table(results, files%crit, results%stem//'.crit', 'kind step lambda'//track_names(model)// &
                      step_column(model)//trim(merge(' step_name', '          ', allocated(model%steps))), &
                      comments, csv, error)
      if (allocated(error)) return
      call open_table(results, files%shape, results%stem//'.shape', &
                      'step lambda node x0 y0 ux uy rz x y reaction', comments, csv, error)
      if (allocated(error)) return
      if (allocated(model%contacts)) then
         if (size(model%contacts) > 0) call write_surface(model, results, comments, csv, error)
      end if
      if (allocated(error) .or. .not. model%output%forces) return
      call open_table(results, files%forces, results%stem//'.forces', &
                      'step lambda element node_start node_end N_start V_start M_start N_end V_end M_end'// &
                      step_column(model), comments, csv, error)
      if (allocated(error)) return
      files%with_forces = .true.
      files%step_column = allocated(model%steps)
      if (.not. allocated(model%contacts)) return
      if (size(model%contacts) == 0) return
      ! plastic media: two more columns, the slip and whether the candidate yields; Pasternak beds one,
      ! the deflection of the bed's surface (docs/contracts.md)
      call open_table(results, files%contact, results%stem//'.contact', &
                      'step lambda medium candidate node s gap reaction length pressure tangential_displacement '// &
                      'tangential_force shear'//trim(merge(' slip yielding', '              ', &
                      any(model%contacts%plastic)))// &
                      trim(merge(' surface_deflection', '                   ', &
                                 any(model%contacts%bed_stiffness(2) > 0.0_dp)))//step_column(model), &
                      comments, csv, error)
      if (allocated(error)) return
      files%with_contact = .true.
   end subroutine open_outputs

   !> `STEM.surface`: one row per contact candidate, `medium candidate node x y rigid`: the name of its
   !> foundation or obstacle, its number, its node's label, the point of the medium's surface that
   !> the node meets when its gap closes (surface_point) and 1 for a rigid medium, 0 for an elastic one.
   subroutine write_surface(model, results, comments, csv, error)
      type(model_t), intent(in) :: model
      type(result_directory_t), intent(inout) :: results
      character(len=*), intent(in) :: comments(:)
      logical, intent(in) :: csv
      type(error_t), allocatable, intent(out) :: error
      type(table_t) :: surface
      real(dp) :: point(2)
      integer :: c, rigid
      call open_table(results, surface, results%stem//'.surface', 'medium candidate node x y rigid', comments, &
                      csv, error)
      if (allocated(error)) return
      do c = 1, size(model%contacts)
         if (model%contacts(c)%tangential) cycle  ! a foundation's shear spring: no surface of its own
         point = surface_point(model, c)
         ! a Pasternak bed point's contact with the surface is rigid, the bed under it is not
         rigid = merge(1, 0, model%contacts(c)%flexibility == 0.0_dp .and. &
                             .not. model%contacts(c)%bed_stiffness(2) > 0.0_dp)
         call put_row(surface, medium_name(model, model%contacts(c)%group)//' '//integer_to_string(c)//' '// &
                      integer_to_string(model%node_label(model%contacts(c)%node))//' '// &
                      trim(format_number(point(1)))//' '//trim(format_number(point(2)))//' '// &
                      integer_to_string(rigid))
      end do
      call close_table(surface, error)
   end subroutine write_surface

   !> The name of contact group `group` (its card's NAME=), or `medium_<group>` for a group without
   !> one: a name is one field of a STEM.surface or STEM.contact row and a part of the group's path
   !> column names, never empty.
   pure function medium_name(model, group) result(name)
      type(model_t), intent(in) :: model
      integer, intent(in) :: group
      character(len=:), allocatable :: name
      name = 'medium_'//integer_to_string(group)
      if (.not. allocated(model%contact_groups)) return
      if (group < 1 .or. group > size(model%contact_groups)) return
      if (.not. allocated(model%contact_groups(group)%name)) return
      if (len(model%contact_groups(group)%name) > 0) name = model%contact_groups(group)%name
   end function medium_name

   !> Where contact candidate `c` meets its medium, (2) in model units: the point its node reaches when
   !> the candidate's gap closes moving straight to the medium (uniarc_contact_law, candidate_gap).
   !> Fixed direction n with initial gap g0: x0 − g0 n (a bed without gap: the node itself). Circle of
   !> centre c and radius R: c + R (x0 − c)/|x0 − c|.
   pure function surface_point(model, c) result(point)
      type(model_t), intent(in) :: model
      integer, intent(in) :: c
      real(dp) :: point(2)
      real(dp) :: x0(2), d(2)
      associate (candidate => model%contacts(c))
         x0 = model%coordinates(:, candidate%node)
         if (candidate%gap_kind == gap_fixed_direction) then
            point = x0 - candidate%offset*candidate%direction
         else
            d = x0 - candidate%centre
            point = candidate%centre + candidate%radius*d/max(norm2(d), tiny(1.0_dp))
         end if
      end associate
   end function surface_point

   !> Header line of the path file: `step lambda <tracks> <contact columns> [<each group's contact
   !> columns>] <solver columns>`. A model with more than one contact group has, after the contact
   !> columns of all groups together, those of each group under the group's name (medium_name):
   !> `n_contact_NAME contact_regions_NAME s_contact_1_NAME s_contact_2_NAME reaction_max_NAME
   !> reaction_sum_NAME`.
   pure function path_header(model) result(header)
      type(model_t), intent(in) :: model
      character(len=:), allocatable :: header
      character(len=*), parameter :: contact_columns(6) = [character(len=15) :: 'n_contact', 'contact_regions', &
                                                          's_contact_1', 's_contact_2', 'reaction_max', 'reaction_sum']
      integer :: g, k
      header = 'step lambda'//track_names(model)// &
               ' n_contact contact_regions s_contact_1 s_contact_2 reaction_max reaction_sum'
      if (n_groups(model) > 1) then
         do g = 1, n_groups(model)
            do k = 1, size(contact_columns)
               header = header//' '//trim(contact_columns(k))//'_'//medium_name(model, g)
            end do
         end do
      end if
      if (has_prescribed(model)) header = header//' prescribed_force'
      header = header//' lcp_residual lcp_pivots iterations neg_pivots'//step_column(model)
   end function path_header

   !> The number of contact groups of the model.
   pure integer function n_groups(model)
      type(model_t), intent(in) :: model
      n_groups = 0
      if (allocated(model%contact_groups)) n_groups = size(model%contact_groups)
   end function n_groups

   !> The last column of the path and crit files of a deck with analysis steps (*STEP): ' analysis_step'.
   pure function step_column(model) result(name)
      type(model_t), intent(in) :: model
      character(len=:), allocatable :: name
      name = ''
      if (allocated(model%steps)) name = ' analysis_step'
   end function step_column

   !> The tracks' names, each after a blank (the header columns of the path and crit files).
   pure function track_names(model) result(names)
      type(model_t), intent(in) :: model
      character(len=:), allocatable :: names
      integer :: i, used, total
      names = ''
      if (.not. allocated(model%tracks)) return
      ! the length first, then each name copied once: linear time (issue 14)
      total = 0
      do i = 1, size(model%tracks)
         total = total + 1 + len(model%tracks(i)%name)
      end do
      deallocate (names)
      allocate (character(len=total) :: names)
      used = 0
      do i = 1, size(model%tracks)
         names(used + 1:used + 1 + len(model%tracks(i)%name)) = ' '//model%tracks(i)%name
         used = used + 1 + len(model%tracks(i)%name)
      end do
   end function track_names

   !> One row of the path file, flushed: the counts (step, n_contact, contact_regions, lcp_pivots,
   !> iterations, neg_pivots) as integers, the rest in the number format.
   subroutine write_path_row(files, model, record, error)
      type(output_files_t), intent(inout) :: files
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: line
      type(contact_summary_t) :: group
      integer :: g
      line = integer_to_string(record%step)//' '//trim(format_number(record%lambda))// &
             numbers_text(tracked_values(model, record%displacement))//' '// &
             integer_to_string(record%n_contact)//' '//integer_to_string(record%contact_regions)// &
             numbers_text([record%s_contact, record%reaction_max, record%reaction_sum])
      if (n_groups(model) > 1) then
         do g = 1, n_groups(model)
            if (allocated(record%groups)) group = record%groups(g)
            line = line//' '//integer_to_string(group%n_contact)//' '//integer_to_string(group%regions)// &
                   numbers_text([group%s_contact, group%reaction_max, group%reaction_sum])
         end do
      end if
      if (has_prescribed(model)) line = line//numbers_text([record%prescribed_force])
      line = line//numbers_text([record%lcp_residual])// &
             ' '//integer_to_string(record%lcp_pivots)//' '//integer_to_string(record%iterations)//' '// &
             integer_to_string(record%neg_pivots)
      if (allocated(model%steps)) line = line//' '//integer_to_string(record%analysis_step)
      call put_row(files%path, line)
      call flush_table(files%path, error)
   end subroutine write_path_row

   !> One event of the critical-point file: kind, where it lies (a step number, fractional when the
   !> event was located between two steps), λ and the tracked values at the event; `analysis_step`
   !> (given for a deck with *STEP cards only) the analysis step it happened in, `step_name` (with it)
   !> that step's name (*STEP, NAME=; Step-k by default). Flushed.
   subroutine write_crit_row(files, kind, position, lambda, tracked, error, analysis_step, step_name)
      type(output_files_t), intent(inout) :: files
      character(len=*), intent(in) :: kind
      real(dp), intent(in) :: position
      real(dp), intent(in) :: lambda
      real(dp), intent(in) :: tracked(:)
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in), optional :: analysis_step
      character(len=*), intent(in), optional :: step_name
      character(len=:), allocatable :: step_text
      step_text = ''
      if (present(analysis_step)) step_text = ' '//integer_to_string(analysis_step)
      if (present(step_name)) step_text = step_text//' '//step_name
      call put_row(files%crit, kind//' '//trim(format_number(position))//' '//trim(format_number(lambda))// &
                   numbers_text(tracked)//step_text)
      call flush_table(files%crit, error)
   end subroutine write_crit_row

   !> A snapshot of the deformed shape: one line per node (the last column the sum of the contact
   !> reactions at the node), snapshots separated by two blank lines (gnuplot's `index`). Flushed.
   subroutine write_shape(files, model, record, error)
      type(output_files_t), intent(inout) :: files
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: nodal_reaction(:)
      character(len=:), allocatable :: line
      integer :: i, k, status
      allocate (nodal_reaction(model%n_nodes), stat=status)
      call allocation_failure(status, 'the nodal reactions of the shape of step '//integer_to_string(record%step), &
                              8.0_dp*model%n_nodes, error_analysis, error)
      if (allocated(error)) return
      call nodal_reactions(model, record%reactions, nodal_reaction)
      do i = 1, model%n_nodes
         line = integer_to_string(record%step)//' '//trim(format_number(record%lambda))//' '// &
                integer_to_string(model%node_label(i))
         do k = 1, 2
            line = line//' '//trim(format_number(model%coordinates(k, i)))
         end do
         do k = 1, 3
            line = line//' '//trim(format_number(record%displacement(k, i)))
         end do
         do k = 1, 2
            line = line//' '//trim(format_number(model%coordinates(k, i) + record%displacement(k, i)))
         end do
         call put_row(files%shape, line//' '//trim(format_number(nodal_reaction(i))))
      end do
      call put_row(files%shape, '')
      call put_row(files%shape, '')
      call flush_table(files%shape, error)
   end subroutine write_shape

   !> Whether the deck asks for the forces tables at step `step` (*OUTPUT, FORCES): a step listed on the
   !> card, a multiple of its EVERY=, or, with neither, a step of the shape file (every shape_every).
   !> The last converged step is written in any case (write_forces after the path).
   pure logical function forces_due(model, step)
      type(model_t), intent(in) :: model
      integer, intent(in) :: step
      logical :: listed
      forces_due = .false.
      if (.not. model%output%forces) return
      listed = .false.
      if (allocated(model%output%forces_steps)) listed = size(model%output%forces_steps) > 0
      if (model%output%forces_every > 0) then
         forces_due = mod(step, model%output%forces_every) == 0
      else if (.not. listed) then
         forces_due = mod(step, max(model%analysis%shape_every, 1)) == 0
      end if
      if (listed) forces_due = forces_due .or. any(model%output%forces_steps == step)
   end function forces_due

   !> The rows of step `record` in STEM.forces and STEM.contact (when they are open and the step is not
   !> the one last written), flushed; blocks of steps are separated by two blank lines (gnuplot's
   !> `index`), as in STEM.shape.
   !> STEM.forces, one row per element: `step lambda element node_start node_end N_start V_start M_start
   !> N_end V_end M_end` — the section forces at node 1 and node 2 (uniarc_output_forces,
   !> element_end_forces: element frame, N tension positive, M = EI κ positive toward the left normal,
   !> V = dM/ds). STEM.contact, one row per candidate: `step lambda medium candidate node s gap reaction
   !> length pressure tangential_displacement tangential_force shear` — its coordinate along its group,
   !> gap, reaction, tributary length (candidate_lengths) and reaction/length; then, where its foundation
   !> has tangential springs (tangential_springs), the spring's gap t·u, its reaction on the node along t
   !> and reaction/length (0 0 0 without one); with plastic media also `slip yielding` (the plastic slip
   !> of the candidate and 1 where it is at its bearing limit, −1 at its uplift limit (TU=), else 0,
   !> docs/theory.md §3.9), the gap then measured to the medium's surface sunk by the slip; with
   !> Pasternak beds also `surface_deflection` (the bed surface's own deflection w_b at the candidate,
   !> positive into the medium; 0 for candidates of other media).
   subroutine write_forces(files, model, record, error)
      type(output_files_t), intent(inout) :: files
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: forces(:, :), gaps(:), lengths(:), reactions(:), slip(:)
      real(dp) :: tangential(3)
      integer, allocatable :: spring(:)
      logical, allocatable :: yielding(:)
      character(len=:), allocatable :: head, tail, surface
      real(dp) :: bytes
      integer :: e, c, status, m
      logical :: plastic, pasternak
      if (.not. files%with_forces .or. files%forces_last == record%step) return
      ! Every array of the tables computed first, allocated with stat=: an allocation refused leaves no
      ! row of this step in either table (error: out of memory, error_analysis).
      bytes = 0.0_dp
      if (allocated(record%joint_plastic) .and. allocated(record%reactions)) then
         call element_end_forces(model, record%displacement, record%lambda, forces, status, bytes, record%joint_plastic, &
                                 record%reactions)
      else if (allocated(record%joint_plastic)) then
         call element_end_forces(model, record%displacement, record%lambda, forces, status, bytes, record%joint_plastic)
      else if (allocated(record%reactions)) then
         call element_end_forces(model, record%displacement, record%lambda, forces, status, bytes, &
                                 reactions=record%reactions)
      else
         call element_end_forces(model, record%displacement, record%lambda, forces, status, bytes)
      end if
      call allocation_failure(status, 'the section forces of step '//integer_to_string(record%step), bytes, &
                              error_analysis, error)
      if (allocated(error)) return
      if (files%with_contact) then
         m = 0
         if (allocated(model%contacts)) m = size(model%contacts)
         bytes = 8.0_dp*m
         call candidate_gaps(model, record%displacement, gaps, status, record%lambda)
         if (status == 0) call candidate_lengths(model, lengths, status)
         if (status == 0) call tangential_springs(model, spring, status)
         if (status == 0) allocate (reactions(m), slip(m), yielding(m), stat=status)
         call allocation_failure(status, 'the contact table of step '//integer_to_string(record%step), &
                                 max(bytes, 8.0_dp*model%n_nodes), error_analysis, error)
         if (allocated(error)) return
      end if
      files%forces_last = record%step
      head = integer_to_string(record%step)//' '//trim(format_number(record%lambda))//' '
      tail = ''
      if (files%step_column) tail = ' '//integer_to_string(record%analysis_step)
      do e = 1, model%n_elements
         call put_row(files%forces, head//integer_to_string(model%element_label(e))//' '// &
                      integer_to_string(model%node_label(model%connectivity(1, e)))//' '// &
                      integer_to_string(model%node_label(model%connectivity(2, e)))//numbers_text(forces(:, e))//tail)
      end do
      call put_row(files%forces, '')
      call put_row(files%forces, '')
      call flush_table(files%forces, error)
      if (allocated(error) .or. .not. files%with_contact) return
      ! a moving obstacle's gap at the record's λ (docs/theory.md §3.11; the others untouched)
      where (model%contacts%gap_rate /= 0.0_dp) gaps = gaps + record%lambda*model%contacts%gap_rate
      ! a Pasternak bed point's gap is with the bed's surface (the others untouched, −0 included)
      if (allocated(record%bed_deflections)) then
         where (model%contacts%bed_stiffness(2) > 0.0_dp) gaps = gaps + record%bed_deflections
      end if
      reactions = 0.0_dp
      if (allocated(record%reactions)) reactions(1:min(size(reactions), size(record%reactions))) = &
         record%reactions(1:min(size(reactions), size(record%reactions)))
      plastic = any(model%contacts%plastic)
      pasternak = any(model%contacts%bed_stiffness(2) > 0.0_dp)
      slip = 0.0_dp
      yielding = .false.
      if (allocated(record%slip)) slip(1:min(size(slip), size(record%slip))) = &
         record%slip(1:min(size(slip), size(record%slip)))
      if (allocated(record%yielding)) yielding(1:min(size(yielding), size(record%yielding))) = &
         record%yielding(1:min(size(yielding), size(record%yielding)))
      do c = 1, size(model%contacts)
         if (model%contacts(c)%tangential) cycle   ! a foundation's tangential spring: on its radial one's row
         tangential = 0.0_dp
         if (spring(c) > 0) tangential = [gaps(spring(c)), reactions(spring(c)), reactions(spring(c))/lengths(spring(c))]
         ! a Pasternak bed's surface deflection (into the medium; 0 for the other candidates)
         surface = ''
         if (pasternak) then
            if (model%contacts(c)%bed_stiffness(2) > 0.0_dp .and. allocated(record%bed_deflections)) then
               surface = numbers_text([record%bed_deflections(c)])
            else
               surface = numbers_text([0.0_dp])
            end if
         end if
         if (plastic) then
            ! the gap to the medium's surface sunk by the plastic slip
            call put_row(files%contact, head//medium_name(model, model%contacts(c)%group)//' '// &
                         integer_to_string(c)//' '//integer_to_string(model%node_label(model%contacts(c)%node))// &
                         numbers_text([model%contacts(c)%coordinate, gaps(c) + slip(c), reactions(c), lengths(c), &
                                       reactions(c)/lengths(c), tangential, slip(c)])//' '//yield_flag(c)//surface//tail)
         else
            call put_row(files%contact, head//medium_name(model, model%contacts(c)%group)//' '// &
                         integer_to_string(c)//' '//integer_to_string(model%node_label(model%contacts(c)%node))// &
                         numbers_text([model%contacts(c)%coordinate, gaps(c), reactions(c), lengths(c), &
                                       reactions(c)/lengths(c), tangential])//surface//tail)
         end if
      end do
      call put_row(files%contact, '')
      call put_row(files%contact, '')
      call flush_table(files%contact, error)

   contains

      !> The `yielding` column of candidate c: 1 at its bearing limit, −1 at its uplift limit (its
      !> reaction the tension −t), 0 elastic or open.
      pure function yield_flag(c) result(flag)
         integer, intent(in) :: c
         character(len=:), allocatable :: flag
         flag = '0'
         if (.not. yielding(c)) return
         flag = '1'
         if (model%contacts(c)%uplift_force > 0.0_dp .and. reactions(c) < 0.0_dp) flag = '-1'
      end function yield_flag
   end subroutine write_forces

   !> Sum of the contact reactions at each node (a node may carry candidates of several groups); the
   !> tangential springs of a foundation are not contact reactions and are left out.
   !> nodal (n_nodes): the caller's (no function result of the model's length, docs/contracts.md "Memory").
   pure subroutine nodal_reactions(model, reactions, nodal)
      type(model_t), intent(in) :: model
      real(dp), allocatable, intent(in) :: reactions(:)
      real(dp), intent(out) :: nodal(:)
      integer :: c
      nodal = 0.0_dp
      if (.not. (allocated(reactions) .and. allocated(model%contacts))) return
      do c = 1, min(size(reactions), size(model%contacts))
         if (model%contacts(c)%tangential) cycle  ! a foundation's shear spring, not a contact reaction
         nodal(model%contacts(c)%node) = nodal(model%contacts(c)%node) + reactions(c)
      end do
   end subroutine nodal_reactions

   !> Close every file; the first failure (of a close, or of a write not yet reported) as an error.
   !> Every file is closed either way.
   subroutine close_outputs(files, error)
      type(output_files_t), intent(inout) :: files
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: crit_error, shape_error, forces_error, contact_error
      call close_table(files%path, error)
      call close_table(files%crit, crit_error)
      call close_table(files%shape, shape_error)
      if (files%with_forces) call close_table(files%forces, forces_error)
      if (files%with_contact) call close_table(files%contact, contact_error)
      if (.not. allocated(error) .and. allocated(crit_error)) call move_alloc(crit_error, error)
      if (.not. allocated(error) .and. allocated(shape_error)) call move_alloc(shape_error, error)
      if (.not. allocated(error) .and. allocated(forces_error)) call move_alloc(forces_error, error)
      if (.not. allocated(error) .and. allocated(contact_error)) call move_alloc(contact_error, error)
   end subroutine close_outputs

   !> Close and remove every file (after a failure that is reported already).
   subroutine discard_outputs(files)
      type(output_files_t), intent(inout) :: files
      call discard_table(files%path)
      call discard_table(files%crit)
      call discard_table(files%shape)
      if (files%with_forces) call discard_table(files%forces)
      if (files%with_contact) call discard_table(files%contact)
   end subroutine discard_outputs

   !> A real as text in the files' number format, without surrounding blanks.
   pure function format_number(x) result(text)
      real(dp), intent(in) :: x
      character(len=:), allocatable :: text
      ! x + 0 turns a negative zero (a product of zero and a negative number) into +0 (IEEE 754
      ! round-to-nearest), so that no column shows -0.000000000000E+000.
      text = real_to_string(x + 0.0_dp, number_format)
   end function format_number

   !> The numbers as text, each after a blank. Built in time linear in the length of the text: each
   !> number is appended into a buffer whose capacity doubles when full (issue 14: joining text to
   !> the whole row, number by number, took time quadratic in the number of tracks).
   pure function numbers_text(values) result(text)
      real(dp), intent(in) :: values(:)
      character(len=:), allocatable :: text
      character(len=:), allocatable :: buffer, grown, number
      integer :: i, used, needed
      allocate (character(len=max(64, 24*size(values))) :: buffer)
      used = 0
      do i = 1, size(values)
         number = trim(format_number(values(i)))
         needed = used + 1 + len(number)
         if (needed > len(buffer)) then
            allocate (character(len=max(needed, 2*len(buffer))) :: grown)
            grown(1:used) = buffer(1:used)
            call move_alloc(grown, buffer)
         end if
         buffer(used + 1:needed) = ' '//number
         used = needed
      end do
      text = buffer(1:used)
   end function numbers_text

   !> Start the table `name` (and `name.csv` when `csv`) in the work directory with its header line
   !> and the comment lines.
   subroutine open_table(results, table, name, header, comments, csv, error)
      type(result_directory_t), intent(inout) :: results
      type(table_t), intent(out) :: table
      character(len=*), intent(in) :: name, header
      character(len=*), intent(in) :: comments(:)
      logical, intent(in) :: csv
      type(error_t), allocatable, intent(out) :: error
      integer :: i
      call add_result_file(results, name)
      call create_text_file(table%text, work_path(results, name), final_path(results, name), error)
      if (allocated(error)) return
      if (csv) then
         call add_result_file(results, name//'.csv')
         call create_text_file(table%csv, work_path(results, name//'.csv'), final_path(results, name//'.csv'), &
                               error)
         if (allocated(error)) return
         table%with_csv = .true.
      end if
      call put_row(table, header)
      do i = 1, size(comments)
         call put_line(table%text, trim(comments(i)))
         if (table%with_csv) call put_line(table%csv, trim(comments(i)))
      end do
   end subroutine open_table

   !> One line of a table whose fields are separated by single blanks (none inside a field); the CSV
   !> twin gets the same fields separated by commas.
   subroutine put_row(table, line)
      type(table_t), intent(inout) :: table
      character(len=*), intent(in) :: line
      character(len=len(line)) :: csv_line
      integer :: i
      call put_line(table%text, line)
      if (.not. table%with_csv) return
      csv_line = line
      do i = 1, len(csv_line)
         if (csv_line(i:i) == ' ') csv_line(i:i) = ','
      end do
      call put_line(table%csv, csv_line)
   end subroutine put_row

   subroutine flush_table(table, error)
      type(table_t), intent(inout) :: table
      type(error_t), allocatable, intent(out) :: error
      call flush_text_file(table%text, error)
      if (.not. allocated(error) .and. table%with_csv) call flush_text_file(table%csv, error)
   end subroutine flush_table

   !> Close both files of the table (both either way); the first failure as an error.
   subroutine close_table(table, error)
      type(table_t), intent(inout) :: table
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: csv_error
      call close_text_file(table%text, error)
      if (table%with_csv) call close_text_file(table%csv, csv_error)
      if (.not. allocated(error) .and. allocated(csv_error)) call move_alloc(csv_error, error)
   end subroutine close_table

   subroutine discard_table(table)
      type(table_t), intent(inout) :: table
      call discard_text_file(table%text)
      if (table%with_csv) call discard_text_file(table%csv)
   end subroutine discard_table

end module uniarc_output
