!> The support and load cards of the deck: *BOUNDARY, *CLOAD and *DLOAD (docs/input.md). Loads are
!> reference loads, multiplied by the load parameter λ of the analysis.
module uniarc_deck_loads
   use uniarc_kinds, only: dp
   use uniarc_error, only: error_t
   use uniarc_strings, only: field_t, to_upper, is_name, integer_to_string
   use uniarc_expression, only: find_parameter
   use uniarc_deck_source, only: source_t, card_t, raise, clip, check_options, option_index, data_fields, &
                                 require_field_count, field_real
   use uniarc_model, only: dof_ux, dof_uy, dof_rz, element_truss
   use uniarc_model_builder, only: add_support, add_nodal_load, add_line_load, add_pressure, element_kinds
   use uniarc_deck_state, only: deck_t, resolve_nodes, resolve_elements, read_dof
   implicit none
   private
   public :: read_boundary, read_concentrated_load, read_distributed_load

contains

   !> *BOUNDARY: lines `target, type` with a named type, or `target, first_dof [, last_dof]`.
   subroutine read_boundary(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, first_dof, last_dof
      logical :: held(3), named
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: nodes(:)

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 2, 3, 'target, type or target, first_dof, last_dof', error)
         if (allocated(error)) return
         call resolve_nodes(source, deck, line, fields(1), nodes, error)
         if (allocated(error)) return

         named = .true.
         held = .false.
         select case (to_upper(fields(2)%text))
         case ('FIXED', 'ENCASTRE')
            held = [.true., .true., .true.]
         case ('PINNED')
            held = [.true., .true., .false.]
         case ('ROLLER_X')
            held(dof_uy) = .true.
         case ('ROLLER_Y')
            held(dof_ux) = .true.
         case ('XSYMM')
            held(dof_ux) = .true.
            held(dof_rz) = .true.
         case ('YSYMM')
            held(dof_uy) = .true.
            held(dof_rz) = .true.
         case default
            named = .false.
         end select
         if (named) then
            if (size(fields) > 2) then
               call raise(source, line, fields(3)%column, 'expected no field after '''// &
                          to_upper(fields(2)%text)//''', found '''//clip(fields(3)%text)//'''', error)
               return
            end if
         else
            if (is_name(fields(2)%text) .and. find_parameter(deck%parameters, fields(2)%text) == 0) then
               call raise(source, line, fields(2)%column, 'expected FIXED, PINNED, ROLLER_X, ROLLER_Y, ' // &
                          'XSYMM, YSYMM or a DOF 1 to 3, found '''//clip(fields(2)%text)//'''', error)
               return
            end if
            call read_dof(source, deck, line, fields(2), first_dof, error)
            if (allocated(error)) return
            last_dof = first_dof
            if (size(fields) > 2) then
               call read_dof(source, deck, line, fields(3), last_dof, error)
               if (allocated(error)) return
               if (last_dof < first_dof) then
                  call raise(source, line, fields(3)%column, 'expected a last DOF not below the first (' // &
                             integer_to_string(first_dof)//'), found '//integer_to_string(last_dof), error)
                  return
               end if
            end if
            held(first_dof:last_dof) = .true.
         end if
         do j = 1, size(nodes)
            call add_support(deck%model, nodes(j), held)
         end do
      end do
   end subroutine read_boundary

   !> *CLOAD: lines `target, dof, value` with dof 1|2|3 or FX|FY|MZ; loads on one node are summed.
   subroutine read_concentrated_load(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line, dof
      real(dp) :: value
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: nodes(:)

      call check_options(source, card, [character(len=1) ::], error)
      if (allocated(error)) return
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 3, 3, 'target, dof, value', error)
         if (allocated(error)) return
         call resolve_nodes(source, deck, line, fields(1), nodes, error)
         if (allocated(error)) return
         select case (to_upper(fields(2)%text))
         case ('FX')
            dof = dof_ux
         case ('FY')
            dof = dof_uy
         case ('MZ')
            dof = dof_rz
         case default
            if (is_name(fields(2)%text) .and. find_parameter(deck%parameters, fields(2)%text) == 0) then
               call raise(source, line, fields(2)%column, 'expected FX, FY, MZ or a DOF 1 to 3, found '''// &
                          clip(fields(2)%text)//'''', error)
               return
            end if
            call read_dof(source, deck, line, fields(2), dof, error)
            if (allocated(error)) return
         end select
         call field_real(source, deck%parameters, line, fields(3), 'a load value', value, error)
         if (allocated(error)) return
         do j = 1, size(nodes)
            call add_nodal_load(deck%model, nodes(j), dof, value)
         end do
      end do
   end subroutine read_concentrated_load

   !> *DLOAD [, FOLLOWER]: lines `elset, type, value` with type PX, PY (per unit initial length, global)
   !> or P (normal pressure along the element's left normal). FOLLOWER is only for P.
   !>
   !> Loads of one kind on one element are summed into one record: an element has at most one fixed-
   !> direction record, one pressure record and one follower-pressure record.
   subroutine read_distributed_load(source, card, deck, error)
      type(source_t), intent(in) :: source
      type(card_t), intent(in) :: card
      type(deck_t), intent(inout) :: deck
      type(error_t), allocatable, intent(out) :: error
      integer :: i, j, line
      logical :: follower
      real(dp) :: value
      type(field_t), allocatable :: fields(:)
      integer, allocatable :: elements(:), kinds(:)
      character(len=:), allocatable :: load_type

      call check_options(source, card, [character(len=8) :: 'FOLLOWER'], error)
      if (allocated(error)) return
      follower = option_index(card, 'FOLLOWER') > 0
      do i = 1, card%n_data
         line = card%data_lines(i)
         call data_fields(source, line, fields)
         call require_field_count(source, line, fields, 3, 3, 'elset, type, value', error)
         if (allocated(error)) return
         call resolve_elements(source, deck, line, fields(1), elements, error)
         if (allocated(error)) return
         ! A truss, pinned at both ends, has no transverse stiffness over its span: it takes loads at
         ! its nodes only.
         kinds = element_kinds(deck%model, deck%model%n_elements)
         do j = 1, size(elements)
            if (kinds(elements(j)) == element_truss) then
               call raise(source, line, fields(1)%column, 'expected beam elements for a distributed load, '// &
                          'found truss element '//integer_to_string(deck%model%element_label(elements(j)))// &
                          ' (a truss takes loads at its nodes: *CLOAD)', error)
               return
            end if
         end do
         load_type = to_upper(fields(2)%text)
         select case (load_type)
         case ('PX', 'PY')
            if (follower) then
               call raise(source, line, fields(2)%column, 'expected type P with FOLLOWER, found '''// &
                          load_type//'''', error)
               return
            end if
         case ('P')
            continue
         case default
            call raise(source, line, fields(2)%column, 'expected a load type PX, PY or P, found '''// &
                       clip(fields(2)%text)//'''', error)
            return
         end select
         call field_real(source, deck%parameters, line, fields(3), 'a load value', value, error)
         if (allocated(error)) return
         do j = 1, size(elements)
            select case (load_type)
            case ('PX')
               call add_line_load(deck%model, elements(j), dof_ux, value)
            case ('PY')
               call add_line_load(deck%model, elements(j), dof_uy, value)
            case default
               call add_pressure(deck%model, elements(j), value, follower)
            end select
         end do
      end do
   end subroutine read_distributed_load

end module uniarc_deck_loads
