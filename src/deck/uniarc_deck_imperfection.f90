!> *IMPERFECTION (docs/input.md): a geometric imperfection, a buckling mode scaled and added to the
!> initial coordinates of the nodes, as engineers model the imperfections of a real structure to
!> follow it past a bifurcation (Abaqus' *IMPERFECTION; EN 1993-1-6 §8.7 on equivalent geometric
!> imperfections in the shape of the critical buckling mode).
!>
!>     *IMPERFECTION [, FILE=modes_file] [, BIFURCATION=n]
!>     amplitude
!>
!> With FILE=, the mode is block n (default 1) of a modes table `STEM.modes` written by an earlier run
!> with `*OUTPUT, MODES` (uniarc_modes_output) on the same mesh — matched node by node through the
!> labels, with the initial coordinates checked — and added here. Without it, the mode is that of the
!> n-th bifurcation of the perfect structure's path, which the program computes in a first run before
!> the analysis (uniarc_path_imperfection): the card records the request in the analysis options. The amplitude (length) is the largest nodal translation of
!> the added shape, sqrt(dx² + dy²); a negative one flips the mode. Applied to the nodes when the card
!> is read: the contact cards, which build their candidates from the coordinates, come after it.
module uniarc_deck_imperfection
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_input
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: field_t, integer_to_string, real_to_string, same_text
   use uniarc_deck_source, only: source_t, card_t, raise, clip, check_options, option_index, require_option, &
                                 data_fields, require_field_count, field_real, field_integer, read_source
   use uniarc_deck_state, only: deck_t, option_field
   implicit none
   private
   public :: read_imperfection

   !> The initial coordinates of a node in the modes file and in the deck agree to this fraction of
   !> the model's size: the file writes 13 significant digits.
   real(dp), parameter :: coordinate_tolerance = 1.0e-10_dp
   !> The largest magnitude of a coordinate or translation in a modes table (a deck's numbers are bounded
   !> alike): the norm of a node's translation then stays finite.
   real(dp), parameter :: largest_value = 1.0e100_dp

contains

   !> *IMPERFECTION [, FILE=] [, BIFURCATION=n] with one data line, the amplitude (module header).
   !> Errors (file:line:col, exit 2): an unreadable file, no block n in it, a table
   !> without the columns bifurcation, node, x0, y0, ux, uy, a row that is not numbers, a node of the
   !> file that is not a node of the deck or lies elsewhere, a node of the deck without a row, a zero
   !> mode, a contact card before this one, a second *IMPERFECTION.
   subroutine read_imperfection(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      type(source_t) :: table
      type(field_t), allocatable :: fields(:)
      type(field_t) :: path_field
      character(len=:), allocatable :: path, message
      real(dp), allocatable :: shift(:, :)
      logical, allocatable :: seen(:)
      real(dp) :: amplitude, largest, size_model
      integer :: k, file_option, block, missing

      call check_options(source, card, [character(len=12) :: 'FILE=', 'BIFURCATION='], error)
      if (allocated(error)) return
      if (deck%imperfection_line > 0) then
         call raise(source, card%line, card%column, 'expected one *IMPERFECTION card, found another after the '// &
                    'one at line '//integer_to_string(deck%imperfection_line), error)
         return
      end if
      if (deck%model%n_contacts > 0 .or. deck%model%n_foundations > 0) then
         call raise(source, card%line, card%column, 'expected *IMPERFECTION before the contact cards '// &
                    '(*FOUNDATION, *SPRING, *OBSTACLE build their candidates from the coordinates it changes)', &
                    error)
         return
      end if
      if (deck%model%n_nodes == 0) then
         call raise(source, card%line, card%column, 'expected *IMPERFECTION after the nodes it moves, found '// &
                    'no node yet', error)
         return
      end if
      deck%imperfection_line = card%line
      block = 1
      k = option_index(card, 'BIFURCATION')
      if (k > 0) then
         call field_integer(source, deck%parameters, card%line, option_field(card, k), &
                            'the number of a bifurcation for BIFURCATION=', block, error)
         if (allocated(error)) return
         if (block < 1) then
            call raise(source, card%line, card%options(k)%value_column, 'expected BIFURCATION=n with n >= 1, '// &
                       'found '//integer_to_string(block), error)
            return
         end if
      end if
      if (card%n_data /= 1) then
         call raise(source, card%line, card%column, 'expected one data line after *IMPERFECTION, the amplitude '// &
                    '(the largest nodal displacement of the added mode), found '//integer_to_string(card%n_data), &
                    error)
         return
      end if
      call data_fields(source, card%data_lines(1), fields)
      call require_field_count(source, card%data_lines(1), fields, 1, 1, 'amplitude', error)
      if (allocated(error)) return
      call field_real(source, deck%parameters, card%data_lines(1), fields(1), 'an amplitude', amplitude, error)
      if (allocated(error)) return
      ! An imperfection is a small deviation of the geometry: one beyond the structure's own size (its
      ! largest extent in x or y) makes another structure, and amplitudes of 1e150 put the imperfect
      ! coordinates past the bounds checked before (element lengths cubed overflowed: SIGFPE in Debug).
      associate (x => deck%model%coordinates(:, 1:deck%model%n_nodes))
         size_model = maxval(maxval(x, dim=2) - minval(x, dim=2))
      end associate
      if (.not. abs(amplitude) <= size_model) then
         call raise(source, card%data_lines(1), fields(1)%column, 'expected an amplitude at most the model''s '// &
                    'size '//trim(real_to_string(size_model, '(es10.3)'))//' in magnitude (its largest extent '// &
                    'in x or y: an imperfection is a small deviation of the geometry), found '// &
                    trim(real_to_string(amplitude, '(es10.3)')), error)
         return
      end if
      file_option = option_index(card, 'FILE')
      if (file_option == 0) then
         ! The mode of the perfect structure's n-th bifurcation, computed by the program in a first run
         ! (uniarc_path_imperfection); the deck's end checks that it can be (check_whole_deck).
         if (amplitude == 0.0_dp) return
         deck%model%analysis%imperfection_bifurcation = block
         deck%model%analysis%imperfection_amplitude = amplitude
         return
      end if
      path_field = option_field(card, file_option)

      ! A relative path is relative to the deck's folder, so that a deck and its modes file move together.
      path = path_field%text
      if (path(1:1) /= '/') path = folder_of(source%path)//path
      call read_source(path, table, error)
      if (allocated(error)) then
         message = error%message   ! raise() reallocates error: keep the text apart
         call raise(source, card%line, path_field%column, 'expected a readable modes table for FILE=: '// &
                    message, error)
         return
      end if
      size_model = max(maxval(abs(deck%model%coordinates(:, 1:deck%model%n_nodes))), tiny(1.0_dp))
      call read_mode(table, block, shift, seen, error)
      if (allocated(error)) return
      if (.not. allocated(shift)) then
         call raise(source, card%line, card%options(max(k, file_option))%value_column, 'expected bifurcation '// &
                    integer_to_string(block)//' in '//path//', found no such block', error)
         return
      end if
      missing = findloc(seen, .false., 1)
      if (missing > 0) then
         call raise(source, card%line, path_field%column, 'expected a row of bifurcation '// &
                    integer_to_string(block)//' for every node, found none for node '// &
                    integer_to_string(deck%model%node_label(missing))//' in '//path, error)
         return
      end if
      ! (the translations are at most 1e100 in magnitude, read_mode: no overflow; scaled by the
      ! largest component first, so that a mode of tiny numbers does not underflow to zero)
      largest = maxval(abs(shift))
      if (largest > 0.0_dp) largest = largest*maxval(norm2(shift/largest, dim=1))
      if (.not. largest > 0.0_dp) then
         call raise(source, card%line, path_field%column, 'expected a mode that moves some node, found a '// &
                    'zero translation in bifurcation '//integer_to_string(block)//' of '//path, error)
         return
      end if
      deck%model%coordinates(:, 1:deck%model%n_nodes) = deck%model%coordinates(:, 1:deck%model%n_nodes) + &
                                                        (amplitude/largest)*shift

   contains

      !> The translations (2, n_nodes) of block `wanted` of the modes table `table`, with `found`
      !> marking the nodes that have a row; `mode` unallocated if the block is absent.
      subroutine read_mode(table, wanted, mode, found, error)
         type(source_t), intent(in) :: table
         integer, intent(in) :: wanted
         real(dp), allocatable, intent(out) :: mode(:, :)
         logical, allocatable, intent(out) :: found(:)
         type(error_t), allocatable, intent(out) :: error
         character(len=:), allocatable :: names(:), words(:)
         integer :: columns(6), i, j, line, node, label, status, starts(64)
         real(dp) :: values(6)
         character(len=*), parameter :: wanted_names(6) = [character(len=11) :: 'bifurcation', 'node', 'x0', &
                                                              'y0', 'ux', 'uy']
         allocate (found(deck%model%n_nodes), stat=status)
         call allocation_failure(status, 'the nodes of the modes table '//table%path, 4.0_dp*deck%model%n_nodes, &
                                 error_input, error)
         if (allocated(error)) return
         found(:) = .false.
         if (table%n_lines < 1) then
            call raise(table, 1, 1, 'expected a modes table (column names on line 1), found an empty file', error)
            return
         end if
         call split_blanks(table%lines(1)%text, names, starts)
         do j = 1, size(wanted_names)
            columns(j) = 0
            do i = 1, size(names)
               if (same_text(names(i), wanted_names(j))) columns(j) = i
            end do
            if (columns(j) == 0) then
               call raise(table, 1, 1, 'expected the column '''//trim(wanted_names(j))//''' of a modes table '// &
                          '(*OUTPUT, MODES) on line 1', error)
               return
            end if
         end do
         do line = 2, table%n_lines
            associate (text => table%lines(line)%text)
               if (len_trim(text) == 0) cycle
               if (text(verify(text, ' '):verify(text, ' ')) == '#') cycle
               call split_blanks(text, words, starts)
               if (size(words) /= size(names)) then
                  call raise(table, line, 1, 'expected '//integer_to_string(size(names))//' fields as line 1 '// &
                             'names, found '//integer_to_string(size(words)), error)
                  return
               end if
               do j = 1, size(columns)
                  read (words(columns(j)), *, iostat=status) values(j)
                  if (status /= 0) then
                     call raise(table, line, starts(columns(j)), 'expected a number in column '// &
                                trim(wanted_names(j))//', found '''//clip(trim(words(columns(j))))//'''', error)
                     return
                  end if
                  ! NaN, Infinity and numbers past the largest real (1e309 reads as Infinity) are
                  ! no mode: they made the imperfection NaN or, through its overflowing norm, zero
                  if (.not. ieee_is_finite(values(j))) then
                     call raise(table, line, starts(columns(j)), 'expected a finite number in column '// &
                                trim(wanted_names(j))//', found '''//clip(trim(words(columns(j))))//'''', error)
                     return
                  end if
                  if (j <= 2) then
                     ! the bifurcation's number and the node's label: whole numbers of an integer's range
                     if (.not. (abs(values(j)) < 2.0e9_dp .and. values(j) == anint(values(j)))) then
                        call raise(table, line, starts(columns(j)), 'expected a whole number below 2e9 in '// &
                                   'column '//trim(wanted_names(j))//', found '''//clip(trim(words(columns(j))))// &
                                   '''', error)
                        return
                     end if
                  else if (.not. abs(values(j)) <= largest_value) then
                     ! coordinates and translations within the deck's own range of numbers, so that
                     ! the mode's norm cannot overflow
                     call raise(table, line, starts(columns(j)), 'expected a number of magnitude at most '// &
                                '1e100 in column '//trim(wanted_names(j))//', found '''// &
                                clip(trim(words(columns(j))))//'''', error)
                     return
                  end if
               end do
               if (nint(values(1)) /= wanted) cycle
               if (.not. allocated(mode)) then
                  allocate (mode(2, deck%model%n_nodes), stat=status)
                  call allocation_failure(status, 'the imperfection read from the modes table '//table%path, &
                                          16.0_dp*deck%model%n_nodes, error_input, error)
                  if (allocated(error)) return
                  mode(:, :) = 0.0_dp
               end if
               label = nint(values(2))
               node = 0
               if (label >= 1 .and. label <= size(deck%model%node_of_label)) node = deck%model%node_of_label(label)
               if (node == 0) then
                  call raise(table, line, starts(columns(2)), 'expected a node of the deck, found node '// &
                             integer_to_string(label)//' (a modes table of another mesh?)', error)
                  return
               end if
               if (any(abs(values(3:4) - deck%model%coordinates(:, node)) > coordinate_tolerance*size_model)) then
                  call raise(table, line, starts(columns(3)), 'expected node '//integer_to_string(label)//' at ('// &
                             real_to_string(deck%model%coordinates(1, node))//', '// &
                             real_to_string(deck%model%coordinates(2, node))//') as in the deck, found it '// &
                             'elsewhere (a modes table of another mesh?)', error)
                  return
               end if
               mode(:, node) = values(5:6)
               found(node) = .true.
            end associate
         end do
      end subroutine read_mode

   end subroutine read_imperfection

   !> The blank-separated words of `text` and the column where each starts (at most size(starts)).
   pure subroutine split_blanks(text, words, starts)
      character(len=*), intent(in) :: text
      character(len=:), allocatable, intent(out) :: words(:)
      integer, intent(out) :: starts(:)
      integer :: i, n, first, longest, ends(size(starts))
      n = 0
      i = 1
      longest = 1
      do while (i <= len_trim(text) .and. n < size(starts))
         if (text(i:i) == ' ') then
            i = i + 1
            cycle
         end if
         first = i
         do while (i <= len(text))
            if (text(i:i) == ' ') exit
            i = i + 1
         end do
         n = n + 1
         starts(n) = first
         ends(n) = i - 1
         longest = max(longest, i - first)
      end do
      allocate (character(len=longest) :: words(n))
      do i = 1, n
         words(i) = text(starts(i):ends(i))
      end do
   end subroutine split_blanks

   !> The folder of a file path, with its trailing '/' ('' for a bare name).
   pure function folder_of(path) result(folder)
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: folder
      folder = path(1:index(path, '/', back=.true.))
   end function folder_of

end module uniarc_deck_imperfection
