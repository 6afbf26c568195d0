// Phase 3: the logic program (schedule.h) over this step's activity. External inputs
// and the effects of delayed flows are applied first; the inputs the components
// acted on in the previous step are cleared before that.
#include "engine/runtime.h"

#include "graph/kinds.h"

#include <algorithm>

namespace plant::engine {

using namespace plant::graph;

namespace {

bool holds(Cond c, bool source, bool target) {
    switch (c) {
    case Cond::Source: return source;
    case Cond::Target: return target;
    case Cond::Both: return source && target;
    case Cond::Either: return source || target;
    }
    return false;
}

// The slot a dynamic end names now: the access target for the ordinal, among its
// type, of the object held in the reference slot; -1 (and a warning) if none.
SlotId resolve(Runtime& r, AccessId access, bool warn) {
    const Access& a = r.g.accesses[access];
    const DoId d(*r.val(a.ref_slot));  // a ref slot's value is a DO id
    if (!d.valid()) {
        if (warn) r.st.warn.access_null++;
        return SlotId{};
    }
    if (!r.g.dos.contains(d) || r.g.dos[d].type != a.do_type || r.g.dos[d].ordinal < 0 ||
        r.g.dos[d].ordinal >= a.target_num) {
        if (warn) r.st.warn.access_type++;
        return SlotId{};
    }
    return r.g.access_targets[a.target_adr + r.g.dos[d].ordinal].v;
}

void copy(Runtime& r, Adr<Value> from, Adr<Value> to, int32_t width) {
    if (width <= 0 || !from.valid() || !to.valid()) return;
    double* v = r.st.values.data();
    for (int32_t i = 0; i < width; ++i) v[to.v + i] = v[from.v + i];
}

// A singular flow runs once when its condition holds, and is re-armed by a step in
// which its condition does not hold: it runs in a step whose condition holds when it did
// not hold in the step before. Kept as the last step it held, so a step in which the flow is
// not due (its condition cannot hold) needs no visit.
bool gate(Runtime& r, FlowId f, bool once, bool ok) {
    if (!once || !ok) return ok;
    int64_t& held = r.st.once_held[f];
    const bool runs = held != r.st.step - 1;
    held = r.st.step;
    return runs;
}

void run_flow(Runtime& r, FlowId f, bool delayed) {
    const FlowOp& op = r.sched.flows[f];
    const uint8_t* act = r.st.act.data();  // by slot number: the hot path reads it directly
    SlotId to = op.to;
    if (!op.from_access.valid() && !op.to_access.valid()) {  // the common, static case
        if (!gate(r, f, op.once, holds(op.cond, act[op.from.v], act[to.v]))) return;
        copy(r, op.from_val, op.to_val, op.width);
    } else {
        // A dynamic source is active when the reference was (re)published this step
        // or the referenced slot is active: "the object the trigger just saw".
        SlotId from = op.from;
        bool source = act[from.v];
        if (op.from_access.valid()) {
            from = resolve(r, op.from_access, false);
            source = source || (from.valid() && act[from.v]);
        }
        if (op.to_access.valid()) to = resolve(r, op.to_access, false);
        const bool target = to.valid() && act[to.v];
        if (!gate(r, f, op.once, holds(op.cond, source, target))) return;
        if (!from.valid() || !to.valid()) {  // would run, but an object is missing: warn, skip
            if (op.from_access.valid() && !from.valid()) resolve(r, op.from_access, true);
            if (op.to_access.valid() && !to.valid()) resolve(r, op.to_access, true);
            if (op.once) r.st.once_held[f] = kNeverHeld;  // re-armed: it runs again next step
            return;
        }
        copy(r, r.g.slots[from].value_adr, r.g.slots[to].value_adr, op.width);
    }
    if (delayed) r.st.pending.push_back(to);
    else r.activate(to);
}

void run_connector(Runtime& r, LogicId i) {
    const Logic& l = r.g.logics[i];
    const bool all = l.op == LogicOp::And;
    bool v = all;
    for (const LogicIn& in : r.g.logic_inputs.slice(l.in_adr, l.in_num)) {
        const bool a = bool(r.st.act[in.slot]) != in.negated;
        v = all ? (v && a) : (v || a);
    }
    if (v) r.activate(l.out_slot);
    if (!r.st.forced_out.empty()) force_again(r, l.out_slot);
}

void run_router(Runtime& r, CompId comp) {
    const SlotId q = r.comp_slot(comp, routerslot::query);
    if (!r.st.act[q]) return;
    const std::string_view id = r.str(int32_t(*r.val(q)));
    for (Id<Route> k : r.tab.comp_routes[comp])
        if (glob_match(r.str(r.g.routes[k].pattern.id), id)) {
            r.activate(r.g.routes[k].out_slot);
            if (!r.st.forced_out.empty()) force_again(r, r.g.routes[k].out_slot);
            return;
        }
}

void run_label(Runtime& r, Id<Label> i) {
    const SlotId set = r.comp_slot(r.g.labels[i].comp, labelslot::set);
    if (!r.st.act[set]) return;
    const SlotId out = r.comp_slot(r.g.labels[i].comp, labelslot::value);
    r.emit(out, *r.val(set));
    if (!r.st.forced_out.empty()) force_again(r, out);
}

}  // namespace

namespace {

// Inlined into both loops of the phase (every op, the due ops): a call per op cost the logic
// bench 16 % more instructions per step than the loop of 7c4b2ca, which had it inline.
[[gnu::always_inline]] inline void run_op(Runtime& r, const Op& op) {
    switch (op.kind) {
    case OpKind::Flow: run_flow(r, op.flow(), false); break;
    case OpKind::Pulse:
        if (r.st.act[op.from]) r.activate_in(op.to);  // flows end at inputs
        break;
    case OpKind::Logic: run_connector(r, op.logic()); break;
    case OpKind::Router: run_router(r, op.router()); break;
    case OpKind::Label: run_label(r, op.label()); break;
    }
}

// The ops due (schedule.h), in order: a bit per op; the activity lists read from where the
// last look ended, each new active slot's readers after the op running made due.
void run_due(Runtime& r) {
    State& s = r.st;
    const Schedule& sc = r.sched;
    uint64_t* due = s.logic_due.data();
    std::copy(sc.always.begin(), sc.always.end(), due);
    size_t out_seen = 0, in_seen = 0;
    int32_t ran = -1;  // position of the op that ran last
    auto look = [&] {
        auto due_from = [&](const int32_t* q, const int32_t* end) {
            for (; q != end; ++q) {
                if (*q <= ran) continue;
                const size_t p = *q;  // a position, >= 0
                due[p / 64] |= uint64_t(1) << (p % 64);
            }
        };
        auto mark = [&](size_t x) {  // a slot (>= 0)
            due_from(sc.readers.data() + sc.reader_adr[x], sc.readers.data() + sc.reader_adr[x + 1]);
            for (int32_t k = sc.group_adr[x]; k < sc.group_adr[x + 1]; ++k) {
                const size_t group = sc.groups[k];  // >= 0
                due_from(sc.group_readers.data() + sc.group_reader_adr[group],
                         sc.group_readers.data() + sc.group_reader_adr[group + 1]);
            }
        };
        for (; out_seen < s.out_list.size(); ++out_seen) mark(index(s.out_list[out_seen]));
        for (; in_seen < s.in_list.size(); ++in_seen) mark(index(s.in_list[in_seen]));
    };
    look();
    const size_t words = sc.always.size();
    for (size_t w = 0; w < words;) {
        const uint64_t bits = due[w];
        if (!bits) {
            ++w;
            continue;
        }
        due[w] = bits & (bits - 1);
        const size_t at = w * 64 + __builtin_ctzll(bits);
        ran = static_cast<int32_t>(at);
        run_op(r, sc.ops[at]);
        look();
    }
}

}  // namespace

void phase_logic(Runtime& r) {
    State& s = r.st;
    for (SlotId x : s.in_list) s.act[x] = 0;
    s.in_list.clear();
    for (SlotId x : s.pending) r.activate(x);
    s.pending.clear();
    forces_logic_begin(r);
    // Many slots active: most ops are due anyway, and all run (schedule.h, `dense_at`). A step
    // computes the same activity and values either way (logic_due_test), so the choice is
    // one of speed only.
    const bool dense = s.out_list.size() + s.in_list.size() >= r.sched.dense_at;
    if (s.forced_out.empty() && !r.logic_every_node && !dense) {
        run_due(r);
    } else {
        for (const Op& op : r.sched.ops) run_op(r, op);
    }
    for (FlowId f : r.sched.delayed) run_flow(r, f, true);
    forces_logic_end(r);
}

}  // namespace plant::engine
