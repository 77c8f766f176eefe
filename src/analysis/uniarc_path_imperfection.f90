!> The imperfection of `*IMPERFECTION` without FILE= (docs/input.md, docs/theory.md §2.6): the buckling
!> mode of the perfect structure's n-th located bifurcation, computed by a first run of the deck's own
!> path, scaled so that its largest nodal translation is the amplitude and added to the initial
!> coordinates — what `*OUTPUT, MODES` and `*IMPERFECTION, FILE=` do in two runs, in one.
module uniarc_path_imperfection
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis, add_context
   use uniarc_strings, only: integer_to_string, real_to_string
   use uniarc_model, only: model_t
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
   !> Errors (error_analysis): the first run fails, or ends by a stop rule before the n-th bifurcation.
   subroutine computed_imperfection(model, imperfect, error)
      type(model_t), intent(in) :: model
      type(model_t), intent(out) :: imperfect
      type(error_t), allocatable, intent(out) :: error
      type(model_t) :: perfect
      type(path_driver_t) :: driver
      type(step_outcome_t) :: outcome
      real(dp), allocatable :: mode(:, :)
      real(dp) :: largest
      integer :: wanted
      character(len=:), allocatable :: deck
      deck = ''
      if (allocated(model%deck_path)) deck = model%deck_path
      wanted = model%analysis%imperfection_bifurcation
      perfect = model
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
            mode = nodal_mode(perfect, driver%state%map, driver%state%bifurcation%mode)
            largest = maxval(sqrt(mode(1, :)**2 + mode(2, :)**2))
            imperfect = model
            imperfect%coordinates = model%coordinates + (model%analysis%imperfection_amplitude/largest)*mode(1:2, :)
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
