// Phase 2: what the world looks like after the physics step, as output activity:
// bodies (outputs, and warnings for bodies that left the world), graphics poses and
// animations, triggers, timers, grippers carrying their objects, exits.
#include "engine/runtime.h"

#include "graph/kinds.h"

#include <cmath>

namespace plant::engine {

using namespace plant::graph;

namespace {

bool finite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// An object that falls off the plant or blows up is taken out, all its bodies, once,
// with one warning.
void check_bodies(Runtime& r) {
    for (int32_t b : r.tab.dyn_bodies) {
        if (!r.phys.in_world(b) || r.st.gone[b]) continue;
        const btRigidBody& rb = r.phys.rb(b);
        const btVector3& p = rb.getWorldTransform().getOrigin();
        const bool nan = !finite(p) || !finite(rb.getLinearVelocity()) || !finite(rb.getAngularVelocity());
        if (!nan && p.z() >= -10 && p.length2() <= 1e6) continue;
        (nan ? r.st.warn.nan_state : r.st.warn.left_world)++;
        const int32_t d = r.tab.body_do[b];
        if (r.st.lost_at[d] < 0) r.st.lost_at[d] = r.st.time;
        for (const int32_t* x = r.tab.do_bodies.begin(d); x != r.tab.do_bodies.end(d); ++x) {
            if (r.st.gone[*x]) continue;
            r.st.gone[*x] = 1;
            if (r.phys.in_world(*x)) take_body_out(r, *x);
        }
    }
}

void body_outputs(Runtime& r) {
    for (int32_t b : r.st.observed_bodies) {
        if (!r.phys.in_world(b)) continue;
        const uint8_t bits = r.st.body_outputs[b];
        const int32_t s0 = r.comp_slot(r.g.bodies[b].comp, bodyslot::pose);
        if (bits & 7) {
            const Pose p = r.phys.pose(b);
            if (bits & 1) r.emit_pose(s0, p);
            if (bits & 2) {
                double* v = r.val(s0 + 1);
                for (int i = 0; i < 3; ++i) v[i] = p.p[i];
                r.activate(s0 + 1);
            }
            if (bits & 4) {
                double* v = r.val(s0 + 2);
                for (int i = 0; i < 4; ++i) v[i] = p.q[i];
                r.activate(s0 + 2);
            }
        }
        for (int k = 3; k < 5; ++k) {
            if (!(bits & (1u << k))) continue;
            const btVector3 v = k == 3 ? r.phys.velocity(b) : r.phys.angular_velocity(b);
            double* out = r.val(s0 + k);
            out[0] = v.x();
            out[1] = v.y();
            out[2] = v.z();
            r.activate(s0 + k);
        }
    }
}

// Ticks at n·dt >= deadline: counting steps, not adding dt, so periods do not drift.
void run_timers(Runtime& r) {
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

}  // namespace

void take_body_out(Runtime& r, int32_t b) {
    int32_t gr = r.st.held_by[b];
    r.st.held_by[b] = -1;
    if (gr >= 0) {  // a gripper loses what it held when it is taken away
        bool any = false;
        for (const int32_t* x = r.tab.do_bodies.begin(r.st.gripper_held[gr]);
             x != r.tab.do_bodies.end(r.st.gripper_held[gr]); ++x)
            any = any || r.st.held_by[*x] == gr;
        if (!any) r.st.gripper_held[gr] = -1;
    }
    r.st.cmd_lin[b] = Vec3{0, 0, 0};
    r.st.cmd_ang[b] = Vec3{0, 0, 0};
    r.phys.take_out(b);
}

void phase_sensors(Runtime& r) {
    check_bodies(r);
    body_outputs(r);
    advance_graphics(r);
    sense_triggers(r);
    run_timers(r);
    follow_grippers(r);
    run_exits(r);
    sense_plugins(r);
}

}  // namespace plant::engine
