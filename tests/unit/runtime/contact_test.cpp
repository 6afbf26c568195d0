// Box against hull (runtime/engine/contact.cpp): the contacts of Bullet's own polyhedral path,
// for both orders of the pair, a box inside a compound, closest-point queries, random poses
// and a bottle sliding over a band step after step (persistent manifolds).
#include "engine/contact.h"

#include <BulletCollision/CollisionDispatch/btConvexConvexAlgorithm.h>
#include <btBulletCollisionCommon.h>
#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

using plant::engine::BoxHullContacts;

namespace {

// std.bottle's hull: an octagonal prism, r = 2 cm, h = 8 cm, margin 1 mm (runtime/engine/shapes.cpp).
std::unique_ptr<btConvexHullShape> bottle_hull() {
    auto hull = std::make_unique<btConvexHullShape>();
    const btScalar r = 0.02f, h = 0.08f, c = 0.7071f;
    const btScalar ring[8][2] = {{r, 0}, {r * c, r * c}, {0, r}, {-r * c, r * c},
                                 {-r, 0}, {-r * c, -r * c}, {0, -r}, {r * c, -r * c}};
    for (btScalar z : {-h / 2, h / 2})
        for (auto& p : ring) hull->addPoint(btVector3(p[0], p[1], z), false);
    hull->optimizeConvexHull();
    hull->setMargin(0.001f);
    hull->recalcLocalAabb();
    hull->initializePolyhedralFeatures();
    return hull;
}

// A belt's band: 1 m x 8 cm x 1 cm.
std::unique_ptr<btBoxShape> band_box(bool polyhedral = true) {
    auto box = std::make_unique<btBoxShape>(btVector3(0.5f, 0.04f, 0.005f));
    if (polyhedral) box->initializePolyhedralFeatures();
    return box;
}

struct Contact {
    btVector3 normal, on_b;
    btScalar distance;
};

// A dispatcher set up as the runtime's, with our algorithm or with Bullet's.
struct Narrowphase {
    explicit Narrowphase(bool ours) {
        info.m_enableSatConvex = true;
        if (!ours) return;
        contacts = std::make_unique<BoxHullContacts>();
        contacts->attach(dispatcher, config);
    }
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    std::unique_ptr<BoxHullContacts> contacts;
    btDispatcherInfo info;
};

// One pair's algorithm, kept over steps like the broadphase keeps it.
class Pair {
public:
    Pair(Narrowphase& np, const btCollisionObject& o0, const btCollisionObject& o1,
         ebtDispatcherQueryType query = BT_CONTACT_POINT_ALGORITHMS)
        : np_(np), o0_(o0), o1_(o1), query_(query) {
        btCollisionObjectWrapper w0(nullptr, o0.getCollisionShape(), &o0, o0.getWorldTransform(), -1, -1);
        btCollisionObjectWrapper w1(nullptr, o1.getCollisionShape(), &o1, o1.getWorldTransform(), -1, -1);
        algo_ = np.dispatcher.findAlgorithm(&w0, &w1, nullptr, query);
    }
    ~Pair() {
        algo_->~btCollisionAlgorithm();
        np_.dispatcher.freeCollisionAlgorithm(algo_);
    }
    Pair(const Pair&) = delete;
    Pair& operator=(const Pair&) = delete;

    btCollisionAlgorithm& algorithm() { return *algo_; }

    std::vector<Contact> step() {
        btCollisionObjectWrapper w0(nullptr, o0_.getCollisionShape(), &o0_, o0_.getWorldTransform(), -1, -1);
        btCollisionObjectWrapper w1(nullptr, o1_.getCollisionShape(), &o1_, o1_.getWorldTransform(), -1, -1);
        btManifoldResult result(&w0, &w1);
        if (query_ == BT_CLOSEST_POINT_ALGORITHMS) result.m_closestPointDistanceThreshold = 0.01f;
        algo_->processCollision(&w0, &w1, np_.info, &result);
        btManifoldArray manifolds;
        algo_->getAllContactManifolds(manifolds);
        std::vector<Contact> out;
        for (int m = 0; m < manifolds.size(); ++m)
            for (int i = 0; i < manifolds[m]->getNumContacts(); ++i) {
                const btManifoldPoint& p = manifolds[m]->getContactPoint(i);
                out.push_back({p.m_normalWorldOnB, p.m_positionWorldOnB, p.getDistance()});
            }
        return out;
    }

private:
    Narrowphase& np_;
    const btCollisionObject& o0_;
    const btCollisionObject& o1_;
    ebtDispatcherQueryType query_;
    btCollisionAlgorithm* algo_;
};

// How the two algorithms' contacts compared over a run of poses.
struct Tally {
    int poses = 0, touching = 0, identical = 0, close = 0;

    void add(const std::vector<Contact>& bullet, const std::vector<Contact>& ours) {
        ++poses;
        touching += !bullet.empty();
        if (bullet.size() != ours.size()) return;
        bool same = true, near = true;
        for (size_t i = 0; i < bullet.size(); ++i) {
            const Contact &b = bullet[i], &o = ours[i];
            same = same && b.normal == o.normal && b.on_b == o.on_b && b.distance == o.distance;
            // Where two axes overlap equally to within rounding, either may win (contact.cpp).
            near = near && (b.normal - o.normal).length() < 1e-5f && (b.on_b - o.on_b).length() < 1e-6f &&
                   std::abs(b.distance - o.distance) < 1e-7f;
        }
        identical += same;
        close += near;
    }
    void check(int min_touching) const {
        CHECK(touching >= min_touching);  // the poses reach the clipping
        CHECK(close == poses);
        CHECK(identical >= poses * 99 / 100);  // bit for bit nearly always
    }
};

// Random poses of a bottle around a band whose top is at z = 0.005 (in the band's frame):
// standing on it (tilted a little or not at all, over its ends and sides too), and any
// orientation anywhere near it (faces, edges and corners in contact, deep, or apart).
class Poses {
public:
    explicit Poses(unsigned seed) : rng_(seed) {}

    btTransform standing(btScalar max_tilt) {
        const btScalar yaw = uni(0, 6.2832f), tilt = uni(0, max_tilt), dir = uni(0, 6.2832f);
        btQuaternion q(btVector3(0, 0, 1), yaw);
        if (tilt > 0) q = btQuaternion(btVector3(std::cos(dir), std::sin(dir), 0), tilt) * q;
        const btScalar sink = uni(-0.0005f, 0.001f);
        return btTransform(q, btVector3(uni(-0.55f, 0.55f), uni(-0.07f, 0.07f), 0.005f + 0.04f - sink));
    }
    btTransform upright() {
        const btScalar sink = uni(0, 0.001f);
        return btTransform(btQuaternion::getIdentity(), btVector3(uni(-0.4f, 0.4f), uni(-0.02f, 0.02f), 0.045f - sink));
    }
    btTransform anywhere() {
        btQuaternion q(uni(-1, 1), uni(-1, 1), uni(-1, 1), uni(-1, 1));
        q.normalize();
        return btTransform(q, btVector3(uni(-0.6f, 0.6f), uni(-0.1f, 0.1f), uni(-0.06f, 0.06f)));
    }

private:
    btScalar uni(btScalar lo, btScalar hi) { return std::uniform_real_distribution<btScalar>(lo, hi)(rng_); }
    std::mt19937 rng_;
};

// Where the band is in the world (away from the origin, turned about z, as in a plant).
const btTransform kBand(btQuaternion(btVector3(0, 0, 1), 0.3f), btVector3(3, -2, 0.8f));

struct Scene {
    std::unique_ptr<btBoxShape> box = band_box();
    std::unique_ptr<btConvexHullShape> hull = bottle_hull();
    btCompoundShape compound{false};  // the band as the runtime builds it: a box at an offset
    btCollisionObject band, bottle;
    Scene(bool in_compound) {
        const btTransform offset(btQuaternion::getIdentity(), btVector3(0.1f, 0, -0.005f));
        compound.addChildShape(offset, box.get());
        band.setCollisionShape(in_compound ? static_cast<btCollisionShape*>(&compound) : box.get());
        band.setWorldTransform(in_compound ? kBand * offset.inverse() : kBand);
        bottle.setCollisionShape(hull.get());
    }
};

// Both algorithms over `n` poses, a new pair for each.
Tally compare(Scene& s, bool box_first, ebtDispatcherQueryType query, int n) {
    Narrowphase bullet(false), ours(true);
    Poses poses(box_first ? 7 : 11);
    Tally tally;
    for (int k = 0; k < n; ++k) {
        const int kind = k % 3;
        s.bottle.setWorldTransform(kBand * (kind == 0   ? poses.standing(0.03f)
                                            : kind == 1 ? poses.upright()
                                                        : poses.anywhere()));
        const btCollisionObject& o0 = box_first ? s.band : s.bottle;
        const btCollisionObject& o1 = box_first ? s.bottle : s.band;
        Pair theirs(bullet, o0, o1, query), mine(ours, o0, o1, query);
        tally.add(theirs.step(), mine.step());
    }
    return tally;
}

}  // namespace

TEST_CASE("contact: box against hull gives Bullet's contacts, both orders, plain and in a compound") {
    for (bool in_compound : {false, true})
        for (bool box_first : {true, false}) {
            Scene s(in_compound);
            CAPTURE(in_compound);
            CAPTURE(box_first);
            compare(s, box_first, BT_CONTACT_POINT_ALGORITHMS, 3000).check(1000);
        }
}

TEST_CASE("contact: closest-point queries give Bullet's points too") {
    for (bool box_first : {true, false}) {
        Scene s(false);
        CAPTURE(box_first);
        compare(s, box_first, BT_CLOSEST_POINT_ALGORITHMS, 600).check(200);
    }
}

TEST_CASE("contact: a bottle sliding and rocking over a band keeps Bullet's manifold, step by step") {
    for (bool box_first : {true, false}) {
        Scene s(false);
        Narrowphase bullet(false), ours(true);
        const btCollisionObject& o0 = box_first ? s.band : s.bottle;
        const btCollisionObject& o1 = box_first ? s.bottle : s.band;
        Pair theirs(bullet, o0, o1), mine(ours, o0, o1);
        Tally tally;
        for (int i = 0; i < 600; ++i) {
            const btScalar t = btScalar(i) / 150;  // 4 s at 150 Hz, from x = -0.6 m to +0.6 m
            const btQuaternion rock(btVector3(std::cos(3 * t), std::sin(3 * t), 0), 0.05f * std::sin(5 * t));
            const btScalar sink = 0.0005f * (1 + std::sin(7 * t));
            s.bottle.setWorldTransform(kBand * btTransform(rock, btVector3(-0.6f + 0.3f * t, 0.01f, 0.045f - sink)));
            tally.add(theirs.step(), mine.step());
        }
        CAPTURE(box_first);
        tally.check(400);
    }
}

TEST_CASE("contact: the algorithm is ours for polyhedra, Bullet's for a box without polyhedral features") {
    Narrowphase np(true);
    auto hull = bottle_hull();
    auto plain = band_box(false), polyhedral = band_box(true);
    btCollisionObject bottle, with, without;
    bottle.setCollisionShape(hull.get());
    with.setCollisionShape(polyhedral.get());
    without.setCollisionShape(plain.get());
    Pair ours(np, with, bottle), reverse(np, bottle, with), fallback(np, without, bottle);
    CHECK(dynamic_cast<btConvexConvexAlgorithm*>(&ours.algorithm()) == nullptr);
    CHECK(dynamic_cast<btConvexConvexAlgorithm*>(&reverse.algorithm()) == nullptr);
    CHECK(dynamic_cast<btConvexConvexAlgorithm*>(&fallback.algorithm()) != nullptr);
}

// Where two axes overlap equally to within Bullet's rounding, Bullet and we may pick either
// (contact.cpp). Then the normals differ by at most the angle between the axes, the clipped
// points (up to 4 of them kept, which depends on their order) lie on the same contact, and
// the deepest is as deep; where the least overlap is that close to 0, one may find the pair
// apart and the other barely touching.
bool tied(const std::vector<Contact>& bullet, const std::vector<Contact>& ours, btScalar max_angle) {
    auto deepest = [](const std::vector<Contact>& v) {
        btScalar d = BT_LARGE_FLOAT;
        for (const Contact& c : v) d = std::min(d, c.distance);
        return d;
    };
    if (bullet.empty() || ours.empty()) return deepest(bullet.empty() ? ours : bullet) > -1e-5f;
    const btScalar sine = bullet[0].normal.cross(ours[0].normal).length();  // precise where acos is not
    return sine <= max_angle && std::abs(deepest(bullet) - deepest(ours)) < 1e-6f;
}

TEST_CASE("contact: a bottle against a rail far from the origin: Bullet's contacts, or a tied axis' normal") {
    // A guide rail (5 mm x 4 cm) 17 m from the origin, its bottom edge level with the bottle's
    // bottom, as in the plant: the rail's face and the edge pairs of its bottom edge with the
    // bottle's side edges then overlap equally, and Bullet's float world coordinates resolve
    // overlaps to about 1e-6 m there.
    btBoxShape rail(btVector3(0.5f, 0.0025f, 0.02f));
    rail.initializePolyhedralFeatures();
    auto hull = bottle_hull();
    btCollisionObject guide, bottle;
    guide.setCollisionShape(&rail);
    bottle.setCollisionShape(hull.get());
    const btTransform at(btQuaternion(btVector3(0, 0, 1), 0.3f), btVector3(10, 14, 0.02f));
    guide.setWorldTransform(at);
    Narrowphase bullet(false), ours(true);
    std::mt19937 rng(5);
    auto uni = [&](btScalar lo, btScalar hi) { return std::uniform_real_distribution<btScalar>(lo, hi)(rng); };
    Tally tally;
    int ties = 0;
    for (int k = 0; k < 3000; ++k) {
        const btScalar yaw = uni(0, 6.2832f), tilt = uni(0, 0.03f), dir = uni(0, 6.2832f);
        const btQuaternion q = btQuaternion(btVector3(std::cos(dir), std::sin(dir), 0), tilt) *
                               btQuaternion(btVector3(0, 0, 1), yaw);
        const btScalar y = 0.0025f + 0.0195f - uni(-0.0003f, 0.001f);  // the bottle's side in the rail
        bottle.setWorldTransform(at * btTransform(q, btVector3(uni(-0.4f, 0.4f), y, 0.02f)));
        Pair theirs(bullet, guide, bottle), mine(ours, guide, bottle);
        const std::vector<Contact> want = theirs.step(), got = mine.step();
        const int before = tally.identical;
        tally.add(want, got);
        ties += tally.identical == before && tied(want, got, tilt + 1e-6f);
    }
    CHECK(tally.touching > 2000);
    CHECK(tally.identical >= tally.poses * 95 / 100);
    CHECK(tally.identical + ties == tally.poses);
    MESSAGE(tally.identical, " of ", tally.poses, " poses identical, ", ties, " tied");
}

TEST_CASE("contact: a hull without volume given polyhedral features gets GJK's contacts, no crash") {
    // The loader refuses such hulls and the runtime builds them without polyhedral features;
    // the algorithm still does not trust its input: a hull of points on a line or in a
    // plane has no faces for Bullet's clipping to index.
    const std::vector<std::vector<btVector3>> flat_hulls = {
        {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}},
        {{0, 0, 0}, {0.01f, 0, 0}, {0.02f, 0, 0}, {0.03f, 0, 0}},
        {{0, 0, 0}, {0.02f, 0, 0}, {0, 0.02f, 0}, {0.02f, 0.02f, 0}},
    };
    for (const auto& points : flat_hulls) {
        CAPTURE(points[1].x());
        btConvexHullShape hull;
        for (const btVector3& p : points) hull.addPoint(p, false);
        hull.optimizeConvexHull();
        hull.setMargin(0.001f);
        hull.recalcLocalAabb();
        hull.initializePolyhedralFeatures();
        CHECK_FALSE(plant::engine::solid_polyhedron(*hull.getConvexPolyhedron()));
        auto box = band_box();
        btCollisionObject band, blob;
        band.setCollisionShape(box.get());
        blob.setCollisionShape(&hull);
        for (bool box_first : {true, false}) {
            CAPTURE(box_first);
            Narrowphase np(true);
            // Resting on the band's top (z = 0.005) with its margin sunk 0.5 mm into it.
            blob.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 0.0055f)));
            Pair pair(np, box_first ? band : blob, box_first ? blob : band);
            const std::vector<Contact> touching = pair.step();
            REQUIRE(!touching.empty());
            CHECK(touching[0].distance < 0);  // about -0.5 mm
            CHECK(touching[0].distance > -0.001f);
            blob.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 0.1f)));
            CHECK(pair.step().empty());  // 9 cm apart
        }
    }
}
