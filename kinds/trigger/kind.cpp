// The trigger's row of the kind table (graph/plugin.h): what the compiler, the loader, the
// language server and the docs know of it.
#include "graph/kinds.h"
#include "graph/plugin.h"

namespace plant::kinds::trigger {

using namespace plant::graph;

namespace {

constexpr SlotSpec kSlots[] = {PLANT_SLOTS_TRIGGER(PLANT_SLOT_SPEC)};
constexpr ParamSpec kParams[] = {
    {"extent", ParamType::Vec3, "m", true, 0, "full extents of the box volume"},
    {"filter", ParamType::Type, "", false, 0, "object type it reacts to; any object when absent"},
};

bool check(const Graph& g, int32_t row, PluginProblem& problem) {
    const Vec3& e = g.triggers[TriggerId(row)].extent;
    if (e[0] > 0 && e[1] > 0 && e[2] > 0) return true;
    problem.message = "field 'extent' must be above 0";
    return false;
}

}  // namespace

constexpr KindDesc desc{
    .word = "trigger",
    .doc = "a box volume that reports objects entering, staying and leaving",
    .slots = kSlots,
    .params = kParams,
    .check = check,
    .placed = true,  // where its box stands (relative to the body it is `on`)
    .kind = CompKind::Trigger,
    .on = true,
    PLANT_KIND_TABLE(triggers),
};

}  // namespace plant::kinds::trigger
