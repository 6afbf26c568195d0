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

// A CSR table of (key, position) pairs: per key, +1, the start of its positions.
void packed(std::vector<std::pair<int32_t, int32_t>>& pairs, size_t keys, std::vector<int32_t>& adr,
            std::vector<int32_t>& out) {
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    adr.assign(keys + 1, 0);
    for (const auto& [key, at] : pairs) ++adr[size_t(key) + 1];
    for (size_t k = 0; k < keys; ++k) adr[k + 1] += adr[k];
    out.resize(pairs.size());
    for (size_t i = 0; i < pairs.size(); ++i) out[i] = pairs[i].second;
}

// Which slots each op reads (the ops a slot's activity makes due), and the ops due always.
void due_by_slot(const Graph& g, Schedule& s) {
    const size_t n = s.ops.size();
    const AccessGroups ag = access_groups(g);
    s.always.assign((n + 63) / 64, 0);
    std::vector<std::pair<int32_t, int32_t>> reads, group_reads;  // (slot or group, position)
    for (size_t p = 0; p < n; ++p) {
        const Op& op = s.ops[p];
        const int32_t at = int32_t(p);
        bool always = false;
        switch (op.kind) {
        case OpKind::Pulse: reads.emplace_back(op.from, at); break;
        case OpKind::Flow: {
            const FlowOp& f = s.flows[size_t(op.index)];
            if (f.cond != Cond::Target) {  // Source, Both, Either: its source (a dynamic one's reference)
                reads.emplace_back(f.from, at);
                if (f.from_access >= 0) group_reads.emplace_back(ag.of[size_t(f.from_access)], at);
            }
            if (f.cond != Cond::Source) {  // Target, Both, Either
                if (f.to_access >= 0) group_reads.emplace_back(ag.of[size_t(f.to_access)], at);
                else reads.emplace_back(f.to, at);
            }
            break;
        }
        case OpKind::Logic: {
            // An `and` is off while any input that is not negated is inactive: due when one of
            // those is active (always when it has none). An `or` with a negated input is on
            // while that input is inactive: always due.
            const Logic& l = g.logics[size_t(op.index)];
            bool plain = false, negated = false;
            for (int32_t k = 0; k < l.in_num; ++k) {
                const LogicIn& in = g.logic_inputs[size_t(l.in_adr + k)];
                (in.negated ? negated : plain) = true;
                if (!in.negated || l.op != LogicOp::And) reads.emplace_back(in.slot, at);
            }
            always = l.op == LogicOp::And ? !plain : (negated || !plain);
            break;
        }
        case OpKind::Router: reads.emplace_back(g.comps[size_t(op.index)].slot_adr + routerslot::query, at); break;
        case OpKind::Label: reads.emplace_back(g.comps[size_t(g.labels[size_t(op.index)].comp)].slot_adr + labelslot::set, at); break;
        }
        if (always) s.always[p / 64] |= uint64_t(1) << (p % 64);
    }
    packed(reads, g.slots.size(), s.reader_adr, s.readers);
    packed(group_reads, ag.first.size(), s.group_reader_adr, s.group_readers);
    // Each slot's groups: only groups some op reads.
    std::vector<std::pair<int32_t, int32_t>> slot_groups;  // (slot, group)
    for (size_t k = 0; k < ag.first.size(); ++k) {
        if (s.group_reader_adr[k] == s.group_reader_adr[k + 1]) continue;
        const Access& a = g.accesses[size_t(ag.first[k])];
        for (int32_t i = 0; i < a.target_num; ++i)
            slot_groups.emplace_back(g.access_targets[size_t(a.target_adr.v + i)].v, int32_t(k));
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
        const FlowOp& f = s.flows[op.index];
        if (f.from_access >= 0 || f.to_access >= 0 || f.cond != Cond::Source || f.once || f.width > 0 ||
            t.slot_out[f.to])
            continue;
        op = {OpKind::Pulse, op.index, f.from, f.to};
    }
    due_by_slot(g, s);
    return s;
}

}  // namespace plant::engine
