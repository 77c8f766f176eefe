!> The state of a model under construction, `model_builder_t` (uniarc_model_builder makes and finishes
!> it; uniarc_builder_loads adds its loads; uniarc_model_contacts its media). Its components may be
!> read; they are written only through the procedures of those modules.
module uniarc_builder_type
   use uniarc_kinds, only: dp
   use uniarc_model, only: section_t, node_set_t, element_set_t, distributed_load_t, track_t, &
                           analysis_options_t, output_options_t, contact_candidate_t, contact_group_t, &
                           foundation_t, thermal_load_t, end_joint_t
   use uniarc_name_table, only: name_table_t
   implicit none
   private
   public :: model_builder_t
   public :: slot_fixed, slot_pressure, slot_follower

   !> Slots of an element's distributed-load records: one fixed-direction, one pressure, one follower.
   integer, parameter :: slot_fixed = 1, slot_pressure = 2, slot_follower = 3

   !> A model under construction (see the module header). Read its components; write them through the
   !> procedures of this module.
   type :: model_builder_t
      character(len=:), allocatable :: title

      integer :: n_nodes = 0
      real(dp), allocatable :: coordinates(:, :)      !< (2, capacity) initial x, y
      integer, allocatable :: node_label(:)
      logical, allocatable :: fixed(:, :)             !< (3, capacity) DOF held at zero
      real(dp), allocatable :: nodal_load(:, :)       !< (3, capacity) reference nodal forces/moments
      integer :: largest_node_label = 0
      integer, allocatable :: node_of_label(:)        !< label → index (0: none), for labels up to its size

      integer :: n_elements = 0
      integer, allocatable :: connectivity(:, :)      !< (2, capacity) internal node indices
      integer, allocatable :: element_label(:)
      integer, allocatable :: element_section(:)      !< index into sections (0: none)
      integer, allocatable :: element_kind(:)         !< kinds set by set_element_kind (others: beam-column)
      type(end_joint_t), allocatable :: end_joints(:, :) !< (2, capacity) set by set_end_joint (others rigid)
      integer, allocatable :: load_index(:, :)        !< (3, element): fixed, pressure, follower record
      integer :: largest_element_label = 0
      integer, allocatable :: element_of_label(:)     !< label → index (0: none), for labels up to its size

      integer :: n_sections = 0
      type(section_t), allocatable :: sections(:)
      integer :: n_node_sets = 0
      type(node_set_t), allocatable :: node_sets(:)
      integer :: n_element_sets = 0
      type(element_set_t), allocatable :: element_sets(:)
      integer :: n_loads = 0
      type(distributed_load_t), allocatable :: loads(:)
      integer :: n_tracks = 0
      type(track_t), allocatable :: tracks(:)
      !> The names of sections(1:n_sections), node_sets(1:n_node_sets), element_sets(1:n_element_sets)
      !> and tracks(1:n_tracks), numbered alike: a hash index, so that a name costs O(1) to look up.
      type(name_table_t) :: section_names, node_set_names, element_set_names, track_names
      type(name_table_t) :: contact_group_names   !< of contact_groups(1:n_contact_groups), alike
      integer :: n_contacts = 0
      type(contact_candidate_t), allocatable :: contacts(:)
      integer :: n_contact_groups = 0
      type(contact_group_t), allocatable :: contact_groups(:)
      integer :: n_foundations = 0
      type(foundation_t), allocatable :: foundations(:)

      type(analysis_options_t) :: analysis            !< linear static unless set otherwise
      type(output_options_t) :: output                !< extra result files
      integer :: n_thermal = 0
      type(thermal_load_t), allocatable :: thermal(:)
      integer :: n_prescribed = 0                     !< prescribed displacements (node, dof, value)
      integer, allocatable :: prescribed_node(:), prescribed_dof(:)
      real(dp), allocatable :: prescribed_value(:)
      !> (2, n_contact_groups) translations of plane obstacles (*MOVE; uniarc_model_contacts add_move)
      real(dp), allocatable :: moves(:, :)
   end type model_builder_t

end module uniarc_builder_type
