// Objects that come and go: grippers (carry an object kinematically, hand it back
// with the gripper's velocity), and what an exit (kinds/exit/run.cpp) or a trainee's hand
// does to take an object out of the world: back into its source's pool (kinds/source/).
#include "engine/runtime.h"

#include "graph/kinds.h"

namespace plant::engine {

using namespace plant::graph;

namespace {

btTransform gripper_frame(const Runtime& r, const Gripper& gr) {
    if (gr.body >= 0) return r.phys.frame(gr.body);
    if (gr.graphics >= 0) return to_bt(r.st.graphics[gr.graphics].pose);
    return btTransform::getIdentity();
}

}  // namespace

// The bar code of an object: its label's text, else its path.
double object_id(Runtime& r, int32_t d) {
    int32_t l = r.tab.do_label[d];
    if (l >= 0) return *r.val(r.comp_slot(r.g.labels[l].comp, labelslot::value));
    return r.g.dos[d].path.id;
}

// The object out of the world, back into its source's pool when it is a pooled one (the
// whole pooled object, also when `obj` is a part of it); its root, or -1 when it was not in
// the world.
int32_t take_object(Runtime& r, int32_t obj) {
    int32_t root = obj;
    for (int32_t d = obj; d >= 0; d = r.g.dos[d].parent)
        if (r.tab.do_source[d] >= 0) {
            root = d;
            break;
        }
    bool any = false;
    for (const int32_t* b = r.tab.do_bodies.begin(root); b != r.tab.do_bodies.end(root); ++b)
        if (r.phys.in_world(*b)) {
            take_body_out(r, *b);
            any = true;
        }
    if (!any) return -1;
    if (int32_t src = r.tab.do_source[root]; src >= 0) {
        SourceState& ss = r.st.sources[src];
        const int32_t num = r.g.sources[src].pool_num;
        r.st.pool_ring[ss.ring_adr + (ss.head + ss.free) % num] = root;
        ss.free++;
    }
    return root;
}

void follow_grippers(Runtime& r) {
    for (size_t i = 0; i < r.g.grippers.size(); ++i) {
        const int32_t obj = r.st.gripper_held[i];
        if (obj < 0) continue;
        const btTransform gp = gripper_frame(r, r.g.grippers[i]);
        for (const int32_t* b = r.tab.do_bodies.begin(obj); b != r.tab.do_bodies.end(obj); ++b)
            if (r.st.held_by[*b] == int32_t(i)) r.phys.move(*b, gp * r.st.grip_rel[*b]);
    }
}

void grip(Runtime& r, int32_t i) {
    const Gripper& gr = r.g.grippers[i];
    if (r.st.gripper_held[i] >= 0 || gr.trigger < 0) return;
    const TriggerState& ts = r.st.triggers[gr.trigger];
    if (ts.num == 0) return;
    // The object the trigger reports, if still inside; else the lowest id inside.
    int32_t obj = r.st.inside[ts.adr];
    const int32_t seen = int32_t(*r.val(r.comp_slot(r.g.triggers[gr.trigger].comp, triggerslot::object)));
    for (int32_t k = 0; k < ts.num; ++k)
        if (r.st.inside[ts.adr + k] == seen) obj = seen;
    const btTransform inv = gripper_frame(r, gr).inverse();
    bool any = false;
    for (const int32_t* b = r.tab.do_bodies.begin(obj); b != r.tab.do_bodies.end(obj); ++b) {
        if (!r.phys.in_world(*b) || !r.phys.declared_dynamic(*b) || r.st.held_by[*b] >= 0) continue;
        r.st.held_by[*b] = i;
        r.st.grip_rel[*b] = inv * r.phys.frame(*b);
        r.phys.set_dynamics(*b, false);
        any = true;
    }
    if (!any) return;
    r.st.gripper_held[i] = obj;
    const int32_t s0 = r.g.comps[gr.comp].slot_adr;
    r.activate(s0 + gripperslot::gripped);
    r.emit(s0 + gripperslot::object, obj);
}

void release(Runtime& r, int32_t i) {
    const int32_t obj = r.st.gripper_held[i];
    if (obj < 0) return;
    const Gripper& gr = r.g.grippers[i];
    // The gripper's motion: its body's (Bullet derives it for kinematic bodies), or
    // the followed graphics' change over the last step.
    btVector3 v(0, 0, 0), w(0, 0, 0), p(0, 0, 0);
    if (gr.body >= 0) {
        v = r.phys.velocity(gr.body);
        w = r.phys.angular_velocity(gr.body);
        p = r.phys.com(gr.body);
    } else if (gr.graphics >= 0) {
        const GraphicsState& gs = r.st.graphics[gr.graphics];
        v = to_bt(scale(sub(gs.pose.p, gs.prev.p), 1.0 / r.dt));
        w = to_bt(angular_velocity(gs.prev.q, gs.pose.q, r.dt));
        p = to_bt(gs.pose.p);
    }
    for (const int32_t* b = r.tab.do_bodies.begin(obj); b != r.tab.do_bodies.end(obj); ++b) {
        if (r.st.held_by[*b] != i) continue;
        r.st.held_by[*b] = -1;
        r.phys.set_dynamics(*b, true);
        btRigidBody& rb = r.phys.write(*b);
        rb.setLinearVelocity(v + w.cross(rb.getWorldTransform().getOrigin() - p));
        rb.setAngularVelocity(w);
    }
    r.st.gripper_held[i] = -1;
    const int32_t s0 = r.g.comps[gr.comp].slot_adr;
    r.activate(s0 + gripperslot::released);
    r.emit(s0 + gripperslot::object, -1);
}

// The reference a gripper holds starts empty.
void start_objects(Runtime& r) {
    for (const Gripper& gr : r.g.grippers) *r.val(r.comp_slot(gr.comp, gripperslot::object)) = -1;
}

void act_gripper(Runtime& r, const Comp& c, int32_t i) {
    const uint8_t* a = r.st.act.data() + c.slot_adr;
    if (a[gripperslot::release]) release(r, i);
    if (a[gripperslot::grip]) grip(r, i);
}

}  // namespace plant::engine
