// The exit's row of the kind table (graph/plugin.h): what the compiler, the loader, the
// language server and the docs know of it.
#include "graph/kinds.h"
#include "graph/plugin.h"

namespace plant::kinds::exit {

using namespace plant::graph;

namespace {

constexpr SlotSpec kSlots[] = {PLANT_SLOTS_EXIT(PLANT_SLOT_SPEC)};
constexpr ParamSpec kParams[] = {
    {"trigger", ParamType::CompRef, "", true, 0, "trigger volume whose objects are taken out"},
};

}  // namespace

constexpr KindDesc desc{
    .word = "exit",
    .doc = "takes the objects in its trigger out of the plant",
    .slots = kSlots,
    .params = kParams,
    .kind = CompKind::Exit,
    PLANT_KIND_TABLE(exits),
};

}  // namespace plant::kinds::exit
