// Phase 3: the logic program (schedule.h) over this step's activity. External inputs
// and the effects of delayed flows are applied first; the inputs the components
// acted on in the previous step are cleared before that.
#include "engine/runtime.h"
#include "engine/workers.h"

#include "graph/kinds.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <climits>

namespace plant::engine {

using namespace plant::graph;

namespace {

// Where the ops' effects go. Direct: into the step's activity lists and warnings. InLane: into
// a lane's own records (schedule.h's lanes), each activation with the position of the op that
// made it, for the lists to be joined in program order after the lanes ran.
struct Direct {
    Runtime& r;
    void activate(SlotId x) { r.activate(x); }
    void activate_in(SlotId x) { r.activate_in(x); }
    void warn_null() { r.st.warn.access_null++; }
    void warn_type() { r.st.warn.access_type++; }
};
struct InLane {
    Runtime& r;
    LaneRun& lane;
    int32_t pos = 0;  // of the op running
    void activate(SlotId x) {
        if (r.flag_active(x)) (r.tab.slot_out[x] ? lane.out : lane.in).push_back({pos, x});
    }
    void activate_in(SlotId x) {
        if (r.flag_active(x)) lane.in.push_back({pos, x});
    }
    void warn_null() { ++lane.access_null; }
    void warn_type() { ++lane.access_type; }
};

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
template <class Sink>
SlotId resolve(Runtime& r, Sink& out, AccessId access, bool warn) {
    const Access& a = r.g.accesses[access];
    const DoId d(*r.val(a.ref_slot));  // a ref slot's value is a DO id
    if (!d.valid()) {
        if (warn) out.warn_null();
        return SlotId{};
    }
    if (!r.g.dos.contains(d) || r.g.dos[d].type != a.do_type || r.g.dos[d].ordinal < 0 ||
        r.g.dos[d].ordinal >= a.target_num) {
        if (warn) out.warn_type();
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

template <class Sink>
void run_flow(Runtime& r, Sink& out, FlowId f, bool delayed) {
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
            from = resolve(r, out, op.from_access, false);
            source = source || (from.valid() && act[from.v]);
        }
        if (op.to_access.valid()) to = resolve(r, out, op.to_access, false);
        const bool target = to.valid() && act[to.v];
        if (!gate(r, f, op.once, holds(op.cond, source, target))) return;
        if (!from.valid() || !to.valid()) {  // would run, but an object is missing: warn, skip
            if (op.from_access.valid() && !from.valid()) resolve(r, out, op.from_access, true);
            if (op.to_access.valid() && !to.valid()) resolve(r, out, op.to_access, true);
            if (op.once) r.st.once_held[f] = kNeverHeld;  // re-armed: it runs again next step
            return;
        }
        copy(r, r.g.slots[from].value_adr, r.g.slots[to].value_adr, op.width);
    }
    if (delayed) r.st.pending.push_back(to);
    else out.activate(to);
}

template <class Sink>
void run_connector(Runtime& r, Sink& out, LogicId i) {
    const Logic& l = r.g.logics[i];
    const bool all = l.op == LogicOp::And;
    bool v = all;
    for (const LogicIn& in : r.g.logic_inputs.slice(l.in_adr, l.in_num)) {
        const bool a = bool(r.st.act[in.slot]) != in.negated;
        v = all ? (v && a) : (v || a);
    }
    if (v) out.activate(l.out_slot);
    if (!r.st.forced_out.empty()) force_again(r, l.out_slot);
}

template <class Sink>
void run_router(Runtime& r, Sink& out, CompId comp) {
    const SlotId q = r.comp_slot(comp, routerslot::query);
    if (!r.st.act[q]) return;
    const std::string_view id = r.str(int32_t(*r.val(q)));
    for (Id<Route> k : r.tab.comp_routes[comp])
        if (glob_match(r.str(r.g.routes[k].pattern.id), id)) {
            out.activate(r.g.routes[k].out_slot);
            if (!r.st.forced_out.empty()) force_again(r, r.g.routes[k].out_slot);
            return;
        }
}

template <class Sink>
void run_label(Runtime& r, Sink& out, Id<Label> i) {
    const SlotId set = r.comp_slot(r.g.labels[i].comp, labelslot::set);
    if (!r.st.act[set]) return;
    const SlotId value = r.comp_slot(r.g.labels[i].comp, labelslot::value);
    *r.val(value) = *r.val(set);
    out.activate(value);
    if (!r.st.forced_out.empty()) force_again(r, value);
}

}  // namespace

namespace {

// Inlined into both loops of the phase (every op, the due ops): a call per op cost the logic
// bench 16 % more instructions per step than the loop of 7c4b2ca, which had it inline.
template <class Sink>
[[gnu::always_inline]] inline void run_op(Runtime& r, Sink& out, const Op& op) {
    switch (op.kind) {
    case OpKind::Flow: run_flow(r, out, op.flow(), false); break;
    case OpKind::Pulse:
        if (r.st.act[op.from]) out.activate_in(op.to);  // flows end at inputs
        break;
    case OpKind::Logic: run_connector(r, out, op.logic()); break;
    case OpKind::Router: run_router(r, out, op.router()); break;
    case OpKind::Label: run_label(r, out, op.label()); break;
    }
}

// Marks due the readers of slot x after position `ran`: `readers` and `group_readers` are the
// schedule's lists as positions in the program (`ops`) or in `lane_ops`. `kShared`: other
// threads mark the same words at the same time (an atomic or; the bits come out the same
// whatever the order).
template <bool kShared = false>
[[gnu::always_inline]] inline void mark_readers(const Schedule& sc, const int32_t* readers, const int32_t* group_readers,
                                                uint64_t* due, int32_t ran, size_t x) {
    const uint64_t word = sc.read_any[x / 64], bit = uint64_t(1) << (x % 64);
    if (!(word & bit)) return;  // read by no op
    const Schedule::ReadAt* at = sc.read_at.data() + sc.read_rank[x / 64] + std::popcount(word & (bit - 1));
    auto due_from = [due, ran](const int32_t* q, const int32_t* end) {
        for (; q != end; ++q) {
            if (*q <= ran) continue;
            const size_t p = *q;  // a position, >= 0
            if constexpr (kShared) std::atomic_ref(due[p / 64]).fetch_or(uint64_t(1) << (p % 64), std::memory_order_relaxed);
            else due[p / 64] |= uint64_t(1) << (p % 64);
        }
    };
    due_from(readers + at[0].readers, readers + at[1].readers);
    for (int32_t k = at[0].groups; k < at[1].groups; ++k) {
        const size_t group = sc.groups[k];  // >= 0
        due_from(group_readers + sc.group_reader_adr[group], group_readers + sc.group_reader_adr[group + 1]);
    }
}

// Calls f(position) for each due bit of words [first, end), lowest first, clearing it; f may
// set bits after its position (the readers of what it made active).
template <class F>
[[gnu::always_inline]] inline void each_due(uint64_t* due, size_t first, size_t end, F&& f) {
    for (size_t w = first; w < end;) {
        const uint64_t bits = due[w];
        if (!bits) {
            ++w;
            continue;
        }
        due[w] = bits & (bits - 1);
        f(w * 64 + __builtin_ctzll(bits));
    }
}

// The ops due (schedule.h), in order: a bit per op; the activity lists read from where the
// last look ended, each new active slot's readers after the op running made due.
void run_due(Runtime& r) {
    State& s = r.st;
    const Schedule& sc = r.sched;
    uint64_t* due = s.logic_due.data();
    std::copy(sc.always.begin(), sc.always.end(), due);
    Direct out{r};
    size_t out_seen = 0, in_seen = 0;
    int32_t ran = -1;  // position of the op that ran last
    auto look = [&] {
        for (; out_seen < s.out_list.size(); ++out_seen)
            mark_readers(sc, sc.readers.data(), sc.group_readers.data(), due, ran, index(s.out_list[out_seen]));
        for (; in_seen < s.in_list.size(); ++in_seen)
            mark_readers(sc, sc.readers.data(), sc.group_readers.data(), due, ran, index(s.in_list[in_seen]));
    };
    look();
    each_due(due, 0, sc.always.size(), [&](size_t at) {
        ran = static_cast<int32_t>(at);
        run_op(r, out, sc.ops[at]);
        look();
    });
}

// Lane k's ops due, as run_due runs the program's, on one of the physics threads: its due bits
// are words of its own, and it looks only at what its own ops activate (whose readers are all
// in the lane: schedule.h).
void run_lane(Runtime& r, size_t k) {
    const Schedule& sc = r.sched;
    LaneRun& lane = r.st.lane_runs[k];
    lane.out.clear();
    lane.in.clear();
    lane.access_null = lane.access_type = 0;
    uint64_t* due = r.st.lane_due.data();
    // The ops due always join what the marking made due (the lane's words are all clear when
    // its run ends: each_due clears every bit it visits, and an op marks only later ones).
    for (size_t w = size_t(sc.lane_adr[k]) / 64; w < size_t(sc.lane_adr[k + 1]) / 64; ++w) due[w] |= sc.lane_always[w];
    InLane out{r, lane};
    size_t out_seen = 0, in_seen = 0;
    int32_t ran = -1;  // position in lane_ops of the op that ran last
    auto look = [&] {
        for (; out_seen < lane.out.size(); ++out_seen)
            mark_readers(sc, sc.lane_readers.data(), sc.lane_group_readers.data(), due, ran, index(lane.out[out_seen].slot));
        for (; in_seen < lane.in.size(); ++in_seen)
            mark_readers(sc, sc.lane_readers.data(), sc.lane_group_readers.data(), due, ran, index(lane.in[in_seen].slot));
    };
    each_due(due, sc.lane_adr[k] / 64, sc.lane_adr[k + 1] / 64, [&](size_t at) {
        ran = static_cast<int32_t>(at);
        out.pos = sc.lane_op_pos[at];
        run_op(r, out, sc.lane_ops[at]);
        look();
    });
}

// What the lanes activated, appended to the step's two lists in program order (each lane's
// records are in it already; an op's own, in the order it made them). In slices of the
// program's positions (whole words of the bitmap below) on the physics threads: where each
// slice's records begin in each lane's two lists is found by bisection (they are in position
// order), so where its part of each step's list begins; each slice marks the positions of its
// ops that made a record in a bitmap of the program, reads it in order, and takes each
// position's records from its lane's lists where that lane's reading stands, into its part.
void join_lanes(Runtime& r) {
    State& s = r.st;
    const size_t lanes = s.lane_runs.size();
    size_t first = s.lane_made.size(), end = 0, total = 0;  // the words marked
    for (const LaneRun& l : s.lane_runs) {
        for (const auto* list : {&l.out, &l.in}) {
            if (list->empty()) continue;
            first = std::min(first, size_t(list->front().pos) / 64);
            end = std::max(end, size_t(list->back().pos) / 64 + 1);
            total += list->size();
        }
    }
    if (total == 0) return;
    const size_t words = end - first, slices = std::min(slice_count(total, 128, kMaxSlices), words);
    // Row i: where slice i's records begin in each lane's out and in lists (row `slices`: their ends).
    size_t* const at = s.join_at.data();
    auto row = [at, lanes](size_t i, size_t k, size_t list) -> size_t& { return at[(i * lanes + k) * 2 + list]; };
    for (size_t i = 0; i <= slices; ++i) {
        const int32_t from = int32_t((first + slice_of(words, slices, i).first) * 64);
        for (size_t k = 0; k < lanes; ++k) {
            const LaneRun& l = s.lane_runs[k];
            auto begin = [from](const std::vector<LaneRec>& v) {
                return size_t(std::partition_point(v.begin(), v.end(), [from](const LaneRec& x) { return x.pos < from; }) -
                              v.begin());
            };
            row(i, k, 0) = begin(l.out);
            row(i, k, 1) = begin(l.in);
        }
    }
    // Where each slice's part of the two lists begins.
    std::array<size_t, kMaxSlices * 2> into;  // [slice * 2 + list]
    size_t out_n = s.out_list.size(), in_n = s.in_list.size();
    for (size_t i = 0; i < slices; ++i) {
        into[i * 2] = out_n;
        into[i * 2 + 1] = in_n;
        for (size_t k = 0; k < lanes; ++k) {
            out_n += row(i + 1, k, 0) - row(i, k, 0);
            in_n += row(i + 1, k, 1) - row(i, k, 1);
        }
    }
    s.out_list.resize(out_n);  // within their room (reserved for every slot)
    s.in_list.resize(in_n);
    auto joining = [&r, &row, &into, lanes, first, words, slices](int i) {
        State& st = r.st;
        const Schedule& sc = r.sched;
        uint64_t* made = st.lane_made.data();
        const auto [w0, w1] = slice_of(words, slices, size_t(i));
        std::array<size_t, Schedule::kLanes> out_at{}, in_at{};
        for (size_t k = 0; k < lanes; ++k) {
            const LaneRun& l = st.lane_runs[k];
            out_at[k] = row(size_t(i), k, 0);
            in_at[k] = row(size_t(i), k, 1);
            for (size_t j = out_at[k]; j < row(size_t(i) + 1, k, 0); ++j)
                made[size_t(l.out[j].pos) / 64] |= uint64_t(1) << (l.out[j].pos % 64);
            for (size_t j = in_at[k]; j < row(size_t(i) + 1, k, 1); ++j)
                made[size_t(l.in[j].pos) / 64] |= uint64_t(1) << (l.in[j].pos % 64);
        }
        size_t o = into[size_t(i) * 2], n = into[size_t(i) * 2 + 1];
        // The positions a chunk at a time, each one's lane asked for as it is found and read once
        // the chunk is full: the positions lie far apart in the program (a few hundred in tens of
        // thousands), so each lane number is a miss of its own, and the misses of a chunk overlap.
        std::array<uint32_t, 64> chunk;
        size_t got = 0;
        auto take = [&] {
            for (size_t c = 0; c < got; ++c) {
                const size_t pos = chunk[c], k = sc.lane_of[pos];
                const LaneRun& l = st.lane_runs[k];
                for (size_t& j = out_at[k]; j < l.out.size() && size_t(l.out[j].pos) == pos; ++j) st.out_list[o++] = l.out[j].slot;
                for (size_t& j = in_at[k]; j < l.in.size() && size_t(l.in[j].pos) == pos; ++j) st.in_list[n++] = l.in[j].slot;
            }
            got = 0;
        };
        each_due(made, first + w0, first + w1, [&](size_t pos) {
            __builtin_prefetch(&sc.lane_of[pos]);
            chunk[got++] = uint32_t(pos);
            if (got == chunk.size()) take();
        });
        take();
    };
    run_slices(r.phys.workers(), slices, joining);
}

// The program in lanes on the physics threads: the readers of the activity at the phase's
// start made due in whichever lanes they are, the lanes run, their records joined.
void run_lanes(Runtime& r) {
    State& s = r.st;
    const Schedule& sc = r.sched;
    uint64_t* due = s.lane_due.data();  // all clear (run_lane); each lane adds its ops due always
    // The readers of what is active at the phase's start, in slices of the two lists on the
    // physics threads (the job's end orders the marks before the lanes read them).
    const size_t n_out = s.out_list.size(), n = n_out + s.in_list.size();
    const size_t slices = slice_count(n, 64, kMaxSlices);
    auto marking = [&s, &sc, due, n, n_out, slices](int i) {
        const auto [b, e] = slice_of(n, slices, i);
        for (size_t k = b; k < e; ++k) {
            const SlotId x = k < n_out ? s.out_list[k] : s.in_list[k - n_out];
            mark_readers<true>(sc, sc.lane_readers.data(), sc.lane_group_readers.data(), due, -1, index(x));
        }
    };
    run_slices(r.phys.workers(), slices, marking);
    auto lane = [&r](int k) { run_lane(r, k); };
    r.phys.workers().run(int(sc.lanes()), lane);
    join_lanes(r);
    for (const LaneRun& l : s.lane_runs) s.warn.access_null += l.access_null, s.warn.access_type += l.access_type;
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
    // one of speed only; so is running the program in lanes (with more than one thread).
    const bool dense = s.out_list.size() + s.in_list.size() >= r.sched.dense_at;
    Direct out{r};
    if (s.forced_out.empty() && !r.logic_every_node && !dense) {
        if (s.lane_runs.empty()) run_due(r);
        else run_lanes(r);
    } else {
        for (const Op& op : r.sched.ops) run_op(r, out, op);
    }
    for (FlowId f : r.sched.delayed) run_flow(r, out, f, true);
    forces_logic_end(r);
}

}  // namespace plant::engine
