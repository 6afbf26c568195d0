// The body's behaviour (docs/runtime.md): in phase 2 what left the world is taken out and
// the outputs read this step are refreshed (timed as StepProfile::Bodies); in phase 5 it acts
// on its inputs. Its world (the Bullet bodies, their modes and poses) is the physics phase's
// (engine/physics.h); what the other kinds share with it (taking a body out, whether an
// input's value is in range) is engine/bodies.cpp.
#include "engine/plugin.h"
#include "engine/runtime.h"
#include "engine/workers.h"

#include "graph/kinds.h"

#include <cassert>
#include <cmath>

namespace plant::kinds::body {

using namespace plant::engine;
using namespace plant::graph;
namespace slot = plant::graph::bodyslot;

namespace {

bool finite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// Where and when object d was lost, one of its bodies leaving the world at p: the last field one of its
// bodies rode (the latest; the first body of a tie), or where b left when none did.
void note_loss(Runtime& r, DoId d, const btVector3& p) {
    r.st.lost.push_back(d);  // once per DO: within its reserve
    Loss& l = r.st.loss[d];
    l.step = r.st.step;
    l.out = from_bt(p);
    l.field = FieldId{};
    l.field_step = r.st.step;
    l.place = l.out;
    for (BodyId x : r.tab.do_bodies[d]) {
        if (!r.st.ride_field[x].valid() || (l.field.valid() && r.st.ride_step[x] <= l.field_step)) continue;
        l.field = r.st.ride_field[x];
        l.field_step = r.st.ride_step[x];
        l.place = from_bt(r.st.ride_at[x]);
    }
}

// An object that falls off the plant or blows up is taken out, all its bodies, once,
// with one warning.
bool body_off(const Runtime& r, BodyId b) {
    if (!r.phys.in_world(b) || r.st.gone[b]) return false;
    const btRigidBody& rb = r.phys.rb(b);
    const btVector3& p = rb.getWorldTransform().getOrigin();
    const bool nan = !finite(p) || !finite(rb.getLinearVelocity()) || !finite(rb.getAngularVelocity());
    return nan || p.z() < -10 || p.length2() > 1e6;
}

void check_bodies(Runtime& r) {
    // Whether any body left the world or went NaN: looked for on the physics threads, in
    // slices of the bodies (reads only); the rare step that has one then handles them here.
    const std::vector<BodyId>& dyn = r.tab.dyn_bodies;
    const size_t n = dyn.size();
    const size_t slices = slice_count(n, 128, r.st.slice_left.size());
    auto look = [&r, n, slices](int i) {
        const auto [b, e] = slice_of(n, slices, i);
        bool off = false;
        // A hint a few bodies ahead: their Bullet bodies lie scattered in memory.
        constexpr size_t kAhead = 8;
        for (size_t k = b; k < e && !off; ++k) {
            if (k + kAhead < e) r.phys.ask_body(r.tab.dyn_bodies[k + kAhead]);
            off = body_off(r, r.tab.dyn_bodies[k]);
        }
        r.st.slice_left[i] = off;
    };
    if (slices > 1) {
        run_slices(r.phys.workers(), slices, look);
        bool any = false;
        for (size_t i = 0; i < slices; ++i) any |= r.st.slice_left[i] != 0;
        if (!any) return;
    }
    for (BodyId b : dyn) {
        if (!r.phys.in_world(b) || r.st.gone[b]) continue;
        const btRigidBody& rb = r.phys.rb(b);
        const btVector3& p = rb.getWorldTransform().getOrigin();
        const bool nan = !finite(p) || !finite(rb.getLinearVelocity()) || !finite(rb.getAngularVelocity());
        if (!nan && p.z() >= -10 && p.length2() <= 1e6) continue;
        (nan ? r.st.warn.nan_state : r.st.warn.left_world)++;
        const DoId d = r.tab.body_do[b];
        if (r.st.lost_at[d] < 0) {
            r.st.lost_at[d] = r.st.time;
            note_loss(r, d, p);
        }
        for (BodyId x : r.tab.do_bodies[d]) {
            if (r.st.gone[x]) continue;
            r.st.gone[x] = 1;
            if (r.phys.in_world(x)) take_body_out(r, x);
        }
    }
}

void sense_bodies(Runtime& r) {
    for (BodyId b : r.st.observed_bodies) {
        if (!r.phys.in_world(b)) continue;
        const uint8_t bits = r.st.body_outputs[b];
        const Adr<Slot> s0 = r.g.comps[r.g.bodies[b].comp].slot_adr;
        if (bits & 7) {
            const Pose p = r.phys.pose(b);
            if (bits & 1) r.emit_pose(s0 + slot::pose, p);
            if (bits & 2) {
                double* v = r.val(s0 + (slot::pose + 1));
                for (int i = 0; i < 3; ++i) v[i] = p.p[i];
                r.activate(s0 + (slot::pose + 1));
            }
            if (bits & 4) {
                double* v = r.val(s0 + (slot::pose + 2));
                for (int i = 0; i < 4; ++i) v[i] = p.q[i];
                r.activate(s0 + (slot::pose + 2));
            }
        }
        for (int k = 3; k < 5; ++k) {
            if (!(bits & (1u << k))) continue;
            const btVector3 v = k == 3 ? r.phys.velocity(b) : r.phys.angular_velocity(b);
            double* out = r.val(s0 + (slot::pose + k));
            out[0] = v.x();
            out[1] = v.y();
            out[2] = v.z();
            r.activate(s0 + (slot::pose + k));
        }
    }
}

void sense_all(Runtime& r) {
    check_bodies(r);
    sense_bodies(r);
}

void act_one(Runtime& r, const graph::Comp& c) {
    const BodyId b = graph::detail_of<graph::Body>(c);
    const uint8_t* a = r.st.act.slice(c.slot_adr, c.slot_num).data();
    Physics& ph = r.phys;
    const bool held = r.st.held_by[b].valid();  // a gripper owns its mode and pose
    if (a[slot::collision_off]) ph.set_collision(b, false);
    if (a[slot::collision_on]) ph.set_collision(b, true);
    if (!held && a[slot::dynamics_off]) ph.set_dynamics(b, false);
    if (!held && a[slot::dynamics_on]) ph.set_dynamics(b, true);
    const graph::Adr<graph::Slot> s0 = c.slot_adr;
    const bool pose_in = !a[slot::set_pose] || input_in_range(r, c, s0 + slot::set_pose);
    const bool position_in = !a[slot::set_position] || input_in_range(r, c, s0 + slot::set_position);
    const bool pose_ok = pose_in && position_in;  // a move out of range is not made at all
    if (!held && pose_ok && (a[slot::set_pose] || a[slot::set_position] || a[slot::set_orientation])) {
        btTransform f = ph.frame(b);
        if (a[slot::set_pose]) {
            const double* v = r.val(s0 + slot::set_pose);
            f = to_bt(Pose{{v[0], v[1], v[2]}, qnormalized({v[3], v[4], v[5], v[6]})});
        }
        if (a[slot::set_position]) {
            const double* v = r.val(s0 + slot::set_position);
            f.setOrigin(to_bt(Vec3{v[0], v[1], v[2]}));
        }
        if (a[slot::set_orientation]) {
            const double* v = r.val(s0 + slot::set_orientation);
            f.setRotation(to_bt(qnormalized({v[0], v[1], v[2], v[3]})));
        }
        // Dynamic and static bodies jump; a kinematic one travels there during the
        // next physics step, so what it pushes sees its speed.
        if (ph.declared_dynamic(b) ? ph.dynamics_on(b) : ph.declared_static(b)) ph.place(b, f);
        else ph.move(b, f);
        ph.rb(b).activate();
    }
    for (int k = 0; k < 2; ++k) {
        const int s = k == 0 ? slot::set_velocity : slot::set_angular_velocity;
        if (held || !a[s] || !input_in_range(r, c, s0 + s)) continue;
        const double* v = r.val(s0 + s);
        const Vec3 vel{v[0], v[1], v[2]};
        if (ph.dynamic_now(b)) {
            btRigidBody& rb = ph.write(b);
            if (k == 0) rb.setLinearVelocity(to_bt(vel));
            else rb.setAngularVelocity(to_bt(vel));
            rb.activate();
        } else {
            assert(!ph.declared_static(b));  // refused: graph/range.h's input_range
            (k == 0 ? r.st.cmd_lin : r.st.cmd_ang)[b] = vel;  // kinematic: we move it
            if (!r.st.is_commanded[b]) {
                r.st.is_commanded[b] = 1;
                r.st.commanded.push_back(b);
            }
        }
    }
}

// A kinematic body's place and orientation: act_one then moves only this body (Physics::move)
// and reads only its own row, so the bodies with only these inputs active move on the
// physics threads. Any other input (collision, dynamics, velocity) and a body of another
// mode (placing a dynamic or static one touches its world's broadphase) act in order.
bool acts_alone(const graph::Graph& g, const graph::Comp& c, int s) {
    return (s == slot::set_pose || s == slot::set_position || s == slot::set_orientation) &&
           g.bodies[detail_of<Body>(c)].mode == BodyMode::Kinematic;
}

}  // namespace

constexpr KindBehaviour behaviour{
    .sense_all = sense_all,
    .sense_segment = StepProfile::Bodies,
    .act_one = act_one,
    .acts_alone = acts_alone,
};

}  // namespace plant::kinds::body
