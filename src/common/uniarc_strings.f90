!> Small string helpers shared by the deck reader and the output writers.
!>
!> Everything here is pure and works on plain `character(len=*)`; results are deferred-length strings.
module uniarc_strings
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: field_t
   public :: to_upper, to_lower, same_text, is_name, is_digit, is_letter, is_blank
   public :: split_fields, first_nonblank, last_nonblank
   public :: integer_to_string, real_to_string
   public :: counted

   !> One comma-separated field of a line: its text (blanks at both ends removed) and the column of
   !> its first character in the line (of the comma's successor when the field is empty).
   type :: field_t
      character(len=:), allocatable :: text
      integer :: column = 1
   end type field_t

contains

   !> Copy of `text` with a–z turned into A–Z (ASCII only, which is all a deck may use in names).
   pure function to_upper(text) result(upper)
      character(len=*), intent(in) :: text
      character(len=len(text)) :: upper
      integer :: i, code
      upper = text
      do i = 1, len(text)
         code = iachar(text(i:i))
         if (code >= iachar('a') .and. code <= iachar('z')) upper(i:i) = achar(code - 32)
      end do
   end function to_upper

   !> Copy of `text` with A–Z turned into a–z.
   pure function to_lower(text) result(lower)
      character(len=*), intent(in) :: text
      character(len=len(text)) :: lower
      integer :: i, code
      lower = text
      do i = 1, len(text)
         code = iachar(text(i:i))
         if (code >= iachar('A') .and. code <= iachar('Z')) lower(i:i) = achar(code + 32)
      end do
   end function to_lower

   !> True when `a` and `b` are equal ignoring case and trailing blanks (deck names are case-insensitive).
   pure logical function same_text(a, b)
      character(len=*), intent(in) :: a, b
      same_text = to_upper(trim(a)) == to_upper(trim(b))
   end function same_text

   !> True for a decimal digit.
   elemental logical function is_digit(c)
      character(len=1), intent(in) :: c
      is_digit = c >= '0' .and. c <= '9'
   end function is_digit

   !> True for an ASCII letter.
   elemental logical function is_letter(c)
      character(len=1), intent(in) :: c
      is_letter = (c >= 'a' .and. c <= 'z') .or. (c >= 'A' .and. c <= 'Z')
   end function is_letter

   !> True for a blank or a tab (a tab in a deck separates like a blank).
   elemental logical function is_blank(c)
      character(len=1), intent(in) :: c
      is_blank = c == ' ' .or. c == achar(9)
   end function is_blank

   !> True when `text` is a name: a letter, then letters, digits and underscores.
   pure logical function is_name(text)
      character(len=*), intent(in) :: text
      integer :: i
      is_name = .false.
      if (len(text) == 0) return
      if (.not. is_letter(text(1:1))) return
      do i = 2, len(text)
         if (.not. (is_letter(text(i:i)) .or. is_digit(text(i:i)) .or. text(i:i) == '_')) return
      end do
      is_name = .true.
   end function is_name

   !> Position of the first character of `text` that is not a blank or tab (0 if none).
   pure integer function first_nonblank(text)
      character(len=*), intent(in) :: text
      integer :: i
      first_nonblank = 0
      do i = 1, len(text)
         if (.not. is_blank(text(i:i))) then
            first_nonblank = i
            return
         end if
      end do
   end function first_nonblank

   !> Position of the last character of `text` that is not a blank or tab (0 if none).
   pure integer function last_nonblank(text)
      character(len=*), intent(in) :: text
      integer :: i
      last_nonblank = 0
      do i = len(text), 1, -1
         if (.not. is_blank(text(i:i))) then
            last_nonblank = i
            return
         end if
      end do
   end function last_nonblank

   !> Split `text` on the commas that are outside parentheses, so that `max(a, b)` stays one field.
   !>
   !> Each field keeps the column where it starts within `text` (plus `offset`), so that an error in
   !> a field can point at the right column of the original line. A comma at the very end of the text
   !> (a trailing comma) does not open an empty last field.
   pure subroutine split_fields(text, fields, offset)
      character(len=*), intent(in) :: text
      type(field_t), allocatable, intent(out) :: fields(:)
      integer, intent(in), optional :: offset
      integer :: i, depth, start, count, shift, last
      integer :: starts(len(text) + 1), ends(len(text) + 1)

      shift = 0
      if (present(offset)) shift = offset
      last = last_nonblank(text)
      count = 0
      depth = 0
      start = 1
      do i = 1, last
         select case (text(i:i))
         case ('(')
            depth = depth + 1
         case (')')
            depth = max(depth - 1, 0)
         case (',')
            if (depth == 0) then
               count = count + 1
               starts(count) = start
               ends(count) = i - 1
               start = i + 1
            end if
         end select
      end do
      if (start <= last .or. count == 0) then
         count = count + 1
         starts(count) = start
         ends(count) = last
      end if
      if (last == 0) count = 0

      allocate (fields(count))
      do i = 1, count
         call trim_field(text, starts(i), ends(i), fields(i))
         fields(i)%column = fields(i)%column + shift
      end do
   end subroutine split_fields

   !> The field text(first:last) without blanks at its ends, with the column of its first character.
   pure subroutine trim_field(text, first, last, field)
      character(len=*), intent(in) :: text
      integer, intent(in) :: first, last
      type(field_t), intent(out) :: field
      integer :: a, b
      if (last < first) then
         field%text = ''
         field%column = first
         return
      end if
      a = first_nonblank(text(first:last))
      if (a == 0) then
         field%text = ''
         field%column = first
         return
      end if
      b = last_nonblank(text(first:last))
      field%text = text(first + a - 1:first + b - 1)
      field%column = first + a - 1
   end subroutine trim_field

   !> Decimal representation of an integer without blanks.
   pure function integer_to_string(value) result(text)
      integer, intent(in) :: value
      character(len=:), allocatable :: text
      character(len=24) :: buffer
      write (buffer, '(i0)') value
      text = trim(buffer)
   end function integer_to_string

   !> A count and its noun, the noun plural unless the count is 1: "1 critical point", "2 critical
   !> points", "0 steps". The plural is the noun with "s" (the nouns the messages count take it).
   pure function counted(n, noun) result(text)
      integer, intent(in) :: n
      character(len=*), intent(in) :: noun
      character(len=:), allocatable :: text
      text = integer_to_string(n)//' '//noun
      if (n /= 1) text = text//'s'
   end function counted

   !> A real as text, without surrounding blanks: the one real-to-text conversion of the program.
   !>
   !> With `edit` (a Fortran format of one real edit descriptor of at most 48 characters' width, e.g.
   !> '(es21.12e3)', the result files' format), exactly what that format writes. Without it, the readable
   !> form of messages ("found 2.5"): 12 significant digits, fixed notation between 1e-3 and 1e9,
   !> scientific notation outside, trailing zeros of the mantissa removed either way.
   pure function real_to_string(value, edit) result(text)
      real(dp), intent(in) :: value
      character(len=*), intent(in), optional :: edit
      character(len=:), allocatable :: text
      character(len=48) :: buffer
      integer :: e_position, last, digits_before

      if (present(edit)) then
         write (buffer, edit) value
         text = trim(adjustl(buffer))
         ! An E or D edit of an exponent of three digits drops the letter (Fortran 2008, 10.7.2.3.2:
         ! 1.000+100): it is put back, so that the text reads as a number.
         if (scan(text, 'EeDd') == 0) then
            e_position = scan(text(2:), '+-', back=.true.)
            if (e_position > 0) text = text(1:e_position)//'E'//text(e_position + 1:)
         end if
         return
      end if
      if (abs(value) < tiny(1.0_dp)) then
         text = '0'
         return
      end if
      if (abs(value) >= 1.0e-3_dp .and. abs(value) < 1.0e9_dp) then
         ! 12 significant digits: as many decimals as are left after the integer digits
         digits_before = max(1, floor(log10(abs(value))) + 1)
         write (buffer, '(f48.' // integer_to_string(max(12 - digits_before, 1)) // ')') value
         buffer = adjustl(buffer)
         last = len_trim(buffer)
         do while (last > 1 .and. buffer(last:last) == '0')
            last = last - 1
         end do
         if (buffer(last:last) == '.') last = last - 1
         text = buffer(1:last)
         return
      end if
      write (buffer, '(es22.11e3)') value
      buffer = adjustl(buffer)
      e_position = index(buffer, 'E')
      last = e_position - 1
      do while (last > 1 .and. buffer(last:last) == '0')
         last = last - 1
      end do
      if (buffer(last:last) == '.') last = last - 1
      text = buffer(1:last)//'e'//trim_exponent(buffer(e_position + 1:len_trim(buffer)))
   end function real_to_string

   !> '+012' → '12', '-005' → '-5'.
   pure function trim_exponent(exponent_text) result(text)
      character(len=*), intent(in) :: exponent_text
      character(len=:), allocatable :: text
      integer :: exponent_value, status
      read (exponent_text, *, iostat=status) exponent_value
      if (status /= 0) then
         text = exponent_text
      else
         text = integer_to_string(exponent_value)
      end if
   end function trim_exponent

end module uniarc_strings
