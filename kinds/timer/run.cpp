// The timer's behaviour: its state, `running` published at the start, its ticks in phase 2,
// start and stop in phase 5.
#include "engine/plugin.h"
#include "engine/runtime.h"

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

struct Timers : KindData {
    graph::IdVector<TimerId, Run> run;                     // per row of `timers`
    graph::IdVector<TimerId, graph::Adr<graph::Slot>> s0;  // the first slot of each timer's component
};

std::unique_ptr<KindData> make_state(const graph::Graph& g) {
    auto t = std::make_unique<Timers>();
    t->run.resize(g.timers.size());  // running from the start: start_all
    for (const graph::Timer& tm : g.timers) t->s0.push_back(g.comps[tm.comp].slot_adr);
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

// Ticks at n·dt >= deadline: counting steps, not adding dt, so periods do not drift.
void sense_all(Runtime& r) {
    Timers& t = timers(r);
    for (TimerId i : ids_of(r.g.timers)) {
        Run& ts = t.run[i];
        if (!ts.running) continue;
        const graph::Adr<graph::Slot> s0 = t.s0[i];
        ts.n++;
        const double elapsed = double(ts.n) * r.dt;
        // Only a read or watched `elapsed` is made active: most timers just tick.
        if (r.st.watched[s0 + graph::timerslot::elapsed]) r.emit(s0 + graph::timerslot::elapsed, elapsed);
        else *r.val(s0 + graph::timerslot::elapsed) = elapsed;
        if (elapsed + 1e-9 < ts.deadline) continue;
        r.activate(s0 + graph::timerslot::tick);
        const graph::Timer& tm = r.g.timers[i];
        if (tm.periodic) {
            ts.deadline += tm.period;
        } else {
            ts.running = false;
            r.emit(s0 + graph::timerslot::running, 0);
        }
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
    .make_state = make_state, .start_all = start_all, .sense_all = sense_all, .act_one = act_one};

}  // namespace plant::kinds::timer
