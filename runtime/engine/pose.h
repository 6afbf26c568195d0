// Pose algebra in double precision (graphics, bookkeeping) and the conversions to
// Bullet's single-precision transforms. Quaternions are x, y, z, w like graph::Quat.
#pragma once

#include "graph/graph.h"

#include <LinearMath/btTransform.h>

#include <cmath>

namespace plant::engine {

using graph::Pose;
using graph::Quat;
using graph::Vec3;

inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

inline Quat qmul(const Quat& a, const Quat& b) {
    return {a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
            a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
            a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
            a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
}
inline Quat qconj(const Quat& q) { return {-q[0], -q[1], -q[2], q[3]}; }
inline Vec3 qrot(const Quat& q, const Vec3& v) {
    const Vec3 u{q[0], q[1], q[2]};
    const Vec3 t = scale(cross(u, v), 2.0);
    return add(add(v, scale(t, q[3])), cross(u, t));
}
inline Quat qnormalized(const Quat& q) {
    double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (n == 0) return {0, 0, 0, 1};
    return {q[0] / n, q[1] / n, q[2] / n, q[3] / n};
}
// The same rotation with w >= 0, so outputs do not flip sign between steps.
inline Quat qcanonical(const Quat& q) { return q[3] < 0 ? Quat{-q[0], -q[1], -q[2], -q[3]} : q; }

inline Pose pmul(const Pose& a, const Pose& b) { return {add(a.p, qrot(a.q, b.p)), qmul(a.q, b.q)}; }
inline Pose pinv(const Pose& a) {
    const Quat c = qconj(a.q);
    return {scale(qrot(c, a.p), -1.0), c};
}

// Linear in position, spherical-linear in orientation; s in [0, 1].
inline Quat qslerp(const Quat& a, Quat b, double s) {
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    if (d < 0) {
        d = -d;
        b = {-b[0], -b[1], -b[2], -b[3]};
    }
    double wa = 1 - s, wb = s;
    if (d < 0.9995) {
        double th = std::acos(d), sn = std::sin(th);
        wa = std::sin((1 - s) * th) / sn;
        wb = std::sin(s * th) / sn;
    }
    return qnormalized({wa * a[0] + wb * b[0], wa * a[1] + wb * b[1], wa * a[2] + wb * b[2],
                        wa * a[3] + wb * b[3]});
}
inline Pose pinterp(const Pose& a, const Pose& b, double s) {
    return {add(a.p, scale(sub(b.p, a.p), s)), qslerp(a.q, b.q, s)};
}

// Angular velocity that turns `from` into `to` in dt (world frame).
inline Vec3 angular_velocity(const Quat& from, const Quat& to, double dt) {
    Quat d = qcanonical(qmul(to, qconj(from)));
    double s = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (s < 1e-12 || dt <= 0) return {0, 0, 0};
    double angle = 2 * std::atan2(s, d[3]);
    return scale(Vec3{d[0], d[1], d[2]}, angle / (s * dt));
}

inline btVector3 to_bt(const Vec3& v) {
    return btVector3(btScalar(v[0]), btScalar(v[1]), btScalar(v[2]));
}
inline btQuaternion to_bt(const Quat& q) {
    return btQuaternion(btScalar(q[0]), btScalar(q[1]), btScalar(q[2]), btScalar(q[3]));
}
inline btTransform to_bt(const Pose& p) { return btTransform(to_bt(p.q), to_bt(p.p)); }
inline Vec3 from_bt(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
inline Pose from_bt(const btTransform& t) {
    btQuaternion q = t.getRotation();
    return {from_bt(t.getOrigin()), qcanonical({q.x(), q.y(), q.z(), q.w()})};
}

inline bool is_identity(const Pose& p, double eps = 1e-12) {
    return std::abs(p.p[0]) < eps && std::abs(p.p[1]) < eps && std::abs(p.p[2]) < eps &&
           std::abs(p.q[0]) < eps && std::abs(p.q[1]) < eps && std::abs(p.q[2]) < eps;
}

}  // namespace plant::engine
