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
   use uniarc_model, only: model_t
   implicit none
   private
   public :: contact_summary_t, summarize_contact, summarize_group, summarize_groups, closed_group

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

   !> The contact columns of all groups together at the candidates' `reactions` and working set
   !> `active` (one each per candidate): counts and reactions summed (largest reaction: the largest of
   !> all), and the first region the one lying first (smallest coordinate) over all groups.
   pure function summarize_contact(model, reactions, active) result(summary)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: reactions(:)
      logical, intent(in) :: active(:)
      type(contact_summary_t) :: summary
      type(contact_summary_t) :: group
      integer :: g, k, c
      if (.not. allocated(model%contact_groups)) return
      do g = 1, size(model%contact_groups)
         ! the reactions summed in one sequence over all candidates, in group order
         do k = 1, size(model%contact_groups(g)%candidates)
            c = model%contact_groups(g)%candidates(k)
            if (model%contacts(c)%tangential) cycle   ! a foundation's tangential spring: not a contact
            if (.not. (active(c) .and. reactions(c) > 0.0_dp)) cycle
            summary%n_contact = summary%n_contact + 1
            summary%reaction_max = max(summary%reaction_max, reactions(c))
            summary%reaction_sum = summary%reaction_sum + reactions(c)
         end do
         group = summarize_group(model, g, reactions, active)
         summary%regions = summary%regions + group%regions
         if (group%regions > 0 .and. group%first_key < summary%first_key) then
            summary%first_key = group%first_key
            summary%s_contact = group%s_contact
         end if
      end do
   end function summarize_contact

   !> The contact columns of every contact group (summarize_group), one element per group (none when
   !> the model has no contact groups).
   pure function summarize_groups(model, reactions, active) result(groups)
      type(model_t), intent(in) :: model
      real(dp), intent(in) :: reactions(:)
      logical, intent(in) :: active(:)
      type(contact_summary_t), allocatable :: groups(:)
      integer :: g
      if (.not. allocated(model%contact_groups)) then
         allocate (groups(0))
         return
      end if
      allocate (groups(size(model%contact_groups)))
      do g = 1, size(groups)
         groups(g) = summarize_group(model, g, reactions, active)
      end do
   end function summarize_groups

   !> The contact columns of contact group `g` alone (see summarize_contact and the module header).
   pure function summarize_group(model, g, reactions, active) result(summary)
      type(model_t), intent(in) :: model
      integer, intent(in) :: g
      real(dp), intent(in) :: reactions(:)
      logical, intent(in) :: active(:)
      type(contact_summary_t) :: summary
      integer :: k, c, m, run_start
      logical, allocatable :: touching(:)
      real(dp), allocatable :: s(:)
      logical :: wraps

      associate (candidates => contacts_of_group(model, g))
         allocate (touching(size(candidates)), s(size(candidates)))
         m = size(candidates)
         do k = 1, m
            c = candidates(k)
            touching(k) = active(c) .and. reactions(c) > 0.0_dp
            s(k) = model%contacts(c)%coordinate
            if (.not. touching(k)) cycle
            summary%n_contact = summary%n_contact + 1
            summary%reaction_max = max(summary%reaction_max, reactions(c))
            summary%reaction_sum = summary%reaction_sum + reactions(c)
         end do
      end associate
      if (m == 0) return
      ! A run at the end of a closed chain goes on at its start (module header).
      wraps = touching(1) .and. touching(m) .and. .not. all(touching)
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
            summary%first_key = minval(s)
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
   end function summarize_group

   !> Whether the candidates of contact group `g` form a closed chain: more than two, and the nodes of
   !> the last and the first joined by an element of the model.
   pure logical function closed_group(model, g) result(closed)
      type(model_t), intent(in) :: model
      integer, intent(in) :: g
      integer :: e, first, last
      closed = .false.
      associate (candidates => contacts_of_group(model, g))
         if (size(candidates) < 3) return
         first = model%contacts(candidates(1))%node
         last = model%contacts(candidates(size(candidates)))%node
      end associate
      do e = 1, model%n_elements
         associate (ends => model%connectivity(:, e))
            if ((ends(1) == first .and. ends(2) == last) .or. (ends(1) == last .and. ends(2) == first)) then
               closed = .true.
               return
            end if
         end associate
      end do
   end function closed_group

   !> The candidates of contact group `g` that are contacts, in the group's order: all of them but a
   !> foundation's tangential springs (`KT=`), which carry shear along the surface, not contact.
   pure function contacts_of_group(model, g) result(candidates)
      type(model_t), intent(in) :: model
      integer, intent(in) :: g
      integer, allocatable :: candidates(:)
      integer :: k
      candidates = pack(model%contact_groups(g)%candidates, &
                        [(.not. model%contacts(model%contact_groups(g)%candidates(k))%tangential, &
                          k=1, size(model%contact_groups(g)%candidates))])
   end function contacts_of_group

end module uniarc_contact_summary
