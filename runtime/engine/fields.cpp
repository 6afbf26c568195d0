// Phase 1: kinematic motion, the conveyor law, the Bullet step.
//
// The law F = k·diag(d)·(v_tar − v), taken in the field's local frame (d there;
// diag of |d| so a field pointing along −x drives towards −x instead of pushing
// away), is linear in v. Applied explicitly with k = 16 kg/s it diverges for a 20 g
// bottle at 150 Hz (k·dt/m = 5.3 > 2). Over one step its exact solution, with v_tar
// constant, is e' = e·exp(−k·dt/m): we apply the law's forces scaled by
// s = (1 − exp(−a))/a, a = K·dt/M, which gives exactly that velocity change.
// K and M are summed over a rigid group (bodies joined by enabled fixed joints), so
// a bottle's light bottom body still pulls in proportion to k, not to its mass, and
// tips the bottle; only the group's common speed is made exact and stable.
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

// Rigid groups, rebuilt only when a joint, a dynamics mode or membership changed.
void rebuild_groups(Runtime& r) {
    State& s = r.st;
    const size_t nb = r.g.bodies.size();
    for (size_t b = 0; b < nb; ++b) {
        s.group_of[b] = int32_t(b);
        s.group_mass[b] = 0;
    }
    for (size_t j = 0; j < r.g.joints.size(); ++j) {
        const Joint& jt = r.g.joints[j];
        if (jt.kind != JointKind::Fixed || !r.phys.joint_on(int32_t(j)) || jt.body_b < 0) continue;
        if (!r.phys.dynamic_now(jt.body_a) || !r.phys.dynamic_now(jt.body_b)) continue;
        s.group_of[root(s.group_of, jt.body_a)] = root(s.group_of, jt.body_b);
    }
    for (size_t b = 0; b < nb; ++b) {
        int32_t g = root(s.group_of, int32_t(b));
        s.group_of[b] = g;
        if (r.phys.dynamic_now(int32_t(b))) s.group_mass[g] += r.phys.mass(int32_t(b));
    }
    s.groups_version = r.phys.version();
}

btTransform field_pose(const Runtime& r, size_t f) {
    const Field& fd = r.g.fields[f];
    if (fd.body >= 0) return r.phys.frame(fd.body) * r.tab.field_local[f];
    return to_bt(fd.pose);
}

void move_kinematic(Runtime& r) {
    State& s = r.st;
    for (size_t b = 0; b < r.g.bodies.size(); ++b) {
        const Vec3 &v = s.cmd_lin[b], &w = s.cmd_ang[b];
        if (v == Vec3{0, 0, 0} && w == Vec3{0, 0, 0}) continue;
        if (!r.phys.in_world(int32_t(b)) || r.phys.dynamic_now(int32_t(b)) || s.held_by[b] >= 0) continue;
        btRigidBody& rb = r.phys.rb(int32_t(b));
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
        const btVector3 d = to_bt(fd.dir);
        const btVector3 gain = btVector3(std::abs(d.x()), std::abs(d.y()), std::abs(d.z())) * btScalar(fd.gain);
        const btScalar kmax = gain[gain.maxAxis()];
        if (kmax <= 0) continue;
        const btVector3 target = d * btScalar(s.field_speed[f]);
        const btTransform pose = field_pose(r, f);
        const btMatrix3x3& R = pose.getBasis();
        const btVector3& c = pose.getOrigin();
        const btVector3 h = to_bt(fd.extent) * btScalar(0.5);
        const btScalar rx = std::abs(R[0][0]) * h.x() + std::abs(R[0][1]) * h.y() + std::abs(R[0][2]) * h.z();
        auto [first, last] = r.index.range(c.x() - rx, c.x() + rx);
        for (size_t i = first; i < last; ++i) {
            const int32_t b = r.index.body_at(i);
            if (!r.phys.dynamic_now(b) || s.held_by[b] >= 0) continue;
            const btVector3 local = (r.index.com(b) - c) * R;  // R^T (p - c): into the field frame
            if (std::abs(local.x()) > h.x() || std::abs(local.y()) > h.y() || std::abs(local.z()) > h.z())
                continue;
            const btVector3 v = r.phys.rb(b).getLinearVelocity() * R;
            if (s.body_k[b] == 0) s.touched.push_back(b);
            s.body_k[b] += kmax;
            s.force[b] += R * (gain * (target - v));
        }
    }
    for (int32_t b : s.touched) s.group_k[s.group_of[b]] += s.body_k[b];
    for (int32_t b : s.touched) {
        const int32_t grp = s.group_of[b];
        const double a = s.group_k[grp] * r.dt / s.group_mass[grp];
        const double scale = a > 1e-12 ? -std::expm1(-a) / a : 1.0;
        btRigidBody& rb = r.phys.rb(b);
        rb.applyCentralForce(s.force[b] * btScalar(scale));
        rb.activate();
        s.force[b].setZero();
        s.body_k[b] = 0;
    }
    for (int32_t b : s.touched) s.group_k[s.group_of[b]] = 0;
}

void phase_physics(Runtime& r) {
    move_kinematic(r);
    apply_fields(r);
    r.phys.step(r.dt);
    r.st.step++;
    r.st.time = double(r.st.step) * r.dt;  // no accumulated rounding
}

}  // namespace plant::engine
