#include "engine/schedule.h"

#include "graph/kinds.h"
#include "graph/network.h"

#include <algorithm>
#include <utility>

namespace plant::engine {

using namespace plant::graph;

namespace {

FlowOp make_op(const Graph& g, const Flow& f) {
    FlowOp op;
    op.from = f.from;  // the ref slot of a dynamic source (the Flow contract)
    op.to = f.to;
    op.from_access = f.from_access;
    op.to_access = f.to_access;
    if (!f.from_access.valid()) op.from_val = g.slots[f.from].value_adr;
    if (!f.to_access.valid()) op.to_val = g.slots[f.to].value_adr;
    SlotId typed = f.to_access.valid() ? SlotId{} : f.to;
    if (!typed.valid() && g.accesses[f.to_access].target_num > 0)
        typed = g.access_targets[g.accesses[f.to_access].target_adr.first()].v;
    op.width = typed.valid() ? slot_width(g.slots[typed].type) : 0;
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

// A CSR table of (key, position) pairs: per key, +1, the start of its positions.
void packed(std::vector<std::pair<int32_t, int32_t>>& pairs, size_t keys, std::vector<int32_t>& adr,
            std::vector<int32_t>& out) {
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    adr.assign(keys + 1, 0);
    for (const auto& [key, at] : pairs) ++adr[key + 1];
    for (size_t k = 0; k < keys; ++k) adr[k + 1] += adr[k];
    out.resize(pairs.size());
    for (size_t i = 0; i < pairs.size(); ++i) out[i] = pairs[i].second;
}

// Which slots each op reads (the ops a slot's activity makes due), and the ops due always.
void due_by_slot(const Graph& g, Schedule& s) {
    const size_t n = s.ops.size();
    const AccessGroups ag = access_groups(g);
    s.always.assign((n + 63) / 64, 0);
    s.dense_at = n / 8 + 1;
    std::vector<std::pair<int32_t, int32_t>> reads, group_reads;  // (slot or group, position)
    for (int32_t at = 0; const Op& op : s.ops) {
        const int32_t p = at++;  // its position
        bool always = false;
        switch (op.kind) {
        case OpKind::Pulse: reads.emplace_back(op.from.v, p); break;
        case OpKind::Flow: {
            const FlowOp& f = s.flows[op.flow()];
            if (f.cond != Cond::Target) {  // Source, Both, Either: its source (a dynamic one's reference)
                reads.emplace_back(f.from.v, p);
                if (f.from_access.valid()) group_reads.emplace_back(ag.of[f.from_access].v, p);
            }
            if (f.cond != Cond::Source) {  // Target, Both, Either
                if (f.to_access.valid()) group_reads.emplace_back(ag.of[f.to_access].v, p);
                else reads.emplace_back(f.to.v, p);
            }
            break;
        }
        case OpKind::Logic: {
            // An `and` is off while any input that is not negated is inactive: due when one of
            // those is active (always when it has none). An `or` with a negated input is on
            // while that input is inactive: always due.
            const Logic& l = g.logics[op.logic()];
            bool plain = false, negated = false;
            for (const LogicIn& in : g.logic_inputs.slice(l.in_adr, l.in_num)) {
                (in.negated ? negated : plain) = true;
                if (!in.negated || l.op != LogicOp::And) reads.emplace_back(in.slot.v, p);
            }
            always = l.op == LogicOp::And ? !plain : (negated || !plain);
            break;
        }
        case OpKind::Router: reads.emplace_back((g.comps[op.router()].slot_adr + routerslot::query).v, p); break;
        case OpKind::Label: reads.emplace_back((g.comps[g.labels[op.label()].comp].slot_adr + labelslot::set).v, p); break;
        }
        if (always) s.always[p / 64] |= uint64_t(1) << (p % 64);
    }
    packed(reads, g.slots.size(), s.reader_adr, s.readers);
    packed(group_reads, ag.first.size(), s.group_reader_adr, s.group_readers);
    // Each slot's groups: only groups some op reads.
    std::vector<std::pair<int32_t, int32_t>> slot_groups;  // (slot, group)
    for (AccessGroupId k : ag.first.ids()) {
        if (s.group_reader_adr[k.v] == s.group_reader_adr[k.v + 1]) continue;
        const Access& a = g.accesses[ag.first[k]];
        for (const AccessTarget& t : g.access_targets.slice(a.target_adr, a.target_num)) slot_groups.emplace_back(t.v.v, k.v);
    }
    packed(slot_groups, g.slots.size(), s.group_adr, s.groups);
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
        const FlowOp& f = s.flows[op.flow()];
        if (f.from_access.valid() || f.to_access.valid() || f.cond != Cond::Source || f.once || f.width > 0 ||
            t.slot_out[f.to])
            continue;
        op = {OpKind::Pulse, op.index, f.from, f.to};
    }
    due_by_slot(g, s);
    return s;
}

}  // namespace plant::engine
