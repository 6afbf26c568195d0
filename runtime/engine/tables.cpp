#include "engine/tables.h"

#include "engine/plugin.h"
#include "graph/kinds.h"

#include <stdexcept>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace plant::engine {

using namespace plant::graph;

namespace {

// Builds a Csr from (key, value) pairs; values keep their order within a key.
template <class Key, class Val>
Csr<Key, Val> make_csr(size_t keys, const std::vector<std::pair<Key, Val>>& pairs) {
    Csr<Key, Val> c;
    c.adr.assign(keys, 0);
    c.num.assign(keys, 0);
    for (auto& [k, v] : pairs) c.num[k]++;
    std::exclusive_scan(c.num.begin(), c.num.end(), c.adr.begin(), 0);
    c.list.resize(pairs.size());
    typename Csr<Key, Val>::template PerKey<int32_t> fill;
    fill.assign(keys, 0);
    for (auto& [k, v] : pairs) c.list[c.adr[k] + fill[k]++] = v;
    return c;
}

// Calls f(a) for the DO d and every DO above it (bounded, in case of a broken parent chain).
template <class F>
void for_ancestors(const Graph& g, DoId d, F&& f) {
    for (size_t guard = 0; g.dos.contains(d) && guard <= g.dos.size(); ++guard) {
        f(d);
        d = g.dos[d].parent;
    }
}

btTransform relative(const Pose& frame, const Pose& thing) { return to_bt(pmul(pinv(frame), thing)); }

}  // namespace

Tables::Tables(const Graph& g) {
    const size_t ndo = g.dos.size();
    slot_out.resize(g.slots.size());
    value_adr.resize(g.slots.size());
    for (SlotId s : ids_of(g.slots)) value_adr[s] = g.slots[s].value_adr;
    for (SlotId s : ids_of(g.slots)) slot_out[s] = g.slots[s].dir == Dir::Out;
    // Inputs act in phase 5 where their kind has an act hook (a plugin: acts in
    // Actuators); a connector's inputs, a label's `set` and a router's `query` are read by
    // phase 3, a state's places by phase 4.
    slot_in.resize(g.slots.size());
    for (SlotId s : ids_of(g.slots)) {
        const CompId c = g.slots[s].comp;
        const KindBehaviour* b = builtin_behaviour(g.comps[c].kind);
        if (!slot_out[s] && (b ? b->act_one != nullptr : plugin_of(g, c)->acts == PluginPhase::Actuators))
            slot_in[s].acts = c;
    }
    slot_alone.assign((g.slots.size() + 63) / 64, 0);
    for (SlotId s : ids_of(g.slots)) {
        const Comp& c = g.comps[g.slots[s].comp];
        const KindBehaviour* b = builtin_behaviour(c.kind);
        if (slot_in[s].acts.valid() && b && b->acts_alone && b->acts_alone(g, c, s.v - c.slot_adr.v))
            slot_alone[size_t(s.v) / 64] |= uint64_t(1) << (s.v % 64);
    }
    // Plugin components: the loader checked their kinds are registered; a kind registered
    // without its behaviour (graph::register_kind alone, as a compiler-only program may) is
    // a program that cannot run it.
    for (PluginId i : ids_of(g.plugins)) {
        const std::string_view word = g.str(g.plugins[i].kind);
        const KindBehaviour* b = find_behaviour(word);
        if (!b) throw std::runtime_error("component kind '" + std::string(word) + "' has no runtime in this program");
        plugin_run.push_back({b, plugin_state_size, g.comps[g.plugins[i].comp].slot_adr});
        plugin_state_size += b->state_size;
        if (b->sense) sensing_plugins.push_back(i);
    }

    slot_aux.assign(g.slots.size(), -1);
    auto set_aux = [&](SlotId slot, int32_t i) {
        if (slot_aux.contains(slot)) slot_aux[slot] = i;
    };
    for (PlaceId i : ids_of(g.places))
        if (g.places[i].put_slot.valid()) slot_in[g.places[i].put_slot].put = i;
    for (AnimationId i : ids_of(g.animations)) set_aux(g.animations[i].play_slot, i.v);
    for (VariantId i : ids_of(g.variants)) set_aux(g.variants[i].select_slot, i.v);

    std::vector<std::pair<DoId, BodyId>> do_body;
    body_do.resize(g.bodies.size());
    for (BodyId b : ids_of(g.bodies)) {
        body_do[b] = g.comps[g.bodies[b].comp].owner;
        if (g.bodies[b].mode == BodyMode::Dynamic) dyn_bodies.push_back(b);
        for_ancestors(g, body_do[b], [&](DoId a) { do_body.emplace_back(a, b); });
    }
    do_bodies = make_csr(ndo, do_body);

    std::vector<std::pair<DoId, GraphicsId>> do_gr;
    for (GraphicsId i : ids_of(g.graphics)) {
        const Graphics& gr = g.graphics[i];
        if (gr.body.valid() || gr.parent.valid()) continue;
        for_ancestors(g, g.comps[gr.comp].owner, [&](DoId a) { do_gr.emplace_back(a, i); });
    }
    do_graphics = make_csr(ndo, do_gr);

    do_label.assign(ndo, Id<Label>{});
    for (Id<Label> i : ids_of(g.labels))
        for_ancestors(g, g.comps[g.labels[i].comp].owner, [&](DoId a) {
            if (!do_label[a].valid()) do_label[a] = i;
        });

    do_source.assign(ndo, SourceId{});
    for (SourceId s : ids_of(g.sources)) {
        const Source& src = g.sources[s];
        for (DoId d : children(src.pool_adr, src.pool_num))
            if (do_source.contains(d)) do_source[d] = s;
    }

    // Petri nets: one per State component.
    IdVector<CompId, int32_t> net_of_comp(g.comps.count(), -1);
    for (CompId c : ids_of(g.comps))
        if (g.comps[c].kind == CompKind::State) {
            net_of_comp[c] = count_of(nets);
            nets.push_back(c);
        }
    std::vector<std::pair<int32_t, TransitionId>> net_tr;
    net_always_live.assign(nets.size(), 0);
    for (TransitionId t : ids_of(g.transitions)) {
        int32_t n = net_of_comp[g.transitions[t].comp];
        net_tr.emplace_back(n, t);
        if (g.transitions[t].in_num == 0) net_always_live[n] = 1;
    }
    net_transitions = make_csr(nets.size(), net_tr);
    net_in_adr.reserve(net_transitions.list.size() + 1);
    for (TransitionId t : net_transitions.list) {
        net_in_adr.push_back(count_of(net_in));
        for (const Arc& a : g.arcs.slice(g.transitions[t].in_adr, g.transitions[t].in_num)) net_in.push_back(a);
    }
    net_in_adr.push_back(count_of(net_in));
    place_net.resize(g.places.size());
    std::vector<std::pair<int32_t, PlaceId>> net_pl;
    for (PlaceId p : ids_of(g.places)) {
        place_net[p] = net_of_comp[g.places[p].comp];
        net_pl.emplace_back(place_net[p], p);
    }
    net_places = make_csr(nets.size(), net_pl);
    // Phase 4 steps each net on its own (petri.cpp): a transition's arcs are on its net's places.
    for (TransitionId t : ids_of(g.transitions)) {
        const Transition& tr = g.transitions[t];
        auto own = [&](const Arc& a) { return place_net[a.place] == net_of_comp[tr.comp]; };
        const auto in = g.arcs.slice(tr.in_adr, tr.in_num), out = g.arcs.slice(tr.out_adr, tr.out_num);
        if (!std::all_of(in.begin(), in.end(), own) || !std::all_of(out.begin(), out.end(), own))
            throw std::runtime_error("a transition's arc is on a place of another state component");
    }

    std::vector<std::pair<CompId, Id<Route>>> comp_route;
    for (Id<Route> r : ids_of(g.routes)) comp_route.emplace_back(g.routes[r].comp, r);
    comp_routes = make_csr(g.comps.size(), comp_route);

    field_local.resize(g.fields.size(), btTransform::getIdentity());
    for (FieldId f : ids_of(g.fields))
        if (g.fields[f].body.valid())
            field_local[f] = relative(g.bodies[g.fields[f].body].pose, g.fields[f].pose);
    field_gain.resize(g.fields.size());
    field_turns.resize(g.fields.size(), 0);
    field_pivot.resize(g.fields.size(), btVector3(0, 0, 0));
    for (FieldId f : ids_of(g.fields)) {
        const Vec3& d = g.fields[f].dir;
        field_turns[f] = g.fields[f].radius > 0;
        field_pivot[f] = to_bt(g.fields[f].pivot);
        field_gain[f] = field_turns[f] ? btVector3(1, 1, 0) * btScalar(g.fields[f].gain)
                                       : btVector3(btScalar(std::abs(d[0])), btScalar(std::abs(d[1])),
                                                   btScalar(std::abs(d[2]))) * btScalar(g.fields[f].gain);
    }
    trigger_local.resize(g.triggers.size(), btTransform::getIdentity());
    trigger_half.resize(g.triggers.size(), btVector3(0, 0, 0));
    trigger_body.resize(g.triggers.size(), BodyId{});
    trigger_reach.resize(g.triggers.size(), btVector3(0, 0, 0));
    for (TriggerId t : ids_of(g.triggers)) {
        const Trigger& tg = g.triggers[t];
        trigger_local[t] = tg.body.valid() ? relative(g.bodies[tg.body].pose, tg.pose) : to_bt(tg.pose);
        trigger_half[t] = to_bt(tg.extent) * btScalar(0.5);
        trigger_body[t] = tg.body;
        trigger_reach[t] = trigger_box_reach(trigger_local[t].getBasis(), trigger_half[t]);
    }
    exit_trigger.resize(g.exits.size(), TriggerId{});
    for (ExitId e : ids_of(g.exits)) exit_trigger[e] = g.exits[e].trigger;
}

}  // namespace plant::engine
