// The gripper's behaviour: its `object` starts empty; in phase 2 what it holds follows it;
// in phase 5 it releases and grips. What it holds (State::gripper_held, held_by, grip_rel)
// is shared with the bodies (engine/bodies.cpp: a held body that leaves the world).
#include "engine/plugin.h"
#include "engine/runtime.h"
#include "engine/workers.h"

#include "graph/kinds.h"

namespace plant::kinds::gripper {

using namespace plant::engine;
namespace slot = plant::graph::gripperslot;

namespace {

btTransform gripper_frame(const Runtime& r, const graph::Gripper& gr) {
    if (gr.body.valid()) return r.phys.frame(gr.body);
    if (gr.graphics.valid()) return to_bt(r.st.graphics[gr.graphics].pose);
    return btTransform::getIdentity();
}

void grip(Runtime& r, graph::GripperId i) {
    const graph::Gripper& gr = r.g.grippers[i];
    if (r.st.gripper_held[i].valid() || !gr.trigger.valid()) return;
    const TriggerState& ts = r.st.triggers[gr.trigger];
    if (ts.num == 0) return;
    // The object the trigger reports, if still inside; else the lowest id inside.
    const std::span<const graph::DoId> inside = r.st.inside(ts);
    graph::DoId obj = inside.front();
    const graph::DoId seen(int32_t(*r.val(r.comp_slot(r.g.triggers[gr.trigger].comp, graph::triggerslot::object))));
    for (const graph::DoId o : inside)
        if (o == seen) obj = seen;
    const btTransform inv = gripper_frame(r, gr).inverse();
    bool any = false;
    for (graph::BodyId b : r.tab.do_bodies[obj]) {
        if (!r.phys.in_world(b) || !r.phys.declared_dynamic(b) || r.st.held_by[b].valid()) continue;
        r.st.held_by[b] = i;
        r.st.grip_rel[b] = inv * r.phys.frame(b);
        r.phys.set_dynamics(b, false);
        any = true;
    }
    if (!any) return;
    r.st.gripper_held[i] = obj;
    const graph::Adr<graph::Slot> s0 = r.g.comps[gr.comp].slot_adr;
    r.activate(s0 + slot::gripped);
    r.emit(s0 + slot::object, obj.v);
}

void release(Runtime& r, graph::GripperId i) {
    const graph::DoId obj = r.st.gripper_held[i];
    if (!obj.valid()) return;
    const graph::Gripper& gr = r.g.grippers[i];
    // The gripper's motion: its body's (Bullet derives it for kinematic bodies), or
    // the followed graphics' change over the last step.
    btVector3 v(0, 0, 0), w(0, 0, 0), p(0, 0, 0);
    if (gr.body.valid()) {
        v = r.phys.velocity(gr.body);
        w = r.phys.angular_velocity(gr.body);
        p = r.phys.com(gr.body);
    } else if (gr.graphics.valid()) {
        const GraphicsState& gs = r.st.graphics[gr.graphics];
        v = to_bt(scale(sub(gs.pose.p, gs.prev.p), 1.0 / r.dt));
        w = to_bt(angular_velocity(gs.prev.q, gs.pose.q, r.dt));
        p = to_bt(gs.pose.p);
    }
    for (graph::BodyId b : r.tab.do_bodies[obj]) {
        if (r.st.held_by[b] != i) continue;
        r.st.held_by[b] = graph::GripperId{};
        r.phys.set_dynamics(b, true);
        btRigidBody& rb = r.phys.write(b);
        rb.setLinearVelocity(v + w.cross(rb.getWorldTransform().getOrigin() - p));
        rb.setAngularVelocity(w);
    }
    r.st.gripper_held[i] = graph::DoId{};
    const graph::Adr<graph::Slot> s0 = r.g.comps[gr.comp].slot_adr;
    r.activate(s0 + slot::released);
    r.emit(s0 + slot::object, -1);
}

void start_all(Runtime& r) {
    for (const graph::Gripper& gr : r.g.grippers) *r.val(r.comp_slot(gr.comp, slot::object)) = -1;
}

// What a gripper holds moves with it, kinematically.
// What each gripper holds follows it, in slices of the grippers on the physics threads (a
// body is held by one gripper at most: each moves only its own).
void sense_all(Runtime& r) {
    const size_t n = r.g.grippers.size();
    const size_t slices = slice_count(n, 16, kMaxSlices);
    auto follow = [&r, n, slices](int k) {
        for (graph::GripperId i : slice_ids<graph::GripperId>(n, slices, k)) {
            const graph::DoId obj = r.st.gripper_held[i];
            if (!obj.valid()) continue;
            const btTransform gp = gripper_frame(r, r.g.grippers[i]);
            for (graph::BodyId b : r.tab.do_bodies[obj])
                if (r.st.held_by[b] == i) r.phys.move(b, gp * r.st.grip_rel[b]);
        }
    };
    run_slices(r.phys.workers(), slices, follow);
}

void act_one(Runtime& r, const graph::Comp& c) {
    const graph::GripperId i = graph::detail_of<graph::Gripper>(c);
    const uint8_t* a = r.st.act.slice(c.slot_adr, c.slot_num).data();
    if (a[slot::release]) release(r, i);
    if (a[slot::grip]) grip(r, i);
}

}  // namespace

constexpr KindBehaviour behaviour{.start_all = start_all, .sense_all = sense_all, .act_one = act_one};

}  // namespace plant::kinds::gripper
