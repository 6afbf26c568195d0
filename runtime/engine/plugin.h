// The runtime side of a component kind's row (graph/plugin.h): its behaviour, as hooks the
// step's phases call. A plugin kind's hooks get the narrow view of one component
// (PluginCtx); it registers its descriptor and its behaviour together with
// register_plugin(), before any plant is compiled or run. A kind on the kind table
// (kinds/NAME/run.cpp) works on its typed graph table and typed state of its own, a whole
// table at a time (docs/architecture.md, "The kind table").
//
// The hooks run inside the step: they must not allocate, block or keep pointers into
// the view. What they emit goes the way every component output goes: an output emitted
// in phase 2 is seen by this step's logic phase, one emitted in phase 5 by the next.
#pragma once

#include "graph/plugin.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

namespace plant::engine {

struct Runtime;

// One plugin component while it runs. Slots are numbered as in the descriptor's table.
class PluginCtx {
public:
    PluginCtx(Runtime& r, graph::PluginId plugin);

    // What the kinds so far use; a kind that needs more (an input's value, a text parameter)
    // adds its accessor here, with a test.
    bool active(int slot) const;     // an input activated this step, an output emitted
    void emit(int slot, double v);   // writes an output and makes it active
    double value(int slot) const;    // a slot's (first) number: an input's value this step
    // Parameters, numbered in declared order, each by the accessor of its type:
    double param(int i) const;                   // Number, Int, Bool (0/1)
    std::string_view param_text(int i) const;    // String
    graph::Vec3 param_vec3(int i) const;         // Vec3, in SI units
    int param_list_size(int i) const;            // StringList: its number of strings,
    std::string_view param_list(int i, int k) const;  // and its k-th
    graph::DoTypeId param_type(int i) const;     // Type: the object type (none when not given)
    graph::CompId param_comp(int i) const;       // CompRef: a component of the same object
    const graph::Graph& graph() const;           // the plant, read-only: what a type or a component is
    std::span<double> state() const;  // KindBehaviour::state_size numbers, 0 at start
    // Its entries (graph/plugin.h: EntrySpec), in declaration order; for an entry that reads
    // an output, whether that output is active in this step.
    int entry_count() const;
    std::string_view entry_word(int e) const;
    bool entry_active(int e) const;
    double entry_option(int e, int k) const;
    double time() const;  // simulated seconds at the start of this step

private:
    const graph::PluginEntry& entry(int e) const;
    const graph::PluginParam& param_row(int i) const;
    Runtime& r_;
    graph::PluginId plugin_;
    graph::Adr<graph::Slot> slot_adr_;
};

struct Event;  // engine/events.h
struct KindData;  // engine/state.h

struct KindBehaviour {
    int state_size = 0;                   // numbers of state per component
    void (*start)(PluginCtx&) = nullptr;  // once per component, when the engine is built
    void (*sense)(PluginCtx&) = nullptr;  // phase 2, every step (KindDesc::senses)
    void (*act)(PluginCtx&) = nullptr;    // phase 5, in a step one of its inputs is active
    // Timed inputs the component declares (a fault scheduled in the plant file): appended to
    // `out` before a run starts, they are applied like --event's, by apply_event
    // (plant_events in engine/events.h). Outside the step: may allocate.
    void (*schedule)(const graph::Graph& g, graph::PluginId plugin, std::vector<Event>& out) = nullptr;

    // ---- A kind on the kind table: its whole table at a time ----
    // Its state (State::kinds[its CompKind]), made when the engine is built; nullptr: none.
    std::unique_ptr<KindData> (*make_state)(const graph::Graph& g) = nullptr;
    void (*start_all)(Runtime& r) = nullptr;  // once, in the kind table's order (start_kinds)
    void (*sense_all)(Runtime& r) = nullptr;  // phase 2, in the kind table's order (sense_kinds)
    // The step profile's segment (StepProfile::Segment, engine/workers.h) that sense_all's
    // time is counted in; -1: the phase's last, with the plugins'.
    int sense_segment = -1;
    // Phase 5, for a component with an active input `c` (its row: detail_of<R>(c)).
    // nullptr: its inputs are read elsewhere (phases 3, 4), never by phase 5.
    void (*act_one)(Runtime& r, const graph::Comp& c) = nullptr;
    // Whether input `slot` (its index among c's slots) is one whose act, when every active
    // input of c is such a one, reads and writes only c's own row and its own body (a
    // kinematic body's pose): such components act as the items of a job on the physics
    // threads (actuators.cpp). Asked once per input, when the engine is built; nullptr: none.
    bool (*acts_alone)(const graph::Graph& g, const graph::Comp& c, int slot) = nullptr;
    // Its act reads and writes no body and nothing of the physics: it commutes with the acts
    // of the components that act alone, and need not wait for them (a graphics' animation, a
    // timer's start).
    bool acts_off_physics = false;
    // Phase 5, once every component with an active input acted: the whole table, in the
    // kind table's order (act_kinds); a source with a rate issues.
    void (*act_all)(Runtime& r) = nullptr;
};

// The behaviour of a kind on the kind table (kinds/list.h), nullptr for any other kind.
const KindBehaviour* builtin_behaviour(graph::CompKind kind);
std::span<const KindBehaviour* const> builtin_behaviours();  // in the kind table's order

// Registers the kind's descriptor (graph::register_kind) and its behaviour; false if the
// descriptor is refused or a hook the descriptor's phases name is missing.
bool register_plugin(const graph::KindDesc& desc, const KindBehaviour& behaviour);
const KindBehaviour* find_behaviour(std::string_view word);

}  // namespace plant::engine
