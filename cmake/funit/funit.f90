!> uniarc's own runtime for pFUnit-style unit tests, used where pFUnit is not installed.
!>
!> cmake/funit/pf2f90.py expands each `@assert...` macro of a `.pf` file into a call to one of the
!> `funit_assert_*` generics below, followed by `if (funit_failed()) return`; the generated driver
!> runs each test through `funit_run_test`. The module has pFUnit's name so that test files say
!> `use funit` either way, and every public name starts with `funit_` so that none clashes with a
!> name of a test.
!>
!> Unlike uniarc's library this module keeps state: pFUnit's module-style tests are procedures
!> without arguments whose assertions report through a query (pFUnit's `anyExceptions()`), so the
!> failure record of the running test cannot be passed to them. `funit_run_test` resets it.
!>
!> Comparisons follow pFUnit 4: reals agree when |actual - expected| <= tolerance (absolute) or
!> |actual - expected| <= tolerance |expected| (relative, which fails for expected = 0); a missing
!> tolerance means exact equality; equal infinities agree, NaN agrees with nothing; strings are
!> compared without trailing blanks. The checks never raise a floating-point exception, so they
!> work under `-ffpe-trap=invalid,zero,overflow`.
module funit
   use, intrinsic :: iso_fortran_env, only: int32, int64, real32, real64, output_unit
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
   implicit none
   private
   public :: funit_assert_true, funit_assert_false, funit_assert_is_finite
   public :: funit_assert_equal, funit_assert_relatively_equal
   public :: funit_assert_less_than, funit_assert_less_than_or_equal
   public :: funit_assert_greater_than, funit_assert_greater_than_or_equal
   public :: funit_failed
   public :: funit_test_procedure, funit_runner_t, funit_run_test, funit_skip_test, funit_finish

   !> Formats that print enough significant digits to tell any two values of the kind apart
   !> (9 for IEEE single, 17 for IEEE double).
   character(len=*), parameter :: format32 = '(ES16.8E2)', format64 = '(ES25.16E3)'
   !> Indentation of the detail lines of a failure under the test's own line.
   character(len=*), parameter :: detail_indent = '          '

   !> Assert that a logical scalar, or every element of a logical array, is true.
   interface funit_assert_true
      module procedure true_scalar, true_vector
   end interface funit_assert_true

   !> Assert that a logical scalar, or every element of a logical array, is false.
   interface funit_assert_false
      module procedure false_scalar, false_vector
   end interface funit_assert_false

   !> Assert that a real scalar or every element of a real array is finite (neither NaN nor Inf).
   interface funit_assert_is_finite
      module procedure finite_real32_0, finite_real32_1, finite_real32_2
      module procedure finite_real64_0, finite_real64_1, finite_real64_2
   end interface funit_assert_is_finite

   !> Assert equality: integers and logicals exactly, strings without trailing blanks, reals within
   !> an absolute `tolerance` (exactly without one). Arrays compare element by element; a scalar
   !> `expected` is compared with every element of an array `actual`.
   interface funit_assert_equal
      module procedure equal_int32_0_0, equal_int32_0_1, equal_int32_1_1, equal_int32_2_2
      module procedure equal_int64_0_0, equal_int64_1_1
      module procedure equal_real32_0_0, equal_real32_0_1, equal_real32_1_1
      module procedure equal_real32_0_2, equal_real32_2_2
      module procedure equal_real64_0_0, equal_real64_0_1, equal_real64_1_1
      module procedure equal_real64_0_2, equal_real64_2_2
      module procedure equal_logical_0_0, equal_logical_1_1
      module procedure equal_character_0_0
   end interface funit_assert_equal

   !> Assert that reals agree within a relative `tolerance`:
   !> |actual - expected| <= tolerance |expected|.
   interface funit_assert_relatively_equal
      module procedure relative_real32_0_0, relative_real32_0_1, relative_real32_1_1
      module procedure relative_real32_0_2, relative_real32_2_2
      module procedure relative_real64_0_0, relative_real64_0_1, relative_real64_1_1
      module procedure relative_real64_0_2, relative_real64_2_2
   end interface funit_assert_relatively_equal

   !> Assert lhs < rhs (integer or real scalars of one kind).
   interface funit_assert_less_than
      module procedure less_int32, less_int64, less_real32, less_real64
   end interface funit_assert_less_than

   !> Assert lhs <= rhs (integer or real scalars of one kind).
   interface funit_assert_less_than_or_equal
      module procedure less_equal_int32, less_equal_int64, less_equal_real32, less_equal_real64
   end interface funit_assert_less_than_or_equal

   !> Assert lhs > rhs (integer or real scalars of one kind).
   interface funit_assert_greater_than
      module procedure greater_int32, greater_int64, greater_real32, greater_real64
   end interface funit_assert_greater_than

   !> Assert lhs >= rhs (integer or real scalars of one kind).
   interface funit_assert_greater_than_or_equal
      module procedure greater_equal_int32, greater_equal_int64
      module procedure greater_equal_real32, greater_equal_real64
   end interface funit_assert_greater_than_or_equal

   abstract interface
      !> A test, @before or @after procedure: module-style pFUnit tests take no arguments.
      subroutine funit_test_procedure()
      end subroutine funit_test_procedure
   end interface

   !> Counts of one test executable's results.
   type :: funit_runner_t
      integer :: passed = 0   !< tests whose assertions all held
      integer :: failed = 0   !< tests with at least one failed assertion
      integer :: skipped = 0  !< tests marked @disable
   end type funit_runner_t

   ! The failures of the running test, one block of lines each; unallocated while none failed.
   character(len=:), allocatable :: failure_text

contains

   ! ---- runner ---------------------------------------------------------------------------------

   !> True once an assertion of the running test (or of its @before/@after) has failed.
   logical function funit_failed()
      funit_failed = allocated(failure_text)
   end function funit_failed

   !> Run one test: `before`, then, unless `before` failed, the test and `after` (even when the test
   !> failed), as pFUnit's TestCase%runBare does; print the verdict and the failures below it.
   subroutine funit_run_test(runner, name, test, before, after)
      type(funit_runner_t), intent(inout) :: runner
      character(len=*), intent(in) :: name
      procedure(funit_test_procedure) :: test
      procedure(funit_test_procedure), optional :: before, after

      if (allocated(failure_text)) deallocate (failure_text)
      if (present(before)) call before()
      if (.not. funit_failed()) then
         call test()
         if (present(after)) call after()
      end if
      if (funit_failed()) then
         runner%failed = runner%failed + 1
         write (output_unit, '(a)') '  FAIL      '//name
         write (output_unit, '(6x,a)') failure_text
         deallocate (failure_text)
      else
         runner%passed = runner%passed + 1
         write (output_unit, '(a)') '  pass      '//name
      end if
      flush (output_unit)
   end subroutine funit_run_test

   !> Count and report a test marked @disable without running it.
   subroutine funit_skip_test(runner, name)
      type(funit_runner_t), intent(inout) :: runner
      character(len=*), intent(in) :: name
      runner%skipped = runner%skipped + 1
      write (output_unit, '(a)') '  disabled  '//name
   end subroutine funit_skip_test

   !> Print the closing summary line; `success` is false if any test failed.
   subroutine funit_finish(runner, success)
      type(funit_runner_t), intent(in) :: runner
      logical, intent(out) :: success
      write (output_unit, '(i0,a,i0,a,i0,a)') runner%passed, ' passed, ', runner%failed, &
         ' failed, ', runner%skipped, ' skipped'
      flush (output_unit)
      success = runner%failed == 0
   end subroutine funit_finish

   ! ---- failure record and formatting ----------------------------------------------------------

   !> Add a failure: `location: assertion failed[: message]`, then the detail lines.
   subroutine record_failure(location, assertion, message, details)
      character(len=*), intent(in) :: location, assertion
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: details
      character(len=:), allocatable :: text

      text = location//': '//assertion//' failed'
      if (present(message)) text = text//': '//message
      text = text//details
      if (allocated(failure_text)) then
         failure_text = failure_text//new_line('a')//text
      else
         failure_text = text
      end if
   end subroutine record_failure

   !> One detail line of a failure: a label and a value.
   pure function detail(label, value) result(text)
      character(len=*), intent(in) :: label, value
      character(len=:), allocatable :: text
      text = new_line('a')//detail_indent//label//value
   end function detail

   pure function integer_text(value) result(text)
      integer(int64), intent(in) :: value
      character(len=:), allocatable :: text
      character(len=24) :: buffer
      write (buffer, '(i0)') value
      text = trim(buffer)
   end function integer_text

   pure function real_text(value, real_format) result(text)
      real(real64), intent(in) :: value
      character(len=*), intent(in) :: real_format
      character(len=:), allocatable :: text
      character(len=32) :: buffer
      write (buffer, real_format) value
      text = trim(adjustl(buffer))
   end function real_text

   pure function logical_text(value) result(text)
      logical, intent(in) :: value
      character(len=:), allocatable :: text
      text = merge('.true. ', '.false.', value)
      text = trim(text)
   end function logical_text

   !> `(i,j,...)` for element `position` (1-based, array element order) of an array of `extents`;
   !> empty for a scalar.
   pure function index_text(position, extents) result(text)
      integer, intent(in) :: position
      integer, intent(in) :: extents(:)
      character(len=:), allocatable :: text
      integer :: dimension, rest

      if (size(extents) == 0) then
         text = ''
         return
      end if
      text = '('
      rest = position - 1
      do dimension = 1, size(extents)
         text = text//integer_text(int(mod(rest, extents(dimension)) + 1, int64))
         rest = rest/extents(dimension)
         if (dimension < size(extents)) text = text//','
      end do
      text = text//')'
   end function index_text

   pure function shape_text(extents) result(text)
      integer, intent(in) :: extents(:)
      character(len=:), allocatable :: text
      integer :: dimension
      text = '('
      do dimension = 1, size(extents)
         text = text//integer_text(int(extents(dimension), int64))
         if (dimension < size(extents)) text = text//','
      end do
      text = text//')'
   end function shape_text

   !> Record a failure and return true if two arrays that must be compared element by element
   !> have different shapes.
   logical function shapes_differ(assertion, expected_shape, actual_shape, message, location)
      character(len=*), intent(in) :: assertion
      integer, intent(in) :: expected_shape(:), actual_shape(:)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      shapes_differ = any(expected_shape /= actual_shape)
      if (shapes_differ) call record_failure(location, assertion, message, &
         detail('expected shape: ', shape_text(expected_shape))// &
         detail('actual shape:   ', shape_text(actual_shape)))
   end function shapes_differ

   ! ---- comparison cores -----------------------------------------------------------------------

   !> Whether `actual` agrees with `expected` within `tolerance`, absolute or relative to
   !> |expected|. Written so that no operation can overflow or meet a NaN: both values are halved
   !> when large (exact for normal numbers), and a tolerance above 1 divides instead of multiplies.
   pure logical function reals_agree(expected, actual, tolerance, relative)
      real(real64), intent(in) :: expected, actual, tolerance
      logical, intent(in) :: relative
      real(real64) :: scale, gap, bound

      if (ieee_is_nan(expected) .or. ieee_is_nan(actual)) then
         reals_agree = .false.
      else if (.not. (ieee_is_finite(expected) .and. ieee_is_finite(actual))) then
         reals_agree = .not. ieee_is_finite(expected) .and. .not. ieee_is_finite(actual) &
                       .and. ((expected > 0.0_real64) .eqv. (actual > 0.0_real64))
      else
         scale = 1.0_real64
         if (max(abs(expected), abs(actual)) > huge(1.0_real64)/4) scale = 0.5_real64
         gap = abs(scale*actual - scale*expected)
         bound = scale
         if (relative) bound = scale*abs(expected)
         if (tolerance <= 1.0_real64) then
            reals_agree = gap <= tolerance*bound
         else
            reals_agree = gap/tolerance <= bound
         end if
      end if
   end function reals_agree

   !> Compare reals element by element; `expected` holds one value (compared with every element)
   !> or as many as `actual`, which is flattened from an array of shape `actual_shape`.
   subroutine check_reals(assertion, expected, actual, actual_shape, tolerance, relative, &
                          real_format, message, location)
      character(len=*), intent(in) :: assertion
      real(real64), intent(in) :: expected(:), actual(:)
      integer, intent(in) :: actual_shape(:)
      real(real64), intent(in) :: tolerance
      logical, intent(in) :: relative
      character(len=*), intent(in) :: real_format
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      character(len=:), allocatable :: details
      real(real64) :: wanted
      integer :: position

      do position = 1, size(actual)
         wanted = expected(min(position, size(expected)))
         if (relative .and. ieee_is_finite(wanted)) then
            if (.not. abs(wanted) > 0.0_real64) then
               call record_failure(location, assertion, message, &
                  detail('expected is zero, so no relative tolerance applies', '')// &
                  position_detail(position, actual_shape))
               return
            end if
         end if
         if (.not. reals_agree(wanted, actual(position), tolerance, relative)) then
            details = position_detail(position, actual_shape)// &
               detail('expected:  ', real_text(wanted, real_format))// &
               detail('actual:    ', real_text(actual(position), real_format))
            if (ieee_is_finite(wanted) .and. ieee_is_finite(actual(position))) then
               if (max(abs(wanted), abs(actual(position))) <= huge(1.0_real64)/4) &
                  details = details//detail('|actual - expected|: ', &
                  real_text(abs(actual(position) - wanted), real_format))
            end if
            if (relative) then
               details = details//detail('tolerance: ', real_text(tolerance, real_format)// &
                  ' (relative to |expected|)')
            else
               details = details//detail('tolerance: ', real_text(tolerance, real_format))
            end if
            call record_failure(location, assertion, message, details)
            return
         end if
      end do
   end subroutine check_reals

   !> The detail line naming the first differing element of an array (nothing for a scalar).
   pure function position_detail(position, actual_shape) result(text)
      integer, intent(in) :: position
      integer, intent(in) :: actual_shape(:)
      character(len=:), allocatable :: text
      if (size(actual_shape) == 0) then
         text = ''
      else
         text = detail('first failing element at index ', index_text(position, actual_shape))
      end if
   end function position_detail

   !> Compare integers element by element (same broadcasting rule as check_reals).
   subroutine check_integers(expected, actual, actual_shape, message, location)
      integer(int64), intent(in) :: expected(:), actual(:)
      integer, intent(in) :: actual_shape(:)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      integer :: position

      do position = 1, size(actual)
         if (expected(min(position, size(expected))) /= actual(position)) then
            call record_failure(location, 'assertEqual', message, &
               position_detail(position, actual_shape)// &
               detail('expected: ', integer_text(expected(min(position, size(expected)))))// &
               detail('actual:   ', integer_text(actual(position))))
            return
         end if
      end do
   end subroutine check_integers

   !> Check that every element is finite; the array is flattened from shape `actual_shape`.
   subroutine check_finite(values, actual_shape, real_format, message, location)
      real(real64), intent(in) :: values(:)
      integer, intent(in) :: actual_shape(:)
      character(len=*), intent(in) :: real_format
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      integer :: position

      do position = 1, size(values)
         if (.not. ieee_is_finite(values(position))) then
            call record_failure(location, 'assertIsFinite', message, &
               position_detail(position, actual_shape)// &
               detail('value: ', real_text(values(position), real_format)))
            return
         end if
      end do
   end subroutine check_finite

   !> Record the failure of an ordering assertion `lhs relation rhs` unless it `holds`.
   subroutine check_order(assertion, holds, relation, lhs, rhs, message, location)
      character(len=*), intent(in) :: assertion, relation, lhs, rhs
      logical, intent(in) :: holds
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (.not. holds) call record_failure(location, assertion, message, &
         detail('expected lhs '//relation//' rhs, with', '')// &
         detail('lhs: ', lhs)//detail('rhs: ', rhs))
   end subroutine check_order

   !> `lhs < rhs` for reals, false when either is NaN (tested first: an ordered comparison with a
   !> NaN may raise the invalid exception).
   pure logical function real_less(lhs, rhs, or_equal)
      real(real64), intent(in) :: lhs, rhs
      logical, intent(in) :: or_equal
      if (ieee_is_nan(lhs) .or. ieee_is_nan(rhs)) then
         real_less = .false.
      else if (or_equal) then
         real_less = lhs <= rhs
      else
         real_less = lhs < rhs
      end if
   end function real_less

   !> The tolerance to use: the given one, or zero (exact comparison) when absent.
   pure real(real64) function tolerance32(tolerance)
      real(real32), intent(in), optional :: tolerance
      tolerance32 = 0.0_real64
      if (present(tolerance)) tolerance32 = real(tolerance, real64)
   end function tolerance32

   !> The tolerance to use: the given one, or zero (exact comparison) when absent.
   pure real(real64) function tolerance64(tolerance)
      real(real64), intent(in), optional :: tolerance
      tolerance64 = 0.0_real64
      if (present(tolerance)) tolerance64 = tolerance
   end function tolerance64

   ! ---- logical assertions ---------------------------------------------------------------------

   subroutine true_scalar(condition, message, location)
      logical, intent(in) :: condition
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (.not. condition) call record_failure(location, 'assertTrue', message, '')
   end subroutine true_scalar

   subroutine true_vector(condition, message, location)
      logical, intent(in) :: condition(:)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      integer :: position
      do position = 1, size(condition)
         if (.not. condition(position)) then
            call record_failure(location, 'assertTrue', message, &
               position_detail(position, shape(condition)))
            return
         end if
      end do
   end subroutine true_vector

   subroutine false_scalar(condition, message, location)
      logical, intent(in) :: condition
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (condition) call record_failure(location, 'assertFalse', message, '')
   end subroutine false_scalar

   subroutine false_vector(condition, message, location)
      logical, intent(in) :: condition(:)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      integer :: position
      do position = 1, size(condition)
         if (condition(position)) then
            call record_failure(location, 'assertFalse', message, &
               position_detail(position, shape(condition)))
            return
         end if
      end do
   end subroutine false_vector

   ! ---- finiteness -----------------------------------------------------------------------------

   subroutine finite_real32_0(value, message, location)
      real(real32), intent(in) :: value
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_finite([real(value, real64)], shape(value), format32, message, location)
   end subroutine finite_real32_0

   subroutine finite_real32_1(value, message, location)
      real(real32), intent(in) :: value(:)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_finite(real(value, real64), shape(value), format32, message, location)
   end subroutine finite_real32_1

   subroutine finite_real32_2(value, message, location)
      real(real32), intent(in) :: value(:, :)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_finite(reshape(real(value, real64), [size(value)]), shape(value), format32, &
                        message, location)
   end subroutine finite_real32_2

   subroutine finite_real64_0(value, message, location)
      real(real64), intent(in) :: value
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_finite([value], shape(value), format64, message, location)
   end subroutine finite_real64_0

   subroutine finite_real64_1(value, message, location)
      real(real64), intent(in) :: value(:)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_finite(value, shape(value), format64, message, location)
   end subroutine finite_real64_1

   subroutine finite_real64_2(value, message, location)
      real(real64), intent(in) :: value(:, :)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_finite(reshape(value, [size(value)]), shape(value), format64, message, location)
   end subroutine finite_real64_2

   ! ---- equality: integers ---------------------------------------------------------------------

   subroutine equal_int32_0_0(expected, actual, message, location)
      integer(int32), intent(in) :: expected, actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_integers([int(expected, int64)], [int(actual, int64)], shape(actual), message, &
                          location)
   end subroutine equal_int32_0_0

   subroutine equal_int32_0_1(expected, actual, message, location)
      integer(int32), intent(in) :: expected, actual(:)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_integers([int(expected, int64)], int(actual, int64), shape(actual), message, &
                          location)
   end subroutine equal_int32_0_1

   subroutine equal_int32_1_1(expected, actual, message, location)
      integer(int32), intent(in) :: expected(:), actual(:)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (shapes_differ('assertEqual', shape(expected), shape(actual), message, location)) return
      call check_integers(int(expected, int64), int(actual, int64), shape(actual), message, &
                          location)
   end subroutine equal_int32_1_1

   subroutine equal_int32_2_2(expected, actual, message, location)
      integer(int32), intent(in) :: expected(:, :), actual(:, :)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (shapes_differ('assertEqual', shape(expected), shape(actual), message, location)) return
      call check_integers(reshape(int(expected, int64), [size(expected)]), &
                          reshape(int(actual, int64), [size(actual)]), shape(actual), message, &
                          location)
   end subroutine equal_int32_2_2

   subroutine equal_int64_0_0(expected, actual, message, location)
      integer(int64), intent(in) :: expected, actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_integers([expected], [actual], shape(actual), message, location)
   end subroutine equal_int64_0_0

   subroutine equal_int64_1_1(expected, actual, message, location)
      integer(int64), intent(in) :: expected(:), actual(:)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (shapes_differ('assertEqual', shape(expected), shape(actual), message, location)) return
      call check_integers(expected, actual, shape(actual), message, location)
   end subroutine equal_int64_1_1

   ! ---- equality: logicals and strings ---------------------------------------------------------

   subroutine equal_logical_0_0(expected, actual, message, location)
      logical, intent(in) :: expected, actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (expected .neqv. actual) call record_failure(location, 'assertEqual', message, &
         detail('expected: ', logical_text(expected))//detail('actual:   ', logical_text(actual)))
   end subroutine equal_logical_0_0

   subroutine equal_logical_1_1(expected, actual, message, location)
      logical, intent(in) :: expected(:), actual(:)
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      integer :: position
      if (shapes_differ('assertEqual', shape(expected), shape(actual), message, location)) return
      do position = 1, size(actual)
         if (expected(position) .neqv. actual(position)) then
            call record_failure(location, 'assertEqual', message, &
               position_detail(position, shape(actual))// &
               detail('expected: ', logical_text(expected(position)))// &
               detail('actual:   ', logical_text(actual(position))))
            return
         end if
      end do
   end subroutine equal_logical_1_1

   subroutine equal_character_0_0(expected, actual, message, location)
      character(len=*), intent(in) :: expected, actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (expected /= actual) call record_failure(location, 'assertEqual', message, &
         detail('expected: ', '"'//trim(expected)//'"')// &
         detail('actual:   ', '"'//trim(actual)//'"'))
   end subroutine equal_character_0_0

   ! ---- equality: reals (absolute tolerance) ---------------------------------------------------

   subroutine equal_real32_0_0(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected, actual
      real(real32), intent(in), optional :: tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertEqual', [real(expected, real64)], [real(actual, real64)], &
                       shape(actual), tolerance32(tolerance), .false., format32, message, location)
   end subroutine equal_real32_0_0

   subroutine equal_real32_0_1(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected, actual(:)
      real(real32), intent(in), optional :: tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertEqual', [real(expected, real64)], real(actual, real64), &
                       shape(actual), tolerance32(tolerance), .false., format32, message, location)
   end subroutine equal_real32_0_1

   subroutine equal_real32_1_1(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(:), actual(:)
      real(real32), intent(in), optional :: tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (shapes_differ('assertEqual', shape(expected), shape(actual), message, location)) return
      call check_reals('assertEqual', real(expected, real64), real(actual, real64), &
                       shape(actual), tolerance32(tolerance), .false., format32, message, location)
   end subroutine equal_real32_1_1

   subroutine equal_real32_0_2(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected, actual(:, :)
      real(real32), intent(in), optional :: tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertEqual', [real(expected, real64)], &
                       reshape(real(actual, real64), [size(actual)]), shape(actual), &
                       tolerance32(tolerance), .false., format32, message, location)
   end subroutine equal_real32_0_2

   subroutine equal_real32_2_2(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(:, :), actual(:, :)
      real(real32), intent(in), optional :: tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (shapes_differ('assertEqual', shape(expected), shape(actual), message, location)) return
      call check_reals('assertEqual', reshape(real(expected, real64), [size(expected)]), &
                       reshape(real(actual, real64), [size(actual)]), shape(actual), &
                       tolerance32(tolerance), .false., format32, message, location)
   end subroutine equal_real32_2_2

   subroutine equal_real64_0_0(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected, actual
      real(real64), intent(in), optional :: tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertEqual', [expected], [actual], shape(actual), &
                       tolerance64(tolerance), .false., format64, message, location)
   end subroutine equal_real64_0_0

   subroutine equal_real64_0_1(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected, actual(:)
      real(real64), intent(in), optional :: tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertEqual', [expected], actual, shape(actual), &
                       tolerance64(tolerance), .false., format64, message, location)
   end subroutine equal_real64_0_1

   subroutine equal_real64_1_1(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected(:), actual(:)
      real(real64), intent(in), optional :: tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (shapes_differ('assertEqual', shape(expected), shape(actual), message, location)) return
      call check_reals('assertEqual', expected, actual, shape(actual), &
                       tolerance64(tolerance), .false., format64, message, location)
   end subroutine equal_real64_1_1

   subroutine equal_real64_0_2(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected, actual(:, :)
      real(real64), intent(in), optional :: tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertEqual', [expected], reshape(actual, [size(actual)]), shape(actual), &
                       tolerance64(tolerance), .false., format64, message, location)
   end subroutine equal_real64_0_2

   subroutine equal_real64_2_2(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected(:, :), actual(:, :)
      real(real64), intent(in), optional :: tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (shapes_differ('assertEqual', shape(expected), shape(actual), message, location)) return
      call check_reals('assertEqual', reshape(expected, [size(expected)]), &
                       reshape(actual, [size(actual)]), shape(actual), &
                       tolerance64(tolerance), .false., format64, message, location)
   end subroutine equal_real64_2_2

   ! ---- equality: reals (relative tolerance) ---------------------------------------------------

   subroutine relative_real32_0_0(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected, actual, tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertRelativelyEqual', [real(expected, real64)], [real(actual, real64)], &
                       shape(actual), real(tolerance, real64), .true., format32, message, location)
   end subroutine relative_real32_0_0

   subroutine relative_real32_0_1(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected, actual(:), tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertRelativelyEqual', [real(expected, real64)], real(actual, real64), &
                       shape(actual), real(tolerance, real64), .true., format32, message, location)
   end subroutine relative_real32_0_1

   subroutine relative_real32_1_1(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(:), actual(:), tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (shapes_differ('assertRelativelyEqual', shape(expected), shape(actual), message, &
                        location)) return
      call check_reals('assertRelativelyEqual', real(expected, real64), real(actual, real64), &
                       shape(actual), real(tolerance, real64), .true., format32, message, location)
   end subroutine relative_real32_1_1

   subroutine relative_real32_0_2(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected, actual(:, :), tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertRelativelyEqual', [real(expected, real64)], &
                       reshape(real(actual, real64), [size(actual)]), shape(actual), &
                       real(tolerance, real64), .true., format32, message, location)
   end subroutine relative_real32_0_2

   subroutine relative_real32_2_2(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(:, :), actual(:, :), tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (shapes_differ('assertRelativelyEqual', shape(expected), shape(actual), message, &
                        location)) return
      call check_reals('assertRelativelyEqual', reshape(real(expected, real64), [size(expected)]), &
                       reshape(real(actual, real64), [size(actual)]), shape(actual), &
                       real(tolerance, real64), .true., format32, message, location)
   end subroutine relative_real32_2_2

   subroutine relative_real64_0_0(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected, actual, tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertRelativelyEqual', [expected], [actual], shape(actual), tolerance, &
                       .true., format64, message, location)
   end subroutine relative_real64_0_0

   subroutine relative_real64_0_1(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected, actual(:), tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertRelativelyEqual', [expected], actual, shape(actual), tolerance, &
                       .true., format64, message, location)
   end subroutine relative_real64_0_1

   subroutine relative_real64_1_1(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected(:), actual(:), tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (shapes_differ('assertRelativelyEqual', shape(expected), shape(actual), message, &
                        location)) return
      call check_reals('assertRelativelyEqual', expected, actual, shape(actual), tolerance, &
                       .true., format64, message, location)
   end subroutine relative_real64_1_1

   subroutine relative_real64_0_2(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected, actual(:, :), tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_reals('assertRelativelyEqual', [expected], reshape(actual, [size(actual)]), &
                       shape(actual), tolerance, .true., format64, message, location)
   end subroutine relative_real64_0_2

   subroutine relative_real64_2_2(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected(:, :), actual(:, :), tolerance
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      if (shapes_differ('assertRelativelyEqual', shape(expected), shape(actual), message, &
                        location)) return
      call check_reals('assertRelativelyEqual', reshape(expected, [size(expected)]), &
                       reshape(actual, [size(actual)]), shape(actual), tolerance, .true., &
                       format64, message, location)
   end subroutine relative_real64_2_2

   ! ---- ordering -------------------------------------------------------------------------------

   subroutine less_int32(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertLessThan', lhs < rhs, '<', integer_text(int(lhs, int64)), &
                       integer_text(int(rhs, int64)), message, location)
   end subroutine less_int32

   subroutine less_int64(lhs, rhs, message, location)
      integer(int64), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertLessThan', lhs < rhs, '<', integer_text(lhs), integer_text(rhs), &
                       message, location)
   end subroutine less_int64

   subroutine less_real32(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertLessThan', real_less(real(lhs, real64), real(rhs, real64), .false.), &
                       '<', real_text(real(lhs, real64), format32), &
                       real_text(real(rhs, real64), format32), message, location)
   end subroutine less_real32

   subroutine less_real64(lhs, rhs, message, location)
      real(real64), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertLessThan', real_less(lhs, rhs, .false.), '<', &
                       real_text(lhs, format64), real_text(rhs, format64), message, location)
   end subroutine less_real64

   subroutine less_equal_int32(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertLessThanOrEqual', lhs <= rhs, '<=', integer_text(int(lhs, int64)), &
                       integer_text(int(rhs, int64)), message, location)
   end subroutine less_equal_int32

   subroutine less_equal_int64(lhs, rhs, message, location)
      integer(int64), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertLessThanOrEqual', lhs <= rhs, '<=', integer_text(lhs), &
                       integer_text(rhs), message, location)
   end subroutine less_equal_int64

   subroutine less_equal_real32(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertLessThanOrEqual', &
                       real_less(real(lhs, real64), real(rhs, real64), .true.), '<=', &
                       real_text(real(lhs, real64), format32), &
                       real_text(real(rhs, real64), format32), message, location)
   end subroutine less_equal_real32

   subroutine less_equal_real64(lhs, rhs, message, location)
      real(real64), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertLessThanOrEqual', real_less(lhs, rhs, .true.), '<=', &
                       real_text(lhs, format64), real_text(rhs, format64), message, location)
   end subroutine less_equal_real64

   subroutine greater_int32(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertGreaterThan', lhs > rhs, '>', integer_text(int(lhs, int64)), &
                       integer_text(int(rhs, int64)), message, location)
   end subroutine greater_int32

   subroutine greater_int64(lhs, rhs, message, location)
      integer(int64), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertGreaterThan', lhs > rhs, '>', integer_text(lhs), integer_text(rhs), &
                       message, location)
   end subroutine greater_int64

   subroutine greater_real32(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertGreaterThan', &
                       real_less(real(rhs, real64), real(lhs, real64), .false.), '>', &
                       real_text(real(lhs, real64), format32), &
                       real_text(real(rhs, real64), format32), message, location)
   end subroutine greater_real32

   subroutine greater_real64(lhs, rhs, message, location)
      real(real64), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertGreaterThan', real_less(rhs, lhs, .false.), '>', &
                       real_text(lhs, format64), real_text(rhs, format64), message, location)
   end subroutine greater_real64

   subroutine greater_equal_int32(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertGreaterThanOrEqual', lhs >= rhs, '>=', &
                       integer_text(int(lhs, int64)), integer_text(int(rhs, int64)), message, &
                       location)
   end subroutine greater_equal_int32

   subroutine greater_equal_int64(lhs, rhs, message, location)
      integer(int64), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertGreaterThanOrEqual', lhs >= rhs, '>=', integer_text(lhs), &
                       integer_text(rhs), message, location)
   end subroutine greater_equal_int64

   subroutine greater_equal_real32(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertGreaterThanOrEqual', &
                       real_less(real(rhs, real64), real(lhs, real64), .true.), '>=', &
                       real_text(real(lhs, real64), format32), &
                       real_text(real(rhs, real64), format32), message, location)
   end subroutine greater_equal_real32

   subroutine greater_equal_real64(lhs, rhs, message, location)
      real(real64), intent(in) :: lhs, rhs
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: location
      call check_order('assertGreaterThanOrEqual', real_less(rhs, lhs, .true.), '>=', &
                       real_text(lhs, format64), real_text(rhs, format64), message, location)
   end subroutine greater_equal_real64

end module funit
