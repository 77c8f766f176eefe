!> Where a run's result tables come from: the uniarc version, the deck as given on the command line,
!> the `-D NAME=VALUE` overrides and the time of the run in UTC. The tables carry these as comment
!> lines under their header (docs/contracts.md), which numpy, pandas and gnuplot skip.
!>
!> The time is the clock's (date_and_time, converted from local time with its zone offset), or, when
!> the environment variable SOURCE_DATE_EPOCH holds a number of seconds since 1970-01-01 00:00 UTC,
!> that time (the reproducible-builds convention), so that two runs can give byte-identical files.
module uniarc_provenance
   use, intrinsic :: iso_fortran_env, only: int64
   use uniarc_deck, only: parameter_override_t
   implicit none
   private
   public :: provenance_t, make_provenance, provenance_lines, utc_timestamp, days_from_civil, &
             civil_from_days

   !> What the provenance lines of a run's tables say.
   type :: provenance_t
      character(len=:), allocatable :: version   !< e.g. `uniarc 0.1.0`
      character(len=:), allocatable :: deck      !< the deck's path as given on the command line
      character(len=:), allocatable :: defines   !< `NAME=VALUE` of every -D, blank separated; '' if none
      character(len=:), allocatable :: utc_time  !< ISO 8601, `2026-12-01T03:04:05Z`
   end type provenance_t

contains

   !> The provenance of a run of `version` on `deck` with the command line's -D `overrides` (written
   !> `NAME=VALUE` in their order), stamped with the current time (or SOURCE_DATE_EPOCH, see above).
   function make_provenance(version, deck, overrides) result(provenance)
      character(len=*), intent(in) :: version, deck
      type(parameter_override_t), intent(in) :: overrides(:)
      type(provenance_t) :: provenance
      integer :: i
      provenance%version = version
      provenance%deck = deck
      provenance%defines = ''
      do i = 1, size(overrides)
         if (i > 1) provenance%defines = provenance%defines//' '
         provenance%defines = provenance%defines//overrides(i)%name//'='//without_blanks(overrides(i)%value)
      end do
      provenance%utc_time = utc_timestamp()
   end function make_provenance

   !> `text` without its blanks (an expression means the same without them; the defines line is blank
   !> separated).
   pure function without_blanks(text) result(packed)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: packed
      integer :: i
      packed = ''
      do i = 1, len(text)
         if (text(i:i) /= ' ') packed = packed//text(i:i)
      end do
   end function without_blanks

   !> The comment lines of the provenance, in this order (docs/contracts.md):
   !> `# uniarc 0.1.0`, `# deck: PATH`, `# defines: NAME=VALUE ...` (`none` without -D), `# utc: TIME`.
   !> Lines of a provenance never made (version unallocated) are none at all.
   function provenance_lines(provenance) result(lines)
      type(provenance_t), intent(in) :: provenance
      character(len=:), allocatable :: lines(:)
      character(len=:), allocatable :: defines
      integer :: width
      if (.not. allocated(provenance%version)) then
         allocate (character(len=0) :: lines(0))
         return
      end if
      defines = 'none'
      if (allocated(provenance%defines)) then
         if (len(provenance%defines) > 0) defines = provenance%defines
      end if
      width = max(len(provenance%version) + 2, len(provenance%deck) + 8, len(defines) + 11, &
                  len(provenance%utc_time) + 7)
      allocate (character(len=width) :: lines(4))
      lines(1) = '# '//provenance%version
      lines(2) = '# deck: '//provenance%deck
      lines(3) = '# defines: '//defines
      lines(4) = '# utc: '//provenance%utc_time
   end function provenance_lines

   !> The time now in UTC as `YYYY-MM-DDThh:mm:ssZ` (ISO 8601), or SOURCE_DATE_EPOCH's if it is set
   !> to a whole number of seconds.
   function utc_timestamp() result(text)
      character(len=:), allocatable :: text
      integer :: values(8), status, length
      integer(int64) :: seconds
      character(len=32) :: epoch
      call get_environment_variable('SOURCE_DATE_EPOCH', epoch, length, status)
      if (status == 0 .and. length > 0) then
         read (epoch, *, iostat=status) seconds
         if (status == 0) then
            text = timestamp_of(seconds)
            return
         end if
      end if
      ! values: year, month, day, minutes ahead of UTC, hour, minute, second, millisecond
      call date_and_time(values=values)
      seconds = 86400_int64*days_from_civil(values(1), values(2), values(3)) + &
                3600_int64*values(5) + 60_int64*(values(6) - values(4)) + values(7)
      text = timestamp_of(seconds)
   end function utc_timestamp

   !> `YYYY-MM-DDThh:mm:ssZ` of a time in seconds since 1970-01-01 00:00 UTC.
   pure function timestamp_of(seconds) result(text)
      integer(int64), intent(in) :: seconds
      character(len=20) :: text
      integer(int64) :: days, rest
      integer :: year, month, day
      days = seconds/86400_int64
      rest = seconds - 86400_int64*days
      if (rest < 0) then   ! before 1970: Fortran's division truncates toward zero
         days = days - 1
         rest = rest + 86400_int64
      end if
      call civil_from_days(days, year, month, day)
      write (text, '(i4.4,"-",i2.2,"-",i2.2,"T",i2.2,":",i2.2,":",i2.2,"Z")') year, month, day, &
         int(rest/3600), int(mod(rest, 3600_int64)/60), int(mod(rest, 60_int64))
   end function timestamp_of

   !> Days from 1970-01-01 to the date year-month-day of the proleptic Gregorian calendar (negative
   !> before). H. Hinnant, "chrono-Compatible Low-Level Date Algorithms", days_from_civil: years counted
   !> from March, so that the leap day ends the year, in 400-year eras of 146097 days.
   pure function days_from_civil(year, month, day) result(days)
      integer, intent(in) :: year, month, day
      integer(int64) :: days
      integer(int64) :: y, era, year_of_era, day_of_year, day_of_era
      y = year
      if (month <= 2) y = y - 1
      era = merge(y, y - 399, y >= 0)/400
      year_of_era = y - era*400
      day_of_year = (153*(month + merge(-3, 9, month > 2)) + 2)/5 + day - 1
      day_of_era = year_of_era*365 + year_of_era/4 - year_of_era/100 + day_of_year
      days = era*146097 + day_of_era - 719468
   end function days_from_civil

   !> The date of the day `days` after 1970-01-01 (proleptic Gregorian); the inverse of
   !> days_from_civil (Hinnant, civil_from_days).
   pure subroutine civil_from_days(days, year, month, day)
      integer(int64), intent(in) :: days
      integer, intent(out) :: year, month, day
      integer(int64) :: z, era, day_of_era, year_of_era, day_of_year, mp
      z = days + 719468
      era = merge(z, z - 146096, z >= 0)/146097
      day_of_era = z - era*146097
      year_of_era = (day_of_era - day_of_era/1460 + day_of_era/36524 - day_of_era/146096)/365
      day_of_year = day_of_era - (365*year_of_era + year_of_era/4 - year_of_era/100)
      mp = (5*day_of_year + 2)/153
      day = int(day_of_year - (153*mp + 2)/5 + 1)
      month = int(merge(mp + 3, mp - 9, mp < 10))
      year = int(year_of_era + era*400)
      if (month <= 2) year = year + 1
   end subroutine civil_from_days

end module uniarc_provenance
