!> The text layer of the deck reader: lines, cards, options, data fields and positioned messages.
!>
!> A deck is read whole into memory, then walked card by card (`next_card`), so that every message can
!> quote its line. Messages follow fpm: `FILE:LINE:COL: what was expected, found 'x'`, then the line
!> and a caret under the column. Nothing here knows what a card means; uniarc_deck does.
module uniarc_deck_source
   use, intrinsic :: iso_fortran_env, only: int64
   use uniarc_kinds, only: dp
   use uniarc_foreign, only: file_status, interrupt_signal
   use uniarc_error, only: error_t, make_error, error_input, add_context
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: field_t, split_fields, to_upper, is_name, first_nonblank, last_nonblank, &
                             same_text, integer_to_string
   use uniarc_expression, only: parameter_table_t, evaluate_expression, evaluate_integer
   implicit none
   private
   public :: source_t, card_t, option_t
   public :: read_source, next_card, raise, raise_plain, clip, echo_window
   public :: check_options, option_index, require_option
   public :: data_fields, require_field_count, field_real, field_integer
   public :: max_line_length, max_deck_bytes, max_fields

   !> Longest line a deck may have, in characters (64 MiB).
   integer, parameter :: max_line_length = 67108864

   !> Most comma-separated fields a keyword or data line may have (2**20): each field costs about 64
   !> bytes apart from its text, so that a long line of commas cannot take 30 times its size.
   integer, parameter :: max_fields = 1048576

   !> Largest deck, in bytes (1 GiB): it is held in memory twice while it is split into lines.
   integer(int64), parameter :: max_deck_bytes = 1073741824_int64

   !> Bytes read from the deck at a time.
   integer, parameter :: chunk_bytes = 1048576

   !> A line longer than this is shown in a message as a window of about this width around the column.
   integer, parameter :: echo_width = 120

   !> One line of the deck, tabs replaced by blanks so that columns and carets agree.
   type :: line_t
      character(len=:), allocatable :: text
   end type line_t

   !> The deck's text: the path as given and its lines.
   type :: source_t
      character(len=:), allocatable :: path
      integer :: n_lines = 0
      type(line_t), allocatable :: lines(:)
   end type source_t

   !> An option of a keyword line: `NAME` or `NAME=value`.
   type :: option_t
      character(len=:), allocatable :: name    !< upper case
      character(len=:), allocatable :: value   !< as written; '' for a flag
      logical :: has_value = .false.
      integer :: column = 1                    !< of the name
      integer :: value_column = 1              !< of the value (or just after '=')
   end type option_t

   !> A card: its keyword line and the numbers of its data lines.
   type :: card_t
      character(len=:), allocatable :: keyword   !< upper case, without the '*'
      integer :: line = 0                        !< line number of the keyword line
      integer :: column = 1                      !< column of the '*'
      type(option_t), allocatable :: options(:)
      integer :: n_data = 0
      integer, allocatable :: data_lines(:)      !< line numbers, comments and blanks skipped
   end type card_t

contains

   !> Read the deck `path` into `source`.
   !>
   !> The deck must be a regular file (a directory, a device such as /dev/null or /dev/zero, a FIFO
   !> are refused by name) of at most `max_deck_bytes`; it is read in chunks of `chunk_bytes` and split
   !> at line feeds, in time linear in its size. A trailing carriage return (files written on Windows)
   !> is dropped and tabs become single blanks. A line longer than `line_limit` characters (default
   !> `max_line_length`) is refused at `PATH:LINE:COL`, COL the first character past the limit, and a
   !> card or data line of more than `max_fields` fields at the start of the field too many.
   subroutine read_source(path, source, error, line_limit)
      character(len=*), intent(in) :: path
      type(source_t), intent(out) :: source
      type(error_t), allocatable, intent(out) :: error
      integer, intent(in), optional :: line_limit
      character(len=:), allocatable :: kind, failure, buffer
      character(len=512) :: message
      integer(int64) :: bytes
      integer :: unit, status, offset, limit

      source%path = path
      allocate (source%lines(0))
      limit = max_line_length
      if (present(line_limit)) limit = line_limit
      if (len(path) == 0) then
         call make_error(error, 'the deck: expected the path of a deck file, found an empty argument', error_input)
         return
      end if
      call file_status(path, kind, bytes, failure)
      if (allocated(failure)) then
         call make_error(error, path//': cannot open ('//failure//')', error_input)
         return
      end if
      if (kind /= 'regular file') then
         call make_error(error, path//': expected a regular file as the deck, found a '//kind, error_input)
         return
      end if
      if (bytes > max_deck_bytes) then
         call make_error(error, path//': expected a deck of at most '//integer_to_string(int(max_deck_bytes))// &
                         ' bytes, found '//trim(adjustl(bytes_text(bytes)))//' bytes', error_input)
         return
      end if
      if (bytes == 0) then
         ! A size of 0 is what an empty file reports, and also a kernel file (/proc, /sys) whose text is
         ! made when it is read: read it to its end rather than take it for empty.
         call read_unsized(path, buffer, error)
         if (allocated(error)) return
         call split_lines(buffer, limit, source, error)
         return
      end if
      allocate (character(len=bytes) :: buffer, stat=status)
      if (status /= 0) then
         call make_error(error, path//': cannot hold the deck in memory ('// &
                         integer_to_string(int(bytes))//' bytes)', error_input)
         return
      end if
      call open_deck(path, unit, error)
      if (allocated(error)) return
      do offset = 0, int(bytes) - 1, chunk_bytes
         read (unit, iostat=status, iomsg=message) buffer(offset + 1:min(offset + chunk_bytes, int(bytes)))
         if (is_iostat_end(status)) then
            ! shorter than its reported size (a kernel file of /sys reports a page, 4096 bytes, for a
            ! few bytes of text): read to its end as a file of unknown size
            close (unit)
            call read_unsized(path, buffer, error)
            if (allocated(error)) return
            call split_lines(buffer, limit, source, error)
            return
         end if
         if (status /= 0) then
            call make_error(error, path//': cannot read ('//trim(message)//')', error_input)
            close (unit)
            return
         end if
      end do
      close (unit)
      call split_lines(buffer, limit, source, error)
   end subroutine read_source

   !> `text` := the whole of the file `path` that reports a size of 0 (module procedure read_source),
   !> read to its end as formatted stream records (libgfortran's buffered reads, a line or a chunk of
   !> a long line at a time) into a buffer that doubles as it fills; more than max_deck_bytes is
   !> refused as a deck too large, and a SIGINT or SIGTERM stops the reading (an endless kernel file
   !> such as /proc/self/pagemap is read until either). Errors: error_input, naming the file.
   subroutine read_unsized(path, text, error)
      character(len=*), intent(in) :: path
      character(len=:), allocatable, intent(out) :: text
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: buffer
      character(len=65536) :: chunk
      character(len=512) :: message
      integer :: unit, status, used, got
      integer(int64) :: capacity
      allocate (character(len=65536) :: buffer)
      open (newunit=unit, file=path, status='old', action='read', access='stream', form='formatted', &
            iostat=status, iomsg=message)
      if (status /= 0) then
         call make_error(error, path//': cannot open ('//runtime_reason(message)//')', error_input)
         return
      end if
      used = 0
      do
         if (interrupt_signal() /= 0) then
            call make_error(error, path//': reading stopped by a signal', error_input)
            close (unit)
            return
         end if
         read (unit, '(a)', advance='no', size=got, iostat=status, iomsg=message) chunk
         if (is_iostat_end(status)) exit
         if (status /= 0 .and. .not. is_iostat_eor(status)) then
            call make_error(error, path//': cannot read ('//trim(message)//')', error_input)
            close (unit)
            return
         end if
         ! the chunk read, and a line feed where its record (line) ended
         capacity = int(used, int64) + got + 1
         if (capacity > max_deck_bytes) then
            call make_error(error, path//': expected a deck of at most '// &
                            integer_to_string(int(max_deck_bytes))//' bytes, found more', error_input)
            close (unit)
            return
         end if
         if (capacity > len(buffer)) then
            call grow(buffer, int(min(max(2*int(len(buffer), int64), capacity), max_deck_bytes)), used, status)
            if (status /= 0) then
               call make_error(error, path//': cannot hold the deck in memory ('// &
                               integer_to_string(2*used)//' bytes)', error_input)
               close (unit)
               return
            end if
         end if
         buffer(used + 1:used + got) = chunk(1:got)
         used = used + got
         if (is_iostat_eor(status)) then
            used = used + 1
            buffer(used:used) = achar(10)
         end if
      end do
      close (unit)
      text = buffer(1:used)
   contains
      !> buffer := a buffer of `length` holding its first `used` characters (stat= in `status`).
      subroutine grow(buffer, length, used, status)
         character(len=:), allocatable, intent(inout) :: buffer
         integer, intent(in) :: length, used
         integer, intent(out) :: status
         character(len=:), allocatable :: grown
         allocate (character(len=length) :: grown, stat=status)
         if (status /= 0) return
         grown(1:used) = buffer(1:used)
         call move_alloc(grown, buffer)
      end subroutine grow
   end subroutine read_unsized

   !> `unit` := the deck `path` opened for reading as a stream of bytes; error_input naming the file
   !> and the system's reason when it cannot be opened.
   subroutine open_deck(path, unit, error)
      character(len=*), intent(in) :: path
      integer, intent(out) :: unit
      type(error_t), allocatable, intent(out) :: error
      character(len=512) :: message
      integer :: status
      open (newunit=unit, file=path, status='old', action='read', access='stream', form='unformatted', &
            iostat=status, iomsg=message)
      if (status /= 0) call make_error(error, path//': cannot open ('//runtime_reason(message)//')', error_input)
   end subroutine open_deck

   !> The reason in gfortran's message of a failed OPEN, "Cannot open file 'PATH': REASON", without its
   !> prefix (the caller names the file and says it cannot be opened); the whole message otherwise.
   pure function runtime_reason(message) result(reason)
      character(len=*), intent(in) :: message
      character(len=:), allocatable :: reason
      integer :: at
      reason = trim(message)
      if (index(reason, 'Cannot open file ') /= 1) return
      at = index(reason, "': ", back=.true.)
      if (at > 0) reason = reason(at + 3:)
   end function runtime_reason

   !> Split the deck's text into `source%lines` at line feeds (a last line without one counts).
   subroutine split_lines(text, limit, source, error)
      character(len=*), intent(in) :: text
      integer, intent(in) :: limit
      type(source_t), intent(inout) :: source
      type(error_t), allocatable, intent(out) :: error
      character(len=1), parameter :: line_feed = achar(10), carriage_return = achar(13), tab = achar(9)
      integer :: n, start, length, i, k, status, kept

      n = 0
      start = 1
      do while (start <= len(text))
         n = n + 1
         length = index(text(start:), line_feed)
         if (length == 0) exit
         start = start + length
      end do
      deallocate (source%lines)
      allocate (source%lines(n), stat=status)
      if (status /= 0) then
         call raise_plain(source, 'cannot hold the deck in memory ('//integer_to_string(n)//' lines)', error)
         return
      end if

      start = 1
      do i = 1, n
         length = index(text(start:), line_feed) - 1
         if (length < 0) length = len(text) - start + 1
         associate (line => source%lines(i))
            ! the line's text (less a carriage return before its line feed) allocated with stat= at its
            ! length: the assignment then allocates nothing
            kept = length
            if (length > 0) then
               if (text(start + length - 1:start + length - 1) == carriage_return) kept = length - 1
            end if
            allocate (character(len=kept) :: line%text, stat=status)
            if (status /= 0) then
               call allocation_failure(status, 'the text of line '//integer_to_string(i)//' of the deck', &
                                       real(kept, dp), error_input, error)
               call add_context(error, source%path//':'//integer_to_string(i))
               return
            end if
            line%text(:) = text(start:start + kept - 1)
            start = start + length + 1
            if (len(line%text) > limit) then
               source%n_lines = i
               call raise(source, i, limit + 1, 'expected a line of at most '//integer_to_string(limit)// &
                          ' characters, found '//integer_to_string(len(line%text)), error)
               return
            end if
            do k = 1, len(line%text)
               if (line%text(k:k) == tab) line%text(k:k) = ' '
            end do
            k = field_past_limit(line%text)
            if (k > 0) then
               source%n_lines = i
               call raise(source, i, k, 'expected at most '//integer_to_string(max_fields)// &
                          ' fields in a line, found more', error)
               return
            end if
         end associate
      end do
      source%n_lines = n
   end subroutine split_lines

   !> Column of the first character of field max_fields + 1 of a card or data line (fields split as
   !> `split_fields` does: at commas outside parentheses), 0 when it has no more fields or is a comment.
   pure integer function field_past_limit(text) result(column)
      character(len=*), intent(in) :: text
      integer :: i, depth, commas, first
      column = 0
      first = first_nonblank(text)
      if (first == 0) return
      if (is_comment(text, first)) return
      depth = 0
      commas = 0
      do i = first, len(text)
         select case (text(i:i))
         case ('(')
            depth = depth + 1
         case (')')
            depth = max(depth - 1, 0)
         case (',')
            if (depth > 0) cycle
            commas = commas + 1
            if (commas == max_fields) then
               ! a trailing comma opens no field
               if (last_nonblank(text) > i) column = i + 1
               return
            end if
         end select
      end do
   end function field_past_limit

   !> A byte count as text (64-bit: a deck may be larger than the default integer).
   pure function bytes_text(bytes) result(text)
      integer(int64), intent(in) :: bytes
      character(len=24) :: text
      write (text, '(i0)') bytes
   end function bytes_text

   !> Find the card that starts at or after line `position`; on return `position` is the line after its
   !> last data line. `found` is false at the end of the deck.
   !>
   !> Blank lines and `**` comments are skipped anywhere; a data line before the first card is an error.
   subroutine next_card(source, position, card, found, error)
      type(source_t), intent(in) :: source
      integer, intent(inout) :: position
      type(card_t), intent(out) :: card
      logical, intent(out) :: found
      type(error_t), allocatable, intent(out) :: error
      integer :: i, first, status
      integer, allocatable :: grown(:)

      found = .false.
      do i = position, source%n_lines
         first = first_nonblank(source%lines(i)%text)
         if (first == 0) cycle
         if (is_comment(source%lines(i)%text, first)) cycle
         if (source%lines(i)%text(first:first) /= '*') then
            call raise(source, i, first, 'expected a card (a line starting with ''*''), found '''// &
                       clip(source%lines(i)%text(first:))//'''', error)
            return
         end if
         call parse_keyword_line(source, i, first, card, error)
         if (allocated(error)) return
         found = .true.
         exit
      end do
      if (.not. found) then
         position = source%n_lines + 1
         return
      end if

      allocate (card%data_lines(8))
      do i = card%line + 1, source%n_lines
         first = first_nonblank(source%lines(i)%text)
         if (first == 0) cycle
         if (is_comment(source%lines(i)%text, first)) cycle
         if (source%lines(i)%text(first:first) == '*') exit
         if (card%n_data == size(card%data_lines)) then
            allocate (grown(2*size(card%data_lines)), stat=status)
            if (status /= 0) then
               call allocation_failure(status, 'the data lines of the card', 8.0_dp*size(card%data_lines), &
                                       error_input, error)
               call add_context(error, source%path//':'//integer_to_string(card%line))
               return
            end if
            grown(1:card%n_data) = card%data_lines(1:card%n_data)
            call move_alloc(grown, card%data_lines)
         end if
         card%n_data = card%n_data + 1
         card%data_lines(card%n_data) = i
      end do
      position = i
   end subroutine next_card

   !> True for a `**` comment line whose first nonblank character is at `first`.
   pure logical function is_comment(text, first)
      character(len=*), intent(in) :: text
      integer, intent(in) :: first
      is_comment = .false.
      if (first + 1 <= len(text)) is_comment = text(first:first + 1) == '**'
   end function is_comment

   !> The keyword `END STEP` (any case, one or more blanks between the words).
   pure logical function is_end_step(text)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: upper
      upper = to_upper(trim(adjustl(text)))
      is_end_step = .false.
      if (len(upper) < 8) return
      if (upper(1:3) /= 'END' .or. upper(4:4) /= ' ') return
      is_end_step = trim(adjustl(upper(4:))) == 'STEP'
   end function is_end_step

   !> Split `*KEYWORD, OPTION, OPTION=value ...` into the card's keyword and options.
   subroutine parse_keyword_line(source, line, star, card, error)
      type(source_t), intent(in) :: source
      integer, intent(in) :: line, star
      type(card_t), intent(out) :: card
      type(error_t), allocatable, intent(out) :: error
      type(field_t), allocatable :: fields(:)
      character(len=:), allocatable :: text
      integer :: i, equals, name_end

      text = source%lines(line)%text
      card%line = line
      card%column = star
      call split_fields(text(star + 1:), fields, offset=star)
      if (size(fields) == 0) then
         call raise(source, line, star + 1, 'expected a keyword after ''*'', found nothing', error)
         return
      end if
      if (.not. is_name(fields(1)%text) .and. .not. is_end_step(fields(1)%text)) then
         call raise(source, line, fields(1)%column, 'expected a keyword after ''*'', found '''// &
                    clip(fields(1)%text)//'''', error)
         return
      end if
      card%keyword = to_upper(fields(1)%text)
      ! *END STEP, the one keyword of two words (docs/input.md, *STEP), whatever blanks part them
      if (is_end_step(fields(1)%text)) card%keyword = 'END STEP'

      allocate (card%options(size(fields) - 1))
      do i = 2, size(fields)
         associate (option => card%options(i - 1), field => fields(i))
            option%column = field%column
            if (len(field%text) == 0) then
               call raise(source, line, field%column, 'expected an option, found an empty field', error)
               return
            end if
            equals = index(field%text, '=')
            name_end = len(field%text)
            if (equals > 0) name_end = equals - 1
            option%name = to_upper(trim(field%text(1:name_end)))
            if (.not. is_name(option%name)) then
               call raise(source, line, field%column, 'expected an option name, found '''// &
                          clip(field%text(1:name_end))//'''', error)
               return
            end if
            if (equals > 0) then
               option%has_value = .true.
               option%value = field%text(equals + 1:)
               option%value_column = field%column + equals
               if (first_nonblank(option%value) > 0) then
                  option%value_column = option%value_column + first_nonblank(option%value) - 1
                  option%value = option%value(first_nonblank(option%value):)
               end if
               if (len_trim(option%value) == 0) then
                  call raise(source, line, field%column + equals, 'expected a value after '''// &
                             clip(option%name)//'='', found nothing', error)
                  return
               end if
            else
               option%value = ''
            end if
         end associate
      end do
   end subroutine parse_keyword_line

   !> Check the options of `card` against `allowed`: each entry is an option name, followed by '=' when
   !> the option takes a value (`'NAME='`) and alone when it is a flag (`'FOLLOWER'`).
   !>
   !> Unknown, repeated, valueless or wrongly valued options are errors at their column.
   subroutine check_options(source, card, allowed, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      character(len=*), intent(in) :: allowed(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, k
      character(len=:), allocatable :: list
      logical :: takes_value

      do i = 1, size(card%options)
         associate (option => card%options(i))
            k = 0
            do j = 1, size(allowed)
               if (spec_name(allowed(j)) == option%name) k = j
            end do
            if (k == 0) then
               if (size(allowed) == 0) then
                  list = 'no options'
               else
                  list = 'one of the options '//trim(allowed(1))
                  do j = 2, size(allowed)
                     list = list//', '//trim(allowed(j))
                  end do
               end if
               call raise(source, card%line, option%column, 'expected '//list//' on *'//card%keyword// &
                          ', found '''//clip(option%name)//'''', error)
               return
            end if
            takes_value = index(allowed(k), '=') > 0
            if (takes_value .and. .not. option%has_value) then
               call raise(source, card%line, option%column + len(option%name), 'expected a value: '''// &
                          option%name//'=...'', found nothing', error)
               return
            end if
            if (.not. takes_value .and. option%has_value) then
               call raise(source, card%line, option%value_column, 'expected no value for the option '''// &
                          option%name//''', found '''//clip(option%value)//'''', error)
               return
            end if
            do j = 1, i - 1
               if (card%options(j)%name == option%name) then
                  call raise(source, card%line, option%column, 'expected each option once, found '''// &
                             option%name//''' again', error)
                  return
               end if
            end do
         end associate
      end do
   end subroutine check_options

   !> The option name of an `allowed` entry ('NAME=' → 'NAME').
   pure function spec_name(spec) result(name)
      character(len=*), intent(in) :: spec
      character(len=:), allocatable :: name
      if (index(spec, '=') > 0) then
         name = to_upper(spec(1:index(spec, '=') - 1))
      else
         name = to_upper(trim(spec))
      end if
   end function spec_name

   !> Index of option `name` among the card's options, 0 when absent.
   pure integer function option_index(card, name) result(index)
      type(card_t), intent(in) :: card
      character(len=*), intent(in) :: name
      integer :: i
      index = 0
      do i = 1, size(card%options)
         if (same_text(card%options(i)%name, name)) index = i
      end do
   end function option_index

   !> Index of option `name`, which the card must have (error at the keyword otherwise).
   subroutine require_option(source, card, name, index, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      character(len=*), intent(in) :: name
      integer, intent(out) :: index
      type(error_t), allocatable, intent(out) :: error
      index = option_index(card, name)
      if (index == 0) then
         call raise(source, card%line, card%column, 'expected the option '//name//'=... on *'// &
                    card%keyword//', found none', error)
      end if
   end subroutine require_option

   !> The comma-separated fields of data line `line` (commas inside parentheses do not split).
   subroutine data_fields(source, line, fields)
      type(source_t), intent(in) :: source
      integer, intent(in) :: line
      type(field_t), allocatable, intent(out) :: fields(:)
      call split_fields(source%lines(line)%text, fields)
   end subroutine data_fields

   !> Check that a data line has between `minimum` and `maximum` fields; `layout` names them for the
   !> message (e.g. 'label, x, y'). Too few: error just after the line; too many: at the first extra.
   subroutine require_field_count(source, line, fields, minimum, maximum, layout, error)
      type(source_t), intent(in) :: source
      integer, intent(in) :: line
      type(field_t), intent(in) :: fields(:)
      integer, intent(in) :: minimum, maximum
      character(len=*), intent(in) :: layout
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: wanted
      if (minimum == maximum) then
         wanted = integer_to_string(minimum)
      else
         wanted = integer_to_string(minimum)//' to '//integer_to_string(maximum)
      end if
      if (size(fields) < minimum) then
         call raise(source, line, last_nonblank(source%lines(line)%text) + 1, 'expected '//wanted// &
                    ' fields ('//layout//'), found '//integer_to_string(size(fields)), error)
      else if (size(fields) > maximum) then
         call raise(source, line, fields(maximum + 1)%column, 'expected '//wanted//' fields ('//layout// &
                    '), found '//integer_to_string(size(fields)), error)
      end if
   end subroutine require_field_count

   !> Evaluate a real data field; `what` names it in the message when it is empty. `context`, when
   !> present, ends the message of an expression that fails to evaluate: where it was evaluated (an
   !> expression of position is evaluated once per element: ' at element 7 (x = 6.5, ...)').
   subroutine field_real(source, parameters, line, field, what, value, error, context)
      type(source_t), intent(in) :: source
      type(parameter_table_t), intent(in) :: parameters
      integer, intent(in) :: line
      type(field_t), intent(in) :: field
      character(len=*), intent(in) :: what
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: context
      integer :: column
      character(len=:), allocatable :: message
      value = 0.0_dp
      if (len(field%text) == 0) then
         call raise(source, line, field%column, 'expected '//what//', found an empty field', error)
         return
      end if
      call evaluate_expression(field%text, parameters, value, error, column)
      if (allocated(error)) then
         message = error%message   ! raise() reallocates error: keep the text apart
         if (present(context)) message = message//context
         call raise(source, line, field%column + column - 1, message, error)
      end if
   end subroutine field_real

   !> Evaluate an integer data field (label, count, DOF): the expression must give a whole number.
   subroutine field_integer(source, parameters, line, field, what, value, error)
      type(source_t), intent(in) :: source
      type(parameter_table_t), intent(in) :: parameters
      integer, intent(in) :: line
      type(field_t), intent(in) :: field
      character(len=*), intent(in) :: what
      integer, intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer :: column
      character(len=:), allocatable :: message
      value = 0
      if (len(field%text) == 0) then
         call raise(source, line, field%column, 'expected '//what//', found an empty field', error)
         return
      end if
      call evaluate_integer(field%text, parameters, value, error, column)
      if (allocated(error)) then
         message = error%message   ! raise() reallocates error: keep the text apart
         call raise(source, line, field%column + column - 1, message, error)
      end if
   end subroutine field_integer

   !> Make an input error at line `line`, column `column`: `PATH:LINE:COL: message`, the line, a caret.
   !> A line longer than `echo_width` is shown as the part of it around the column (`echo_window`).
   subroutine raise(source, line, column, message, error)
      type(source_t), intent(in) :: source
      integer, intent(in) :: line, column
      character(len=*), intent(in) :: message
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: text, shown
      integer :: caret
      text = source%path//':'//integer_to_string(line)//':'//integer_to_string(column)//': '//message
      if (line >= 1 .and. line <= source%n_lines) then
         call echo_window(source%lines(line)%text, column, shown, caret)
         text = text//new_line('a')//shown//new_line('a')//repeat(' ', max(caret - 1, 0))//'^'
      end if
      call make_error(error, text, error_input)
   end subroutine raise

   !> The line `text` as a message shows it, with the caret's column in what is shown: the whole
   !> line when it has at most `echo_width` characters, else `echo_width` of them around `column`,
   !> with '...' where the line was cut.
   pure subroutine echo_window(text, column, shown, caret)
      character(len=*), intent(in) :: text
      integer, intent(in) :: column
      character(len=:), allocatable, intent(out) :: shown
      integer, intent(out) :: caret
      integer :: first, last
      if (len(text) <= echo_width) then
         shown = text
         caret = column
         return
      end if
      first = max(1, min(column - echo_width/2, len(text) - echo_width + 1))
      last = first + echo_width - 1
      shown = text(first:last)
      caret = column - first + 1
      if (first > 1) then
         shown = '...'//shown
         caret = caret + 3
      end if
      if (last < len(text)) shown = shown//'...'
   end subroutine echo_window

   !> Make an input error about the deck as a whole: `PATH: message`.
   subroutine raise_plain(source, message, error)
      type(source_t), intent(in) :: source
      character(len=*), intent(in) :: message
      type(error_t), allocatable, intent(out) :: error
      call make_error(error, source%path//': '//message, error_input)
   end subroutine raise_plain

   !> At most 40 characters of `text`, for quoting in a message.
   pure function clip(text) result(short)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: short
      if (len_trim(text) > 40) then
         short = text(1:37)//'...'
      else
         short = trim(text)
      end if
   end function clip

end module uniarc_deck_source
