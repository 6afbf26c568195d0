// Collision shapes and mass properties of bodies. Equal shapes are built once and
// shared (a pool of 500 bottles has one hull and one compound), and owned here.
#pragma once

#include "graph/graph.h"

#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <LinearMath/btTransform.h>

#include <map>
#include <memory>
#include <vector>

namespace plant::engine {

// Hull margin: Bullet's default of 4 cm is larger than a bottle; 1 mm keeps the
// surface where the hull points are (the margin lies outside them) at low cost.
constexpr double kHullMargin = 0.001;

// What Bullet needs to create a body. Bullet's body frame is the principal frame at
// the centre of mass: `local` places it relative to our body frame.
struct BodyShape {
    btCollisionShape* shape = nullptr;
    btTransform local = btTransform::getIdentity();
    btVector3 inertia{0, 0, 0};  // principal moments, 0 for static and kinematic bodies
    double mass = 0;
};

// What bounds a convex shape's reach in (x, y) about its centre of mass however it turns
// (steady transport's outline_clear), about each of its local axes k: the largest distance of its
// points (the shape with its margin, as Bullet's supporting vertices give it) from that axis
// (rho[k]) and along it (along[k]).
struct ShapeReach {
    btScalar rho[3] = {0, 0, 0}, along[3] = {0, 0, 0};
};
// Measures it: about each local axis, the largest of the shape's extents along 64 directions
// square to it over cos(pi/64) (which bounds the extents between them), and its extent along
// it both ways.
ShapeReach measure_reach(const btConvexShape& shape);
// The largest distance in (x, y) of the shape's points from its centre, turned by `basis`: at
// most rho[k] + along[k] sin(t), for the local axis k nearest the vertical and t its tilt from
// it (a point's distance from the vertical through the centre is at most its distance from that
// axis plus its length along it times sin(t)). Upright about an axis it is round about, within
// 0.12 % of it (the 64 directions).
inline btScalar reach_bound(const ShapeReach& m, const btMatrix3x3& basis) {
    const btVector3 up = basis[2];  // the world's z in local axes
    const int k = up.absolute().maxAxis();
    const btScalar sin_t = btSqrt(btMax(btScalar(1) - up[k] * up[k], btScalar(0)));
    return m.rho[k] + m.along[k] * sin_t;
}

class ShapeCache {
public:
    ShapeCache() = default;
    ~ShapeCache();
    ShapeCache(const ShapeCache&) = delete;
    ShapeCache& operator=(const ShapeCache&) = delete;

    BodyShape build(const graph::Graph& g, const graph::Body& b);
    // Two bodies welded together as one Bullet body: the host's shapes and both masses
    // about their common centre of mass, in the host's body frame. `rel` is the
    // passenger's body frame in the host's; the passenger takes no collisions.
    BodyShape build_welded(const graph::Graph& g, const graph::Body& host, const graph::Body& pass,
                           const graph::Pose& rel);

    // A convex shape's ShapeReach, measured when it was made (its user index says where),
    // or null for a shape this cache did not make convex.
    const ShapeReach* reach(const btCollisionShape& s) const {
        const int i = s.getUserIndex();
        return i >= 0 && size_t(i) < reach_.size() ? &reach_[size_t(i)] : nullptr;
    }

private:
    btCollisionShape* keep(std::unique_ptr<btCollisionShape> shape, std::vector<double> key);
    btCollisionShape* primitive(const graph::Graph& g, const graph::Shape& s);
    btCollisionShape* hull(const graph::Graph& g, const graph::Shape& s, const graph::Pose& to);
    btCollisionShape* compound_in(const graph::Graph& g, const graph::Body& b, const graph::Pose& frame);
    btCollisionShape* compound(const std::vector<double>& key,
                               const std::vector<std::pair<btCollisionShape*, btTransform>>& kids);
    std::map<std::vector<double>, btCollisionShape*> cache_;
    std::vector<std::unique_ptr<btCollisionShape>> owned_;  // creation order; freed in reverse
    std::vector<ShapeReach> reach_;                         // per convex shape made (its user index)
};

}  // namespace plant::engine
