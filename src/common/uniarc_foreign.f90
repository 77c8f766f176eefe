!> The one module of interface blocks: the routines uniarc calls outside Fortran (LAPACK, libc).
!>
!> Keeping them here means every call is checked against an explicit interface
!> (-Werror=implicit-interface) and LAPACK's `info` is translated into an error in one place.
module uniarc_foreign
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_analysis, error_internal
   use uniarc_strings, only: integer_to_string
   implicit none
   private
   public :: dgbtrf, dgbtrs, dgetrf, dgetrs
   public :: lapack_check, rename_file, make_directory, exit_program

   interface
      !> LU factorisation of a general band matrix with partial pivoting (LAPACK).
      subroutine dgbtrf(m, n, kl, ku, ab, ldab, ipiv, info)
         import :: dp
         integer, intent(in) :: m, n, kl, ku, ldab
         real(dp), intent(inout) :: ab(ldab, *)
         integer, intent(out) :: ipiv(*)
         integer, intent(out) :: info
      end subroutine dgbtrf

      !> Solve with the band LU factors of dgbtrf (LAPACK).
      subroutine dgbtrs(trans, n, kl, ku, nrhs, ab, ldab, ipiv, b, ldb, info)
         import :: dp
         character(len=1), intent(in) :: trans
         integer, intent(in) :: n, kl, ku, nrhs, ldab, ldb
         real(dp), intent(in) :: ab(ldab, *)
         integer, intent(in) :: ipiv(*)
         real(dp), intent(inout) :: b(ldb, *)
         integer, intent(out) :: info
      end subroutine dgbtrs

      !> LU factorisation of a general dense matrix with partial pivoting (LAPACK).
      subroutine dgetrf(m, n, a, lda, ipiv, info)
         import :: dp
         integer, intent(in) :: m, n, lda
         real(dp), intent(inout) :: a(lda, *)
         integer, intent(out) :: ipiv(*)
         integer, intent(out) :: info
      end subroutine dgetrf

      !> Solve with the dense LU factors of dgetrf (LAPACK).
      subroutine dgetrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
         import :: dp
         character(len=1), intent(in) :: trans
         integer, intent(in) :: n, nrhs, lda, ldb
         real(dp), intent(in) :: a(lda, *)
         integer, intent(in) :: ipiv(*)
         real(dp), intent(inout) :: b(ldb, *)
         integer, intent(out) :: info
      end subroutine dgetrs

      function c_rename(old_path, new_path) bind(c, name='rename') result(status)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: old_path(*), new_path(*)
         integer(c_int) :: status
      end function c_rename

      subroutine c_exit(status) bind(c, name='exit')
         import :: c_int
         integer(c_int), value, intent(in) :: status
      end subroutine c_exit

      function c_mkdir(path, mode) bind(c, name='mkdir') result(status)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int), value, intent(in) :: mode
         integer(c_int) :: status
      end function c_mkdir
   end interface

contains

   !> Translate a LAPACK `info` into an error: the one place where LAPACK failures get their words.
   !> info > 0 from a factorisation means an exactly zero pivot: the tangent is singular there.
   subroutine lapack_check(routine, info, error)
      character(len=*), intent(in) :: routine
      integer, intent(in) :: info
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: text
      if (info == 0) return
      text = integer_to_string(abs(info))
      if (info < 0) then
         call make_error(error, routine//': argument '//text//' has an illegal value', error_internal)
      else
         call make_error(error, routine//': the matrix is singular (zero pivot at equation '// &
                         text//')', error_analysis)
      end if
   end subroutine lapack_check

   !> Rename a file atomically (POSIX rename): output is written to a temporary name, then renamed.
   subroutine rename_file(old_path, new_path, error)
      character(len=*), intent(in) :: old_path, new_path
      type(error_t), allocatable, intent(out) :: error
      if (c_rename(old_path//c_null_char, new_path//c_null_char) /= 0) then
         call make_error(error, 'cannot rename '//old_path//' to '//new_path, error_analysis)
      end if
   end subroutine rename_file

   !> Create a directory and its missing parents (mode 0755), like `mkdir -p`.
   subroutine make_directory(path, error)
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(out) :: error
      logical :: exists
      integer :: i
      integer(c_int) :: status
      ! Every prefix that ends before a '/' is a parent, created first if missing.
      do i = 2, len(path)
         if (path(i:i) /= '/') cycle
         inquire (file=path(:i - 1)//'/.', exist=exists)
         if (.not. exists) status = c_mkdir(path(:i - 1)//c_null_char, int(o'755', c_int))
      end do
      inquire (file=path//'/.', exist=exists)
      if (exists) return
      status = c_mkdir(path//c_null_char, int(o'755', c_int))
      if (status /= 0) call make_error(error, 'cannot create output directory '//path, error_analysis)
   end subroutine make_directory

   !> End the program with an exit status and no further words: Fortran's `stop n` would add
   !> "STOP n" to stderr under the error message. libgfortran closes its units at exit.
   subroutine exit_program(status)
      integer, intent(in) :: status
      flush (output_unit)
      flush (error_unit)
      call c_exit(int(status, c_int))
   end subroutine exit_program

end module uniarc_foreign
