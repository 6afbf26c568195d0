// The label's row of the kind table (graph/plugin.h): what the compiler, the loader, the
// language server and the docs know of it.
#include "graph/kinds.h"
#include "graph/plugin.h"

namespace plant::kinds::label {

using namespace plant::graph;

namespace {

constexpr SlotSpec kSlots[] = {PLANT_SLOTS_LABEL(PLANT_SLOT_SPEC)};
constexpr ParamSpec kParams[] = {
    {"value", ParamType::String, "", false, 0, "the text, default empty"},
};

}  // namespace

constexpr KindDesc desc{
    .word = "label",
    .doc = "a text the viewer shows",
    .slots = kSlots,
    .params = kParams,
    .kind = CompKind::Label,
    PLANT_KIND_TABLE(labels),
};

}  // namespace plant::kinds::label
