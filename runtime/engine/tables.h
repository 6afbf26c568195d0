// Lookups derived once from the graph so that no phase searches or walks the graph
// per step: ownership lists as (adr, num) pairs, the role of dynamic slots. Constant after
// construction, like the graph itself.
#pragma once

#include "graph/graph.h"

#include "engine/pose.h"

#include <LinearMath/btTransform.h>

#include <cmath>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

namespace plant::engine {

// Per key, a list of ids in one array, in the style of the graph's child lists:
// list[adr[k] .. adr[k] + num[k]); csr[k] is key k's list (for (BodyId b : do_bodies[d])).
// A key is a typed id, or a plain position (int32_t) where no table names it.
template <class Key, class Val>
struct Csr {
    template <class T>
    using PerKey = std::conditional_t<graph::is_typed_id<Key>, graph::IdVector<Key, T>, std::vector<T>>;
    PerKey<int32_t> adr, num;
    std::vector<Val> list;
    std::span<const Val> operator[](Key k) const {
        const Val* first = list.data() + adr[k];
        return {first, first + num[k]};
    }
};

struct KindBehaviour;  // engine/plugin.h

// A plugin component's behaviour, where its state is in State::plugin_state, and its
// component's first slot (Comp::slot_adr, kept here for the step's visits: PluginCtx).
struct PluginRun {
    const KindBehaviour* behaviour = nullptr;
    int32_t state_adr = 0;
    graph::Adr<graph::Slot> slot_adr;
};

// Per-id arrays are IdVectors (graph/ids.h): indexed by the id of the table they follow.
struct Tables {
    template <class IdT, class T>
    using IdVector = graph::IdVector<IdT, T>;

    IdVector<graph::SlotId, uint8_t> slot_out;  // 1 for outputs
    IdVector<graph::SlotId, graph::Adr<graph::Value>> value_adr; // Slot::value_adr, packed: the hot lookup of every step
    // What an active input is for after the logic phase, for the lists phases 4 and 5 walk
    // (one lookup a slot): the component that acts on it in phase 5, the place it puts a token
    // into in phase 4; -1 where none (an output: both).
    struct SlotIn {
        graph::CompId acts;
        graph::PlaceId put;
    };
    IdVector<graph::SlotId, SlotIn> slot_in;
    // A bit per slot: an input whose component acts alone while only such inputs of it are
    // active (KindBehaviour::acts_alone): phase 5 gives those components to the physics threads.
    std::vector<uint64_t> slot_alone;
    bool alone(graph::SlotId x) const { return (slot_alone[size_t(x.v) / 64] >> (x.v % 64)) & 1; }
    // Dynamic slots: the animation of a play slot, the variant of a select slot; -1 for
    // every other slot.
    IdVector<graph::SlotId, int32_t> slot_aux;

    IdVector<graph::BodyId, graph::DoId> body_do;  // owner DO of each body
    std::vector<graph::BodyId> dyn_bodies;  // bodies declared dynamic: what fields and triggers see
    Csr<graph::DoId, graph::BodyId> do_bodies;        // bodies of a DO and of the DOs below it
    Csr<graph::DoId, graph::GraphicsId> do_graphics;  // graphics of a DO and below, not attached to a body
    IdVector<graph::DoId, graph::Id<graph::Label>> do_label;  // the first Label of a DO or below, -1
    IdVector<graph::DoId, graph::SourceId> do_source;         // Source whose pool holds this DO, -1

    std::vector<graph::CompId> nets;  // State components, in id order
    Csr<int32_t, graph::TransitionId> net_transitions;  // by position in `nets`
    IdVector<graph::PlaceId, int32_t> place_net;  // position in `nets` of each place
    Csr<int32_t, graph::PlaceId> net_places;      // by position in `nets`
    std::vector<uint8_t> net_always_live;  // has a transition without inputs
    // The transitions' input arcs packed in net_transitions' order, so the enabling check
    // reads them in a row: per position in its list, +1, the first in net_in.
    std::vector<int32_t> net_in_adr;
    std::vector<graph::Arc> net_in;
    Csr<graph::CompId, graph::Id<graph::Route>> comp_routes;  // routes of each Router component

    IdVector<graph::FieldId, btTransform> field_local;      // field box relative to its body frame
    IdVector<graph::FieldId, btVector3> field_gain;         // the law's gain along the field's own axes: k·|d|
                                                            // (a turning field's: k along x and y)
    IdVector<graph::FieldId, uint8_t> field_turns;          // Field::radius > 0: the target turns about a pivot
    IdVector<graph::FieldId, btVector3> field_pivot;        // ... Field::pivot, in the field's frame
    // A trigger's box: relative to its body's frame, or in the world for one on no body (its
    // pose never changes); its half extents; the body it is on (Trigger::body, beside the
    // rest: each step reads it for every trigger); for one on no body, how far its box
    // reaches from its centre along x and y.
    IdVector<graph::TriggerId, btTransform> trigger_local;
    IdVector<graph::TriggerId, btVector3> trigger_half;
    IdVector<graph::TriggerId, graph::BodyId> trigger_body;
    IdVector<graph::TriggerId, btVector3> trigger_reach;
    // Each exit's trigger (Exit::trigger, packed: every step looks at every exit's).
    IdVector<graph::ExitId, graph::TriggerId> exit_trigger;

    IdVector<graph::PluginId, PluginRun> plugin_run;  // per row of Graph::plugins
    std::vector<graph::PluginId> sensing_plugins;     // rows whose kind senses in phase 2
    int32_t plugin_state_size = 0;

    explicit Tables(const graph::Graph& g);
};

// How far a box turned by R, with half extents h, reaches from its centre along x and y (z 0):
// the triggers' lookups add the bodies' reach to it (kinds/trigger/run.cpp).
inline btVector3 trigger_box_reach(const btMatrix3x3& R, const btVector3& h) {
    return btVector3(std::abs(R[0][0]) * h.x() + std::abs(R[0][1]) * h.y() + std::abs(R[0][2]) * h.z(),
                     std::abs(R[1][0]) * h.x() + std::abs(R[1][1]) * h.y() + std::abs(R[1][2]) * h.z(), 0);
}

}  // namespace plant::engine
