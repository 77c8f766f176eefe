!> The contact columns of the path file (docs/contracts.md, `STEM.path`): per contact group (a
!> foundation, a spring group, an obstacle) and for all groups together, the candidates in contact,
!> the contact regions, the ends of the first region and the largest and total reaction.
!>
!> A region is a run of consecutive candidates of a group (in the group's order, which is the order
!> along its nodes) that are in contact (in the working set with a positive reaction). The candidates
!> of a closed chain — a ring, whose last candidate's node and first candidate's node are joined by an
!> element — follow each other round the ring: a run at the end of the group and a run at its start
!> are one region that crosses the group's first node, counted once.
module uniarc_contact_summary
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_analysis
   use uniarc_memory, only: allocation_failure
   use uniarc_model, only: model_t
   implicit none
   private
   public :: contact_summary_t, summarize_contacts, closed_group

   !> What the path file reports of the contact state of one group or of all of them.
   type :: contact_summary_t
      integer :: n_contact = 0            !< candidates in contact
      integer :: regions = 0              !< contact regions (module header)
      !> Coordinates (the candidates' `coordinate`: arc length × SCALE) of the start and end of the
      !> first region: the one that reaches the smallest coordinate of its group; a region that crosses
      !> the first node of a ring starts at the larger coordinate, s_contact(1) > s_contact(2).
      real(dp) :: s_contact(2) = 0.0_dp
      real(dp) :: reaction_max = 0.0_dp
      real(dp) :: reaction_sum = 0.0_dp
      !> Where the first region lies, for ordering regions of several groups: its smallest coordinate
      !> (the group's first coordinate for a region that crosses the first node); huge when none.
      real(dp) :: first_key = huge(1.0_dp)
   end type contact_summary_t

contains

   !> The contact columns at the candidates' `reactions` and working set `active` (one each per
   !> candidate): `summary` of all groups together — counts and reactions summed (largest reaction: the
   !> largest of all), and the first region the one lying first (smallest coordinate) over all groups —
   !> and `groups` (n_groups, none without contact groups) each group's alone.
   !> The work arrays (the largest group's length) are allocated once, with stat=. Errors: they or
   !> `groups` refused by the system (error_analysis, out of memory; docs/contracts.md, "Memory").
   subroutine summarize_contacts(model, reactions, active, summary, groups, error)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: reactions(:)
      logical, intent(in) :: active(:)
      type(contact_summary_t), intent(out) :: summary
      type(contact_summary_t), allocatable, intent(out) :: groups(:)
      type(error_t), allocatable, intent(out) :: error
      integer, allocatable :: members(:)
      logical, allocatable :: touching(:)
      real(dp), allocatable :: s(:)
      type(contact_summary_t) :: group
      integer :: g, k, c, largest, n_groups, status
      n_groups = 0
      if (allocated(model%contact_groups)) n_groups = size(model%contact_groups)
      largest = 0
      do g = 1, n_groups
         largest = max(largest, size(model%contact_groups(g)%candidates))
      end do
      allocate (groups(n_groups), members(largest), touching(largest), s(largest), stat=status)
      call allocation_failure(status, 'the contact summary of the row', 16.0_dp*largest, error_analysis, error)
      if (allocated(error)) return
      do g = 1, n_groups
         ! the reactions summed in one sequence over all candidates, in group order
         do k = 1, size(model%contact_groups(g)%candidates)
            c = model%contact_groups(g)%candidates(k)
            if (model%contacts(c)%tangential) cycle   ! a foundation's tangential spring: not a contact
            if (.not. (active(c) .and. reactions(c) > 0.0_dp)) cycle
            summary%n_contact = summary%n_contact + 1
            summary%reaction_max = max(summary%reaction_max, reactions(c))
            summary%reaction_sum = summary%reaction_sum + reactions(c)
         end do
         call summarize_group(model, g, reactions, active, members, touching, s, group)
         groups(g) = group
         summary%regions = summary%regions + group%regions
         if (group%regions > 0 .and. group%first_key < summary%first_key) then
            summary%first_key = group%first_key
            summary%s_contact = group%s_contact
         end if
      end do
   end subroutine summarize_contacts

   !> The contact columns of contact group `g` alone (see summarize_contacts and the module header).
   !> members, touching, s: work space of at least the group's length.
   pure subroutine summarize_group(model, g, reactions, active, members, touching, s, summary)
      type(model_t), intent(in) :: model
      integer, intent(in) :: g
      real(dp), intent(in) :: reactions(:)
      logical, intent(in) :: active(:)
      integer, intent(out) :: members(:)
      logical, intent(out) :: touching(:)
      real(dp), intent(out) :: s(:)
      type(contact_summary_t), intent(out) :: summary
      integer :: k, c, m, run_start
      logical :: wraps

      call contacts_of_group(model, g, members, m)
      do k = 1, m
         c = members(k)
         touching(k) = active(c) .and. reactions(c) > 0.0_dp
         s(k) = model%contacts(c)%coordinate
         if (.not. touching(k)) cycle
         summary%n_contact = summary%n_contact + 1
         summary%reaction_max = max(summary%reaction_max, reactions(c))
         summary%reaction_sum = summary%reaction_sum + reactions(c)
      end do
      if (m == 0) return
      ! A run at the end of a closed chain goes on at its start (module header).
      wraps = touching(1) .and. touching(m) .and. .not. all(touching(1:m))
      if (wraps) wraps = closed_group(model, g)
      k = 1
      do while (k <= m)
         if (.not. touching(k)) then
            k = k + 1
            cycle
         end if
         run_start = k
         do while (k < m)
            if (.not. touching(k + 1)) exit
            k = k + 1
         end do
         ! the run is candidates run_start..k
         if (wraps .and. run_start == 1) then
            ! counted with the run that ends the chain, which ends here
            summary%first_key = minval(s(1:m))
            summary%s_contact(2) = s(k)
         else if (wraps .and. k == m) then
            summary%regions = summary%regions + 1
            summary%s_contact(1) = s(run_start)
         else
            summary%regions = summary%regions + 1
            if (min(s(run_start), s(k)) < summary%first_key) then
               summary%first_key = min(s(run_start), s(k))
               summary%s_contact = [min(s(run_start), s(k)), max(s(run_start), s(k))]
            end if
         end if
         k = k + 1
      end do
   end subroutine summarize_group

   !> Whether the candidates of contact group `g` form a closed chain: more than two, and the nodes of
   !> the last and the first joined by an element of the model.
   pure logical function closed_group(model, g) result(closed)
      type(model_t), intent(in) :: model
      integer, intent(in) :: g
      integer :: e, first, last, k, m, c
      closed = .false.
      ! the first and the last of its contacts (contacts_of_group), and how many there are
      first = 0
      last = 0
      m = 0
      do k = 1, size(model%contact_groups(g)%candidates)
         c = model%contact_groups(g)%candidates(k)
         if (model%contacts(c)%tangential) cycle
         m = m + 1
         if (m == 1) first = model%contacts(c)%node
         last = model%contacts(c)%node
      end do
      if (m < 3) return
      do e = 1, model%n_elements
         associate (ends => model%connectivity(:, e))
            if ((ends(1) == first .and. ends(2) == last) .or. (ends(1) == last .and. ends(2) == first)) then
               closed = .true.
               return
            end if
         end associate
      end do
   end function closed_group

   !> The candidates of contact group `g` that are contacts, in the group's order, into members(1:m):
   !> all of them but a foundation's tangential springs (`KT=`), which carry shear along the surface,
   !> not contact.
   pure subroutine contacts_of_group(model, g, members, m)
      type(model_t), intent(in) :: model
      integer, intent(in) :: g
      integer, intent(out) :: members(:)   !< at least the group's length
      integer, intent(out) :: m
      integer :: k, c
      m = 0
      do k = 1, size(model%contact_groups(g)%candidates)
         c = model%contact_groups(g)%candidates(k)
         if (model%contacts(c)%tangential) cycle
         m = m + 1
         members(m) = c
      end do
   end subroutine contacts_of_group

end module uniarc_contact_summary
