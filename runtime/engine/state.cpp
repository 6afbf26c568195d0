#include "engine/state.h"

#include "engine/plugin.h"
#include "engine/workers.h"

#include <algorithm>

namespace plant::engine {

using namespace plant::graph;

void init_state(State& s, const Graph& g, const Tables& t) {
    s.plugin_state.assign(t.plugin_state_size, 0.0);
    const size_t ns = g.slots.size(), nb = g.bodies.size();
    s.values.resize(g.values.size());
    for (Id<Value> i : ids_of(g.values)) s.values[index(i)] = g.values[i].v;
    s.act.assign(ns, 0);
    for (auto& x : s.seen) x.assign(ns, 0);
    // Each slot is in a list at most once per step: the slot count bounds them.
    s.out_list.reserve(ns);
    s.seen_list.reserve(ns);
    s.in_list.reserve(ns);
    s.pending.reserve(ns + 64);
    s.once_held.assign(g.flows.size(), kNeverHeld);
    s.watched.assign(ns, 0);
    s.body_outputs.assign(nb, 0);
    s.observed_bodies.reserve(nb);
    s.comp_list.reserve(g.comps.size());
    s.comp_mark.assign(g.comps.size(), 0);

    s.cmd_lin.assign(nb, Vec3{0, 0, 0});
    s.cmd_ang.assign(nb, Vec3{0, 0, 0});
    s.commanded.reserve(nb);  // the step allocates nothing
    s.is_commanded.assign(nb, 0);
    s.held_by.assign(nb, GripperId{});
    s.grip_rel.assign(nb, btTransform::getIdentity());
    s.gone.assign(nb, 0);
    s.lost_at.assign(g.dos.size(), -1.0);
    s.loss.assign(g.dos.size(), Loss{});
    s.lost.reserve(g.dos.size());
    s.ride_field.assign(nb, FieldId{});
    s.ride_step.assign(nb, -1);
    s.ride_at.assign(nb, btVector3(0, 0, 0));
    s.stall_since.assign(nb, 0.0);
    s.field_run.assign(nb, 0.0);
    s.slow_step.assign(nb, -1);

    s.field_speed.resize(g.fields.size());
    s.field_on.resize(g.fields.size());
    s.field_frame.resize(g.fields.size());
    s.field_xy.resize(g.fields.size());
    for (FieldId f : ids_of(g.fields)) {
        s.field_speed[f] = g.fields[f].speed;
        s.field_on[f] = g.fields[f].enabled;
    }
    s.force.assign(nb, btVector3(0, 0, 0));
    s.gain.assign(nb, btMatrix3x3(0, 0, 0, 0, 0, 0, 0, 0, 0));
    s.group_adr.assign(nb, 0);
    s.group_num.assign(nb, 0);
    s.group_list.assign(nb, BodyId{});
    s.group_mark.assign(nb, 0);
    s.body_k.assign(nb, 0);
    s.body_cap.assign(nb, 0);
    s.law_sat.assign(nb, 0);
    s.sat_force.assign(nb, btVector3(0, 0, 0));
    s.group_mass.assign(nb, 0);
    s.group_of.resize(nb);
    for (BodyId b : ids_of(g.bodies)) s.group_of[b] = b;
    s.touched.assign(nb, BodyId{});
    s.world_list.assign(nb, BodyId{});
    s.law_on.assign(nb, 0);
    s.field_act.assign(g.fields.size(), 0);
    s.field_target.assign(g.fields.size(), btVector3(0, 0, 0));
    s.field_spin.assign(g.fields.size(), 0);
    s.field_carried.clear();
    for (FieldId f : ids_of(g.fields))
        if (g.fields[f].body.valid() && g.bodies[g.fields[f].body].mode != BodyMode::Static) s.field_carried.push_back(f);
    s.field_touched.clear();
    s.field_touched.reserve(g.fields.size());
    s.field_is_touched.assign(g.fields.size(), 0);
    s.field_statics = UINT64_MAX;

    const size_t np = g.places.size();
    s.tokens.resize(np);
    for (PlaceId p : ids_of(g.places)) s.tokens[p] = g.places[p].initial;
    s.place_step.resize(np);
    for (PlaceId p : ids_of(g.places))
        s.place_step[p] = {.entered = g.places[p].entered_slot, .tokens_slot = g.places[p].tokens_slot, .net = t.place_net[p]};
    s.net_live.assign(t.nets.size(), 1);  // every net is examined in the first step
    // Each slice's list holds what its nets can make active in a step: a `fired` per transition,
    // an `entered` and a `tokens` per place.
    const size_t net_slices = petri_slices(t.nets.size());
    s.petri_made.assign(net_slices, {});
    for (size_t k = 0; k < net_slices; ++k) {
        const auto [b, e] = slice_of(t.nets.size(), net_slices, k);
        size_t most = 0;
        for (size_t n = b; n < e; ++n) most += size_t(t.net_transitions.num[n]) + 2 * size_t(t.net_places.num[n]);
        s.petri_made[k].reserve(most);
    }

    s.triggers.resize(g.triggers.size());
    s.trigger_occupied.assign(g.triggers.size(), 0);
    for (auto& lists : s.trigger_lists) lists.resize(kMaxSlices);
    s.trigger_made.resize(kMaxSlices);  // the slices in use are sized at the start (kinds/trigger/run.cpp)
    s.slice_moved.assign(kMaxSlices, 0);
    s.slice_left.assign(kMaxSlices, 0);

    for (const graph::KindDesc* k : graph::builtin_kinds())  // the kinds on the kind table
        if (const KindBehaviour* b = builtin_behaviour(k->kind); b->make_state) s.kinds[size_t(k->kind)] = b->make_state(g);

    s.gripper_held.assign(g.grippers.size(), DoId{});

    s.graphics.resize(g.graphics.size());
    s.graphics_placed.assign(g.graphics.size(), 0);
    s.variant.resize(g.graphics.size());
    for (GraphicsId i : ids_of(g.graphics)) {
        s.graphics[i].base = s.graphics[i].pose = s.graphics[i].prev = g.graphics[i].pose;
        const Graphics& gr = g.graphics[i];
        s.variant[i] = gr.variant >= 0 ? (gr.variant_adr + gr.variant).v : -1;  // a Variant id
    }

    s.sources.resize(g.sources.size());
    for (SourceId i : ids_of(g.sources)) {
        const Source& src = g.sources[i];
        SourceState& ss = s.sources[i];
        ss.ring_adr = count_of(s.pool_ring);
        ss.free = src.pool_num;
        for (DoId d : children(src.pool_adr, src.pool_num)) s.pool_ring.push_back(d);
    }
    s.exit_count.assign(g.exits.size(), 0);
    s.in_hand.assign(g.bodies.size(), 0);
    s.hands.reserve(16);  // a few trainees' hands; more grow it between steps, never in one
}

}  // namespace plant::engine
