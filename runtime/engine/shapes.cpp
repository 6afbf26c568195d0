#include "engine/shapes.h"

#include "engine/contact.h"
#include "engine/pose.h"

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

namespace plant::engine {

using namespace plant::graph;

namespace {

std::vector<double> primitive_key(const Graph& g, const Shape& s) {
    std::vector<double> k{double(s.kind), s.size[0], s.size[1], s.size[2]};
    if (s.kind == ShapeKind::Hull)
        for (int32_t i = 0; i < s.point_num; ++i)
            for (double c : g.points[s.point_adr + i].p) k.push_back(c);
    return k;
}

// Volume, to share a compound's mass among its children.
double volume(const Shape& s) {
    const double pi = std::numbers::pi, r = s.size[0], h = s.size[1];
    switch (s.kind) {
    case ShapeKind::Box: return s.size[0] * s.size[1] * s.size[2];
    case ShapeKind::Sphere: return 4.0 / 3.0 * pi * r * r * r;
    case ShapeKind::Cylinder: return pi * r * r * h;
    case ShapeKind::Capsule: return pi * r * r * std::max(h - 2 * r, 0.0) + 4.0 / 3.0 * pi * r * r * r;
    case ShapeKind::Hull: return 0;  // measured from the built shape's bounding box
    }
    return 0;
}

Eigen::Matrix3d rotation(const Quat& q) {
    return Eigen::Quaterniond(q[3], q[0], q[1], q[2]).toRotationMatrix();
}

Eigen::Vector3d vec(const Vec3& v) { return {v[0], v[1], v[2]}; }

// Principal moments and axes (a proper rotation) of a symmetric inertia tensor; the
// axes stay the frame's own while the tensor is diagonal.
std::pair<Eigen::Vector3d, Eigen::Matrix3d> principal_axes(const Eigen::Matrix3d& tensor) {
    const double off = std::abs(tensor(0, 1)) + std::abs(tensor(0, 2)) + std::abs(tensor(1, 2));
    if (off <= 1e-9 * tensor.trace()) return {tensor.diagonal(), Eigen::Matrix3d::Identity()};
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(tensor);
    Eigen::Matrix3d axes = eig.eigenvectors();
    if (axes.determinant() < 0) axes.col(2) *= -1;
    return {eig.eigenvalues(), axes};
}

// Adds a part of mass m, principal moments `moments` in the frame `at`, to a tensor
// about the point c (parallel axes).
void add_inertia(Eigen::Matrix3d& tensor, const Pose& at, const Eigen::Vector3d& moments, double m,
                 const Eigen::Vector3d& c) {
    const Eigen::Matrix3d r = rotation(at.q);
    const Eigen::Vector3d d = vec(at.p) - c;
    tensor += r * moments.asDiagonal() * r.transpose();
    tensor += m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
}

}  // namespace

ShapeCache::~ShapeCache() {
    while (!owned_.empty()) owned_.pop_back();  // compounds (created last) before children
}

btCollisionShape* ShapeCache::primitive(const Graph& g, const Shape& s) {
    std::vector<double> key = primitive_key(g, s);
    if (auto it = cache_.find(key); it != cache_.end()) return it->second;
    const btScalar r = btScalar(s.size[0]), h = btScalar(s.size[1]);
    std::unique_ptr<btCollisionShape> shape;
    switch (s.kind) {
    case ShapeKind::Box: {
        auto box = std::make_unique<btBoxShape>(to_bt(s.size) * btScalar(0.5));
        box->initializePolyhedralFeatures();  // exact contact manifolds: see Physics()
        shape = std::move(box);
        break;
    }
    case ShapeKind::Sphere: shape = std::make_unique<btSphereShape>(r); break;
    case ShapeKind::Cylinder: shape = std::make_unique<btCylinderShapeZ>(btVector3(r, r, h / 2)); break;
    // The graph gives a capsule's total height; Bullet wants the distance between its caps.
    case ShapeKind::Capsule: shape = std::make_unique<btCapsuleShapeZ>(r, std::max<btScalar>(h - 2 * r, 0)); break;
    case ShapeKind::Hull: return hull(g, s, Pose{});  // its own cache entry, the same key
    }
    return keep(std::move(shape), std::move(key));
}

ShapeReach measure_reach(const btConvexShape& shape) {
    ShapeReach m;
    for (int k = 0; k < 3; ++k) {
        btVector3 u(0, 0, 0), e1(0, 0, 0), e2(0, 0, 0);
        u[k] = 1, e1[(k + 1) % 3] = 1, e2[(k + 2) % 3] = 1;
        btScalar rho = 0;
        for (int i = 0; i < 64; ++i) {
            const btScalar a = btScalar(i) * SIMD_PI / 32;
            const btVector3 d = e1 * std::cos(a) + e2 * std::sin(a);
            rho = std::max(rho, shape.localGetSupportingVertex(d).dot(d));
        }
        m.rho[k] = rho / std::cos(SIMD_PI / 64);
        m.along[k] = std::max({shape.localGetSupportingVertex(u).dot(u), -shape.localGetSupportingVertex(-u).dot(u),
                               btScalar(0)});
    }
    return m;
}

// Owns a shape made for `key`; a convex one is measured (ShapeReach) and its user index says
// where that is kept.
btCollisionShape* ShapeCache::keep(std::unique_ptr<btCollisionShape> shape, std::vector<double> key) {
    btCollisionShape* raw = shape.get();
    if (raw->isConvex()) {
        raw->setUserIndex(int(reach_.size()));
        reach_.push_back(measure_reach(*static_cast<const btConvexShape*>(raw)));
    }
    owned_.push_back(std::move(shape));
    cache_.emplace(std::move(key), raw);
    return raw;
}

// A hull's points moved by `to`: a hull placed off its body's centre of mass without
// a compound around it.
btCollisionShape* ShapeCache::hull(const Graph& g, const Shape& s, const Pose& to) {
    std::vector<double> key = primitive_key(g, s);
    if (!is_identity(to, 0)) {
        key.insert(key.end(), to.p.begin(), to.p.end());
        key.insert(key.end(), to.q.begin(), to.q.end());
    }
    if (auto it = cache_.find(key); it != cache_.end()) return it->second;
    const btTransform t = to_bt(to);
    auto make = [&] {
        auto h = std::make_unique<btConvexHullShape>();
        for (int32_t i = 0; i < s.point_num; ++i) h->addPoint(t * to_bt(g.points[s.point_adr + i].p), false);
        h->optimizeConvexHull();
        h->setMargin(btScalar(kHullMargin));  // before the AABB: Bullet's default 4 cm outgrows a bottle
        h->recalcLocalAabb();
        return h;
    };
    auto h = make();
    h->initializePolyhedralFeatures();
    // A hull without volume (the loader refuses one; a hand-built graph may not) keeps no
    // polyhedral features: Bullet's polyhedral contacts would index a face it lacks.
    if (const btConvexPolyhedron* p = h->getConvexPolyhedron(); !p || !solid_polyhedron(*p)) h = make();
    return keep(std::move(h), std::move(key));
}

btCollisionShape* ShapeCache::compound(const std::vector<double>& key,
                                       const std::vector<std::pair<btCollisionShape*, btTransform>>& kids) {
    if (auto it = cache_.find(key); it != cache_.end()) return it->second;
    // A dynamic AABB tree only pays off for many children.
    auto c = std::make_unique<btCompoundShape>(kids.size() > 8, int(kids.size()));
    for (auto& [shape, local] : kids) c->addChildShape(local, shape);
    btCollisionShape* raw = c.get();
    owned_.push_back(std::move(c));
    cache_.emplace(key, raw);
    return raw;
}

BodyShape ShapeCache::build(const Graph& g, const Body& b) {
    struct Kid {
        btCollisionShape* shape;
        Pose in_com;  // relative to the centre-of-mass frame `b.com`
        const Shape* src;
    };
    std::vector<Kid> kids;
    for (int32_t i = 0; i < b.shape_num; ++i) {
        const Shape& s = g.shapes[b.shape_adr + i];
        kids.push_back({primitive(g, s), pmul(pinv(b.com), s.local), &s});
    }

    BodyShape out;
    Eigen::Matrix3d principal = Eigen::Matrix3d::Identity();  // principal axes in the com frame
    const bool dynamic = b.mode == BodyMode::Dynamic && b.mass > 0;
    if (dynamic) {
        out.mass = b.mass;
        if (b.inertia_set) {
            out.inertia = to_bt(b.inertia);
        } else if (kids.size() == 1 && is_identity(kids[0].in_com)) {
            kids[0].shape->calculateLocalInertia(btScalar(b.mass), out.inertia);
        } else {
            // Mass shared by volume, each child's tensor rotated and moved to the com.
            std::vector<double> vol;
            double total = 0;
            for (const Kid& k : kids) {
                double v = volume(*k.src);
                if (v <= 0) {
                    btVector3 lo, hi;
                    k.shape->getAabb(btTransform::getIdentity(), lo, hi);
                    v = double((hi - lo).x() * (hi - lo).y() * (hi - lo).z());
                }
                vol.push_back(v);
                total += v;
            }
            Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
            for (size_t i = 0; i < kids.size(); ++i) {
                double m = total > 0 ? b.mass * vol[i] / total : b.mass / double(kids.size());
                btVector3 li;
                kids[i].shape->calculateLocalInertia(btScalar(m), li);
                add_inertia(tensor, kids[i].in_com, Eigen::Vector3d(li.x(), li.y(), li.z()), m, Eigen::Vector3d::Zero());
            }
            Eigen::Vector3d moments;
            std::tie(moments, principal) = principal_axes(tensor);
            out.inertia = btVector3(btScalar(moments.x()), btScalar(moments.y()), btScalar(moments.z()));
        }
    }

    Eigen::Quaterniond pq(principal);
    const Pose rot{{0, 0, 0}, {pq.x(), pq.y(), pq.z(), pq.w()}};
    out.local = to_bt(pmul(b.com, rot));

    if (kids.size() == 1 && is_identity(pmul(pinv(rot), kids[0].in_com), 1e-9)) {
        out.shape = kids[0].shape;
        return out;
    }
    out.shape = compound_in(g, b, pmul(b.com, rot));
    return out;
}

// The body's shapes placed in `frame` (Bullet's frame of the body, in its body frame).
btCollisionShape* ShapeCache::compound_in(const Graph& g, const Body& b, const Pose& frame) {
    const Pose to_frame = pinv(frame);
    std::vector<double> key{-1.0, double(b.shape_num)};
    std::vector<std::pair<btCollisionShape*, btTransform>> parts;
    for (int32_t i = 0; i < b.shape_num; ++i) {
        const Shape& s = g.shapes[b.shape_adr + i];
        const Pose local = pmul(to_frame, s.local);
        for (double v : primitive_key(g, s)) key.push_back(v);
        key.insert(key.end(), local.p.begin(), local.p.end());
        key.insert(key.end(), local.q.begin(), local.q.end());
        parts.emplace_back(primitive(g, s), to_bt(local));
    }
    return compound(key, parts);
}

BodyShape ShapeCache::build_welded(const Graph& g, const Body& host, const Body& pass, const Pose& rel) {
    const BodyShape hs = build(g, host), ps = build(g, pass);
    const Pose at_h = from_bt(hs.local), at_p = pmul(rel, from_bt(ps.local));  // in the host's frame
    BodyShape out;
    out.mass = hs.mass + ps.mass;
    const Eigen::Vector3d c = (hs.mass * vec(at_h.p) + ps.mass * vec(at_p.p)) / out.mass;
    Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
    add_inertia(tensor, at_h, Eigen::Vector3d(hs.inertia.x(), hs.inertia.y(), hs.inertia.z()), hs.mass, c);
    add_inertia(tensor, at_p, Eigen::Vector3d(ps.inertia.x(), ps.inertia.y(), ps.inertia.z()), ps.mass, c);
    const auto [moments, axes] = principal_axes(tensor);
    out.inertia = btVector3(btScalar(moments.x()), btScalar(moments.y()), btScalar(moments.z()));
    const Eigen::Quaterniond q(axes);
    const Pose com{{c.x(), c.y(), c.z()}, {q.x(), q.y(), q.z(), q.w()}};
    out.local = to_bt(com);
    // The host's shapes about the common centre of mass (the passenger takes no collisions):
    // a lone hull moved there, not wrapped in a compound.
    const Shape& first = g.shapes[host.shape_adr.first()];
    out.shape = host.shape_num == 1 && first.kind == ShapeKind::Hull ? hull(g, first, pmul(pinv(com), first.local))
                                                                      : compound_in(g, host, com);
    return out;
}

}  // namespace plant::engine
