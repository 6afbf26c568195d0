#include "engine/schedule.h"

#include "graph/network.h"

namespace plant::engine {

using namespace plant::graph;

namespace {

FlowOp make_op(const Graph& g, const Flow& f) {
    FlowOp op;
    op.from = f.from;  // the ref slot of a dynamic source (the Flow contract)
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

OpKind kind_of(NodeKind k) {
    switch (k) {
    case NodeKind::Flow: return OpKind::Flow;
    case NodeKind::Logic: return OpKind::Logic;
    case NodeKind::Router: return OpKind::Router;
    case NodeKind::Label: return OpKind::Label;
    }
    return OpKind::Flow;
}

}  // namespace

Schedule build_schedule(const Graph& g, const Tables& t) {
    Schedule s;
    for (const Flow& f : g.flows) s.flows.push_back(make_op(g, f));
    const Network net = analyse_network(g);
    for (const Node& n : net.order) s.ops.push_back({kind_of(n.kind), n.index});
    s.delayed = net.delayed;
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
