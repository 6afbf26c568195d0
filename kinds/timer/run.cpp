// The timer's behaviour: its state, `running` published at the start, its ticks in phase 2,
// start and stop in phase 5.
#include "engine/plugin.h"
#include "engine/runtime.h"
#include "engine/workers.h"

#include "graph/kinds.h"

#include <memory>
#include <vector>

namespace plant::kinds::timer {

using namespace plant::engine;
using graph::CompKind;

namespace {

struct Run {
    bool running = false;
    int64_t n = 0;        // steps since start
    double deadline = 0;  // next tick, seconds since start
};

using TimerId = graph::Id<graph::Timer>;

// What a timer's step makes active (sense_all): its `elapsed` (when watched), `tick`,
// `running` (a one-shot that ended).
enum : uint8_t { kElapsed = 1, kTick = 2, kStopped = 4 };

struct Timers : KindData {
    graph::IdVector<TimerId, Run> run;                     // per row of `timers`
    graph::IdVector<TimerId, graph::Adr<graph::Slot>> s0;  // the first slot of each timer's component
    graph::IdVector<TimerId, uint8_t> made;                // this step's kElapsed, kTick, kStopped
    // The timers that made any, each slice's from its own first timer on, and how many.
    std::vector<TimerId> made_by_slice;
    std::vector<size_t> slice_made;
};

std::unique_ptr<KindData> make_state(const graph::Graph& g) {
    auto t = std::make_unique<Timers>();
    t->run.resize(g.timers.size());  // running from the start: start_all
    for (const graph::Timer& tm : g.timers) t->s0.push_back(g.comps[tm.comp].slot_adr);
    t->made.resize(g.timers.size());
    t->made_by_slice.resize(g.timers.size());
    t->slice_made.resize(kMaxSlices);
    return t;
}

Timers& timers(Runtime& r) { return kind_data<Timers>(r.st, CompKind::Timer); }

// Autostarting timers run from the first step; `running` is published once.
void start_all(Runtime& r) {
    Timers& t = timers(r);
    for (TimerId i : ids_of(r.g.timers)) {
        if (r.g.timers[i].autostart) t.run[i] = {true, 0, r.g.timers[i].period};
        r.emit(t.s0[i] + graph::timerslot::running, t.run[i].running ? 1 : 0);
    }
}

// Timer i's step. It ticks at n·dt >= deadline: counting steps, not adding dt, so periods do
// not drift. It writes only its own state and its own slots' values. kDefer: what it makes
// active is flagged here (its own slots: Runtime::flag_active) and returned, to be listed
// after the job in timer order (on a physics thread); else made active here.
template <bool kDefer>
[[gnu::always_inline]] inline uint8_t tick(Runtime& r, Timers& t, TimerId i) {
    Run& ts = t.run[i];
    if (!ts.running) return 0;
    const graph::Adr<graph::Slot> s0 = t.s0[i];
    uint8_t made = 0;
    auto make_active = [&r, &made](graph::SlotId x, uint8_t bit) {
        if constexpr (kDefer) made |= r.flag_active(x) ? bit : 0;
        else r.activate(x);
    };
    ts.n++;
    const double elapsed = double(ts.n) * r.dt;
    // Only a read or watched `elapsed` is made active: most timers just tick.
    *r.val(s0 + graph::timerslot::elapsed) = elapsed;
    if (r.st.watched[s0 + graph::timerslot::elapsed]) make_active(s0 + graph::timerslot::elapsed, kElapsed);
    if (elapsed + 1e-9 < ts.deadline) return made;
    make_active(s0 + graph::timerslot::tick, kTick);
    const graph::Timer& tm = r.g.timers[i];
    if (tm.periodic) {
        ts.deadline += tm.period;
    } else {
        ts.running = false;
        *r.val(s0 + graph::timerslot::running) = 0;
        make_active(s0 + graph::timerslot::running, kStopped);
    }
    return made;
}

// What tick<true> flagged, into the step's list of active outputs (a timer's slots are outputs).
void activate(Runtime& r, const Timers& t, TimerId i, uint8_t made) {
    const graph::Adr<graph::Slot> s0 = t.s0[i];
    if (made & kElapsed) r.st.out_list.push_back(s0 + graph::timerslot::elapsed);
    if (made & kTick) r.st.out_list.push_back(s0 + graph::timerslot::tick);
    if (made & kStopped) r.st.out_list.push_back(s0 + graph::timerslot::running);
}

void sense_all(Runtime& r) {
    Timers& t = timers(r);
    Workers& w = r.phys.workers();
    const size_t n = r.g.timers.size();
    const size_t slices = slice_count(n, 256, n + 1);
    if (w.threads() == 1 || slices <= 1) {  // one pass, on this thread
        for (TimerId i : ids_of(r.g.timers)) tick<false>(r, t, i);
        return;
    }
    auto ticking = [&r, &t, n, slices](int k) {
        const size_t first = slice_of(n, slices, size_t(k)).first;
        size_t m = 0;
        for (TimerId i : slice_ids<TimerId>(n, slices, k))
            if ((t.made[i] = tick<true>(r, t, i)) != 0) t.made_by_slice[first + m++] = i;
        t.slice_made[size_t(k)] = m;
    };
    w.run(int(slices), ticking);
    for (size_t k = 0; k < slices; ++k) {  // in timer order
        const size_t first = slice_of(n, slices, k).first;
        for (size_t j = first; j < first + t.slice_made[k]; ++j) activate(r, t, t.made_by_slice[j], t.made[t.made_by_slice[j]]);
    }
}

void act_one(Runtime& r, const graph::Comp& c) {
    const TimerId i = graph::detail_of<graph::Timer>(c);
    const uint8_t* a = r.st.act.slice(c.slot_adr, c.slot_num).data();
    Run& ts = timers(r).run[i];
    const bool was = ts.running;
    if (a[graph::timerslot::stop]) ts.running = false;
    if (a[graph::timerslot::start]) ts = {true, 0, r.g.timers[i].period};
    if (ts.running != was) r.emit(c.slot_adr + graph::timerslot::running, ts.running ? 1 : 0);
}

}  // namespace

constexpr KindBehaviour behaviour{
    .make_state = make_state, .start_all = start_all, .sense_all = sense_all, .act_one = act_one,
    .acts_off_physics = true};  // its own run and its outputs

}  // namespace plant::kinds::timer
