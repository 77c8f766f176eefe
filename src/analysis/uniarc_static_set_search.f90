!> The contact set of a linear static analysis whose tangential springs switch with their radial
!> contacts (*FOUNDATION, KT=, TANGENTIAL=CONTACT; docs/theory.md §3.8): the search by single changes
!> that uniarc_linear_static falls back to when the rounds of the contact LCP do not settle.
!>
!> With such springs the law is not an LCP: a set S is consistent when the solution with the radial
!> contacts of S closed and the tangential springs of S acting has every radial reaction of S ≥ 0 and
!> every gap outside S ≥ 0, and a spring's force jumps where its contact opens, so the LCP of a frame
!> (which holds the springs as they are) can jump between sets that each switch the springs of the
!> other (measured on the segmental lining of input/segmental_lining_bedded.inp with the earlier
!> flexible lining and K_R = 2e4, K_T = K_R: a cycle of 15 sets). The search changes one candidate
!> at a time, the one whose sign condition fails most (a single principal pivot of the kind of
!> Murty 1974, with the largest violation chosen as the design programs' loop chooses its worst node),
!> and a set met before ends it: then no consistent set was reached from the start. On a realistic
!> lining (EI = 1.07e5, joints 7.2e4) over K_R from 1e4 to 3e4, H from 10 to 20 and K0 from 0.5 to 0.7
!> (36 cases) uniarc with this rule solved 33, with the least-index rule (finite for an LCP with a
!> P-matrix) 31; alone from every node in contact, in the lining's own model
!> (tests/regression/lining_sets_check.py), the two rules reach a consistent set in 33 and 28.
!>
!> Reference: K. G. Murty (1974), Note on a Bard-type scheme for solving the complementarity problem,
!> *Opsearch* 11, 123–130.
module uniarc_static_set_search
   use uniarc_kinds, only: dp, i8
   use uniarc_model, only: model_t
   use uniarc_dof_map, only: dof_map_t, candidate_live
   implicit none
   private
   public :: largest_violation, set_signature, switching_springs, switching_group

contains

   !> The candidate whose sign condition fails most at the solution of `set` (r, g its reactions and
   !> linearised gaps, uniarc_linear_static), measured as a gap where it can be: out of the set, its
   !> penetration −w/g_unit (w = g + t r); in the set, an elastic candidate's separation −t r/g_unit
   !> (its spring would pull), a rigid one's pull −r/r_unit. The units are those of
   !> complementarity_violation (uniarc_linear_static). 0: none beyond `tolerance` (the set is
   !> consistent, or only round-off of |r w| is left). Tangential springs and bonded candidates are not
   !> contacts and never change.
   pure integer function largest_violation(model, map, set, r, g, r_unit, g_unit, tolerance) result(worst)
      type(model_t), intent(in) :: model
      type(dof_map_t), intent(in) :: map
      logical, intent(in) :: set(:)
      real(dp), intent(in) :: r(:), g(:), r_unit, g_unit, tolerance
      real(dp) :: v, largest, t
      integer :: c
      worst = 0
      largest = tolerance
      do c = 1, size(set)
         if (.not. candidate_live(map, c) .or. model%contacts(c)%bilateral) cycle
         t = model%contacts(c)%flexibility
         if (set(c)) then
            if (t > 0.0_dp) then
               v = -t*r(c)/g_unit
            else
               v = -r(c)/r_unit
            end if
         else
            v = -(g(c) + t*r(c))/g_unit
         end if
         if (v > largest) then
            largest = v
            worst = c
         end if
      end do
   end function largest_violation

   !> A signature of a set to recognise a set met before: two polynomial hashes of its members'
   !> indices modulo two primes below 2³¹ (no product exceeds 2⁶²: no integer overflow), joined in one
   !> 62-bit integer; two different sets share one with a probability of about 2⁻⁶² per pair.
   pure integer(i8) function set_signature(set) result(signature)
      logical, intent(in) :: set(:)
      integer(i8), parameter :: prime(2) = [2147483647_i8, 2147483629_i8], base(2) = [1000003_i8, 999983_i8]
      integer(i8) :: hash(2)
      integer :: c
      hash = int(size(set), i8)
      do c = 1, size(set)
         if (set(c)) hash = mod(hash*base + int(c, i8), prime)
      end do
      signature = hash(1)*2147483648_i8 + hash(2)
   end function set_signature

   !> Whether the model has tangential springs that follow a radial partner (TANGENTIAL=CONTACT).
   pure logical function switching_springs(model)
      type(model_t), intent(in) :: model
      integer :: c
      switching_springs = .false.
      if (.not. allocated(model%contacts)) return
      do c = 1, size(model%contacts)
         if (model%contacts(c)%tangential .and. model%contacts(c)%partner > 0) then
            switching_springs = .true.
            return
         end if
      end do
   end function switching_springs

   !> The name of the first contact group with tangential springs that follow their radial partners
   !> ('' when none has a name).
   pure function switching_group(model) result(name)
      type(model_t), intent(in) :: model
      character(len=:), allocatable :: name
      integer :: c, group
      name = ''
      do c = 1, size(model%contacts)
         if (.not. (model%contacts(c)%tangential .and. model%contacts(c)%partner > 0)) cycle
         group = model%contacts(c)%group
         if (allocated(model%contact_groups)) then
            if (group >= 1 .and. group <= size(model%contact_groups)) then
               if (allocated(model%contact_groups(group)%name)) name = model%contact_groups(group)%name
            end if
         end if
         return
      end do
   end function switching_group

end module uniarc_static_set_search
