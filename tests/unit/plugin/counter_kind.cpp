#include "counter_kind.h"

#include "engine/plugin.h"

#include <array>

namespace plant::test {
namespace {

using graph::Dir;
using graph::ParamType;
using graph::SlotSpec;
using graph::SlotType;

enum Slot : int { add, reset, value, reached, idle };
constexpr std::array kSlots = {
    SlotSpec{"add", SlotType::Void, Dir::In, "counts one up"},
    SlotSpec{"reset", SlotType::Void, Dir::In, "back to the start value"},
    SlotSpec{"value", SlotType::Int, Dir::Out, "the count"},
    SlotSpec{"reached", SlotType::Void, Dir::Out, "the count got to the limit"},
    SlotSpec{"idle", SlotType::Void, Dir::Out, "nothing was added for idle_after"},
};
enum Param : int { start, limit, idle_after };
constexpr std::array kParams = {
    graph::ParamSpec{"start", ParamType::Int, "", false, 0, "the count at the start and after reset"},
    graph::ParamSpec{"limit", ParamType::Int, "", true, 0, "the count at which `reached` fires"},
    graph::ParamSpec{"idle_after", ParamType::Number, "s", false, 0, "time without `add` before `idle`; 0: never"},
};
constexpr std::array kTapTypes = {SlotType::Void};
constexpr std::array kTapOptions = {
    graph::ParamSpec{"weight", ParamType::Int, "", false, 1, "added per active step"},
};
constexpr std::array kEntries = {
    graph::EntrySpec{"tap", "a void output whose activity counts", Dir::Out, kTapTypes, kTapOptions, 99},
    graph::EntrySpec{"notify", "inputs a controller would drive", Dir::In, {}, {}, 99},
};
constexpr graph::KindDesc kDesc{"counter", "counts pulses (a kind of the tests)", kSlots, kParams, kEntries,
                                graph::PluginPhase::Sensors, graph::PluginPhase::Actuators};

// state: the count, the time of the last add, whether idle fired since.
void start_counter(engine::PluginCtx& c) {
    auto s = c.state();
    s[0] = c.param(start);
    c.emit(value, s[0]);
}
void act_counter(engine::PluginCtx& c) {
    auto s = c.state();
    if (c.active(reset)) s[0] = c.param(start);
    if (c.active(add)) {
        s[0] += 1;
        s[1] = c.time();
        s[2] = 0;
        if (s[0] == c.param(limit)) c.emit(reached, 0);
    }
    c.emit(value, s[0]);
}
void sense_counter(engine::PluginCtx& c) {
    auto s = c.state();
    bool tapped = false;
    for (int e = 0; e < c.entry_count(); ++e)
        if (c.entry_word(e) == "tap" && c.entry_active(e)) {
            s[0] += c.entry_option(e, 0);
            tapped = true;
        }
    if (tapped) c.emit(value, s[0]);
    const double after = c.param(idle_after);
    if (after > 0 && s[2] == 0 && c.time() - s[1] >= after) {
        s[2] = 1;
        c.emit(idle, 0);
    }
}
constexpr engine::KindBehaviour kBehaviour{3, start_counter, sense_counter, act_counter};

}  // namespace

void register_counter_kind() {
    static const bool registered = engine::register_plugin(kDesc, kBehaviour);
    (void)registered;
}

}  // namespace plant::test
