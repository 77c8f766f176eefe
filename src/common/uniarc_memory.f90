!> How much memory a model needs, and how much the system can give: the check that turns a model too
!> large for the machine into a message (exit code 2) before the allocations that would exhaust it
!> (docs/contracts.md, "Memory").
!>
!> The estimate counts the arrays that grow with the model (bytes, 8 per real, 4 per integer):
!>  - per equation: the band tangent K_T held three times (the assembled matrix, its LU factors and a
!>    work copy of the stability test), each (3 b + 1) reals for half bandwidth b (LAPACK dgbtrf's
!>    storage: 2 kl + ku + 1 rows), and about 40 vectors of the Newton iteration, its trial and
!>    committed states and the critical-point search (u, Δu, R, F, residuals, tangents), and the 83
!>    vectors of the memory of the path traced (uniarc_path_trace: the last 64 committed states, the
!>    last 8 corners, the last 8 states past a critical point or a corner, the state where the branch
!>    began and two work vectors, allocated once);
!>  - per node: coordinates, labels, DOF numbering, nodal displacements of the committed, trial and
!>    output states and the deck's source positions;
!>  - per element: connectivity, section, label, set memberships and the element loops' copies;
!>  - per contact candidate: its law (gap, direction, flexibility), its row of the contact LCP
!>    (gradient, Hessian, equations), reactions and gaps of the working set, output summaries.
!> The constants were measured against the peak resident memory of runs of 1e4 to 1e6 elements
!> (docs/contracts.md gives the comparison); the estimate is meant to be an upper bound within a
!> factor of about two, enough to tell a model that fits from one a thousand times too large.
module uniarc_memory
   use, intrinsic :: iso_c_binding, only: c_long_long
   use, intrinsic :: iso_fortran_env, only: int64
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, make_error, error_input
   implicit none
   private
   public :: model_memory_bytes, available_memory, memory_text, memory_shortfall, allocation_failure

   real(dp), parameter :: bytes_per_equation_vectors = 320.0_dp   !< 40 vectors of reals
   !> uniarc_path_trace's traced_vectors (83) vectors of reals: the path traced (kept states, corners,
   !> event states, the branch's origin)
   real(dp), parameter :: bytes_per_equation_traced = 664.0_dp
   real(dp), parameter :: band_copies = 3.0_dp                    !< K_T, its LU factors, a work copy
   real(dp), parameter :: bytes_per_node = 320.0_dp
   real(dp), parameter :: bytes_per_element = 160.0_dp
   real(dp), parameter :: bytes_per_candidate = 640.0_dp
   real(dp), parameter :: fixed_bytes = 16.0e6_dp                 !< program, runtime and libraries

   interface
      function c_address_space_limit() bind(c, name='uniarc_address_space_limit') result(limit)
         import :: c_long_long
         integer(c_long_long) :: limit
      end function c_address_space_limit
   end interface

contains

   !> Estimated peak memory (bytes) of an analysis of a model with these counts; reals, so that counts
   !> beyond the default integer (a generator asked for 1e12 elements) are estimated too.
   !> n_equations: free DOFs (3 per node at most); half_bandwidth: of K_T in the DOF numbering
   !> (uniarc_dof_map; 5 for a chain of two-node elements with 3 DOFs per node).
   pure function model_memory_bytes(n_nodes, n_elements, n_equations, half_bandwidth, n_candidates) result(bytes)
      real(dp), intent(in) :: n_nodes, n_elements, n_equations, half_bandwidth, n_candidates
      real(dp) :: bytes
      bytes = fixed_bytes + n_equations*(band_copies*8.0_dp*(3.0_dp*half_bandwidth + 1.0_dp) + &
                                         bytes_per_equation_vectors + bytes_per_equation_traced) + &
              n_nodes*bytes_per_node + n_elements*bytes_per_element + n_candidates*bytes_per_candidate
   end function model_memory_bytes

   !> The memory the run may use (bytes) and where that figure comes from: the smaller of the
   !> memory the kernel reports available for new allocations (MemAvailable in /proc/meminfo, Linux
   !> 3.14 and later) and the address-space limit (RLIMIT_AS, `ulimit -v`), less what the program
   !> already occupies (VmSize, /proc/self/status) under the latter. `bytes` < 0 when neither is known
   !> (then no model is refused).
   subroutine available_memory(bytes, origin)
      real(dp), intent(out) :: bytes
      character(len=:), allocatable, intent(out) :: origin
      real(dp) :: meminfo, limit, used
      meminfo = proc_field('/proc/meminfo', 'MemAvailable:')
      limit = real(c_address_space_limit(), dp)
      bytes = -1.0_dp
      origin = 'unknown'
      if (meminfo >= 0.0_dp) then
         bytes = meminfo
         origin = 'MemAvailable in /proc/meminfo'
      end if
      if (limit >= 0.0_dp) then
         used = max(proc_field('/proc/self/status', 'VmSize:'), 0.0_dp)
         if (bytes < 0.0_dp .or. limit - used < bytes) then
            bytes = max(limit - used, 0.0_dp)
            origin = 'the address-space limit (ulimit -v) less what uniarc already uses'
         end if
      end if
   end subroutine available_memory

   !> When `need` bytes exceed the memory available, a phrase for a message ("need about 1.2 TB;
   !> 23.4 GB available (MemAvailable in /proc/meminfo)"); unallocated when they fit or the available
   !> memory is unknown.
   subroutine memory_shortfall(need, shortfall)
      real(dp), intent(in) :: need
      character(len=:), allocatable, intent(out) :: shortfall
      real(dp) :: available
      character(len=:), allocatable :: origin
      call available_memory(available, origin)
      if (available < 0.0_dp .or. need <= available) return
      shortfall = 'need about '//memory_text(need)//'; '//memory_text(available)//' available ('//origin//')'
   end subroutine memory_shortfall

   !> The error of an `allocate (..., stat=status)` that the system refused, naming what did not fit
   !> and its size (docs/contracts.md, "Memory"); nothing when `status` is 0, so that every large
   !> allocation reads `allocate (..., stat=status); call allocation_failure(...); if (allocated(error)) return`.
   !> what: the array, as a noun phrase ("the members of element set 'rib'"); bytes: its size (8 per
   !> real, 4 per integer or logical).
   !> category: error_input (exit code 2) while the deck is read and the model built — "the model does
   !> not fit in memory: cannot allocate WHAT (SIZE): the system refused it (stat N)" —, error_analysis
   !> (exit code 1) once the analysis has started — "analysis failed: out of memory: cannot allocate ...".
   !> The runtime's errmsg= is not quoted: gfortran 12 gives "Attempt to allocate an allocated object"
   !> for memory it could not get (stat 5014, measured under `ulimit -v`).
   !> The error is flagged `out_of_memory` (uniarc_error): within an analysis step it ends the run
   !> instead of cutting the step back.
   subroutine allocation_failure(status, what, bytes, category, error)
      integer, intent(in) :: status
      character(len=*), intent(in) :: what
      real(dp), intent(in) :: bytes
      integer, intent(in) :: category
      type(error_t), allocatable, intent(inout) :: error
      character(len=:), allocatable :: text
      character(len=16) :: code
      if (status == 0) return
      write (code, '(i0)') status
      text = 'cannot allocate '//what//' ('//memory_text(bytes)//'): the system refused it (stat '//trim(code)//')'
      if (category == error_input) then
         call make_error(error, 'the model does not fit in memory: '//text, category)
      else
         call make_error(error, 'analysis failed: out of memory: '//text, category)
      end if
      error%out_of_memory = .true.
   end subroutine allocation_failure

   !> Bytes as text with three significant digits and a decimal unit: "512 B", "3.42 MB", "1.20 TB".
   pure function memory_text(bytes) result(text)
      real(dp), intent(in) :: bytes
      character(len=:), allocatable :: text
      character(len=2), parameter :: units(6) = ['B ', 'kB', 'MB', 'GB', 'TB', 'PB']
      character(len=32) :: buffer
      real(dp) :: value
      integer :: k
      value = max(bytes, 0.0_dp)
      k = 1
      do while (value >= 999.5_dp .and. k < size(units))
         value = value/1000.0_dp
         k = k + 1
      end do
      if (k == 1) then
         write (buffer, '(i0)') nint(value)
      else if (value >= 99.95_dp) then
         write (buffer, '(f0.0)') value
         buffer = buffer(:len_trim(buffer) - 1)
      else if (value >= 9.995_dp) then
         write (buffer, '(f0.1)') value
      else
         write (buffer, '(f0.2)') value
      end if
      text = trim(buffer)//' '//trim(units(k))
   end function memory_text

   !> The value in bytes of a "Name:  N kB" line of a /proc file, or -1 when absent or unreadable.
   function proc_field(path, name) result(bytes)
      character(len=*), intent(in) :: path, name
      real(dp) :: bytes
      character(len=256) :: line
      integer :: unit, status, close_status
      integer(int64) :: kib
      bytes = -1.0_dp
      open (newunit=unit, file=path, status='old', action='read', iostat=status)
      if (status /= 0) return
      do
         read (unit, '(a)', iostat=status) line
         if (status /= 0) exit
         if (line(:len(name)) /= name) cycle
         read (line(len(name) + 1:), *, iostat=status) kib
         if (status == 0) bytes = 1024.0_dp*real(kib, dp)
         exit
      end do
      close (unit, iostat=close_status)
   end function proc_field

end module uniarc_memory
