// The gripper's row of the kind table (graph/plugin.h): what the compiler, the loader, the
// language server and the docs know of it.
#include "graph/kinds.h"
#include "graph/plugin.h"

namespace plant::kinds::gripper {

using namespace plant::graph;

namespace {

constexpr SlotSpec kSlots[] = {PLANT_SLOTS_GRIPPER(PLANT_SLOT_SPEC)};
constexpr ParamSpec kParams[] = {
    {"trigger", ParamType::CompRef, "", true, 0, "trigger volume that catches objects"},
};

}  // namespace

constexpr KindDesc desc{
    .word = "gripper",
    .doc = "holds the object its trigger caught, and lets it go",
    .slots = kSlots,
    .params = kParams,
    .kind = CompKind::Gripper,
    .on = true,
    PLANT_KIND_TABLE(grippers),
    .idle_input = gripperslot::grip,
    .idle_warning = "gripper '{}' never grips: nothing drives 'grip'",
};

}  // namespace plant::kinds::gripper
