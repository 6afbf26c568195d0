// The conveyor law's integration (see fields.cpp for the law): one body alone, or a
// rigid group of bodies joined by fixed constraints, in 6 dof.
#include "engine/runtime.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace plant::engine {

namespace {

using Mat3 = Eigen::Matrix3d;
using Vec3d = Eigen::Vector3d;

Vec3d eig(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
btVector3 bt(const Vec3d& v) { return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())); }
Mat3 eig(const btMatrix3x3& m) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = m[i][j];
    return r;
}
Mat3 skew(const Vec3d& r) {  // skew(r) * x == r.cross(x)
    Mat3 s;
    s << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
    return s;
}

// 1/s with s = (exp(a) − 1)/a: integrating implicitly over s·dt instead of dt turns
// backward Euler's e/(1 + a) into the exact exp(−a) for the group's translation
// along the field. Clamped where exp(−a) is negligible anyway.
double inv_stretch(double a) { return a > 1e-12 ? std::max(a / std::expm1(std::min(a, 40.0)), 1e-12) : 1.0; }

}  // namespace

// One body alone: (m/s + dt·K)·Δv = dt·F, applied as the force m·Δv/dt; past the
// slip limit the band slips and pulls with the limit instead, in the same direction
// (less than the exact step's force, so a free body cannot overshoot the belt speed).
void integrate_single(Runtime& r, graph::BodyId b) {
    State& s = r.st;
    const double m = r.phys.mass(b), dt = r.dt;
    const double inv_s = inv_stretch(s.body_k[b] * dt / m);
    const Mat3 lhs = m * inv_s * Mat3::Identity() + dt * eig(s.gain[b]);
    const Vec3d dv = lhs.inverse() * (dt * eig(s.force[b]));
    Vec3d F = m * dv / dt;
    if (const double n = F.norm(); n > s.body_cap[b]) F *= s.body_cap[b] / n;
    r.phys.apply(b, bt(F), btVector3(0, 0, 0));
}

// A rigid group: the same in 6 dof about the group's centre of mass. Each body's
// point moves with J·x = Δv + Δω × r; the law's generalised stiffness is
// A = Σ J^T K J and its generalised force Σ J^T F. Every member then gets the
// force and torque that give it exactly the group's rigid velocity change.
// Slip limit: a member whose law force over the step, s·(F − K·J·x), exceeds its limit
// pulls with the limit instead (a constant force, no stiffness), and the group is solved
// again until no further member saturates (at most once per member).
void integrate_group(Runtime& r, graph::BodyId grp) {
    State& s = r.st;
    const double dt = r.dt, mass = s.group_mass[grp];
    const graph::BodyId* mem = s.group_list.data() + s.group_adr[grp];
    const int32_t n = s.group_num[grp];
    // Each member's centre of mass and world inertia, read once (a bottle's host works them out
    // from its carrier's transform), for the first kKept members; any further ones (no plant's
    // rigid group has them yet) are read where used: the same values.
    constexpr int32_t kKept = 8;
    Vec3d kept_com[kKept];
    Mat3 kept_inertia[kKept];
    for (int32_t i = 0; i < std::min(n, kKept); ++i) {
        kept_com[i] = eig(r.phys.com(mem[i]));
        kept_inertia[i] = eig(r.phys.inertia_world(mem[i]));
    }
    auto com = [&](int32_t i) { return i < kKept ? kept_com[i] : eig(r.phys.com(mem[i])); };
    auto inertia_of = [&](int32_t i) { return i < kKept ? kept_inertia[i] : eig(r.phys.inertia_world(mem[i])); };
    Vec3d c = Vec3d::Zero();
    for (int32_t i = 0; i < n; ++i) c += r.phys.mass(mem[i]) * com(i);
    c /= mass;
    Mat3 inertia = Mat3::Zero();
    for (int32_t i = 0; i < n; ++i) {
        const Vec3d rel = com(i) - c;
        inertia += inertia_of(i) + r.phys.mass(mem[i]) * (rel.squaredNorm() * Mat3::Identity() - rel * rel.transpose());
    }
    Vec3d dv, dw;
    for (int32_t pass = 0; pass <= n; ++pass) {
        double k = 0;
        for (int32_t i = 0; i < n; ++i) k += s.law_sat[mem[i]] ? 0 : s.body_k[mem[i]];
        // The stretch s speeds up time for the law's stiff part only: a saturated member's
        // constant force enters divided by s, so that it adds exactly dt·F to the momentum.
        const double inv_s = inv_stretch(k * dt / mass);
        Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
        Eigen::Matrix<double, 6, 1> f = Eigen::Matrix<double, 6, 1>::Zero();
        for (int32_t i = 0; i < n; ++i) {
            if (s.body_k[mem[i]] == 0) continue;
            const Vec3d rel = com(i) - c;
            const Vec3d F = s.law_sat[mem[i]] ? Vec3d(inv_s * eig(s.sat_force[mem[i]])) : eig(s.force[mem[i]]);
            f.head<3>() += F;
            f.tail<3>() += rel.cross(F);
            if (s.law_sat[mem[i]]) continue;
            const Mat3 K = eig(s.gain[mem[i]]), S = skew(rel);
            A.block<3, 3>(0, 0) += K;
            A.block<3, 3>(0, 3) -= K * S;
            A.block<3, 3>(3, 0) += S * K;
            A.block<3, 3>(3, 3) -= S * K * S;
        }
        Eigen::Matrix<double, 6, 6> lhs = dt * A;
        lhs.block<3, 3>(0, 0) += mass * inv_s * Mat3::Identity();
        lhs.block<3, 3>(3, 3) += inertia * inv_s;
        const Eigen::Matrix<double, 6, 1> x = lhs.ldlt().solve(dt * f);
        dv = x.head<3>(), dw = x.tail<3>();
        bool more = false;
        for (int32_t i = 0; i < n; ++i) {
            const graph::BodyId b = mem[i];
            if (s.body_k[b] == 0 || s.law_sat[b] || s.body_cap[b] == HUGE_VAL) continue;
            const Vec3d rel = com(i) - c;
            const Vec3d G = (eig(s.force[b]) - eig(s.gain[b]) * (dv + dw.cross(rel))) / inv_s;
            if (const double g = G.norm(); g > s.body_cap[b]) {
                s.sat_force[b] = bt(G * (s.body_cap[b] / g));
                s.law_sat[b] = 1;
                more = true;
            }
        }
        if (!more) break;
    }
    for (int32_t i = 0; i < n; ++i) {
        const Vec3d rel = com(i) - c;
        const Mat3 I = inertia_of(i);
        r.phys.apply(mem[i], bt(r.phys.mass(mem[i]) * (dv + dw.cross(rel)) / dt), bt(I * dw / dt));
        r.phys.rb(mem[i]).activate();
        s.law_sat[mem[i]] = 0;
    }
}

}  // namespace plant::engine
