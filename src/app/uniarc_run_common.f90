!> What the program's runs share: how to run (run_options_t), the nearly singular model's warning said
!> once, errors named after their analysis step, the end of the result files, the finite-row test.
module uniarc_run_common
   use, intrinsic :: iso_fortran_env, only: error_unit
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use uniarc_error, only: error_t, error_input
   use uniarc_model, only: model_t
   use uniarc_output, only: output_files_t, step_record_t, close_outputs, discard_outputs
   use uniarc_result_directory, only: result_directory_t, commit_results, abandon_results
   use uniarc_check, only: nearly_mechanism_warning
   use uniarc_strings, only: integer_to_string
   use uniarc_provenance, only: provenance_t
   implicit none
   private
   public :: run_options_t, release_warning, name_analysis_step, step_label, conclude_outputs, finite_record

   !> How to run: where the files go and how much to say.
   type :: run_options_t
      character(len=:), allocatable :: output_directory
      character(len=:), allocatable :: stem
      logical :: quiet = .false.
      logical :: verbose = .false.
      type(provenance_t) :: provenance   !< under the header of every table (uniarc_provenance)
      logical :: csv = .false.           !< also write the tables as STEM.*.csv (--csv)
   end type run_options_t

contains

   !> Write the nearly singular model's warning `warning` (uniarc_check: nearly_mechanism_warning; also
   !> with -q, as errors are) on stderr unless `error` refuses the deck (error_input: exit code 2, whose
   !> stderr is the error alone), and deallocate it: said at most once. Nothing if it is not allocated.
   subroutine release_warning(warning, error)
      character(len=:), allocatable, intent(inout) :: warning
      type(error_t), allocatable, intent(in) :: error
      if (.not. allocated(warning)) return
      if (.not. allocated(error)) then
         write (error_unit, '(a)') 'warning: '//warning
      else if (error%category /= error_input) then
         write (error_unit, '(a)') 'warning: '//warning
      end if
      deallocate (warning)
   end subroutine release_warning

   !> Prefix an error of the analysis with the analysis step it happened in (decks with steps); an
   !> input error (exit code 2) keeps its `file:` first (docs/contracts.md) and names the step after it.
   subroutine name_analysis_step(model, k, error)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      type(error_t), intent(inout) :: error
      character(len=:), allocatable :: label
      integer :: n
      if (.not. allocated(model%steps)) return
      label = 'analysis step '//integer_to_string(k)//' ('//model%steps(k)%name//')'
      n = len(model%deck_path)
      if (error%category == error_input .and. n > 0 .and. len(error%message) > n + 1) then
         if (error%message(1:n + 1) == model%deck_path//':') then
            error%message = error%message(1:n + 1)//' '//label//':'//error%message(n + 2:)
            return
         end if
      end if
      error%message = label//': '//error%message
   end subroutine name_analysis_step

   !> ' (analysis step K NAME)' for the messages of a deck with steps; '' without.
   function step_label(model, k) result(label)
      type(model_t), intent(in) :: model
      integer, intent(in) :: k
      character(len=:), allocatable :: label
      label = ''
      if (allocated(model%steps)) label = ' (analysis step '//integer_to_string(k)//' '//model%steps(k)%name//')'
   end function step_label

   !> End the result files of a run. Without an I/O error (`io_error`) they are closed and moved to
   !> their final names together, and `error` (the analysis' error, if any) is left as it is. After an
   !> I/O error — of a write, a flush, a close or the commit — the files not moved are removed, and
   !> `error` becomes the I/O error (analysis category, exit code 1), which says so and names any
   !> analysis error before it.
   subroutine conclude_outputs(files, results, io_error, error)
      type(output_files_t), intent(inout) :: files
      type(result_directory_t), intent(inout) :: results
      type(error_t), allocatable, intent(inout) :: io_error
      type(error_t), allocatable, intent(inout) :: error
      ! An array of a table the system refused (uniarc_output, uniarc_vtk: out of memory) is no I/O
      ! error: the rows written so far are complete, the files are kept, the run ends with it
      ! (docs/contracts.md, "Memory"), unless the analysis failed first.
      if (allocated(io_error)) then
         if (io_error%out_of_memory) then
            if (.not. allocated(error)) then
               call move_alloc(io_error, error)
            else
               deallocate (io_error)
            end if
         end if
      end if
      if (.not. allocated(io_error)) call close_outputs(files, io_error)
      if (.not. allocated(io_error)) then
         call commit_results(results, io_error)
      else
         call discard_outputs(files)
         call abandon_results(results)
         io_error%message = io_error%message//'; the run stopped and removed its unfinished result files '// &
                            '(no file of this run is in '//results%directory//')'
      end if
      if (.not. allocated(io_error)) return
      if (allocated(error)) io_error%message = io_error%message//'; before that: '//error%message
      call move_alloc(io_error, error)
   end subroutine conclude_outputs

   !> Every number of a step's row is finite (λ, displacements, reactions, contact summaries).
   pure logical function finite_record(record)
      type(step_record_t), intent(in) :: record
      integer :: g
      ! every real column of the path row (the tracked values are formed from the displacements; the
      ! group columns are the groups' own), the reactions of STEM.contact and the joints' plastic
      ! rotations, tested with ieee_is_finite: an ordered comparison with a NaN would itself raise the
      ! invalid-operation trap of the Debug build
      finite_record = ieee_is_finite(record%lambda) .and. all(ieee_is_finite(record%displacement)) .and. &
                      ieee_is_finite(record%reaction_max) .and. ieee_is_finite(record%reaction_sum) .and. &
                      ieee_is_finite(record%prescribed_force) .and. all(ieee_is_finite(record%s_contact)) .and. &
                      ieee_is_finite(record%lcp_residual)
      if (allocated(record%reactions)) finite_record = finite_record .and. all(ieee_is_finite(record%reactions))
      if (allocated(record%bed_deflections)) &
         finite_record = finite_record .and. all(ieee_is_finite(record%bed_deflections))
      if (allocated(record%joint_plastic)) finite_record = finite_record .and. all(ieee_is_finite(record%joint_plastic))
      if (allocated(record%slip)) finite_record = finite_record .and. all(ieee_is_finite(record%slip))
      if (allocated(record%groups)) then
         do g = 1, size(record%groups)
            finite_record = finite_record .and. all(ieee_is_finite(record%groups(g)%s_contact)) .and. &
                            ieee_is_finite(record%groups(g)%reaction_max) .and. &
                            ieee_is_finite(record%groups(g)%reaction_sum)
         end do
      end if
   end function finite_record

end module uniarc_run_common
