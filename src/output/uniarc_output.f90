!> Result files of docs/contracts.md: the path file `STEM.path`, critical points `STEM.crit`, shapes
!> `STEM.shape`, the surfaces of the contact media `STEM.surface` (when the model has any), and with
!> `--csv` the same tables as comma-separated `STEM.path.csv`, ... for spreadsheets.
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
   use uniarc_error, only: error_t
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_model, only: model_t, tracked_values, gap_fixed_direction
   use uniarc_text_file, only: text_file_t, create_text_file, put_line, flush_text_file, close_text_file, &
                               discard_text_file
   use uniarc_result_directory, only: result_directory_t, work_path, final_path, add_result_file
   use uniarc_provenance, only: provenance_t, provenance_lines
   implicit none
   private
   public :: step_record_t, output_files_t
   public :: open_outputs, write_path_row, write_crit_row, write_shape, close_outputs, discard_outputs
   public :: path_header, format_number, nodal_reactions, surface_point

   !> What a converged step reports (one row of the path file).
   type :: step_record_t
      integer :: step = 0
      real(dp) :: lambda = 0.0_dp
      real(dp), allocatable :: displacement(:, :)   !< (3, n_nodes) total nodal displacements
      real(dp), allocatable :: reactions(:)         !< (n_contacts) reaction of every contact candidate
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
   end type step_record_t

   !> One table: its blank-separated file and, with --csv, its comma-separated twin.
   type :: table_t
      type(text_file_t) :: text, csv
      logical :: with_csv = .false.
   end type table_t

   !> The result files of one run.
   type :: output_files_t
      type(table_t) :: path, crit, shape
   end type output_files_t

   !> Number format of every real: ES with 13 significant digits (docs/contracts.md).
   character(len=*), parameter :: number_format = '(es21.12e3)'

contains

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
      call open_table(results, files%crit, results%stem//'.crit', 'kind step lambda'//track_names(model)// &
                      step_column(model), &
                      comments, csv, error)
      if (allocated(error)) return
      call open_table(results, files%shape, results%stem//'.shape', &
                      'step lambda node x0 y0 ux uy rz x y reaction', comments, csv, error)
      if (allocated(error)) return
      if (allocated(model%contacts)) then
         if (size(model%contacts) > 0) call write_surface(model, results, comments, csv, error)
      end if
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
         point = surface_point(model, c)
         rigid = merge(1, 0, model%contacts(c)%flexibility == 0.0_dp)
         call put_row(surface, medium_name(model, model%contacts(c)%group)//' '//integer_to_string(c)//' '// &
                      integer_to_string(model%node_label(model%contacts(c)%node))//' '// &
                      trim(format_number(point(1)))//' '//trim(format_number(point(2)))//' '// &
                      integer_to_string(rigid))
      end do
      call close_table(surface, error)
   end subroutine write_surface

   !> The name of contact group `group` (its card's NAME=), or `medium_<group>` for a group without
   !> one: a name is one field of a STEM.surface row, never empty.
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

   !> Header line of the path file: `step lambda <tracks> <contact and solver columns>`.
   pure function path_header(model) result(header)
      type(model_t), intent(in) :: model
      character(len=:), allocatable :: header
      header = 'step lambda'//track_names(model)// &
               ' n_contact contact_regions s_contact_1 s_contact_2 reaction_max reaction_sum'// &
               ' lcp_residual lcp_pivots iterations neg_pivots'//step_column(model)
   end function path_header

   !> The last column of the path and crit files of a deck with analysis steps (*STEP): ' analysis_step'.
   pure function step_column(model) result(name)
      type(model_t), intent(in) :: model
      character(len=:), allocatable :: name
      name = ''
      if (allocated(model%steps)) name = ' analysis_step'
   end function step_column

   pure function track_names(model) result(names)
      type(model_t), intent(in) :: model
      character(len=:), allocatable :: names
      integer :: i
      names = ''
      if (.not. allocated(model%tracks)) return
      do i = 1, size(model%tracks)
         names = names//' '//model%tracks(i)%name
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
      line = integer_to_string(record%step)//' '//trim(format_number(record%lambda))// &
             numbers_text(tracked_values(model, record%displacement))//' '// &
             integer_to_string(record%n_contact)//' '//integer_to_string(record%contact_regions)// &
             numbers_text([record%s_contact, record%reaction_max, record%reaction_sum, record%lcp_residual])// &
             ' '//integer_to_string(record%lcp_pivots)//' '//integer_to_string(record%iterations)//' '// &
             integer_to_string(record%neg_pivots)
      if (allocated(model%steps)) line = line//' '//integer_to_string(record%analysis_step)
      call put_row(files%path, line)
      call flush_table(files%path, error)
   end subroutine write_path_row

   !> One event of the critical-point file: kind, where it lies (a step number, fractional when the
   !> event was located between two steps), λ and the tracked values at the event; `analysis_step`
   !> (given for a deck with *STEP cards only) the analysis step it happened in. Flushed.
   subroutine write_crit_row(files, kind, position, lambda, tracked, error, analysis_step)
      type(output_files_t), intent(inout) :: files
      character(len=*), intent(in) :: kind
      real(dp), intent(in) :: position
      real(dp), intent(in) :: lambda
      real(dp), intent(in) :: tracked(:)
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in), optional :: analysis_step
      character(len=:), allocatable :: step_text
      step_text = ''
      if (present(analysis_step)) step_text = ' '//integer_to_string(analysis_step)
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
      integer :: i, k
      nodal_reaction = nodal_reactions(model, record%reactions)
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

   !> Sum of the contact reactions at each node (a node may carry candidates of several groups).
   pure function nodal_reactions(model, reactions) result(nodal)
      type(model_t), intent(in) :: model
      real(dp), allocatable, intent(in) :: reactions(:)
      real(dp) :: nodal(model%n_nodes)
      integer :: c
      nodal = 0.0_dp
      if (.not. (allocated(reactions) .and. allocated(model%contacts))) return
      do c = 1, min(size(reactions), size(model%contacts))
         nodal(model%contacts(c)%node) = nodal(model%contacts(c)%node) + reactions(c)
      end do
   end function nodal_reactions

   !> Close every file; the first failure (of a close, or of a write not yet reported) as an error.
   !> Every file is closed either way.
   subroutine close_outputs(files, error)
      type(output_files_t), intent(inout) :: files
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: crit_error, shape_error
      call close_table(files%path, error)
      call close_table(files%crit, crit_error)
      call close_table(files%shape, shape_error)
      if (.not. allocated(error) .and. allocated(crit_error)) call move_alloc(crit_error, error)
      if (.not. allocated(error) .and. allocated(shape_error)) call move_alloc(shape_error, error)
   end subroutine close_outputs

   !> Close and remove every file (after a failure that is reported already).
   subroutine discard_outputs(files)
      type(output_files_t), intent(inout) :: files
      call discard_table(files%path)
      call discard_table(files%crit)
      call discard_table(files%shape)
   end subroutine discard_outputs

   !> A real as text in the files' number format, without surrounding blanks.
   pure function format_number(x) result(text)
      real(dp), intent(in) :: x
      character(len=:), allocatable :: text
      ! x + 0 turns a negative zero (a product of zero and a negative number) into +0 (IEEE 754
      ! round-to-nearest), so that no column shows -0.000000000000E+000.
      text = real_to_string(x + 0.0_dp, number_format)
   end function format_number

   !> The numbers as text, each after a blank.
   pure function numbers_text(values) result(text)
      real(dp), intent(in) :: values(:)
      character(len=:), allocatable :: text
      integer :: i
      text = ''
      do i = 1, size(values)
         text = text//' '//trim(format_number(values(i)))
      end do
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
