// Collision shapes and mass properties of bodies. Equal shapes are built once and
// shared (a pool of 500 bottles has one hull and one compound), and owned here.
#pragma once

#include "graph/graph.h"

#include <BulletCollision/CollisionShapes/btCollisionShape.h>
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

private:
    btCollisionShape* primitive(const graph::Graph& g, const graph::Shape& s);
    btCollisionShape* hull(const graph::Graph& g, const graph::Shape& s, const graph::Pose& to);
    btCollisionShape* compound_in(const graph::Graph& g, const graph::Body& b, const graph::Pose& frame);
    btCollisionShape* compound(const std::vector<double>& key,
                               const std::vector<std::pair<btCollisionShape*, btTransform>>& kids);
    std::map<std::vector<double>, btCollisionShape*> cache_;
    std::vector<std::unique_ptr<btCollisionShape>> owned_;  // creation order; freed in reverse
};

}  // namespace plant::engine
