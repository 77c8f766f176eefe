!> The state of a deck being read, and the pieces every card family shares.
!>
!> A `deck_t` is a local of `read_deck` (never module state): the model under construction (a
!> `model_builder_t`), the parameters with the lines that defined them, the command-line overrides, and
!> what only the deck knows — where each node was defined, which analysis and output cards were seen.
!> The card readers (uniarc_deck_mesh, uniarc_deck_loads, uniarc_deck_contact, uniarc_deck_analysis)
!> take it with the source and the card; the shared pieces here turn option values and target fields
!> (a label or a set name) into values and internal indices, with positioned messages.
module uniarc_deck_state
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_input
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: field_t, is_name, integer_to_string
   use uniarc_growth, only: grow_integers
   use uniarc_expression, only: parameter_table_t, find_parameter
   use uniarc_deck_source, only: source_t, card_t, raise, clip, field_real, field_integer
   use uniarc_model, only: analysis_step_t
   use uniarc_model_builder, only: model_builder_t, add_node, node_index, element_index, node_set_index, &
                                   element_set_index
   implicit none
   private
   public :: parameter_override_t, deck_t
   public :: add_deck_node, option_field, option_real, require_one_data_line
   public :: resolve_nodes, resolve_elements, read_dof

   !> A `-D name=value` of the command line: replaces the deck's definition of parameter `name`.
   type :: parameter_override_t
      character(len=:), allocatable :: name
      character(len=:), allocatable :: value   !< an expression, evaluated where the deck defines `name`
   end type parameter_override_t

   !> Everything the cards have read so far.
   type :: deck_t
      type(model_builder_t) :: model                  !< the model the cards build
      type(parameter_table_t) :: parameters
      integer, allocatable :: parameter_line(:)       !< line that defined each parameter
      type(parameter_override_t), allocatable :: overrides(:)
      logical, allocatable :: override_used(:)
      integer :: analysis_line = 0                    !< line of the analysis card, 0 if none yet
      integer, allocatable :: node_line(:), node_column(:)   !< where each node was defined
      !> where the first nonzero moment (*CLOAD MZ, of the model or of any step) on each node was given,
      !> 0 if none or not yet (may be shorter than the nodes): the place to report a moment that a node
      !> of trusses or hinged ends cannot carry
      integer, allocatable :: moment_line(:), moment_column(:)
      character(len=:), allocatable :: stop_track     !< *PATH stop_track, resolved at the end
      integer :: stop_track_line = 0, stop_track_column = 0
      integer :: vtk_line = 0                         !< line of the *OUTPUT, VTK card, 0 if none yet
      integer :: forces_line = 0                      !< line of the *OUTPUT, FORCES card, 0 if none yet
      !> Where each *TRACK name was given (checked against the contact groups' path columns at the end
      !> of the deck: uniarc_deck_analysis, check_track_names)
      integer, allocatable :: track_line(:), track_column(:)
      !> Analysis steps (*STEP ... *END STEP, uniarc_deck_steps): the steps closed so far, whether one
      !> is open and where it began, and the first load and analysis card met outside every step
      !> (refused once the deck turns out to have steps).
      integer :: n_steps = 0
      type(analysis_step_t), allocatable :: steps(:)
      logical :: in_step = .false.
      integer :: step_line = 0, step_column = 0
      integer :: loose_load_line = 0, loose_load_column = 0
      integer :: loose_analysis_line = 0, loose_analysis_column = 0
      integer :: analysis_column = 0                  !< column of the analysis card of the open step
      integer :: imperfection_line = 0                !< line of the *IMPERFECTION card, 0 if none yet
      !> Where each prescribed displacement (*BOUNDARY with a value) was given, node by node: checked
      !> against the contact candidates at the end of the deck (uniarc_deck_loads, check_prescribed_nodes)
      integer :: n_prescribed = 0
      integer, allocatable :: prescribed_node(:), prescribed_line(:), prescribed_column(:)
      !> (n_contact_groups so far, or fewer) the gap kind of each contact group made by *OBSTACLE, 0 for
      !> the others (uniarc_deck_move: which groups *MOVE may translate)
      integer, allocatable :: obstacle_kind(:)
      !> The supports when the open step began, and where its first *BOUNDARY card is (0: none yet)
      logical, allocatable :: step_start_fixed(:, :)
      integer :: step_boundary_line = 0, step_boundary_column = 0
      !> where the first `*RELEASE, MY=` value is (a moment limit needs *PATH), 0 if none
      integer :: moment_limit_line = 0, moment_limit_column = 0
      !> where the first bearing limit QU= was given (*FOUNDATION, *SPRING), 0 if none: it needs *PATH
      integer :: plastic_line = 0, plastic_column = 0
   end type deck_t

contains

   !> Add node `label` at `point` to the model, remembering that it was defined at `line`, `column`.
   !> Errors: a growth of the node arrays that the system refuses (error_input: the model does not fit
   !> in memory, uniarc_memory); no node is then added.
   subroutine add_deck_node(deck, label, point, line, column, error)
      type(deck_t), intent(inout) :: deck
      integer, intent(in) :: label
      real(dp), intent(in) :: point(2)
      integer, intent(in) :: line, column
      type(error_t), allocatable, intent(out) :: error
      integer :: status
      call add_node(deck%model, label, point, error)
      if (allocated(error)) return
      call grow_integers(deck%node_line, deck%model%n_nodes, status)
      if (status == 0) call grow_integers(deck%node_column, deck%model%n_nodes, status)
      call allocation_failure(status, 'the deck positions of the nodes', 16.0_dp*deck%model%n_nodes, &
                              error_input, error)
      if (allocated(error)) return
      deck%node_line(deck%model%n_nodes) = line
      deck%node_column(deck%model%n_nodes) = column
   end subroutine add_deck_node

   !> An option's value as a field (text and column), to be read like a data field.
   pure function option_field(card, k) result(field)
      type(card_t), intent(in) :: card
      integer, intent(in) :: k
      type(field_t) :: field
      field%text = card%options(k)%value
      field%column = card%options(k)%value_column
   end function option_field

   !> The value of option `k` of the card, an expression; `what` names it when it is empty.
   subroutine option_real(source, card, deck, k, what, value, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: k
      character(len=*), intent(in) :: what
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      call field_real(source, deck%parameters, card%line, option_field(card, k), what, value, error)
   end subroutine option_real

   !> Cards with exactly one data line (sections, generators).
   subroutine require_one_data_line(source, card, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(error_t), allocatable, intent(out) :: error
      if (card%n_data == 0) then
         call raise(source, card%line, len_trim(source%lines(card%line)%text) + 1, &
                    'expected a data line after *'//card%keyword//', found none', error)
      else if (card%n_data > 1) then
         call raise(source, card%data_lines(2), verify(source%lines(card%data_lines(2))%text, ' '), &
                    'expected a new card (*'//card%keyword//' takes one data line), found a second data line', &
                    error)
      end if
   end subroutine require_one_data_line

   !> The nodes a target field names: a node-set name or a node label (an integer expression).
   subroutine resolve_nodes(source, deck, line, field, nodes, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: line
      type(field_t), intent(in) :: field
      integer, allocatable, intent(out) :: nodes(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: set, label, index

      if (is_name(field%text)) then
         set = node_set_index(deck%model, field%text)
         if (set > 0) then
            nodes = deck%model%node_sets(set)%nodes
            return
         end if
         if (find_parameter(deck%parameters, field%text) == 0) then
            call raise(source, line, field%column, 'expected a node label or a node set defined above, found '''// &
                       clip(field%text)//'''', error)
            return
         end if
      end if
      call field_integer(source, deck%parameters, line, field, 'a node label or a node set', label, error)
      if (allocated(error)) return
      index = node_index(deck%model, label)
      if (index == 0) then
         call raise(source, line, field%column, 'expected a defined node label, found '// &
                    integer_to_string(label), error)
         return
      end if
      nodes = [index]
   end subroutine resolve_nodes

   !> The elements a target field names: an element-set name or an element label.
   subroutine resolve_elements(source, deck, line, field, elements, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: line
      type(field_t), intent(in) :: field
      integer, allocatable, intent(out) :: elements(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: set, label, index

      if (is_name(field%text)) then
         set = element_set_index(deck%model, field%text)
         if (set > 0) then
            elements = deck%model%element_sets(set)%elements
            return
         end if
         if (find_parameter(deck%parameters, field%text) == 0) then
            call raise(source, line, field%column, 'expected an element label or an element set defined above, ' // &
                       'found '''//clip(field%text)//'''', error)
            return
         end if
      end if
      call field_integer(source, deck%parameters, line, field, 'an element label or an element set', &
                         label, error)
      if (allocated(error)) return
      index = element_index(deck%model, label)
      if (index == 0) then
         call raise(source, line, field%column, 'expected a defined element label, found '// &
                    integer_to_string(label), error)
         return
      end if
      elements = [index]
   end subroutine resolve_elements

   !> A DOF field: an integer expression 1 (ux), 2 (uy) or 3 (rz).
   subroutine read_dof(source, deck, line, field, dof, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: line
      type(field_t), intent(in) :: field
      integer, intent(out) :: dof
      type(error_t), allocatable, intent(out) :: error
      call field_integer(source, deck%parameters, line, field, 'a DOF', dof, error)
      if (allocated(error)) return
      if (dof < 1 .or. dof > 3) then
         call raise(source, line, field%column, 'expected a DOF 1 (ux), 2 (uy) or 3 (rz), found '// &
                    integer_to_string(dof), error)
      end if
   end subroutine read_dof

end module uniarc_deck_state
