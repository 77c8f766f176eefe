!> The element kinds of the deck: the `TYPE=` option of `*ELEMENT` and what a truss member asks of its
!> nodes (docs/input.md, `*ELEMENT`).
!>
!> Kept apart from uniarc_deck so that the card reader only hands over what it read: the option, the
!> elements a card created, and at the end the tables of the whole deck.
module uniarc_deck_element
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t
   use uniarc_strings, only: to_upper, integer_to_string
   use uniarc_deck_source, only: source_t, card_t, raise, clip, option_index
   use uniarc_model, only: element_beam_column, element_truss, dof_rz
   implicit none
   private
   public :: read_element_type, restrain_truss_nodes

contains

   !> The element kind of an element-defining card: its option `TYPE=BEAM` (the default, the
   !> Euler–Bernoulli beam-column) or `TYPE=TRUSS` (axial force only). Error at the option's value for
   !> any other word.
   subroutine read_element_type(source, card, kind, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      integer, intent(out) :: kind
      type(error_t), allocatable, intent(out) :: error
      integer :: type_option
      kind = element_beam_column
      type_option = option_index(card, 'TYPE')
      if (type_option == 0) return
      select case (to_upper(card%options(type_option)%value))
      case ('BEAM')
         kind = element_beam_column
      case ('TRUSS')
         kind = element_truss
      case default
         call raise(source, card%line, card%options(type_option)%value_column, &
                    'expected TYPE=BEAM or TYPE=TRUSS, found '''//clip(card%options(type_option)%value)//'''', &
                    error)
      end select
   end subroutine read_element_type

   !> Hold the rotation of every node that only truss elements use.
   !>
   !> A truss has no rotational stiffness, so the rotation of a node connected to trusses only would be
   !> a zero pivot of the stiffness: it is held (`fixed(dof_rz, node)` set; docs/input.md). A moment
   !> (`*CLOAD ..., MZ`) on such a node would then do no work and is an error at the node's definition
   !> (`node_line`, `node_column`). (A distributed load on a truss is refused where `*DLOAD` is read,
   !> uniarc_deck_loads.) Arrays: connectivity (2, n_elements), kinds (n_elements),
   !> node_label/node_line/node_column (n_nodes), fixed and nodal_load (3, n_nodes).
   subroutine restrain_truss_nodes(source, connectivity, kinds, node_label, node_line, node_column, &
                                   fixed, nodal_load, error)
      type(source_t), intent(in) :: source
      integer, intent(in) :: connectivity(:, :)
      integer, intent(in) :: kinds(:)
      integer, intent(in) :: node_label(:), node_line(:), node_column(:)
      logical, intent(inout) :: fixed(:, :)
      real(dp), intent(in) :: nodal_load(:, :)
      type(error_t), allocatable, intent(out) :: error
      logical :: has_beam(size(node_label)), has_truss(size(node_label))
      integer :: e, i
      if (all(kinds /= element_truss)) return
      has_beam = .false.
      has_truss = .false.
      do e = 1, size(kinds)
         if (kinds(e) == element_truss) then
            has_truss(connectivity(:, e)) = .true.
         else
            has_beam(connectivity(:, e)) = .true.
         end if
      end do
      do i = 1, size(node_label)
         if (.not. has_truss(i) .or. has_beam(i)) cycle
         if (abs(nodal_load(dof_rz, i)) > 0.0_dp) then
            call raise(source, node_line(i), node_column(i), 'expected no moment (MZ) on node '// &
                       integer_to_string(node_label(i))//', found one: only truss elements use the node, and '// &
                       'a truss carries no moment', error)
            return
         end if
         fixed(dof_rz, i) = .true.
      end do
   end subroutine restrain_truss_nodes

end module uniarc_deck_element
