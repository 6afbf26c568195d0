// Lookups derived once from the graph so that no phase searches or walks the graph
// per step: ownership lists as (adr, num) pairs, the role of dynamic slots, the order
// in which graphics are posed. Constant after construction, like the graph itself.
#pragma once

#include "graph/graph.h"

#include "engine/pose.h"

#include <LinearMath/btTransform.h>

#include <cstdint>
#include <vector>

namespace plant::engine {

// A child list in the style of the graph: list[adr .. adr + num).
struct Csr {
    std::vector<int32_t> adr, num, list;
    const int32_t* begin(int32_t i) const { return list.data() + adr[i]; }
    const int32_t* end(int32_t i) const { return list.data() + adr[i] + num[i]; }
};

struct KindBehaviour;  // engine/plugin.h

// A plugin component's behaviour and where its state is in State::plugin_state.
struct PluginRun {
    const KindBehaviour* behaviour = nullptr;
    int32_t state_adr = 0;
};

struct Tables {
    std::vector<uint8_t> slot_out;  // 1 for outputs
    std::vector<int32_t> value_adr; // Slot::value_adr, packed: the hot lookup of every step
    std::vector<uint8_t> slot_acts; // 1 for inputs of components that act in phase 5
    // Dynamic slots: the animation of a play slot, the variant of a select slot; -1 for
    // every other slot.
    std::vector<int32_t> slot_aux;
    std::vector<int32_t> put_place;  // per slot: the place whose put input it is, -1
    std::vector<int32_t> place_entered, place_tokens;  // per place: its output slots, -1

    std::vector<int32_t> body_do;   // owner DO of each body
    std::vector<int32_t> dyn_bodies;  // bodies declared dynamic: what fields and triggers see
    Csr do_bodies;                  // bodies of a DO and of the DOs below it
    Csr do_graphics;                // graphics of a DO and below, not attached to a body
    std::vector<int32_t> do_label;  // the first Label of a DO or below, -1
    std::vector<int32_t> do_source; // Source whose pool holds this DO, -1

    std::vector<int32_t> nets;      // State components, in id order
    Csr net_transitions;            // by position in `nets`
    std::vector<int32_t> place_net; // position in `nets` of each place
    std::vector<uint8_t> net_always_live;  // has a transition without inputs
    Csr comp_routes;                // routes of each Router component (by comp id)

    std::vector<int32_t> graphics_order;  // parents before children
    size_t graphics_roots = 0;            // its first ones, with no parent (on a body or alone)
    std::vector<Pose> graphics_local;     // relative to the parent or attached body
    std::vector<btTransform> field_local;   // field box relative to its body frame
    std::vector<btVector3> field_gain;      // the law's gain along the field's own axes: k·|d|
    std::vector<btTransform> trigger_local; // trigger box relative to its body frame

    std::vector<PluginRun> plugin_run;      // per row of Graph::plugins
    std::vector<int32_t> sensing_plugins;   // rows whose kind senses in phase 2
    int32_t plugin_state_size = 0;

    explicit Tables(const graph::Graph& g);
};

}  // namespace plant::engine
