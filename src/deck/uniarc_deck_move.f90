!> *MOVE, OBSTACLE=name: a rigid translation of an obstacle (plane, circle, ellipse or polyline) as part
!> of a load pattern (docs/input.md, *MOVE; docs/theory.md §3.11) — a punch, a plate pushed onto a pipe,
!> a roller pressed into a beam, an oval die, a displaced trench profile. The translation d is a reference value scaled by λ like the loads: inside a
!> *STEP it is the step's own (held at λ_end d in the steps after), in a deck without steps the deck's.
module uniarc_deck_move
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t
   use uniarc_strings, only: field_t, real_to_string
   use uniarc_model, only: gap_fixed_direction, gap_polyline
   use uniarc_deck_source, only: source_t, card_t, raise, clip, check_options, require_option, data_fields, &
                                 require_field_count, field_real
   use uniarc_deck_state, only: deck_t, require_one_data_line
   use uniarc_model_contacts, only: add_move
   use uniarc_model_builder, only: contact_group_index
   implicit none
   private
   public :: read_move, record_obstacle

contains

   !> Remember that contact group `group` (just made) is an obstacle of gap kind `gap_kind`, for *MOVE.
   pure subroutine record_obstacle(deck, group, gap_kind)
      type(deck_t), intent(inout) :: deck
      integer, intent(in) :: group, gap_kind
      integer, allocatable :: grown(:)
      if (.not. allocated(deck%obstacle_kind)) allocate (deck%obstacle_kind(0))
      if (size(deck%obstacle_kind) < group) then
         allocate (grown(group), source=0)
         grown(1:size(deck%obstacle_kind)) = deck%obstacle_kind
         call move_alloc(grown, deck%obstacle_kind)
      end if
      deck%obstacle_kind(group) = gap_kind
   end subroutine record_obstacle

   !> *MOVE, OBSTACLE=name with one data line `dx, dy`: the obstacle `name` (an *OBSTACLE above of any
   !> TYPE, by its group name) translated by (dx, dy) times λ. Rotations are not a part of it.
   subroutine read_move(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: option, group, kind, line, i
      character(len=:), allocatable :: name
      type(field_t), allocatable :: fields(:)
      real(dp) :: d(2), moved(2), farthest(2)
      integer :: j, k
      character(len=2), parameter :: names(2) = ['dx', 'dy']
      ! the obstacle cards' bound on a centre, a point or a vertex (uniarc_deck_contact)
      real(dp), parameter :: move_bound = 1.0e50_dp

      call check_options(source, card, [character(len=9) :: 'OBSTACLE='], error)
      if (allocated(error)) return
      call require_option(source, card, 'OBSTACLE', option, error)
      if (allocated(error)) return
      name = card%options(option)%value
      group = contact_group_index(deck%model, name)
      if (group == 0) then
         call raise(source, card%line, card%options(option)%value_column, 'expected the name of an '// &
                    '*OBSTACLE defined above, found '''//clip(name)//'''', error)
         return
      end if
      if (.not. allocated(deck%obstacle_kind)) allocate (deck%obstacle_kind(0))
      kind = 0   ! not made by *OBSTACLE
      if (group <= size(deck%obstacle_kind)) kind = deck%obstacle_kind(group)
      if (kind == 0) then
         call raise(source, card%line, card%options(option)%value_column, 'expected the name of an '// &
                    '*OBSTACLE, found '''//clip(name)//''', a foundation or spring (only obstacles move)', error)
         return
      end if
      call require_one_data_line(source, card, error)
      if (allocated(error)) return
      line = card%data_lines(1)
      call data_fields(source, line, fields)
      call require_field_count(source, line, fields, 2, 2, 'dx, dy: a translation only, no rotation', &
                               error)
      if (allocated(error)) return
      do i = 1, 2
         call field_real(source, deck%parameters, line, fields(i), names(i), d(i), error)
         if (allocated(error)) return
      end do
      ! The moved obstacle within the bounds of the obstacle cards (docs/contracts.md, "Non-finite
      ! results"): its centre, its vertices — for a plane, whose point is not kept, the translation
      ! itself — within ±1e50 after this card's and the earlier cards' translations of the same load
      ! pattern (λ = 1); the gaps are differences and squares of such coordinates.
      moved = d
      if (allocated(deck%model%moves)) then
         if (size(deck%model%moves, 2) >= group) moved = moved + deck%model%moves(:, group)
      end if
      farthest = abs(moved)
      associate (members => deck%model%contact_groups(group)%candidates)
         do k = 1, size(members)
            associate (candidate => deck%model%contacts(members(k)))
               select case (candidate%gap_kind)
               case (gap_fixed_direction)
                  continue
               case (gap_polyline)
                  if (allocated(candidate%vertices)) then
                     do j = 1, size(candidate%vertices, 2)
                        farthest = max(farthest, abs(candidate%vertices(:, j) + moved))
                     end do
                  end if
               case default
                  farthest = max(farthest, abs(candidate%centre + moved))
               end select
            end associate
         end do
      end associate
      do i = 1, 2
         if (.not. farthest(i) <= move_bound) then
            call raise(source, line, fields(i)%column, 'expected a translation '//names(i)//' that keeps the '// &
                       'obstacle '''//clip(name)//''' within 1e50 in magnitude, as its card''s coordinates '// &
                       '(beyond, the gaps overflow double precision: rescale the units), found '// &
                       trim(real_to_string(d(i)))//' (moving it to '//trim(real_to_string(farthest(i)))//')', error)
            return
         end if
      end do
      call add_move(deck%model, group, d)
   end subroutine read_move

end module uniarc_deck_move
