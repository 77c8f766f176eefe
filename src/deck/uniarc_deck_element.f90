!> The element cards and options of the deck: the `TYPE=` option of `*ELEMENT` and the generators, the
!> shear data a Timoshenko beam needs, the `*RELEASE` card (hinges and rotational springs at element
!> ends), and what trusses and hinges ask of their nodes (docs/input.md, `*ELEMENT`, `*RELEASE`).
!>
!> Kept apart from uniarc_deck so that the card reader only hands over what it read: the option, the
!> elements a card created, and at the end the tables of the whole deck.
module uniarc_deck_element
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t, error_input
   use uniarc_memory, only: allocation_failure
   use uniarc_strings, only: field_t, to_upper, integer_to_string, real_to_string
   use uniarc_deck_source, only: source_t, card_t, raise, clip, option_index, check_options, data_fields, &
                                 require_field_count, field_real, field_integer
   use uniarc_deck_state, only: deck_t, resolve_elements, option_real
   use uniarc_model, only: element_beam_column, element_truss, element_timoshenko, dof_rz, section_t, &
                           end_joint_t
   use uniarc_model_builder, only: set_end_joint, element_kind
   implicit none
   private
   public :: read_element_type, check_element_section, read_release, restrain_truss_nodes
   public :: check_moment_limit_analysis

contains

   !> The element kind of an element-defining card: its option `TYPE=BEAM` (the default, the
   !> Euler–Bernoulli beam-column), `TYPE=TRUSS` (axial force only) or `TYPE=TIMOSHENKO` (the
   !> shear-deformable beam-column). Error at the option's value for any other word.
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
      case ('TIMOSHENKO')
         kind = element_timoshenko
      case default
         call raise(source, card%line, card%options(type_option)%value_column, &
                    'expected TYPE=BEAM, TYPE=TRUSS or TYPE=TIMOSHENKO, found '''// &
                    clip(card%options(type_option)%value)//'''', error)
      end select
   end subroutine read_element_type

   !> A Timoshenko beam needs the shear stiffness κGA of its section (`*SECTION` data `E, A, I, G, kappa`
   !> or `EA, EI, GAs`): error at the card's SECTION= value when the section of an element of kind
   !> `kind` has none.
   subroutine check_element_section(source, card, kind, section, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      integer, intent(in) :: kind
      type(section_t), intent(in) :: section
      type(error_t), allocatable, intent(out) :: error
      integer :: k
      if (kind /= element_timoshenko .or. section%gas > 0.0_dp) return
      k = option_index(card, 'SECTION')
      call raise(source, card%line, card%options(k)%value_column, 'expected a section with shear data ' // &
                 '(E, A, I, G, kappa or EA, EI, GAs) for TYPE=TIMOSHENKO, found '''//section%name// &
                 ''' without', error)
   end subroutine check_element_section

   !> *RELEASE: lines `target, end [, k]` — at end `end` (1: node 1, 2: node 2) of every element of the
   !> target (an element label or set), a hinge (no k, or k = 0: no moment passes) or a linear rotational
   !> spring of stiffness k > 0 (moment per radian) between the element end and its node. A truss end
   !> has no moment to release, and an end takes one release: both are errors at the target.
   !> Option `MY=` (> 0, moment): every spring of the card is elastic–perfectly plastic with that moment
   !> limit (uniarc_joint_plasticity); a line of the card without k > 0 (a hinge) is then an error.
   subroutine read_release(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, end, e, status, capacity
      integer, allocatable :: elements(:)
      type(field_t), allocatable :: fields(:)
      type(end_joint_t) :: joint
      real(dp) :: stiffness, moment_limit
      integer :: my_option

      call check_options(source, card, ['MY='], error)
      if (allocated(error)) return
      moment_limit = 0.0_dp
      my_option = option_index(card, 'MY')
      if (my_option > 0) then
         call option_real(source, card, deck, my_option, 'a moment limit', moment_limit, error)
         if (allocated(error)) return
         if (.not. (moment_limit > 0.0_dp .and. moment_limit < huge(1.0_dp))) then
            call raise(source, card%line, card%options(my_option)%value_column, 'expected a moment limit MY > 0, '// &
                       'found '//real_to_string(moment_limit), error)
            return
         end if
         if (deck%moment_limit_line == 0) then
            deck%moment_limit_line = card%line
            deck%moment_limit_column = card%options(my_option)%value_column
         end if
      end if
      if (card%n_data == 0) then
         call raise(source, card%line, len_trim(source%lines(card%line)%text) + 1, 'expected data lines ' // &
                    '`target, end [, k]` after *RELEASE, found none', error)
         return
      end if
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 2, 3, 'target, end [, k]', error)
         if (allocated(error)) return
         call resolve_elements(source, deck, line, fields(1), elements, error)
         if (allocated(error)) return
         call field_integer(source, deck%parameters, line, fields(2), 'an element end (1 or 2)', end, error)
         if (allocated(error)) return
         if (end /= 1 .and. end /= 2) then
            call raise(source, line, fields(2)%column, 'expected an element end 1 or 2, found '// &
                       integer_to_string(end), error)
            return
         end if
         joint = end_joint_t(hinge=.true., compliance=0.0_dp)
         if (size(fields) == 3) then
            call field_real(source, deck%parameters, line, fields(3), 'a rotational stiffness k', stiffness, error)
            if (allocated(error)) return
            ! 0 or from 1e-100 to 1e100, as a section's EI (uniarc_deck_mesh): its compliance 1/k and
            ! the joint's moments stay finite
            if (.not. (stiffness == 0.0_dp .or. (stiffness >= 1.0e-100_dp .and. stiffness <= 1.0e100_dp))) then
               call raise(source, line, fields(3)%column, 'expected a rotational stiffness k of 0 (a ' // &
                          'hinge) or from 1e-100 to 1e100 (beyond, the joint overflows double precision: '// &
                          'rescale the units), found '//real_to_string(stiffness), error)
               return
            end if
            if (stiffness > 0.0_dp) joint = end_joint_t(hinge=.false., compliance=1.0_dp/stiffness)
         end if
         if (moment_limit > 0.0_dp) then
            if (joint%hinge) then
               if (size(fields) == 3) then
                  call raise(source, line, fields(3)%column, 'expected a rotational stiffness k > 0 with MY= (a '// &
                             'moment limit is that of a spring joint; a hinge carries no moment), found 0', error)
               else
                  call raise(source, line, len_trim(source%lines(line)%text) + 1, 'expected a rotational stiffness '// &
                             '`, k` (k > 0) with MY= (a moment limit is that of a spring joint; a hinge carries no '// &
                             'moment), found none', error)
               end if
               return
            end if
            joint%moment_limit = moment_limit
         end if
         do j = 1, size(elements)
            e = elements(j)
            if (element_kind(deck%model, e) == element_truss) then
               call raise(source, line, fields(1)%column, 'expected beam elements, found truss element '// &
                          integer_to_string(deck%model%element_label(e))//' (it carries no moment to release)', &
                          error)
               return
            end if
            if (allocated(deck%model%end_joints)) then
               if (e <= size(deck%model%end_joints, 2)) then
                  if (deck%model%end_joints(end, e)%hinge .or. deck%model%end_joints(end, e)%compliance > 0.0_dp) then
                     call raise(source, line, fields(1)%column, 'expected one release per element end, found ' // &
                                'end '//integer_to_string(end)//' of element '// &
                                integer_to_string(deck%model%element_label(e))//' released again', error)
                     return
                  end if
               end if
            end if
            capacity = 0
            if (allocated(deck%model%end_joints)) capacity = size(deck%model%end_joints, 2)
            call set_end_joint(deck%model, e, end, joint, status)
            ! (the size of set_end_joint's growth: max(e, 2 capacity) elements of two joints)
            call allocation_failure(status, 'the end joints of the model', &
                                    2.0_dp*storage_size(joint)/8.0_dp*max(e, 2*capacity), error_input, error)
            if (allocated(error)) return
         end do
      end do
   end subroutine read_release

   !> A moment limit (`*RELEASE, MY=`) is history that the steps of a path commit: a linear analysis
   !> (*STATIC, or no analysis card; `linear`) cannot follow it. Error at the first MY= value.
   subroutine check_moment_limit_analysis(source, deck, linear, error)
      type(source_t), intent(in) :: source
      type(deck_t), intent(in) :: deck
      logical, intent(in) :: linear
      type(error_t), allocatable, intent(out) :: error
      if (deck%moment_limit_line == 0 .or. .not. linear) return
      call raise(source, deck%moment_limit_line, deck%moment_limit_column, 'expected *PATH with a moment limit MY= '// &
                 '(the plastic rotations of its joints are history that the steps of a path commit), found a '// &
                 'linear analysis (*STATIC)', error)
   end subroutine check_moment_limit_analysis

   !> Hold the rotation of every node that no element end holds: a node used only by truss elements or
   !> by hinged element ends (`*RELEASE` without k).
   !>
   !> Such a node's rotation has no stiffness, a zero pivot: it is held (`fixed(dof_rz, node)` set;
   !> docs/input.md). A moment (`*CLOAD ..., MZ`) on such a node would then do no work and is an error at
   !> `node_line`, `node_column` (the caller gives the node's first moment line, uniarc_deck). (A distributed load on a truss is refused where
   !> `*DLOAD` is read, uniarc_deck_loads.) Arrays: connectivity (2, n_elements), kinds (n_elements),
   !> node_label/node_line/node_column (n_nodes), fixed and nodal_load (3, n_nodes); `joints` (optional,
   !> (2, ≥ 0)) the end joints of the first elements (the others rigid). Its work arrays refused by
   !> the system: error_input, the model does not fit in memory (uniarc_memory).
   subroutine restrain_truss_nodes(source, connectivity, kinds, node_label, node_line, node_column, &
                                   fixed, nodal_load, error, joints)
      type(source_t), intent(in) :: source
      integer, intent(in) :: connectivity(:, :)
      integer, intent(in) :: kinds(:)
      integer, intent(in) :: node_label(:), node_line(:), node_column(:)
      logical, intent(inout) :: fixed(:, :)
      real(dp), intent(in) :: nodal_load(:, :)
      type(error_t), allocatable, intent(out) :: error
      type(end_joint_t), intent(in), optional :: joints(:, :)
      logical, allocatable :: held(:), touched(:), free_end(:, :)
      integer :: e, i, status
      ! allocated with stat= (automatic arrays of the model's length are not checked)
      allocate (held(size(node_label)), touched(size(node_label)), free_end(2, size(kinds)), stat=status)
      call allocation_failure(status, 'the work arrays of the truss nodes'' check', &
                              8.0_dp*size(node_label) + 8.0_dp*size(kinds), error_input, error)
      if (allocated(error)) return
      do e = 1, size(kinds)
         free_end(:, e) = kinds(e) == element_truss
      end do
      if (present(joints)) then
         do e = 1, min(size(kinds), size(joints, 2))
            free_end(:, e) = free_end(:, e) .or. joints(:, e)%hinge
         end do
      end if
      if (.not. any(free_end)) return
      held = .false.
      touched = .false.
      do e = 1, size(kinds)
         do i = 1, 2
            touched(connectivity(i, e)) = .true.
            if (.not. free_end(i, e)) held(connectivity(i, e)) = .true.
         end do
      end do
      do i = 1, size(node_label)
         if (held(i) .or. .not. touched(i)) cycle
         if (abs(nodal_load(dof_rz, i)) > 0.0_dp) then
            call raise(source, node_line(i), node_column(i), 'expected no moment (MZ) on node '// &
                       integer_to_string(node_label(i))//', found one: only truss elements or hinged ' // &
                       'element ends use the node, and they carry no moment', error)
            return
         end if
         fixed(dof_rz, i) = .true.
      end do
   end subroutine restrain_truss_nodes

end module uniarc_deck_element
