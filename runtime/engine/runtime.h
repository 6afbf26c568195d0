// The engine's internals, shared by the phase files: the constant model (graph,
// derived tables, logic schedule), the mutable state, the Bullet world, and the
// phase functions that Engine::step calls in order. Not part of the public API.
#pragma once

#include "engine/engine.h"
#include "engine/pages.h"
#include "engine/physics.h"
#include "engine/schedule.h"
#include "engine/spatial.h"
#include "engine/state.h"
#include "engine/tables.h"
#include "engine/transport.h"

#include <memory>
#include <string>
#include <vector>

namespace plant::engine {

struct Runtime {
    const graph::Graph& g;
    double dt;
    double rate;  // steps per second (Engine::rate)
    Tables tab;
    Schedule sched;
    State st;
    Physics phys;
    Spatial index;
    Steady steady;  // transport.cpp
    bool logic_every_node;  // Options::logic_every_node
    std::vector<std::string> extra_names;  // strings interned at run time (events)
    std::unique_ptr<Pager> pager;  // Options::huge_pages, for a large plant; last: stopped first

    Runtime(const graph::Graph& graph, const Options& opt);

    std::string_view str(int32_t name) const;
    double* val(graph::SlotId slot) { return st.values.data() + tab.value_adr[slot].v; }
    const double* val(graph::SlotId slot) const { return st.values.data() + tab.value_adr[slot].v; }

    // A slot's flag for this step: false if it was active already, else set. A job's item may
    // flag the slots it owns and leave the listing to the calling thread (activate is both).
    bool flag_active(graph::SlotId slot) {
        if (st.act[slot]) return false;
        st.act[slot] = 1;
        return true;
    }
    // Marks a slot active for this step; each slot enters its list at most once.
    void activate(graph::SlotId slot) {
        if (flag_active(slot)) (tab.slot_out[slot] ? st.out_list : st.in_list).push_back(slot);
    }
    // The same, for a slot whose direction the caller knows (hot paths).
    void activate_in(graph::SlotId slot) {
        if (flag_active(slot)) st.in_list.push_back(slot);
    }
    void activate_out(graph::SlotId slot) {
        if (flag_active(slot)) st.out_list.push_back(slot);
    }
    // Writes an output's value and makes it active.
    void emit(graph::SlotId slot, double v) {
        *val(slot) = v;
        activate(slot);
    }
    void emit_pose(graph::SlotId slot, const Pose& p);
    // Writes a pose output's value (emit_pose without making it active: a job's item lists it).
    void write_pose(graph::SlotId slot, const Pose& p);
    graph::SlotId comp_slot(graph::CompId comp, int index) const { return g.comps[comp].slot_adr + index; }

    void refresh_observers();  // after watch(): which body outputs to refresh per step
};

// The five phases of a step (docs/runtime.md), in this order.
void phase_physics(Runtime& r);    // 1: kinematic moves, conveyor forces, Bullet step
void phase_sensors(Runtime& r);    // 2: bodies, the kind table's, plugins
void phase_logic(Runtime& r);      // 3: external inputs, flows, connectors, routers, labels
void phase_petri(Runtime& r);      // 4: clear outputs, puts, all enabled transitions fire
void phase_actuators(Runtime& r);  // 5: components act on their active inputs

// Forced slots (forces.cpp): outputs hold their natural values while components work
// (phases 1, 2, 4, 5) and show the forced ones to the logic phase and to readers after
// the step; inputs are forced after the logic phase, for the phases that act on them.
void forces_step_begin(Runtime& r);
void forces_logic_begin(Runtime& r);  // after the pending inputs are activated
void forces_logic_end(Runtime& r);
// An output the logic phase itself computes (a connector, a router entry, a label), forced
// again after its op ran; callers test `!st.forced_out.empty()` first.
void force_again(Runtime& r, graph::SlotId slot);
void forces_step_end(Runtime& r);

// What the kinds on the kind table share with the physics (each kind's own behaviour is its
// kinds/NAME/run.cpp).
// Whether the value of an active input that moves the physics may be applied (bodies.cpp):
// one out of graph/range.h's range is not, and counts in Warnings::out_of_range.
bool input_in_range(Runtime& r, const graph::Comp& c, graph::SlotId slot);
void take_body_out(Runtime& r, graph::BodyId body);
// The conveyor law of the fields (a kind on the kind table: kinds/field/) in phase 1
// (fields.cpp, conveyor.cpp):
bool prepare_fields(Runtime& r);     // fields.cpp: frames and cells; whether any field acts
void list_field_bodies(Runtime& r);  // the bodies the law acts on, by physics world
void integrate_single(Runtime& r, graph::BodyId body);  // the conveyor law's step
void integrate_group(Runtime& r, graph::BodyId group);  // a rigid group, by its root body
// objects.cpp: an object out of the world (an exit, a trainee's hand), back to its pool
graph::DoId take_object(Runtime& r, graph::DoId obj);  // out of the world, back to its pool; its root or -1
double object_id(Runtime& r, graph::DoId obj);         // its bar code: its label's text, else its path
void apply_hands(Runtime& r);  // hands.cpp: trainees' hands pull what they hold, in phase 1
bool glob_match(std::string_view pattern, std::string_view text);
// Plugin components (plugin.cpp): started once, sensing in phase 2, acting in phase 5.
void start_plugins(Runtime& r);
void sense_plugins(Runtime& r);
void act_plugin(Runtime& r, graph::PluginId plugin);
// The kinds on the kind table (plugin.cpp; each in kinds/NAME/run.cpp): their start, sense
// and act_all hooks in the table's order; their act_one hooks through builtin_behaviour().
void start_kinds(Runtime& r);
void sense_kinds(Runtime& r);
void act_kinds(Runtime& r);  // phase 5's end: their act_all hooks

}  // namespace plant::engine
