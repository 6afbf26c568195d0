#include "faults/kind.h"

#include "engine/plugin.h"
#include "engine/events.h"

#include <fmt/format.h>

#include <array>
#include <cstdlib>

namespace plant::faults {
namespace {

using graph::Dir;
using graph::EntryKey;
using graph::EntrySpec;
using graph::ParamSpec;
using graph::ParamType;
using graph::SlotType;
using engine::ForceMode;

// `until` not given: the force lasts to the end of the run.
constexpr double kNever = -1;

enum Option : int { until, value };  // value: stuck only, after until
constexpr std::array kUntil = {
    ParamSpec{"until", ParamType::Number, "s", false, kNever, "when the force is released; not given: never"},
};
constexpr std::array kStuck = {
    kUntil[0],
    ParamSpec{"value", ParamType::Value, "", true, 0,
              "the value the slot is held at; a void slot: true for on, false for off"},
};
// As `--event "T force PATH ..."` allows: stuck at a value a plant file can write, open
// where a slot has an "off", invert a bool.
constexpr std::array kStuckTypes = {SlotType::Void, SlotType::Bool, SlotType::Int, SlotType::Real, SlotType::String};
constexpr std::array kOpenTypes = {SlotType::Void, SlotType::Bool, SlotType::Int, SlotType::Real, SlotType::String,
                                   SlotType::Ref};
constexpr std::array kInvertTypes = {SlotType::Bool};
constexpr int32_t kNoKeyLimit = 0;  // time keys have no upper limit
constexpr std::array kEntries = {
    EntrySpec{"stuck", "from a time on, the slot holds a value", Dir::In, kStuckTypes, kStuck, kNoKeyLimit,
              EntryKey::Time, true},
    EntrySpec{"open", "from a time on, the slot is cut: it reads as off", Dir::In, kOpenTypes, kUntil, kNoKeyLimit,
              EntryKey::Time, true},
    EntrySpec{"invert", "from a time on, a bool slot reads negated", Dir::In, kInvertTypes, kUntil, kNoKeyLimit,
              EntryKey::Time, true},
    EntrySpec{"release", "at a time, the slot goes back to normal", Dir::In, {}, {}, kNoKeyLimit, EntryKey::Time,
              true},
};

bool check_faults(const graph::Graph& g, graph::PluginId plugin, graph::PluginProblem& problem);
void schedule_faults(const graph::Graph& g, graph::PluginId plugin, std::vector<engine::Event>& out);

constexpr graph::KindDesc kDesc{"faults",
                                "faults scheduled in the plant: slots forced and released at times (docs/plc.md)",
                                {},
                                {},
                                kEntries,
                                graph::PluginPhase::None,
                                graph::PluginPhase::None,
                                graph::plugin_check<check_faults>};

ForceMode mode_of(std::string_view word) {
    return word == "stuck" ? ForceMode::Stuck : word == "open" ? ForceMode::Open : word == "invert" ? ForceMode::Invert
                                                                                                     : ForceMode::None;
}

const graph::PluginParam* option(const graph::Graph& g, const graph::PluginEntry& e, int k) {
    return k < e.param_num ? &g.plugin_params[e.param_adr + k] : nullptr;
}

// A release after its force; a stuck value of the slot's type (the compiler checked it
// against the slot; a graph written by hand is checked here).
bool check_faults(const graph::Graph& g, graph::PluginId plugin, graph::PluginProblem& problem) {
    const graph::Plugin& p = g.plugins[plugin];
    for (int32_t k = 0; k < p.entry_num; ++k) {
        const graph::PluginEntry& e = g.plugin_entries[p.entry_adr + k];
        const std::string_view word = g.str(e.word);
        if (const graph::PluginParam* u = option(g, e, until); u && u->num != kNever && !(u->num > e.key)) {
            problem = {k, fmt::format("'{}' at {} s: until = {} s is not after it", word, e.key, u->num)};
            return false;
        }
        if (mode_of(word) != ForceMode::Stuck) continue;
        const graph::PluginParam* v = option(g, e, value);
        for (int32_t s = 0; v && s < e.slot_num; ++s) {
            const SlotType t = g.slots[g.plugin_entry_slots[e.slot_adr + s].v].type;
            const bool ok = t == SlotType::String                      ? v->text.id >= 0
                            : t == SlotType::Void || t == SlotType::Bool ? (v->num == 0 || v->num == 1)
                            : t == SlotType::Int                         ? v->num == std::floor(v->num)
                                                                         : true;
            if (!ok) {
                problem = {k, fmt::format("'stuck' at {} s: the value is not a {}", e.key, graph::word(t))};
                return false;
            }
        }
    }
    return true;
}

// One event per entry, named by the shortest path to its slots (what the entry wrote, or
// the slot a port forwards to), and a release at `until`.
void schedule_faults(const graph::Graph& g, graph::PluginId plugin, std::vector<engine::Event>& out) {
    const graph::Plugin& p = g.plugins[plugin];
    const engine::SlotIndex index = engine::slot_index(g);
    for (int32_t k = 0; k < p.entry_num; ++k) {
        const graph::PluginEntry& e = g.plugin_entries[p.entry_adr + k];
        const graph::PluginParam* u = option(g, e, until);
        engine::Event ev;
        ev.time = e.key;
        for (const graph::PluginEntrySlot& s : g.plugin_entry_slots.slice(e.slot_adr, e.slot_num)) ev.slots.push_back(s.v);
        if (ev.slots.empty()) continue;
        ev.path = engine::path_of(index, ev.slots);
        if (ev.path.empty()) ev.path = g.slot_path(ev.slots[0]);
        ev.force = true;
        ev.mode = mode_of(g.str(e.word));
        ev.planned = true;
        if (ev.mode == ForceMode::Stuck) {
            const graph::PluginParam* v = option(g, e, value);
            if (g.slots[graph::SlotId(ev.slots[0])].type == SlotType::String) ev.text = std::string(g.str(v->text));
            else ev.value = {v->num};
        }
        out.push_back(ev);
        if (u && u->num != kNever) {
            ev.time = u->num;
            ev.mode = ForceMode::None;
            ev.value.clear();
            ev.text.clear();
            out.push_back(std::move(ev));
        }
    }
}

}  // namespace

void register_faults_kind() {
    static constexpr engine::KindBehaviour kBehaviour{0, nullptr, nullptr, nullptr, schedule_faults};
    static const bool registered = engine::register_plugin(kDesc, kBehaviour);
    if (!registered) std::abort();  // only a second kind named `faults` could refuse it
}

}  // namespace plant::faults
