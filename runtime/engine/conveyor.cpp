// The conveyor law's integration (see fields.cpp for the law): one body alone, or a
// rigid group of bodies joined by fixed constraints, in 6 dof.
#include "engine/runtime.h"

#include <Eigen/Dense>

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

// One body alone: (m/s + dt·K)·Δv = dt·F, applied as the force m·Δv/dt.
void integrate_single(Runtime& r, int32_t b) {
    State& s = r.st;
    const double m = r.phys.mass(b), dt = r.dt;
    const double inv_s = inv_stretch(s.body_k[b] * dt / m);
    const Mat3 lhs = m * inv_s * Mat3::Identity() + dt * eig(s.gain[b]);
    const Vec3d dv = lhs.inverse() * (dt * eig(s.force[b]));
    r.phys.apply(b, bt(m * dv / dt), btVector3(0, 0, 0));
}

// A rigid group: the same in 6 dof about the group's centre of mass. Each body's
// point moves with J·x = Δv + Δω × r; the law's generalised stiffness is
// A = Σ J^T K J and its generalised force Σ J^T F. Every member then gets the
// force and torque that give it exactly the group's rigid velocity change.
void integrate_group(Runtime& r, int32_t grp) {
    State& s = r.st;
    const double dt = r.dt, mass = s.group_mass[grp];
    const int32_t* mem = s.group_list.data() + s.group_adr[grp];
    const int32_t n = s.group_num[grp];
    Vec3d c = Vec3d::Zero(), p = Vec3d::Zero();
    double k = 0;
    for (int32_t i = 0; i < n; ++i) {
        c += r.phys.mass(mem[i]) * eig(r.phys.com(mem[i]));
        k += s.body_k[mem[i]];
    }
    c /= mass;
    Mat3 inertia = Mat3::Zero();
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> f = Eigen::Matrix<double, 6, 1>::Zero();
    for (int32_t i = 0; i < n; ++i) {
        const double m = r.phys.mass(mem[i]);
        const Vec3d rel = eig(r.phys.com(mem[i])) - c;
        inertia += eig(r.phys.inertia_world(mem[i])) + m * (rel.squaredNorm() * Mat3::Identity() - rel * rel.transpose());
        p += m * eig(r.phys.velocity(mem[i]));
        if (s.body_k[mem[i]] == 0) continue;
        const Mat3 K = eig(s.gain[mem[i]]), S = skew(rel);
        A.block<3, 3>(0, 0) += K;
        A.block<3, 3>(0, 3) -= K * S;
        A.block<3, 3>(3, 0) += S * K;
        A.block<3, 3>(3, 3) -= S * K * S;
        const Vec3d F = eig(s.force[mem[i]]);
        f.head<3>() += F;
        f.tail<3>() += rel.cross(F);
    }
    Eigen::Matrix<double, 6, 6> lhs = dt * A;
    const double inv_s = inv_stretch(k * dt / mass);
    lhs.block<3, 3>(0, 0) += mass * inv_s * Mat3::Identity();
    lhs.block<3, 3>(3, 3) += inertia * inv_s;
    const Eigen::Matrix<double, 6, 1> x = lhs.ldlt().solve(dt * f);
    const Vec3d dv = x.head<3>(), dw = x.tail<3>();
    for (int32_t i = 0; i < n; ++i) {
        const Vec3d rel = eig(r.phys.com(mem[i])) - c;
        const Mat3 I = eig(r.phys.inertia_world(mem[i]));
        r.phys.apply(mem[i], bt(r.phys.mass(mem[i]) * (dv + dw.cross(rel)) / dt), bt(I * dw / dt));
        r.phys.rb(mem[i]).activate();
    }
}

}  // namespace plant::engine
