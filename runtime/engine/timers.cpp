// A timer's behaviour: its state at the start, its ticks in phase 2, start and stop in
// phase 5.
#include "engine/runtime.h"

#include "graph/kinds.h"

namespace plant::engine {

using namespace plant::graph;

// Autostarting timers run from the first step; `running` is published once.
void start_timers(Runtime& r) {
    for (size_t i = 0; i < r.g.timers.size(); ++i) {
        if (r.g.timers[i].autostart) r.st.timers[i] = {true, 0, r.g.timers[i].period};
        r.emit(r.comp_slot(r.g.timers[i].comp, timerslot::running), r.st.timers[i].running ? 1 : 0);
    }
}

// Ticks at n·dt >= deadline: counting steps, not adding dt, so periods do not drift.
void sense_timers(Runtime& r) {
    for (size_t i = 0; i < r.g.timers.size(); ++i) {
        TimerState& ts = r.st.timers[i];
        if (!ts.running) continue;
        const int32_t s0 = r.tab.timer_slots[i];
        ts.n++;
        const double elapsed = double(ts.n) * r.dt;
        // Only a read or watched `elapsed` is made active: most timers just tick.
        if (r.st.watched[s0 + timerslot::elapsed]) r.emit(s0 + timerslot::elapsed, elapsed);
        else *r.val(s0 + timerslot::elapsed) = elapsed;
        if (elapsed + 1e-9 < ts.deadline) continue;
        r.activate(s0 + timerslot::tick);
        const Timer& tm = r.g.timers[i];
        if (tm.periodic) {
            ts.deadline += tm.period;
        } else {
            ts.running = false;
            r.emit(s0 + timerslot::running, 0);
        }
    }
}

void act_timer(Runtime& r, const Comp& c, int32_t i) {
    const uint8_t* a = r.st.act.data() + c.slot_adr;
    TimerState& ts = r.st.timers[i];
    const bool was = ts.running;
    if (a[timerslot::stop]) ts.running = false;
    if (a[timerslot::start]) ts = {true, 0, r.g.timers[i].period};
    if (ts.running != was) r.emit(c.slot_adr + timerslot::running, ts.running ? 1 : 0);
}

}  // namespace plant::engine
