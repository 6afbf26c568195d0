// What bounds a convex shape's reach in (x, y) (runtime/engine/shapes.h: measure_reach,
// reach_bound), which steady transport keeps clear of a curve's rails and a funnel's outline
// with: never less than the reach of the shape's points however it is turned, and for a bottle
// tilted by at most 2 degrees (steady transport's own bound) within 0.3 mm of it; a box's
// (whose margin Bullet adds as a larger box) holds too.
#include "engine/shapes.h"

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

using plant::engine::measure_reach;
using plant::engine::reach_bound;

namespace {

// std.bottle's hull (an octagonal prism, r = 2 cm, h = 8 cm, margin 1 mm), its points moved by
// `off` (a welded bottle's hull lies off the pair's centre of mass) and turned by `turn` (a
// principal frame whose axes are not the bottle's).
std::unique_ptr<btConvexHullShape> bottle_hull(const btVector3& off, const btMatrix3x3& turn) {
    auto hull = std::make_unique<btConvexHullShape>();
    const btScalar r = 0.02f, h = 0.08f, c = 0.7071f;
    const btScalar ring[8][2] = {{r, 0}, {r * c, r * c}, {0, r}, {-r * c, r * c},
                                 {-r, 0}, {-r * c, -r * c}, {0, -r}, {r * c, -r * c}};
    for (btScalar z : {-h / 2, h / 2})
        for (auto& p : ring) hull->addPoint(turn * (btVector3(p[0], p[1], z) + off), false);
    hull->setMargin(0.001f);
    hull->recalcLocalAabb();
    return hull;
}

// The shape's reach turned by `basis`: the largest of its extents (with the margin) along 720
// horizontal directions; the true reach is within 0.001 % above it.
btScalar reach_of(const btConvexShape& shape, const btMatrix3x3& basis) {
    btScalar best = 0;
    for (int i = 0; i < 720; ++i) {
        const btScalar a = btScalar(i) * SIMD_PI / 360;
        const btVector3 d(std::cos(a), std::sin(a), 0);
        best = std::max(best, (basis * shape.localGetSupportingVertex(d * basis)).dot(d));
    }
    return best;
}

btMatrix3x3 random_turn(std::mt19937& rng, btScalar max_tilt) {
    std::uniform_real_distribution<btScalar> u(0, 1);
    const btScalar yaw = 2 * SIMD_PI * u(rng), dir = 2 * SIMD_PI * u(rng);
    // max_tilt >= pi: any turn (a tilt whose cosine is uniform)
    const btScalar tilt = max_tilt >= SIMD_PI ? std::acos(1 - 2 * u(rng)) : max_tilt * u(rng);
    btMatrix3x3 m;
    m.setRotation(btQuaternion(btVector3(std::cos(dir), std::sin(dir), 0), tilt) * btQuaternion(btVector3(0, 0, 1), yaw));
    return m;
}

}  // namespace

TEST_CASE("shapes: a convex shape's reach bound holds however it turns, and is tight for an upright bottle") {
    std::mt19937 rng(7);
    const btScalar two_degrees = btScalar(2 * SIMD_PI / 180);
    btMatrix3x3 lying;  // the bottle's axis along the local x
    lying.setRotation(btQuaternion(btVector3(0, 1, 0), SIMD_HALF_PI));
    struct Case {
        const char* name;
        std::unique_ptr<btConvexHullShape> hull;
        bool lying, centred;  // its axis along the local x; its axis through the centre
    };
    std::vector<Case> hulls;
    hulls.push_back({"bottle", bottle_hull(btVector3(0, 0, 0), btMatrix3x3::getIdentity()), false, true});
    hulls.push_back({"bottle off its centre", bottle_hull(btVector3(0.003f, -0.002f, 0.011f), btMatrix3x3::getIdentity()),
                     false, false});
    hulls.push_back({"bottle along local x", bottle_hull(btVector3(0, 0, 0.011f), lying), true, true});
    for (const Case& c : hulls) {
        CAPTURE(c.name);
        const auto m = measure_reach(*c.hull);
        for (int i = 0; i < 400; ++i) {
            const btMatrix3x3 any = random_turn(rng, SIMD_PI);
            CHECK(reach_bound(m, any) >= reach_of(*c.hull, any) - btScalar(1e-6));
        }
        for (int i = 0; i < 400; ++i) {
            // Upright within 2 degrees: the bottle's own axis near the vertical.
            const btMatrix3x3 up = random_turn(rng, two_degrees) * (c.lying ? lying.transpose() : btMatrix3x3::getIdentity());
            const btScalar exact = reach_of(*c.hull, up);
            CHECK(reach_bound(m, up) >= exact - btScalar(1e-6));
            if (c.centred) CHECK(reach_bound(m, up) <= exact + btScalar(0.0003));
        }
    }
    // Primitives: the bound holds for a sphere, a box and a cylinder however they turn; an
    // upright sphere's and cylinder's is their radius (within the 64 directions' 0.12 %).
    btSphereShape ball(0.03f);
    btBoxShape box(btVector3(0.05f, 0.02f, 0.01f));
    btCylinderShapeZ can(btVector3(0.03f, 0.03f, 0.06f));
    const auto mb = measure_reach(ball), mx = measure_reach(box), mc = measure_reach(can);
    for (int i = 0; i < 200; ++i) {
        const btMatrix3x3 any = random_turn(rng, SIMD_PI);
        CHECK(reach_bound(mb, any) >= btScalar(0.03));
        CHECK(reach_bound(mx, any) >= reach_of(box, any) - btScalar(1e-6));
        CHECK(reach_bound(mc, any) >= reach_of(can, any) - btScalar(1e-6));
    }
    for (const auto* m : {&mb, &mc}) {
        CHECK(reach_bound(*m, btMatrix3x3::getIdentity()) >= btScalar(0.03));
        CHECK(reach_bound(*m, btMatrix3x3::getIdentity()) <= btScalar(0.03 * 1.0013));
    }
}
