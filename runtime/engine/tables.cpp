#include "engine/tables.h"

#include "engine/plugin.h"
#include "graph/kinds.h"

#include <stdexcept>

#include <algorithm>
#include <cmath>

namespace plant::engine {

using namespace plant::graph;

namespace {

// Builds a Csr from (key, value) pairs; values keep their order within a key.
Csr make_csr(size_t keys, const std::vector<std::pair<int32_t, int32_t>>& pairs) {
    Csr c;
    c.adr.assign(keys, 0);
    c.num.assign(keys, 0);
    for (auto& [k, v] : pairs) c.num[k]++;
    for (size_t i = 1; i < keys; ++i) c.adr[i] = c.adr[i - 1] + c.num[i - 1];
    c.list.resize(pairs.size());
    std::vector<int32_t> fill(keys, 0);
    for (auto& [k, v] : pairs) c.list[c.adr[k] + fill[k]++] = v;
    return c;
}

// Calls f(a) for the DO d and every DO above it (bounded, in case of a broken parent chain).
template <class F>
void for_ancestors(const Graph& g, int32_t d, F&& f) {
    for (size_t guard = 0; d >= 0 && d < int32_t(g.dos.size()) && guard <= g.dos.size(); ++guard) {
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
    for (size_t s = 0; s < g.slots.size(); ++s) value_adr[s] = g.slots[s].value_adr;
    for (size_t s = 0; s < g.slots.size(); ++s) slot_out[s] = g.slots[s].dir == Dir::Out;
    // State, logic and router inputs are read by phases 3 and 4; the rest act (a kind on the
    // kind table: when it has an act hook; a label's `set` is read by phase 3).
    slot_acts.resize(g.slots.size());
    for (size_t s = 0; s < g.slots.size(); ++s) {
        const CompKind k = g.comps[g.slots[s].comp].kind;
        const KindBehaviour* b = builtin_behaviour(k);
        slot_acts[s] = !slot_out[s] && (b ? b->act_one != nullptr
                                          : k != CompKind::State && k != CompKind::Logic && k != CompKind::Router &&
                                                (k != CompKind::Plugin ||
                                                 plugin_of(g, g.slots[s].comp)->acts == PluginPhase::Actuators));
    }
    // Plugin components: the loader checked their kinds are registered; a kind registered
    // without its behaviour (graph::register_kind alone, as a compiler-only program may) is
    // a program that cannot run it.
    for (size_t i = 0; i < g.plugins.size(); ++i) {
        const std::string_view word = g.str(g.plugins[i].kind);
        const KindBehaviour* b = find_behaviour(word);
        if (!b) throw std::runtime_error("component kind '" + std::string(word) + "' has no runtime in this program");
        plugin_run.push_back({b, plugin_state_size});
        plugin_state_size += b->state_size;
        if (b->sense) sensing_plugins.push_back(int32_t(i));
    }

    slot_aux.assign(g.slots.size(), -1);
    auto set_aux = [&](int32_t slot, size_t i) {
        if (slot >= 0 && size_t(slot) < slot_aux.size()) slot_aux[slot] = int32_t(i);
    };
    put_place.assign(g.slots.size(), -1);
    for (size_t i = 0; i < g.places.size(); ++i) {
        if (g.places[i].put_slot >= 0) put_place[g.places[i].put_slot] = int32_t(i);
        place_entered.push_back(g.places[i].entered_slot);
        place_tokens.push_back(g.places[i].tokens_slot);
    }
    for (size_t i = 0; i < g.animations.size(); ++i) set_aux(g.animations[i].play_slot, i);
    for (size_t i = 0; i < g.variants.size(); ++i) set_aux(g.variants[i].select_slot, i);

    std::vector<std::pair<int32_t, int32_t>> pairs;
    body_do.resize(g.bodies.size());
    for (size_t b = 0; b < g.bodies.size(); ++b) {
        body_do[b] = g.comps[g.bodies[b].comp].owner;
        if (g.bodies[b].mode == BodyMode::Dynamic) dyn_bodies.push_back(int32_t(b));
        for_ancestors(g, body_do[b], [&](int32_t a) { pairs.emplace_back(a, int32_t(b)); });
    }
    do_bodies = make_csr(ndo, pairs);

    pairs.clear();
    for (size_t i = 0; i < g.graphics.size(); ++i) {
        const Graphics& gr = g.graphics[i];
        if (gr.body >= 0 || gr.parent >= 0) continue;
        for_ancestors(g, g.comps[gr.comp].owner, [&](int32_t a) { pairs.emplace_back(a, int32_t(i)); });
    }
    do_graphics = make_csr(ndo, pairs);

    do_label.assign(ndo, -1);
    for (size_t i = 0; i < g.labels.size(); ++i)
        for_ancestors(g, g.comps[g.labels[i].comp].owner, [&](int32_t a) {
            if (do_label[a] < 0) do_label[a] = int32_t(i);
        });

    do_source.assign(ndo, -1);
    for (size_t s = 0; s < g.sources.size(); ++s) {
        const Source& src = g.sources[s];
        for (int32_t d = src.pool_adr; d < src.pool_adr + src.pool_num; ++d)
            if (d >= 0 && size_t(d) < ndo) do_source[d] = int32_t(s);
    }

    // Petri nets: one per State component.
    std::vector<int32_t> net_of_comp(g.comps.size(), -1);
    for (size_t c = 0; c < g.comps.size(); ++c)
        if (g.comps[c].kind == CompKind::State) {
            net_of_comp[c] = int32_t(nets.size());
            nets.push_back(int32_t(c));
        }
    pairs.clear();
    net_always_live.assign(nets.size(), 0);
    for (size_t t = 0; t < g.transitions.size(); ++t) {
        int32_t n = net_of_comp[g.transitions[t].comp];
        pairs.emplace_back(n, int32_t(t));
        if (g.transitions[t].in_num == 0) net_always_live[n] = 1;
    }
    net_transitions = make_csr(nets.size(), pairs);
    place_net.resize(g.places.size());
    for (size_t p = 0; p < g.places.size(); ++p) place_net[p] = net_of_comp[g.places[p].comp];

    pairs.clear();
    for (size_t r = 0; r < g.routes.size(); ++r) pairs.emplace_back(g.routes[r].comp, int32_t(r));
    comp_routes = make_csr(g.comps.size(), pairs);

    // Graphics: parents first (depth order; equal depths by id, which is deterministic).
    std::vector<int32_t> depth(g.graphics.size(), 0);
    for (size_t i = 0; i < g.graphics.size(); ++i) {
        int32_t p = g.graphics[i].parent;
        for (size_t guard = 0; p >= 0 && guard <= g.graphics.size(); ++guard) {
            depth[i]++;
            p = g.graphics[p].parent;
        }
        graphics_order.push_back(int32_t(i));
    }
    std::stable_sort(graphics_order.begin(), graphics_order.end(),
                     [&](int32_t a, int32_t b) { return depth[a] < depth[b]; });
    while (graphics_roots < graphics_order.size() && depth[size_t(graphics_order[graphics_roots])] == 0) ++graphics_roots;
    graphics_local.resize(g.graphics.size());
    for (size_t i = 0; i < g.graphics.size(); ++i) {
        const Graphics& gr = g.graphics[i];
        if (gr.body >= 0) graphics_local[i] = pmul(pinv(g.bodies[gr.body].pose), gr.pose);
        else if (gr.parent >= 0) graphics_local[i] = pmul(pinv(g.graphics[gr.parent].pose), gr.pose);
    }

    field_local.resize(g.fields.size(), btTransform::getIdentity());
    for (size_t f = 0; f < g.fields.size(); ++f)
        if (g.fields[f].body >= 0)
            field_local[f] = relative(g.bodies[g.fields[f].body].pose, g.fields[f].pose);
    field_gain.resize(g.fields.size());
    for (size_t f = 0; f < g.fields.size(); ++f) {
        const Vec3& d = g.fields[f].dir;
        field_gain[f] = btVector3(btScalar(std::abs(d[0])), btScalar(std::abs(d[1])), btScalar(std::abs(d[2]))) *
                        btScalar(g.fields[f].gain);
    }
    trigger_local.resize(g.triggers.size(), btTransform::getIdentity());
    for (size_t t = 0; t < g.triggers.size(); ++t)
        if (g.triggers[t].body >= 0)
            trigger_local[t] = relative(g.bodies[g.triggers[t].body].pose, g.triggers[t].pose);
}

}  // namespace plant::engine
