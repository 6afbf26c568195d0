// The timer's row of the kind table (graph/plugin.h): what the compiler, the loader, the
// language server and the docs know of it.
#include "graph/kinds.h"
#include "graph/plugin.h"

#include <array>

namespace plant::kinds::timer {

using namespace plant::graph;

namespace {

constexpr auto kSlots = [] {
    std::array slots = {PLANT_SLOTS_TIMER(PLANT_SLOT_SPEC)};
    slots[timerslot::elapsed].unit = "s";
    return slots;
}();
constexpr std::string_view kModes[] = {"periodic", "oneshot"};
constexpr ParamSpec kParams[] = {
    {"period", ParamType::Number, "s", true, 0, "period, or delay of a one-shot timer"},
    {"autostart", ParamType::Bool, "", false, 0, "runs from the start, default false"},
};

bool check(const Graph& g, int32_t row, PluginProblem& problem) {
    if (g.timers[Id<Timer>(row)].period > 0) return true;
    problem.message = "field 'period' must be above 0";
    return false;
}

}  // namespace

constexpr KindDesc desc{
    .word = "timer",
    .doc = "ticks after a period, once or periodically",
    .slots = kSlots,
    .params = kParams,
    .check = check,
    .kind = CompKind::Timer,
    .modes = kModes,
    PLANT_KIND_TABLE(timers),
    .idle_input = timerslot::start,
    .runs_alone = [](const Graph& g, int32_t row) { return g.timers[Id<Timer>(row)].autostart; },
    .idle_warning = "timer '{}' never runs: nothing drives its 'start' and it does not autostart",
};

}  // namespace plant::kinds::timer
