!> The text uniarc writes on the console while it runs (not the result files): the progress line of a
!> path step on stderr with its estimate of the time left, durations and rates in words, λ and the
!> like in short form for messages, and the tracked values of a linear static analysis on stdout.
module uniarc_console
   use, intrinsic :: iso_fortran_env, only: output_unit
   use uniarc_kinds, only: dp
   use uniarc_model, only: model_t, tracked_values
   use uniarc_path_driver, only: path_driver_t
   use uniarc_path_pace, only: pace_window_ratio, pace_level
   use uniarc_output, only: step_record_t, format_number
   use uniarc_strings, only: integer_to_string
   implicit none
   private
   public :: progress_line, short_number, print_tracks, step_limit_notes

contains

   !> The progress line of a step on stderr: the step, λ, Newton iterations, contacts, negative pivots,
   !> the share of the target done — the largest of step/max_steps, |λ|/lambda_max and |track|/stop_value,
   !> the stop rule nearest to ending the path, named (max_steps for a path that creeps) — and, from the
   !> rate so far, the time left to it (an estimate: the path may turn or slow down).
   function progress_line(driver, record, elapsed) result(text)
      type(path_driver_t), intent(in) :: driver
      type(step_record_t), intent(in) :: record
      real(dp), intent(in) :: elapsed   !< seconds since the path started
      character(len=:), allocatable :: text
      real(dp) :: done, rate
      character(len=:), allocatable :: target
      ! max_steps counts the steps of the current analysis step (*STEP; step_offset 0 without steps)
      done = real(record%step - driver%step_offset, dp)/real(max(driver%rules%max_steps, 1), dp)
      target = 'max_steps'
      if (driver%rules%lambda_max < huge(1.0_dp)) then
         if (abs(record%lambda)/driver%rules%lambda_max > done) then
            done = abs(record%lambda)/driver%rules%lambda_max
            target = 'lambda_max'
         end if
      end if
      if (driver%rules%track > 0) then
         if (driver%rules%track_limit > 0.0_dp) then
            if (abs(driver%tracked(driver%rules%track))/driver%rules%track_limit > done) then
               done = abs(driver%tracked(driver%rules%track))/driver%rules%track_limit
               target = 'stop_value'
            end if
         end if
      end if
      done = min(done, 1.0_dp)
      rate = real(record%step, dp)/max(elapsed, 1.0e-3_dp)
      text = 'step '//integer_to_string(record%step)//'  lambda '//trim(format_number(record%lambda))// &
             '  iterations '//integer_to_string(record%iterations)//'  contacts '// &
             integer_to_string(record%n_contact)//'  neg_pivots '//integer_to_string(record%neg_pivots)// &
             '  ('//integer_to_string(int(100.0_dp*done))//'% of the target '//target//', '//rate_text(rate)//' steps/s'
      if (done > 0.0_dp .and. done < 1.0_dp) then
         if (elapsed*(1.0_dp - done)/done < 0.5_dp) then
            text = text//', less than 1 s left)'
         else
            text = text//', about '//duration_text(elapsed*(1.0_dp - done)/done)//' left)'
         end if
      else
         text = text//')'
      end if
   end function progress_line

   !> The lines that follow the closing line of a path stopped by its step limit (docs/contracts.md,
   !> "Progress and messages"): the pace of its last steps from the driver's record (uniarc_path_pace) —
   !> how many of the last steps in a row were taken at the largest step (max_increment times the first)
   !> or cut below the first; λ's change over the last tenth of max_steps against its change over all
   !> of them; whether λ's change per step fell at every step of that tenth (with the mean factor and
   !> where λ would level off at that rate, an extrapolation: a limit point may be near, but none is
   !> claimed, since only the locator places one, once a step passes it) — and what to change to go
   !> on. Each line starts with two spaces and ends with a newline; '' when the path has no step.
   function step_limit_notes(driver) result(text)
      type(path_driver_t), intent(in) :: driver
      character(len=:), allocatable :: text
      character(len=*), parameter :: lf = new_line('a')
      real(dp) :: window_change, whole_change, level
      integer :: k
      logical :: levels
      text = ''
      associate (pace => driver%pace)
         if (pace%steps < 1) return
         if (pace%at_cap > 0) then
            if (pace%at_cap == pace%steps) then
               text = text//'  all '//plural(pace%steps, 'step')
            else
               text = text//'  the last '//plural(pace%at_cap, 'step')//' of '//integer_to_string(pace%steps)
            end if
            text = text//' were taken at the largest step, max_increment = '// &
                   short_number(pace%cap_length/pace%first_length)//' times the first'//lf
         end if
         if (pace%below_first > 0) then
            if (pace%below_first == pace%steps) then
               text = text//'  all '//plural(pace%steps, 'step')
            else
               text = text//'  the last '//plural(pace%below_first, 'step')//' of '//integer_to_string(pace%steps)
            end if
            text = text//' were cut below the first increment (an attempt failed or took more iterations '// &
                   'than `iterations`)'//lf
         end if
         if (pace%in_window) then
            k = pace%steps - (pace%max_steps - pace%window)
            window_change = pace%lambda_last - pace%window_lambda
            whole_change = pace%lambda_last - pace%lambda_start
            text = text//'  lambda changed by '//short_number(window_change)//' over the last '// &
                   plural(k, 'step')//' (the last tenth of max_steps), by '//short_number(whole_change)// &
                   ' over all '//integer_to_string(pace%steps)
            ! (the share only where both changes go the same way: past a limit point λ's last change
            ! undoes part of the whole one, and a share of it would mislead)
            if (window_change*whole_change > 0.0_dp) text = text//': '// &
               short_number(100.0_dp*abs(window_change/whole_change))//' % of it in '// &
               short_number(100.0_dp*real(k, dp)/real(pace%steps, dp))//' % of the steps'
            text = text//lf
            if (pace_window_ratio(pace) > 0.0_dp) then
               call pace_level(pace, level, levels)
               text = text//'  its change per step fell at each of those steps, from '// &
                      short_number(pace%window_first_change)//' to '//short_number(pace%last_change)// &
                      ' (by a factor '//short_number(pace_window_ratio(pace))//' a step on average'
               if (levels) text = text//'; lambda would level off near '//short_number(level)// &
                                 ' if it went on falling so'
               text = text//'): a limit point may be near; none is located (the locator places one once a '// &
                      'step passes it)'//lf
            end if
         end if
         text = text//'  to go on: '
         if (pace%at_cap > 0) text = text//'raise max_increment (the last steps were at it) or '
         text = text//'raise steps'//lf
      end associate
   contains
      pure function plural(n, noun) result(words)
         integer, intent(in) :: n
         character(len=*), intent(in) :: noun
         character(len=:), allocatable :: words
         words = integer_to_string(n)//' '//noun
         if (n /= 1) words = words//'s'
      end function plural
   end function step_limit_notes

   !> A duration in seconds as "42 s", "3 min 20 s" or "2 h 05 min".
   function duration_text(seconds) result(text)
      real(dp), intent(in) :: seconds
      character(len=:), allocatable :: text
      integer :: s
      character(len=8) :: minutes
      if (.not. (seconds < 3.6e7_dp)) then
         text = 'more than 10000 h'
         return
      end if
      s = nint(seconds)
      if (s < 60) then
         text = integer_to_string(s)//' s'
      else if (s < 3600) then
         text = integer_to_string(s/60)//' min '//integer_to_string(mod(s, 60))//' s'
      else
         write (minutes, '(i2.2)') mod(s, 3600)/60
         text = integer_to_string(s/3600)//' h '//trim(minutes)//' min'
      end if
   end function duration_text

   !> A rate (steps per second) with three significant digits at most: "727", "52.3", "0.215".
   function rate_text(rate) result(text)
      real(dp), intent(in) :: rate
      character(len=:), allocatable :: text
      if (rate >= 999.5_dp) then
         text = integer_to_string(nint(min(rate, 1.0e9_dp)))
      else if (rate > 0.0_dp) then
         text = short_number(real(nint(rate*10.0_dp**(2 - floor(log10(rate)))), dp)/10.0_dp**(2 - floor(log10(rate))))
      else
         text = '0'
      end if
   end function rate_text

   !> A number for a message with six significant digits and no trailing zeros, in fixed notation from
   !> 1e-4 to 1e6 ("76.219", "0.25", "-208.31"), else in scientific ("1.5e-07").
   function short_number(value) result(text)
      real(dp), intent(in) :: value
      character(len=:), allocatable :: text
      character(len=40) :: buffer
      integer :: magnitude, decimals, e, exponent
      if (.not. (abs(value) <= huge(1.0_dp))) then
         write (buffer, '(g0)') value
         text = trim(adjustl(buffer))
         return
      end if
      if (value == 0.0_dp) then
         text = '0'
         return
      end if
      magnitude = floor(log10(abs(value)))
      if (magnitude >= -4 .and. magnitude < 6) then
         decimals = max(5 - magnitude, 0)
         write (buffer, '(f0.'//integer_to_string(decimals)//')') value
         text = trim(adjustl(buffer))
         if (index(text, '.') > 0) then
            do while (text(len(text):len(text)) == '0')
               text = text(:len(text) - 1)
            end do
            if (text(len(text):len(text)) == '.') text = text(:len(text) - 1)
         end if
         if (text(1:1) == '.') text = '0'//text
         if (text(1:min(2, len(text))) == '-.') text = '-0'//text(2:)
      else
         write (buffer, '(es13.5e3)') value
         text = trim(adjustl(buffer))
         e = index(text, 'E')
         read (text(e + 1:), *) exponent
         text = strip_zeros(text(:e - 1))//'e'//integer_to_string(exponent)
      end if
   contains
      function strip_zeros(mantissa) result(stripped)
         character(len=*), intent(in) :: mantissa
         character(len=:), allocatable :: stripped
         stripped = mantissa
         do while (stripped(len(stripped):len(stripped)) == '0')
            stripped = stripped(:len(stripped) - 1)
         end do
         if (stripped(len(stripped):len(stripped)) == '.') stripped = stripped(:len(stripped) - 1)
      end function strip_zeros
   end function short_number

   subroutine print_tracks(model, record)
      type(model_t), intent(in) :: model
      type(step_record_t), intent(in) :: record
      real(dp), allocatable :: values(:)
      integer :: i
      write (output_unit, '(a,i0,a,i0,a)') 'linear static analysis: ', model%n_nodes, ' nodes, ', &
         model%n_elements, ' elements'
      values = tracked_values(model, record%displacement)
      do i = 1, size(values)
         write (output_unit, '(2x,a,a,a)') model%tracks(i)%name, ' = ', trim(format_number(values(i)))
      end do
   end subroutine print_tracks

end module uniarc_console
