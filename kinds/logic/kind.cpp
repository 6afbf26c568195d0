// The connector's row of the kind table (graph/plugin.h): what the compiler, the loader and
// the docs know of it. A connector is written by a form of its own (`logic NAME = TERM and
// TERM ...`, docs/language.md §17), not as `logic NAME { ... }`: the row says so (own_form),
// and the compiler makes it from that form (lower.cpp).
#include "graph/kinds.h"
#include "graph/plugin.h"

namespace plant::kinds::logic {

using namespace plant::graph;

namespace {

constexpr SlotSpec kSlots[] = {PLANT_SLOTS_LOGIC(PLANT_SLOT_SPEC)};

}  // namespace

constexpr KindDesc desc{
    .word = "logic",
    .doc = "a connector: the activity of void outputs combined with `and` or `or`",
    .slots = kSlots,
    .params = {},
    .kind = CompKind::Logic,
    .own_form = true,
    PLANT_KIND_TABLE(logics),
    .bare_slot = logicslot::out,
    .noun = "connector",
    .idle_output = logicslot::out,
    .idle_output_warning = "connector '{}' drives nothing",
};

}  // namespace plant::kinds::logic
