!> Arithmetic expressions of the input deck: every numeric field of a deck is one.
!>
!> Grammar (recursive descent; one routine per rule, lowest precedence first):
!>
!>     sum     = product { ('+' | '-') product }
!>     product = unary { ('*' | '/') unary }
!>     unary   = ('+' | '-') unary | power
!>     power   = primary [ '**' unary ]          (right associative: 2**3**2 = 2**9)
!>     primary = number | name | name '(' sum { ',' sum } ')' | '(' sum ')'
!>
!> so that, as in Fortran and in mathematics, `-2**2` is -4 and `2**-1` is 0.5. Numbers take `e`, `E`,
!> `d` or `D` exponents. Names are `pi`, the parameters of a `parameter_table_t`, and the functions
!> listed in `function_names` (trigonometry in radians; `sind`, `cosd`, `tand` take degrees).
!>
!> Nothing here may raise a floating-point exception, since Debug builds trap them: every operation that
!> could overflow, divide by zero or leave its domain is checked first and reported as an input error,
!> with the column of the operator or function that failed.
!>
!> Nesting is bounded: each parenthesis, function call, sign and power's exponent opens a level (the
!> grammar recurses there and nowhere else), and more than `max_nesting_depth` open levels are refused
!> at the column of the one too many, so that no expression can exhaust the stack (issue 14).
module uniarc_expression
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input
   use uniarc_strings, only: is_digit, is_letter, is_blank, to_lower, same_text, real_to_string, &
                             integer_to_string
   use uniarc_parameter_table, only: parameter_table_t, set_parameter, find_parameter, parameter_value
   implicit none
   private
   public :: parameter_table_t
   public :: evaluate_expression, set_parameter, find_parameter, is_reserved_name
   public :: evaluate_integer, is_whole_number
   public :: sin_degrees, cos_degrees, pi
   public :: max_nesting_depth

   !> Most levels an expression may nest: parentheses, function calls, signs and powers' exponents
   !> (`-(2*(x + 1))**-2` opens 4). A level of function call, the dearest, takes 1–1.5 KiB of stack
   !> (256 nested calls need between 256 and 384 KiB, Release and Debug builds alike): the limit uses
   !> under 0.4 MiB of the usual 8 MiB stack.
   integer, parameter :: max_nesting_depth = 256

   !> π to double precision.
   real(dp), parameter :: pi = 3.14159265358979323846264338327950288_dp

   !> Largest x with exp(x) finite, and with it the largest |a| that stays finite in a**b.
   real(dp), parameter :: log_huge = 709.0_dp

   !> Names a parameter may not take: the constant and the functions.
   character(len=*), parameter :: function_names(19) = [character(len=7) :: &
      'sin', 'cos', 'tan', 'asin', 'acos', 'atan', 'atan2', 'sqrt', 'exp', 'log', 'log10', 'abs', &
      'min', 'max', 'sind', 'cosd', 'tand', 'deg2rad', 'rad2deg']

   !> Kinds of token.
   integer, parameter :: token_end = 0, token_number = 1, token_name = 2, token_plus = 3, &
                         token_minus = 4, token_times = 5, token_divide = 6, token_power = 7, &
                         token_open = 8, token_close = 9, token_comma = 10, token_bad = 11

   !> The parser's state: the text, the current token and where it is.
   type :: parser_t
      character(len=:), allocatable :: text
      integer :: position = 1        !< first character after the current token
      integer :: kind = token_end     !< current token
      integer :: start = 1           !< column of the current token
      real(dp) :: number = 0.0_dp    !< value of a number token
      character(len=:), allocatable :: lexeme
      integer :: depth = 0           !< levels open (parentheses, calls, signs, exponents)
   end type parser_t

contains

   !> Evaluate `text` with the parameters of `table`.
   !>
   !> On failure `error` holds "what was expected, found 'x'" (no position) and `column` the 1-based
   !> column within `text` where the fault lies, so the caller can point at it in the original line.
   subroutine evaluate_expression(text, table, value, error, column)
      character(len=*), intent(in) :: text
      type(parameter_table_t), intent(in) :: table
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: column
      type(parser_t) :: parser

      value = 0.0_dp
      column = 0
      parser%text = text
      parser%position = 1
      call next_token(parser)
      if (parser%kind == token_end) then
         call fail(parser, parser%start, 'expected an expression, found nothing', error, column)
         return
      end if
      call parse_sum(parser, table, value, error, column)
      if (allocated(error)) return
      if (parser%kind /= token_end) then
         call fail(parser, parser%start, 'expected an operator or the end of the expression, found '// &
                   found(parser), error, column)
      end if
   end subroutine evaluate_expression

   !> Evaluate `text` as an integer field (a label or a count): the value must be a whole number within
   !> the default integer range. Errors as for `evaluate_expression`.
   subroutine evaluate_integer(text, table, value, error, column)
      character(len=*), intent(in) :: text
      type(parameter_table_t), intent(in) :: table
      integer, intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: column
      real(dp) :: real_value

      value = 0
      call evaluate_expression(text, table, real_value, error, column)
      if (allocated(error)) return
      if (abs(real_value) >= real(huge(1), dp) .or. .not. is_whole_number(real_value)) then
         call make_error(error, 'expected an integer, found '''//shortened(trim(text))//''' = '// &
                         real_to_string(real_value), error_input)
         column = max(1, verify(text, ' '//achar(9)))
         return
      end if
      value = nint(real_value)
   end subroutine evaluate_integer

   !> True when `x` is exactly a whole number. The test is meant to be exact (no tolerance), and is
   !> written with `<=` so that -Wcompare-reals sees it is.
   elemental logical function is_whole_number(x)
      real(dp), intent(in) :: x
      is_whole_number = abs(x - aint(x)) <= 0.0_dp
   end function is_whole_number

   !> True for `pi` and the function names, which a parameter may not shadow.
   pure logical function is_reserved_name(name)
      character(len=*), intent(in) :: name
      integer :: i
      is_reserved_name = same_text(name, 'pi')
      do i = 1, size(function_names)
         if (same_text(name, function_names(i))) is_reserved_name = .true.
      end do
   end function is_reserved_name

   !> sin of an angle in degrees, exact (0 or ±1) at multiples of 90°, so that e.g. the crown node of an
   !> arc from 0° to 180° lies exactly on the axis of symmetry.
   elemental real(dp) function sin_degrees(angle)
      real(dp), intent(in) :: angle
      real(dp) :: reduced
      reduced = modulo(angle, 360.0_dp)
      if (is_whole_number(reduced/90.0_dp)) then
         select case (nint(reduced/90.0_dp))
         case (1)
            sin_degrees = 1.0_dp
         case (3)
            sin_degrees = -1.0_dp
         case default
            sin_degrees = 0.0_dp
         end select
      else
         sin_degrees = sin(reduced*(pi/180.0_dp))
      end if
   end function sin_degrees

   !> cos of an angle in degrees, exact at multiples of 90° (see `sin_degrees`).
   elemental real(dp) function cos_degrees(angle)
      real(dp), intent(in) :: angle
      cos_degrees = sin_degrees(angle + 90.0_dp)
   end function cos_degrees

   ! ------------------------------------------------------------------------------------------------
   ! Grammar rules
   ! ------------------------------------------------------------------------------------------------

   !> sum = product { ('+' | '-') product }
   recursive subroutine parse_sum(parser, table, value, error, column)
      type(parser_t), intent(inout) :: parser
      type(parameter_table_t), intent(in) :: table
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: column
      real(dp) :: right
      integer :: operator, operator_column

      call parse_product(parser, table, value, error, column)
      if (allocated(error)) return
      do while (parser%kind == token_plus .or. parser%kind == token_minus)
         operator = parser%kind
         operator_column = parser%start
         call next_token(parser)
         call parse_product(parser, table, right, error, column)
         if (allocated(error)) return
         if (operator == token_minus) right = -right
         ! |a + b| overflows only when a and b have one sign and |a| > huge - |b|
         if ((value > 0.0_dp .eqv. right > 0.0_dp) .and. abs(value) > huge(1.0_dp) - abs(right)) then
            call fail(parser, operator_column, 'expected a result below 1e308, found an overflow', error, column)
            return
         end if
         value = value + right
      end do
   end subroutine parse_sum

   !> product = unary { ('*' | '/') unary }
   recursive subroutine parse_product(parser, table, value, error, column)
      type(parser_t), intent(inout) :: parser
      type(parameter_table_t), intent(in) :: table
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: column
      real(dp) :: right
      integer :: operator, operator_column

      call parse_unary(parser, table, value, error, column)
      if (allocated(error)) return
      do while (parser%kind == token_times .or. parser%kind == token_divide)
         operator = parser%kind
         operator_column = parser%start
         call next_token(parser)
         call parse_unary(parser, table, right, error, column)
         if (allocated(error)) return
         if (operator == token_times) then
            if (abs(right) > 1.0_dp) then
               if (abs(value) > huge(1.0_dp)/abs(right)) then
                  call fail(parser, operator_column, 'expected a result below 1e308, found an overflow', &
                            error, column)
                  return
               end if
            end if
            value = value*right
         else
            ! a subnormal divisor is refused too: almost any numerator would overflow
            if (abs(right) < tiny(1.0_dp)) then
               call fail(parser, operator_column, 'expected a nonzero divisor, found a division by zero', &
                         error, column)
               return
            end if
            if (abs(right) < 1.0_dp) then
               if (abs(value) > huge(1.0_dp)*abs(right)) then
                  call fail(parser, operator_column, 'expected a result below 1e308, found an overflow', &
                            error, column)
                  return
               end if
            end if
            value = value/right
         end if
      end do
   end subroutine parse_product

   !> unary = ('+' | '-') unary | power
   recursive subroutine parse_unary(parser, table, value, error, column)
      type(parser_t), intent(inout) :: parser
      type(parameter_table_t), intent(in) :: table
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: column
      integer :: operator

      if (parser%kind == token_plus .or. parser%kind == token_minus) then
         operator = parser%kind
         call open_level(parser, error, column)
         if (allocated(error)) return
         call next_token(parser)
         call parse_unary(parser, table, value, error, column)
         if (allocated(error)) return
         parser%depth = parser%depth - 1
         if (operator == token_minus) value = -value
      else
         call parse_power(parser, table, value, error, column)
      end if
   end subroutine parse_unary

   !> power = primary [ '**' unary ]; the exponent is a unary, which makes '**' right associative.
   recursive subroutine parse_power(parser, table, value, error, column)
      type(parser_t), intent(inout) :: parser
      type(parameter_table_t), intent(in) :: table
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: column
      real(dp) :: exponent
      integer :: operator_column

      call parse_primary(parser, table, value, error, column)
      if (allocated(error)) return
      if (parser%kind /= token_power) return
      operator_column = parser%start
      call open_level(parser, error, column)
      if (allocated(error)) return
      call next_token(parser)
      call parse_unary(parser, table, exponent, error, column)
      if (allocated(error)) return
      parser%depth = parser%depth - 1
      call checked_power(value, exponent, error)
      if (allocated(error)) then
         column = operator_column
         return
      end if
   end subroutine parse_power

   !> primary = number | name | name '(' arguments ')' | '(' sum ')'
   recursive subroutine parse_primary(parser, table, value, error, column)
      type(parser_t), intent(inout) :: parser
      type(parameter_table_t), intent(in) :: table
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: column
      character(len=:), allocatable :: name
      integer :: name_column, i

      value = 0.0_dp
      select case (parser%kind)
      case (token_number)
         value = parser%number
         call next_token(parser)
      case (token_open)
         call open_level(parser, error, column)
         if (allocated(error)) return
         call next_token(parser)
         call parse_sum(parser, table, value, error, column)
         if (allocated(error)) return
         if (parser%kind /= token_close) then
            call fail(parser, parser%start, 'expected '')'', found '//found(parser), error, column)
            return
         end if
         parser%depth = parser%depth - 1
         call next_token(parser)
      case (token_name)
         name = parser%lexeme
         name_column = parser%start
         call next_token(parser)
         if (parser%kind == token_open) then
            call parse_call(parser, table, name, name_column, value, error, column)
            return
         end if
         if (same_text(name, 'pi')) then
            value = pi
            return
         end if
         i = find_parameter(table, name)
         if (i == 0) then
            do i = 1, size(function_names)
               if (same_text(name, function_names(i))) then
                  call fail(parser, parser%start, 'expected ''('' after the function '''//name// &
                            ''', found '//found(parser), error, column)
                  return
               end if
            end do
            call fail(parser, name_column, 'expected a defined parameter, found '''//shortened(name)//'''', &
                      error, column)
            return
         end if
         value = parameter_value(table, i)
      case (token_bad)
         call fail(parser, parser%start, parser%lexeme, error, column)
      case default
         call fail(parser, parser%start, 'expected a number, a name or ''('', found '//found(parser), &
                   error, column)
      end select
   end subroutine parse_primary

   !> name '(' sum { ',' sum } ')' with the current token on '('.
   recursive subroutine parse_call(parser, table, name, name_column, value, error, column)
      type(parser_t), intent(inout) :: parser
      type(parameter_table_t), intent(in) :: table
      character(len=*), intent(in) :: name
      integer, intent(in) :: name_column
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: column
      real(dp) :: arguments(64)
      integer :: count
      character(len=:), allocatable :: message

      value = 0.0_dp
      count = 0
      call open_level(parser, error, column)
      if (allocated(error)) return
      call next_token(parser)
      do
         if (count == size(arguments)) then
            call fail(parser, parser%start, 'expected at most 64 arguments, found more', error, column)
            return
         end if
         count = count + 1
         call parse_sum(parser, table, arguments(count), error, column)
         if (allocated(error)) return
         if (parser%kind == token_comma) then
            call next_token(parser)
            cycle
         end if
         if (parser%kind == token_close) exit
         call fail(parser, parser%start, 'expected '','' or '')'', found '//found(parser), error, column)
         return
      end do
      parser%depth = parser%depth - 1
      call next_token(parser)
      call apply_function(to_lower(name), arguments(1:count), value, message)
      if (allocated(message)) call fail(parser, name_column, message, error, column)
   end subroutine parse_call

   ! ------------------------------------------------------------------------------------------------
   ! Checked arithmetic
   ! ------------------------------------------------------------------------------------------------

   !> value = value ** exponent, refusing what would be NaN or infinite.
   !>
   !> Integral exponents use the integer power (exact for small cases and defined for negative bases);
   !> the size of the result is bounded beforehand through |e·log|a|| ≤ log_huge.
   subroutine checked_power(value, exponent, error)
      real(dp), intent(inout) :: value
      real(dp), intent(in) :: exponent
      type(error_t), allocatable, intent(out) :: error
      logical :: integral

      integral = .false.
      if (abs(exponent) < 1.0e9_dp) integral = is_whole_number(exponent)
      if (abs(value) < tiny(1.0_dp)) then
         if (exponent < 0.0_dp) then
            call make_error(error, 'expected a nonzero base for a negative power, found 0**' // &
                            real_to_string(exponent), error_input)
         else if (.not. exponent > 0.0_dp) then
            value = 1.0_dp   ! 0**0, as Fortran defines it
         end if
         return
      end if
      if (value < 0.0_dp .and. .not. integral) then
         call make_error(error, 'expected an integer power of a negative number, found ' // &
                         base_text(value)//'**'//real_to_string(exponent), error_input)
         return
      end if
      ! only overflow is refused: a result that underflows to zero is harmless (not trapped)
      if (exponent*log(abs(value)) > log_huge) then
         call make_error(error, 'expected a result below 1e308, found ' // &
                         base_text(value)//'**'//real_to_string(exponent), error_input)
         return
      end if
      if (integral) then
         value = value**nint(exponent)
      else
         value = value**exponent
      end if
   end subroutine checked_power

   !> Evaluate a function; `message` is allocated (and `value` meaningless) when the arguments are not
   !> in its domain or their number is wrong.
   pure subroutine apply_function(name, arguments, value, message)
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: arguments(:)
      real(dp), intent(out) :: value
      character(len=:), allocatable, intent(out) :: message
      real(dp) :: x

      value = 0.0_dp
      select case (name)
      case ('min', 'max')
         if (size(arguments) < 2) then
            message = 'expected at least 2 arguments of '''//name//''', found 1'
            return
         end if
         if (name == 'min') value = minval(arguments)
         if (name == 'max') value = maxval(arguments)
         return
      case ('atan2')
         if (size(arguments) /= 2) then
            message = 'expected 2 arguments of ''atan2'', found '//integer_to_string(size(arguments))
            return
         end if
         if (abs(arguments(1)) < tiny(1.0_dp) .and. abs(arguments(2)) < tiny(1.0_dp)) then
            message = 'expected a nonzero point for ''atan2'', found atan2(0, 0)'
            return
         end if
         value = atan2(arguments(1), arguments(2))
         return
      case ('sin', 'cos', 'tan', 'asin', 'acos', 'atan', 'sqrt', 'exp', 'log', 'log10', 'abs', &
            'sind', 'cosd', 'tand', 'deg2rad', 'rad2deg')
         if (size(arguments) /= 1) then
            message = 'expected 1 argument of '''//name//''', found '//integer_to_string(size(arguments))
            return
         end if
      case default
         message = 'expected a known function, found '''//shortened(name)//''''
         return
      end select

      x = arguments(1)
      select case (name)
      case ('sin')
         value = sin(x)
      case ('cos')
         value = cos(x)
      case ('tan')
         value = tan(x)
      case ('atan')
         value = atan(x)
      case ('abs')
         value = abs(x)
      case ('sind')
         value = sin_degrees(x)
      case ('cosd')
         value = cos_degrees(x)
      case ('tand')
         if (abs(cos_degrees(x)) < tiny(1.0_dp)) then
            message = 'expected an angle that is not an odd multiple of 90 for ''tand'', found ' // &
                      real_to_string(x)
            return
         end if
         value = sin_degrees(x)/cos_degrees(x)
      case ('deg2rad')
         value = x*(pi/180.0_dp)
      case ('rad2deg')
         if (abs(x) > 1.0e300_dp) then
            message = 'expected an angle below 1e300 for ''rad2deg'', found '//real_to_string(x)
            return
         end if
         value = x*(180.0_dp/pi)
      case ('asin', 'acos')
         if (abs(x) > 1.0_dp) then
            message = 'expected an argument in [-1, 1] for '''//name//''', found '//real_to_string(x)
            return
         end if
         if (name == 'asin') value = asin(x)
         if (name == 'acos') value = acos(x)
      case ('sqrt')
         if (x < 0.0_dp) then
            message = 'expected a non-negative argument for ''sqrt'', found '//real_to_string(x)
            return
         end if
         value = sqrt(x)
      case ('exp')
         if (x > log_huge) then
            message = 'expected an argument below 709 for ''exp'', found '//real_to_string(x)
            return
         end if
         value = exp(x)
      case ('log', 'log10')
         if (x <= 0.0_dp) then
            message = 'expected a positive argument for '''//name//''', found '//real_to_string(x)
            return
         end if
         if (name == 'log') value = log(x)
         if (name == 'log10') value = log10(x)
      end select
   end subroutine apply_function

   !> A base of a power as it would be written: negative numbers in parentheses.
   pure function base_text(value) result(text)
      real(dp), intent(in) :: value
      character(len=:), allocatable :: text
      if (value < 0.0_dp) then
         text = '('//real_to_string(value)//')'
      else
         text = real_to_string(value)
      end if
   end function base_text

   ! ------------------------------------------------------------------------------------------------
   ! Tokens
   ! ------------------------------------------------------------------------------------------------

   !> Move to the next token. A malformed number becomes a token_bad whose lexeme is the message.
   pure subroutine next_token(parser)
      type(parser_t), intent(inout) :: parser
      integer :: n, i
      character(len=1) :: c

      n = len(parser%text)
      i = parser%position
      do while (i <= n)
         if (.not. is_blank(parser%text(i:i))) exit
         i = i + 1
      end do
      parser%start = i
      if (i > n) then
         parser%kind = token_end
         parser%lexeme = ''
         parser%position = i
         return
      end if
      c = parser%text(i:i)
      parser%position = i + 1
      parser%lexeme = c
      select case (c)
      case ('+')
         parser%kind = token_plus
      case ('-')
         parser%kind = token_minus
      case ('/')
         parser%kind = token_divide
      case ('(')
         parser%kind = token_open
      case (')')
         parser%kind = token_close
      case (',')
         parser%kind = token_comma
      case ('*')
         parser%kind = token_times
         if (i < n) then
            if (parser%text(i + 1:i + 1) == '*') then
               parser%kind = token_power
               parser%lexeme = '**'
               parser%position = i + 2
            end if
         end if
      case default
         if (is_digit(c) .or. c == '.') then
            call read_number(parser, i)
         else if (is_letter(c)) then
            parser%position = i
            do while (parser%position <= n)
               c = parser%text(parser%position:parser%position)
               if (.not. (is_letter(c) .or. is_digit(c) .or. c == '_')) exit
               parser%position = parser%position + 1
            end do
            parser%kind = token_name
            parser%lexeme = parser%text(i:parser%position - 1)
         else
            parser%kind = token_bad
            parser%lexeme = 'expected a number, a name, an operator or a parenthesis, found '''//c//''''
         end if
      end select
   end subroutine next_token

   !> Scan digits [. digits] [(e|E|d|D) [+|-] digits] starting at `first` and convert them.
   !>
   !> The decimal exponent of the leading digit is worked out from the text before conversion, so
   !> that a number that would overflow (1e400) is refused instead of trapping.
   pure subroutine read_number(parser, first)
      type(parser_t), intent(inout) :: parser
      integer, intent(in) :: first
      integer :: n, i, integer_digits, fraction_digits, leading_zeros, exponent_value, exponent_start
      integer :: status, magnitude
      logical :: seen_nonzero, in_fraction
      character(len=:), allocatable :: literal
      character(len=1) :: c

      n = len(parser%text)
      i = first
      integer_digits = 0
      fraction_digits = 0
      leading_zeros = 0
      seen_nonzero = .false.
      in_fraction = .false.
      do while (i <= n)
         c = parser%text(i:i)
         if (c == '.' .and. .not. in_fraction) then
            in_fraction = .true.
         else if (is_digit(c)) then
            if (in_fraction) then
               fraction_digits = fraction_digits + 1
            else
               integer_digits = integer_digits + 1
            end if
            if (c /= '0') seen_nonzero = .true.
            if (.not. seen_nonzero) leading_zeros = leading_zeros + 1
         else
            exit
         end if
         i = i + 1
      end do
      parser%kind = token_bad
      parser%start = first
      if (integer_digits + fraction_digits == 0) then
         parser%lexeme = 'expected digits in a number, found '''//shortened(parser%text(first:i - 1))//''''
         parser%position = i
         return
      end if

      exponent_value = 0
      if (i <= n) then
         c = parser%text(i:i)
         if (c == 'e' .or. c == 'E' .or. c == 'd' .or. c == 'D') then
            i = i + 1
            exponent_start = i
            if (i <= n) then
               if (parser%text(i:i) == '+' .or. parser%text(i:i) == '-') i = i + 1
            end if
            do while (i <= n)
               if (.not. is_digit(parser%text(i:i))) exit
               i = i + 1
            end do
            if (i == exponent_start .or. .not. is_digit(parser%text(i - 1:i - 1))) then
               parser%lexeme = 'expected exponent digits in the number, found '''// &
                               shortened(parser%text(first:min(i, n)))//''''
               parser%position = i
               return
            end if
            if (i - exponent_start > 6) then
               parser%lexeme = 'expected a number below 1e308, found '''// &
                               shortened(parser%text(first:i - 1))//''''
               parser%position = i
               return
            end if
            read (parser%text(exponent_start:i - 1), *, iostat=status) exponent_value
         end if
      end if
      parser%position = i
      if (i <= n) then
         if (is_letter(parser%text(i:i)) .or. parser%text(i:i) == '_' .or. parser%text(i:i) == '.') then
            parser%lexeme = 'expected an operator after the number, found '''// &
                            shortened(parser%text(first:i))//''''
            return
         end if
      end if

      if (seen_nonzero) then
         ! decimal exponent of the leading nonzero digit
         magnitude = integer_digits - leading_zeros - 1 + exponent_value
         if (magnitude >= 308) then
            parser%lexeme = 'expected a number below 1e308, found '''// &
                            shortened(parser%text(first:i - 1))//''''
            return
         end if
         if (magnitude < -300) then
            parser%kind = token_number
            parser%number = 0.0_dp
            parser%lexeme = parser%text(first:i - 1)
            return
         end if
      end if
      ! the whole literal goes to the run-time library, which rounds correctly and reads d exponents
      literal = parser%text(first:i - 1)
      if (literal(1:1) == '.') literal = '0'//literal
      read (literal, *, iostat=status) parser%number
      if (status /= 0) then
         parser%lexeme = 'expected a number, found '''//shortened(literal)//''''
         return
      end if
      parser%kind = token_number
      parser%lexeme = parser%text(first:i - 1)
   end subroutine read_number

   !> The current token as a message shows it: quoted, or "the end of the expression".
   !> A token_bad's lexeme is its own error message, so its characters are quoted from the deck's
   !> text instead (issue 14: `1.4 $` quoted the message, not the '$').
   pure function found(parser) result(text)
      type(parser_t), intent(in) :: parser
      character(len=:), allocatable :: text
      if (parser%kind == token_end) then
         text = 'the end of the expression'
      else if (parser%kind == token_bad) then
         text = ''''//shortened(parser%text(parser%start:max(parser%start, parser%position - 1)))//''''
      else
         text = ''''//shortened(parser%lexeme)//''''
      end if
   end function found

   !> At most 40 characters of `text`, for quoting in a message.
   pure function shortened(text) result(short)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: short
      if (len(text) > 40) then
         short = text(1:37)//'...'
      else
         short = text
      end if
   end function shortened

   !> Open a level of nesting at the current token (a parenthesis, a call's '(', a sign, '**'); more
   !> than max_nesting_depth levels open is an error at that token.
   subroutine open_level(parser, error, column)
      type(parser_t), intent(inout) :: parser
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: column
      column = 0
      if (parser%depth == max_nesting_depth) then
         call fail(parser, parser%start, 'expected at most '//integer_to_string(max_nesting_depth)// &
                   ' nested parentheses, function calls, signs and powers, found more', error, column)
         return
      end if
      parser%depth = parser%depth + 1
   end subroutine open_level

   !> Record a failure at `at`.
   subroutine fail(parser, at, message, error, column)
      type(parser_t), intent(in) :: parser
      integer, intent(in) :: at
      character(len=*), intent(in) :: message
      type(error_t), allocatable, intent(out) :: error
      integer, intent(out) :: column
      call make_error(error, message, error_input)
      column = max(1, min(at, len(parser%text) + 1))
   end subroutine fail

end module uniarc_expression
