#include "engine/schedule.h"

#include "graph/kinds.h"

#include <algorithm>
#include <functional>
#include <queue>

namespace plant::engine {

using namespace plant::graph;

namespace {

// The slots a flow may write or read: a dynamic end may be any of its access targets.
std::vector<int32_t> end_slots(const Graph& g, int32_t slot, int32_t access, bool with_ref) {
    if (access < 0) return {slot};
    const Access& a = g.accesses[access];
    std::vector<int32_t> out;
    if (with_ref) out.push_back(a.ref_slot);
    for (int32_t i = 0; i < a.target_num; ++i) out.push_back(g.access_targets[a.target_adr + i].v);
    return out;
}

FlowOp make_op(const Graph& g, const Flow& f) {
    FlowOp op;
    op.from = f.from_access >= 0 ? g.accesses[f.from_access].ref_slot : f.from;
    op.to = f.to;
    op.from_access = f.from_access;
    op.to_access = f.to_access;
    if (f.from_access < 0) op.from_val = g.slots[f.from].value_adr;
    if (f.to_access < 0) op.to_val = g.slots[f.to].value_adr;
    int32_t typed = f.to_access < 0 ? f.to : -1;
    if (typed < 0 && g.accesses[f.to_access].target_num > 0)
        typed = g.access_targets[g.accesses[f.to_access].target_adr].v;
    op.width = typed >= 0 ? slot_width(g.slots[typed].type) : 0;
    op.cond = f.cond;
    op.once = f.once;
    return op;
}

}  // namespace

Schedule build_schedule(const Graph& g, const Tables& t) {
    Schedule s;
    std::vector<Op> nodes;
    for (size_t f = 0; f < g.flows.size(); ++f) {
        s.flows.push_back(make_op(g, g.flows[f]));
        nodes.push_back({OpKind::Flow, int32_t(f)});
    }
    for (size_t l = 0; l < g.logics.size(); ++l) nodes.push_back({OpKind::Logic, int32_t(l)});
    for (size_t c = 0; c < g.comps.size(); ++c)
        if (g.comps[c].kind == CompKind::Router) nodes.push_back({OpKind::Router, int32_t(c)});
    for (size_t l = 0; l < g.labels.size(); ++l) nodes.push_back({OpKind::Label, int32_t(l)});

    // Per slot: nodes that activate it, read it, or read it as their target's activity.
    const size_t ns = g.slots.size(), nn = nodes.size();
    std::vector<std::vector<int32_t>> prod(ns), read(ns), tread(ns);
    for (size_t n = 0; n < nn; ++n) {
        const Op& op = nodes[n];
        const int32_t id = int32_t(n);
        switch (op.kind) {
        case OpKind::Pulse:  // made from flows after ordering
        case OpKind::Flow: {
            const Flow& f = g.flows[op.index];
            for (int32_t x : end_slots(g, f.to, f.to_access, false)) {
                prod[x].push_back(id);
                if (f.cond != Cond::Source) tread[x].push_back(id);
            }
            for (int32_t x : end_slots(g, f.from, f.from_access, true)) read[x].push_back(id);
            break;
        }
        case OpKind::Logic: {
            const Logic& l = g.logics[op.index];
            for (int32_t i = 0; i < l.in_num; ++i) read[g.logic_inputs[l.in_adr + i].slot].push_back(id);
            prod[l.out_slot].push_back(id);
            break;
        }
        case OpKind::Router:
            read[g.comps[op.index].slot_adr + routerslot::query].push_back(id);
            for (const int32_t* r = t.comp_routes.begin(op.index); r != t.comp_routes.end(op.index); ++r)
                prod[g.routes[*r].out_slot].push_back(id);
            break;
        case OpKind::Label: {
            const Comp& c = g.comps[g.labels[op.index].comp];
            read[c.slot_adr + labelslot::set].push_back(id);
            prod[c.slot_adr + labelslot::value].push_back(id);
            break;
        }
        }
    }

    std::vector<std::vector<int32_t>> succ(nn), pred(nn);
    auto edge = [&](int32_t a, int32_t b) {
        if (a == b) return;
        succ[a].push_back(b);
        pred[b].push_back(a);
    };
    for (size_t x = 0; x < ns; ++x) {
        for (int32_t p : prod[x])
            for (int32_t c : read[x]) edge(p, c);
        for (int32_t f : tread[x])
            for (int32_t p : prod[x])
                if (std::find(tread[x].begin(), tread[x].end(), p) == tread[x].end()) edge(p, f);
    }

    // Kahn's algorithm, smallest ready node first.
    std::vector<int32_t> indeg(nn);
    for (size_t n = 0; n < nn; ++n) indeg[n] = int32_t(pred[n].size());
    std::vector<uint8_t> gone(nn, 0);  // emitted or delayed
    std::priority_queue<int32_t, std::vector<int32_t>, std::greater<>> ready;
    for (size_t n = 0; n < nn; ++n)
        if (indeg[n] == 0) ready.push(int32_t(n));
    auto release = [&](int32_t n) {
        gone[n] = 1;
        for (int32_t m : succ[n])
            if (!gone[m] && --indeg[m] == 0) ready.push(m);
    };
    for (size_t done = 0; done < nn;) {
        if (!ready.empty()) {
            int32_t n = ready.top();
            ready.pop();
            if (gone[n]) continue;
            s.ops.push_back(nodes[n]);
            release(n);
            ++done;
            continue;
        }
        // Stuck: every node left waits on another, so walking predecessors from the
        // first one must come back to a node already on the path: that is a cycle.
        int32_t cur = 0;
        while (gone[cur]) ++cur;
        std::vector<int32_t> path, pos(nn, -1);
        while (pos[cur] < 0) {
            pos[cur] = int32_t(path.size());
            path.push_back(cur);
            int32_t next = -1;
            for (int32_t p : pred[cur])
                if (!gone[p] && (next < 0 || p < next)) next = p;
            cur = next;
        }
        int32_t cut = -1;
        for (size_t i = size_t(pos[cur]); i < path.size(); ++i)
            if (nodes[path[i]].kind == OpKind::Flow && (cut < 0 || path[i] < cut)) cut = path[i];
        if (cut < 0) cut = cur;  // cannot happen: component nodes only connect through flows
        if (nodes[cut].kind == OpKind::Flow) s.delayed.push_back(nodes[cut].index);
        else s.ops.push_back(nodes[cut]);
        release(cut);
        ++done;
    }
    for (Op& op : s.ops) {
        if (op.kind != OpKind::Flow) continue;
        const FlowOp& f = s.flows[op.index];
        if (f.from_access >= 0 || f.to_access >= 0 || f.cond != Cond::Source || f.once || f.width > 0 ||
            t.slot_out[f.to])
            continue;
        op = {OpKind::Pulse, op.index, f.from, f.to};
    }
    return s;
}

}  // namespace plant::engine
