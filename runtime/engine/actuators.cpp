// Phase 5: components act on their active inputs, in component id order, each
// reading its inputs in a fixed order: what switches something off before what
// switches it on (so "on" wins when both are active), modes before poses and
// velocities. Then sources with a rate issue.
#include "engine/runtime.h"

#include "graph/kinds.h"

#include <algorithm>

namespace plant::engine {

using namespace plant::graph;

namespace {

void act_body(Runtime& r, const Comp& c, int32_t b) {
    const uint8_t* a = r.st.act.data() + c.slot_adr;
    Physics& ph = r.phys;
    const bool held = r.st.held_by[b] >= 0;  // a gripper owns its mode and pose
    if (a[bodyslot::collision_off]) ph.set_collision(b, false);
    if (a[bodyslot::collision_on]) ph.set_collision(b, true);
    if (!held && a[bodyslot::dynamics_off]) ph.set_dynamics(b, false);
    if (!held && a[bodyslot::dynamics_on]) ph.set_dynamics(b, true);
    if (!held && (a[bodyslot::set_pose] || a[bodyslot::set_position] || a[bodyslot::set_orientation])) {
        btTransform f = ph.frame(b);
        if (a[bodyslot::set_pose]) {
            const double* v = r.val(c.slot_adr + bodyslot::set_pose);
            f = to_bt(Pose{{v[0], v[1], v[2]}, qnormalized({v[3], v[4], v[5], v[6]})});
        }
        if (a[bodyslot::set_position]) {
            const double* v = r.val(c.slot_adr + bodyslot::set_position);
            f.setOrigin(to_bt(Vec3{v[0], v[1], v[2]}));
        }
        if (a[bodyslot::set_orientation]) {
            const double* v = r.val(c.slot_adr + bodyslot::set_orientation);
            f.setRotation(to_bt(qnormalized({v[0], v[1], v[2], v[3]})));
        }
        // Dynamic and static bodies jump; a kinematic one travels there during the
        // next physics step, so what it pushes sees its speed.
        if (ph.declared_dynamic(b) ? ph.dynamics_on(b) : r.g.bodies[b].mode == BodyMode::Static) ph.place(b, f);
        else ph.move(b, f);
        ph.rb(b).activate();
    }
    for (int k = 0; k < 2; ++k) {
        const int slot = k == 0 ? bodyslot::set_velocity : bodyslot::set_angular_velocity;
        if (held || !a[slot]) continue;
        const double* v = r.val(c.slot_adr + slot);
        const Vec3 vel{v[0], v[1], v[2]};
        if (ph.dynamic_now(b)) {
            btRigidBody& rb = ph.write(b);
            if (k == 0) rb.setLinearVelocity(to_bt(vel));
            else rb.setAngularVelocity(to_bt(vel));
            rb.activate();
        } else {
            (k == 0 ? r.st.cmd_lin : r.st.cmd_ang)[b] = vel;  // kinematic: we move it
            if (!r.st.is_commanded[b]) {
                r.st.is_commanded[b] = 1;
                r.st.commanded.push_back(b);
            }
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

void act_on(Runtime& r, int32_t comp) {
    const Comp& c = r.g.comps[comp];
    const uint8_t* a = r.st.act.data() + c.slot_adr;
    const int32_t i = c.detail;
    switch (c.kind) {
    case CompKind::Body: act_body(r, c, i); break;
    case CompKind::Field:
        if (a[fieldslot::disable]) r.st.field_on[i] = 0;
        if (a[fieldslot::enable]) r.st.field_on[i] = 1;
        if (a[fieldslot::set_speed]) {
            r.st.field_speed[i] = *r.val(c.slot_adr + fieldslot::set_speed);
            r.emit(c.slot_adr + fieldslot::speed, r.st.field_speed[i]);
        }
        break;
    case CompKind::Constraint:
        if (a[jointslot::disable]) r.phys.set_joint(i, false);
        if (a[jointslot::enable]) r.phys.set_joint(i, true);
        r.emit(c.slot_adr + jointslot::enabled, r.phys.joint_on(i) ? 1 : 0);
        break;
    case CompKind::Timer: act_timer(r, c, i); break;
    case CompKind::Graphics:
        if (a[graphicsslot::set_pose]) {
            const double* v = r.val(c.slot_adr + graphicsslot::set_pose);
            r.st.graphics[i].base = Pose{{v[0], v[1], v[2]}, qnormalized({v[3], v[4], v[5], v[6]})};
            r.st.graphics[i].base_fresh = false;
        }
        for (int32_t x = c.slot_adr + graphicsslot::count; x < c.slot_adr + c.slot_num; ++x) {
            const int32_t aux = r.tab.slot_aux[x];
            if (!r.st.act[x] || aux < 0) continue;
            if (size_t(aux) < r.g.animations.size() && r.g.animations[aux].play_slot == x) play_animation(r, aux);
            else if (size_t(aux) < r.g.variants.size() && r.g.variants[aux].select_slot == x) select_variant(r, aux);
        }
        break;
    case CompKind::Source:
        if (a[sourceslot::issue]) issue(r, i);
        break;
    case CompKind::Gripper:
        if (a[gripperslot::release]) release(r, i);
        if (a[gripperslot::grip]) grip(r, i);
        break;
    case CompKind::Plugin: act_plugin(r, i); break;
    default: break;  // state: phase 4; router, logic, label: phase 3; the rest has no inputs
    }
}

}  // namespace

void phase_actuators(Runtime& r) {
    State& s = r.st;
    s.comp_list.clear();
    for (int32_t x : s.in_list) {
        if (!r.tab.slot_acts[x]) continue;
        const int32_t c = r.g.slots[x].comp;
        if (s.comp_mark[c]) continue;
        s.comp_mark[c] = 1;
        s.comp_list.push_back(c);
    }
    std::sort(s.comp_list.begin(), s.comp_list.end());
    for (int32_t c : s.comp_list) {
        s.comp_mark[c] = 0;
        act_on(r, c);
    }
    for (int32_t src : r.tab.rate_sources) {
        SourceState& ss = s.sources[src];
        if (s.time + 1e-9 < ss.next_issue) continue;
        ss.next_issue += 1.0 / r.g.sources[src].rate;
        issue(r, src);
    }
}

}  // namespace plant::engine
