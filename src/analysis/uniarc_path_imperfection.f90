!> The imperfection of `*IMPERFECTION` without FILE= (docs/input.md, docs/theory.md §2.6): the buckling
!> mode of the perfect structure's n-th located bifurcation, computed by a first run of the deck's own
!> path, scaled so that its largest nodal translation is the amplitude and added to the initial
!> coordinates — what `*OUTPUT, MODES` and `*IMPERFECTION, FILE=` do in two runs, in one.
module uniarc_path_imperfection
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis, add_context
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_model, only: model_t
   use uniarc_model_copy, only: copy_model
   use uniarc_memory, only: allocation_failure
   use uniarc_path_driver, only: path_driver_t, step_outcome_t, driver_start, driver_step, stop_none
   use uniarc_path_branch, only: nodal_mode
   implicit none
   private
   public :: computed_imperfection

contains

   !> `imperfect` is `model` with the mode of its n-th bifurcation (n = model%analysis%
   !> imperfection_bifurcation > 0) added to the coordinates, scaled to a largest nodal translation
   !> model%analysis%imperfection_amplitude (length). The first run traces the perfect model's path
   !> with its own *PATH options (no branch switching) until it has located the n-th bifurcation.
   !> `imperfect` has no analysis steps (uniarc_model_copy: copy_model); the caller moves the deck's
   !> into it. `model` is unchanged on return (intent(inout) for copy_model, which moves its arrays
   !> aside while it copies the scalars).
   !> Errors (error_analysis): the first run fails, or ends by a stop rule before the n-th bifurcation;
   !> a copy of the model or the mode refused by the system (out of memory, uniarc_memory).
   subroutine computed_imperfection(model, imperfect, error)
      type(model_t), intent(inout) :: model
      type(model_t), intent(out) :: imperfect
      type(error_t), allocatable, intent(out) :: error
      type(model_t) :: perfect
      type(path_driver_t) :: driver
      type(step_outcome_t) :: outcome
      real(dp), allocatable :: mode(:, :)
      real(dp) :: largest
      integer :: wanted, status
      real(dp) :: bytes
      character(len=:), allocatable :: deck
      deck = ''
      if (allocated(model%deck_path)) deck = model%deck_path
      wanted = model%analysis%imperfection_bifurcation
      ! Copies checked component by component (an intrinsic assignment of the record is not).
      call copy_model(model, perfect, status, bytes)
      call allocation_failure(status, 'an array of the perfect structure''s model (*IMPERFECTION)', bytes, &
                              error_analysis, error)
      if (allocated(error)) return
      perfect%analysis%switch_bifurcation = 0
      perfect%analysis%imperfection_bifurcation = 0
      call driver_start(perfect, driver, error)
      if (allocated(error)) then
         call add_context(error, 'the first run on the perfect structure (*IMPERFECTION)', deck)
         return
      end if
      do while (driver%stop == stop_none)
         call driver_step(perfect, driver, outcome, error)
         if (allocated(error)) then
            call add_context(error, 'the first run on the perfect structure (*IMPERFECTION), before bifurcation '// &
                             integer_to_string(wanted), deck)
            return
         end if
         if (allocated(driver%state%bifurcation) .and. driver%state%bifurcations == wanted) then
            call nodal_mode(perfect, driver%state%map, driver%state%bifurcation%mode, mode, error, &
                            keep_sign=driver%state%bifurcation%liftoff)
            if (allocated(error)) then
               call add_context(error, 'the first run on the perfect structure (*IMPERFECTION)', deck)
               return
            end if
            largest = maxval(sqrt(mode(1, :)**2 + mode(2, :)**2))
            call copy_model(model, imperfect, status, bytes)
            call allocation_failure(status, 'an array of the imperfect model (*IMPERFECTION)', bytes, &
                                    error_analysis, error)
            if (allocated(error)) return
            imperfect%coordinates(:, :) = model%coordinates + &
                                          (model%analysis%imperfection_amplitude/largest)*mode(1:2, :)
            return
         end if
      end do
      call make_error(error, 'the first run on the perfect structure (*IMPERFECTION) located '// &
                      integer_to_string(driver%state%bifurcations)//' bifurcation(s) up to step '// &
                      integer_to_string(driver%state%point%step)//' (lambda = '// &
                      real_to_string(driver%state%lambda, '(es12.5)')//'), where its path stops, not bifurcation '// &
                      integer_to_string(wanted)//': no mode to add', error_analysis)
   end subroutine computed_imperfection

end module uniarc_path_imperfection
