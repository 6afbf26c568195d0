#include "engine/schedule.h"

#include "graph/kinds.h"
#include "graph/network.h"

#include <algorithm>
#include <numeric>
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
void due_by_slot(const Graph& g, const AccessGroups& ag, Schedule& s) {
    const size_t n = s.ops.size();
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
    const size_t ns = g.slots.size();
    std::vector<int32_t> reader_adr, group_adr;  // per slot, +1
    packed(reads, ns, reader_adr, s.readers);
    packed(group_reads, ag.first.size(), s.group_reader_adr, s.group_readers);
    // Each slot's groups: only groups some op reads.
    std::vector<std::pair<int32_t, int32_t>> slot_groups;  // (slot, group)
    for (AccessGroupId k : ag.first.ids()) {
        if (s.group_reader_adr[k.v] == s.group_reader_adr[k.v + 1]) continue;
        for (const AccessTarget& t : ag.targets(g, k)) slot_groups.emplace_back(t.v.v, k.v);
    }
    packed(slot_groups, ns, group_adr, s.groups);
    // The read slots' rows: a slot read by no op has empty ranges, so a read slot's ranges end
    // where the next read slot's start.
    s.read_any.assign((ns + 63) / 64, 0);
    s.read_rank.assign(s.read_any.size(), 0);
    s.read_at.clear();
    for (size_t x = 0; x < ns; ++x) {
        if (x % 64 == 0) s.read_rank[x / 64] = count_of(s.read_at);
        if (reader_adr[x] == reader_adr[x + 1] && group_adr[x] == group_adr[x + 1]) continue;
        s.read_any[x / 64] |= uint64_t(1) << (x % 64);
        s.read_at.push_back({reader_adr[x], group_adr[x]});
    }
    s.read_at.push_back({reader_adr[ns], group_adr[ns]});
}

// The lanes (schedule.h): which ops share a slot a step changes, joined; the sets to lanes.
void split_lanes(const Graph& g, const Tables& t, const AccessGroups& ag, Schedule& s) {
    const int32_t n = count_of(s.ops), ns = count_of(g.slots);
    // Each op's slots: those it writes (activates), then those it reads (a flow's as the logic
    // network says them, graph/network.h, and the reference of a dynamic target, which names
    // the slot it writes). A dynamic end is its access's group (graph/network.h), not the
    // slots it may be: a router's `(sw.bottle as Bottle).code` may be every bottle's label,
    // and listing them per op grew with the square of the plant (at 417 lines of the bottling
    // plant, 119 million entries where 340,000 are left, and a third of the start). A group
    // stands between its ops and its slots in the union below, joined to each of its slots
    // that some op writes: the same sets of ops as joining each op to those slots.
    const int32_t ng = ag.first.count();
    std::vector<int32_t> adr(n + 1, 0), slots, writes(n, 0), rd;
    std::vector<int32_t> read_group(n, -1), write_group(n, -1);  // per op, a dynamic end's group
    for (int32_t i = 0; i < n; ++i) {
        const Op& op = s.ops[i];
        const size_t first = slots.size();
        rd.clear();
        switch (op.kind) {
        case OpKind::Pulse:  // a flow too
        case OpKind::Flow: {
            const Flow& f = g.flows[op.flow()];
            if (f.to_access.valid()) write_group[i] = ag.of[f.to_access].v;
            else slots.push_back(f.to.v);
            if (f.from_access.valid()) {
                rd.push_back(g.accesses[f.from_access].ref_slot.v);
                read_group[i] = ag.of[f.from_access].v;
            } else {
                rd.push_back(f.from.v);
            }
            if (f.to_access.valid()) rd.push_back(g.accesses[f.to_access].ref_slot.v);
            break;
        }
        case OpKind::Logic: {
            const Logic& l = g.logics[op.logic()];
            for (const LogicIn& in : g.logic_inputs.slice(l.in_adr, l.in_num)) rd.push_back(in.slot.v);
            slots.push_back(l.out_slot.v);
            break;
        }
        case OpKind::Router:
            rd.push_back((g.comps[op.router()].slot_adr + routerslot::query).v);
            for (Id<Route> k : t.comp_routes[op.router()]) slots.push_back(g.routes[k].out_slot.v);
            break;
        case OpKind::Label: {
            const Adr<Slot> s0 = g.comps[g.labels[op.label()].comp].slot_adr;
            rd.push_back((s0 + labelslot::set).v), slots.push_back((s0 + labelslot::value).v);
            break;
        }
        }
        writes[i] = static_cast<int32_t>(slots.size() - first);
        slots.insert(slots.end(), rd.begin(), rd.end());
        adr[i + 1] = count_of(slots);
    }
    // A group's slots (each group's walked once in each pass below).
    auto group_slots = [&g, &ag](int32_t k, auto&& fn) {
        for (const AccessTarget& x : ag.targets(g, AccessGroupId(k))) fn(x.v.v);
    };
    std::vector<uint8_t> written(ns, 0), group_written(ng, 0), group_used(ng, 0), group_counted(ng, 0);
    for (int32_t i = 0; i < n; ++i) {
        for (int32_t k = adr[i]; k < adr[i] + writes[i]; ++k) written[slots[k]] = 1;
        if (write_group[i] >= 0 && !group_written[write_group[i]]) {
            group_written[write_group[i]] = 1;
            group_slots(write_group[i], [&written](int32_t x) { written[x] = 1; });
        }
    }
    // Union-find over ops (0 .. n-1), slots (n ..) and groups (n + ns ..): an op with what it
    // writes, and with what it reads that some op writes (a slot no op writes is the same all
    // through the phase); a group with its slots that some op writes.
    std::vector<int32_t> up(n + ns + ng);
    std::iota(up.begin(), up.end(), 0);
    auto find = [&up](int32_t x) {
        while (up[x] != x) x = up[x] = up[up[x]];
        return x;
    };
    auto join = [&](int32_t x, int32_t y) {
        const int32_t a = find(x), b = find(y);
        if (a != b) up[std::max(a, b)] = std::min(a, b);
    };
    for (int32_t i = 0; i < n; ++i) {
        for (int32_t k = adr[i]; k < adr[i + 1]; ++k) {
            if (k >= adr[i] + writes[i] && !written[slots[k]]) continue;
            join(i, n + slots[k]);
        }
        for (const int32_t k : {write_group[i], read_group[i]}) {
            if (k < 0) continue;
            if (!group_used[k]) {  // 1: joined to its written slots; 2: it has none
                group_used[k] = 2;
                group_slots(k, [&](int32_t x) {
                    if (written[x]) join(n + ns + k, n + x), group_used[k] = 1;
                });
            }
            if (group_used[k] == 1) join(i, n + ns + k);
        }
    }
    // The sets (by their lowest op), largest first, each to the lane with the fewest ops.
    std::vector<int32_t> set_size(n, 0);
    for (int32_t i = 0; i < n; ++i) ++set_size[find(i)];
    std::vector<int32_t> sets;
    for (int32_t i = 0; i < n; ++i)
        if (set_size[i] > 0) sets.push_back(i);
    const int32_t lanes = std::min(Schedule::kLanes, count_of(sets));
    if (lanes < 2) return;
    std::stable_sort(sets.begin(), sets.end(), [&](int32_t a, int32_t b) { return set_size[a] > set_size[b]; });
    std::vector<int32_t> lane_of_set(n, -1), lane_size(lanes, 0);
    for (int32_t root : sets) {
        const int32_t to = std::min_element(lane_size.begin(), lane_size.end()) - lane_size.begin();
        lane_of_set[root] = to;
        lane_size[to] += set_size[root];
    }
    // Each lane's ops in program order, from a multiple of 64.
    s.lane_adr.assign(lanes + 1, 0);
    for (int32_t k = 0; k < lanes; ++k) s.lane_adr[k + 1] = s.lane_adr[k] + (lane_size[k] + 63) / 64 * 64;
    const int32_t total = s.lane_adr.back();
    s.lane_ops.assign(total, Op{OpKind::Pulse, -1, {}, {}});
    s.lane_op_pos.assign(total, -1);
    std::vector<int32_t> at(s.lane_adr.begin(), s.lane_adr.end() - 1), lane_pos(n);
    s.lane_of.assign(n, 0);
    for (int32_t i = 0; i < n; ++i) {
        const int32_t k = lane_of_set[find(i)];
        s.lane_of[i] = uint8_t(k);  // < kLanes
        lane_pos[i] = at[k]++;
        s.lane_ops[lane_pos[i]] = s.ops[i];
        s.lane_op_pos[lane_pos[i]] = i;
    }
    s.lane_always.assign(total / 64, 0);
    for (int32_t i = 0; i < n; ++i)
        if ((s.always[i / 64] >> (i % 64)) & 1) s.lane_always[lane_pos[i] / 64] |= uint64_t(1) << (lane_pos[i] % 64);
    s.lane_readers.resize(s.readers.size());
    for (size_t i = 0; i < s.readers.size(); ++i) s.lane_readers[i] = lane_pos[s.readers[i]];
    s.lane_group_readers.resize(s.group_readers.size());
    for (size_t i = 0; i < s.group_readers.size(); ++i) s.lane_group_readers[i] = lane_pos[s.group_readers[i]];
    // The slots each lane's ops can activate (every writer of a slot is in the slot's lane).
    s.lane_writes.assign(lanes, 0);
    std::vector<uint8_t> counted(ns, 0);
    for (int32_t i = 0; i < n; ++i) {
        int32_t& lane_n = s.lane_writes[lane_of_set[find(i)]];
        for (int32_t k = adr[i]; k < adr[i] + writes[i]; ++k)
            if (!counted[slots[k]]) counted[slots[k]] = 1, ++lane_n;
        if (write_group[i] >= 0 && !group_counted[write_group[i]]) {  // its slots counted once
            group_counted[write_group[i]] = 1;
            group_slots(write_group[i], [&](int32_t x) {
                if (!counted[x]) counted[x] = 1, ++lane_n;
            });
        }
    }
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
    const AccessGroups ag = access_groups(g);
    due_by_slot(g, ag, s);
    split_lanes(g, t, ag, s);
    return s;
}

}  // namespace plant::engine
