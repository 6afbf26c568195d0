// Phase 1: kinematic motion, the conveyor law, the Bullet step.
//
// The law F = k·diag(d)·(v_tar − v) is taken in the field's local frame, with diag
// of |d| so that a field pointing along −x drives towards −x. It is linear in v, and
// stiff: explicit with k = 16 kg/s it diverges for a 20 g bottle at 150 Hz
// (k·dt/m = 5.3 > 2). Its exact one-step solution for a free body is
// e' = e·exp(−k·dt/m), and that is what we apply (see integrate_group).
//
// Bodies joined by enabled fixed joints form a rigid group and are integrated
// together, translation and rotation (6 dof): the light foot of a bottle pulls as
// hard as its main body (the force depends on velocity, not mass) and so tips the
// bottle, but the torque this creates is integrated implicitly too, so the
// bottle's rotation stays stable however light it is.
#include "engine/runtime.h"

#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <LinearMath/btTransformUtil.h>

#include <cmath>

namespace plant::engine {

using namespace plant::graph;

namespace {

int32_t root(std::vector<int32_t>& parent, int32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

// Rigid groups and their member lists, rebuilt only when a joint, a dynamics mode or
// membership changed. All arrays are sized by the body count: no allocation.
void rebuild_groups(Runtime& r) {
    State& s = r.st;
    const int32_t nb = int32_t(r.g.bodies.size());
    for (int32_t b = 0; b < nb; ++b) s.group_of[b] = b;
    for (size_t j = 0; j < r.g.joints.size(); ++j) {
        const Joint& jt = r.g.joints[j];
        if (jt.kind != JointKind::Fixed || !r.phys.joint_on(int32_t(j)) || jt.body_b < 0) continue;
        if (!r.phys.dynamic_now(jt.body_a) || !r.phys.dynamic_now(jt.body_b)) continue;
        s.group_of[root(s.group_of, jt.body_a)] = root(s.group_of, jt.body_b);
    }
    for (int32_t b = 0; b < nb; ++b) {
        s.group_of[b] = root(s.group_of, b);
        s.group_mass[b] = 0;
        s.group_num[b] = 0;
    }
    for (int32_t b = 0; b < nb; ++b)
        if (r.phys.dynamic_now(b)) {
            s.group_mass[s.group_of[b]] += r.phys.mass(b);
            s.group_num[s.group_of[b]]++;
        }
    for (int32_t b = 0, adr = 0; b < nb; ++b) {
        s.group_adr[b] = adr;
        adr += s.group_num[b];
        s.group_num[b] = 0;
    }
    for (int32_t b = 0; b < nb; ++b)
        if (r.phys.dynamic_now(b)) {
            const int32_t g = s.group_of[b];
            s.group_list[s.group_adr[g] + s.group_num[g]++] = b;
        }
    s.groups_version = r.phys.version();
}

btVector3 field_gain(const Field& fd) {
    const btVector3 d = to_bt(fd.dir);
    return btVector3(std::abs(d.x()), std::abs(d.y()), std::abs(d.z())) * btScalar(fd.gain);
}

// The field's frame, recomputed only when its carrier has moved.
const State::FieldFrame& field_frame(Runtime& r, size_t f) {
    const Field& fd = r.g.fields[f];
    State::FieldFrame& ff = r.st.field_frame[f];
    const btTransform carrier = fd.body >= 0 ? r.phys.rb(fd.body).getWorldTransform() : btTransform::getIdentity();
    if (ff.valid && carrier == ff.carrier) return ff;
    ff.carrier = carrier;
    ff.pose = fd.body >= 0 ? r.phys.frame(fd.body) * r.tab.field_local[f] : to_bt(fd.pose);
    const btMatrix3x3& R = ff.pose.getBasis();
    ff.K = R.scaled(field_gain(fd)) * R.transpose();  // R·diag(gain)·R^T
    const btVector3 h = to_bt(fd.extent) * btScalar(0.5);
    ff.rx = std::abs(R[0][0]) * h.x() + std::abs(R[0][1]) * h.y() + std::abs(R[0][2]) * h.z();
    ff.ry = std::abs(R[1][0]) * h.x() + std::abs(R[1][1]) * h.y() + std::abs(R[1][2]) * h.z();
    ff.valid = true;
    return ff;
}

void move_kinematic(Runtime& r) {
    State& s = r.st;
    for (const int32_t b : s.commanded) {
        const Vec3 &v = s.cmd_lin[b], &w = s.cmd_ang[b];
        if (v == Vec3{0, 0, 0} && w == Vec3{0, 0, 0}) continue;
        if (!r.phys.in_world(b) || r.phys.dynamic_now(b) || s.held_by[b] >= 0) continue;
        btRigidBody& rb = r.phys.write(b);
        btTransform next;
        btTransformUtil::integrateTransform(rb.getWorldTransform(), to_bt(v), to_bt(w), btScalar(r.dt), next);
        rb.setWorldTransform(next);  // Bullet derives the kinematic velocity from the move
    }
}

}  // namespace

void apply_fields(Runtime& r) {
    State& s = r.st;
    const Graph& g = r.g;
    if (g.fields.empty()) return;
    if (s.groups_version != r.phys.version()) rebuild_groups(r);
    r.index.refresh(r.phys, false);
    s.touched.clear();
    for (size_t f = 0; f < g.fields.size(); ++f) {
        const Field& fd = g.fields[f];
        if (!s.field_on[f] || fd.gain <= 0) continue;
        const btVector3 gain = field_gain(fd);
        const btScalar kmax = gain[gain.maxAxis()];
        if (kmax <= 0) continue;
        const btVector3 target = to_bt(fd.dir) * btScalar(s.field_speed[f]);
        const State::FieldFrame& ff = field_frame(r, f);
        const btMatrix3x3& R = ff.pose.getBasis();
        const btMatrix3x3& K = ff.K;
        const btVector3& c = ff.pose.getOrigin();
        const btVector3 h = to_bt(fd.extent) * btScalar(0.5);
        r.index.for_each(c.x() - ff.rx, c.x() + ff.rx, c.y() - ff.ry, c.y() + ff.ry, [&](int32_t b) {
            if (!r.phys.dynamic_now(b) || s.held_by[b] >= 0) return;
            const btVector3 local = (r.index.com(b) - c) * R;  // R^T (p - c): into the field frame
            if (std::abs(local.x()) > h.x() || std::abs(local.y()) > h.y() || std::abs(local.z()) > h.z())
                return;
            const btVector3 v = r.phys.velocity(b) * R;
            if (s.body_k[b] == 0) s.touched.push_back(b);
            s.field_run[b] = std::max(s.field_run[b], std::abs(double(s.field_speed[f])));
            s.body_k[b] += kmax;
            s.force[b] += R * (gain * (target - v));
            s.gain[b] += K;
        });
    }
    for (int32_t b : s.touched) {
        // Stalled: slower than a tenth of the running field it is in, as the last
        // physics step left it (a bottle held at a gate, a jam).
        if (s.field_run[b] > 0 && r.phys.velocity(b).length() < 0.1 * s.field_run[b]) {
            if (s.slow_step[b] + 1 < s.step) s.stall_since[b] = s.time;
            s.slow_step[b] = s.step;
        }
        s.field_run[b] = 0;
    }
    for (int32_t b : s.touched) {
        const int32_t grp = s.group_of[b];
        if (s.group_num[grp] <= 1) {
            integrate_single(r, b);
            r.phys.rb(b).activate();
        } else if (!s.group_mark[grp]) {
            s.group_mark[grp] = 1;
            integrate_group(r, grp);
        }
    }
    for (int32_t b : s.touched) {
        s.group_mark[s.group_of[b]] = 0;
        s.force[b].setZero();
        s.gain[b].setValue(0, 0, 0, 0, 0, 0, 0, 0, 0);
        s.body_k[b] = 0;
    }
}

void phase_physics(Runtime& r) {
    r.phys.update_welds();  // before any force of this step
    move_kinematic(r);
    apply_fields(r);
    r.phys.step(r.dt);
    r.st.warn.missed_contacts = r.phys.missed_contacts();
    r.st.step++;
    r.st.time = double(r.st.step) * r.dt;  // no accumulated rounding
}

}  // namespace plant::engine
