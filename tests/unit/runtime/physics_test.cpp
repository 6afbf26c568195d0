// Bodies, the conveyor law, collision and dynamics toggles, constraints.
#include "engine/engine.h"
#include "engine/pose.h"
#include "engine/runtime.h"
#include "scene_builder.h"

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

using namespace plant::test;
using plant::engine::Engine;

namespace {

// A frictionless floor (top at z = 0) and a belt field over it along +x.
int32_t floor_and_belt(SceneBuilder& b, double speed, double gain) {
    b.body(0, "floor", BodyMode::Static, {box({20, 20, 0.2})}, 0, at(0, 0, -0.1));
    return b.field(0, "belt", {20, 2, 0.5}, at(0, 0, 0.25), {1, 0, 0}, speed, gain);
}

// A bottle of two bodies standing on the floor: a cylinder and a small sphere at the centre
// of its bottom (0.5 mm above the floor), joined by a fixed joint.
struct TwoBodyBottle {
    int32_t main, foot, joint;
};
TwoBodyBottle two_body_bottle(SceneBuilder& b, double m_main, double m_foot, double foot_radius, bool foot_collides,
                              double x = 0) {
    const int32_t d = b.dobj("bottle");
    const double main_z = 0.0505, foot_z = foot_radius + 0.0005;
    TwoBodyBottle t;
    t.main = b.body(d, "main", BodyMode::Dynamic, {cylinder(0.02, 0.1)}, m_main, at(x, 0, main_z));
    t.foot = b.body(d, "foot", BodyMode::Dynamic, {sphere(foot_radius)}, m_foot, at(x, 0, foot_z));
    b.g.bodies[plant::graph::BodyId(t.foot)].collision = foot_collides;
    t.joint = b.joint(d, "fix", JointKind::Fixed, t.main, t.foot, at(0, 0, foot_z - main_z), at(0, 0, 0));
    return t;
}

// The angle between a body's z axis and the vertical (rad).
double tilt(const plant::graph::Quat& q) { return 2 * std::asin(std::min(1.0, std::sqrt(q[0] * q[0] + q[1] * q[1]))); }

}  // namespace

TEST_CASE("runtime: conveyor law against its analytic solution on a frictionless plane") {
    for (auto [mass, gain] : {std::pair{1.0, 4.0}, std::pair{0.2, 1.0}, std::pair{0.02, 16.0}}) {
        SceneBuilder b;
        floor_and_belt(b, 0.5, gain);
        int32_t cube = b.body(b.dobj("cube"), "body", BodyMode::Dynamic, {box({0.05, 0.05, 0.05})}, mass,
                              at(0, 0, 0.025));
        Engine e(b.g);
        double worst = 0;
        for (int i = 0; i < 300; ++i) {
            e.step();
            const double want = 0.5 * (1 - std::exp(-gain * e.time() / mass));
            worst = std::max(worst, std::abs(e.body_velocity(plant::graph::BodyId(cube))[0] - want) / 0.5);
        }
        CAPTURE(mass);
        CAPTURE(gain);
        CHECK(worst < 0.01);  // within 1 % of the target speed at every step
        CHECK(std::abs(e.body_velocity(plant::graph::BodyId(cube))[1]) < 1e-6);
    }
}

TEST_CASE("runtime: a field rotated in the world pushes along its own direction, only inside its box") {
    SceneBuilder b;
    b.g.settings.gravity = {0, 0, 0};
    Pose rot = at(0, 0, 0);
    rot.q = {0, 0, std::sin(M_PI / 4), std::cos(M_PI / 4)};  // +90 deg about z: local x is world y
    b.field(0, "f", {1, 1, 1}, rot, {1, 0, 0}, 0.3, 16);
    int32_t in = b.body(b.dobj("in"), "body", BodyMode::Dynamic, {sphere(0.02)}, 0.05, at(0, 0, 0));
    int32_t out = b.body(b.dobj("out"), "body", BodyMode::Dynamic, {sphere(0.02)}, 0.05, at(3, 0, 0));
    Engine e(b.g);
    for (int i = 0; i < 30; ++i) e.step();
    CHECK(e.body_velocity(plant::graph::BodyId(in))[1] == doctest::Approx(0.3).epsilon(0.01));
    CHECK(std::abs(e.body_velocity(plant::graph::BodyId(in))[0]) < 1e-6);
    CHECK(e.body_velocity(plant::graph::BodyId(out))[0] == 0);
}

TEST_CASE("runtime: a light bottle with a bottom body stays stable on a fast belt at 150 Hz") {
    SceneBuilder b;
    floor_and_belt(b, 1.0, 16);
    const int32_t main = two_body_bottle(b, 0.02, 0.002, 0.004, true).main;
    Engine e(b.g);
    double peak = 0;
    for (int i = 0; i < 150; ++i) {
        e.step();
        peak = std::max(peak, tilt(e.body_pose(plant::graph::BodyId(main)).q));
    }
    CHECK(std::isfinite(e.body_com(plant::graph::BodyId(main))[0]));
    CHECK(e.warnings().total() == 0);
    CHECK(peak > 0.01);  // the foot pulls at the bottom: the bottle tips
    const auto v = e.body_velocity(plant::graph::BodyId(main));
    CHECK(std::abs(v[0]) < 2.0);
}

TEST_CASE("runtime: welds alike share what their pair is, and each pair still has its own mass") {
    SceneBuilder b;
    floor_and_belt(b, 1.0, 16);
    // Three bottles alike at different places, and one whose foot is heavier.
    std::vector<TwoBodyBottle> bottles;
    for (int i = 0; i < 3; ++i) bottles.push_back(two_body_bottle(b, 0.036, 0.004, 0.003, false, -1.0 + 0.2 * i));
    bottles.push_back(two_body_bottle(b, 0.036, 0.014, 0.003, false, -0.2));
    Engine e(b.g);
    auto& phys = e.internals().phys;
    CHECK(phys.weld_count() == 4);
    CHECK(phys.weld_shape_count() == 2);
    for (int i = 0; i < 60; ++i) e.step();
    for (size_t k = 0; k < bottles.size(); ++k) {
        CAPTURE(k);
        const plant::graph::BodyId main(bottles[k].main), foot(bottles[k].foot);
        REQUIRE(phys.welded(main));
        CHECK(phys.rb(main).getMass() == doctest::Approx(k < 3 ? 0.040 : 0.050));
        // Each foot where its own joint holds it, beside its own main body.
        const Pose want = plant::engine::pmul(e.body_pose(main), b.g.joints[plant::graph::JointId(bottles[k].joint)].frame_a);
        for (int c = 0; c < 3; ++c) CHECK(e.body_pose(foot).p[c] == doctest::Approx(want.p[c]).epsilon(1e-5));
        // The host's own centre of mass, its cylinder's centre (the body's origin), not the
        // pair's (4.7 mm lower along its axis for the light feet, 13.2 mm for the heavy one).
        for (int c = 0; c < 3; ++c) CHECK(std::abs(e.body_com(main)[c] - e.body_pose(main).p[c]) < 1e-5);
    }
}

TEST_CASE("runtime: a bottom body without collisions rides welded to its main body, and leaves when the joint lets go") {
    SceneBuilder b;
    floor_and_belt(b, 1.0, 16);
    const auto [main, foot, j] = two_body_bottle(b, 0.036, 0.004, 0.003, false);
    Engine e(b.g);
    auto& phys = e.internals().phys;
    double peak = 0;
    for (int i = 0; i < 150; ++i) {
        e.step();
        peak = std::max(peak, tilt(e.body_pose(plant::graph::BodyId(main)).q));
        // The foot is where the joint holds it and moves with the main body's rigid motion.
        const Pose want = plant::engine::pmul(e.body_pose(plant::graph::BodyId(main)), b.g.joints[plant::graph::JointId(j)].frame_a);
        const auto vm = e.body_velocity(plant::graph::BodyId(main)), vf = e.body_velocity(plant::graph::BodyId(foot)),
                   w = e.body_angular_velocity(plant::graph::BodyId(main));
        const Vec3 r = plant::engine::sub(e.body_com(plant::graph::BodyId(foot)), e.body_com(plant::graph::BodyId(main)));
        for (int k = 0; k < 3; ++k) {
            REQUIRE(e.body_pose(plant::graph::BodyId(foot)).p[k] == doctest::Approx(want.p[k]).epsilon(1e-5));
            const double cross = w[(k + 1) % 3] * r[(k + 2) % 3] - w[(k + 2) % 3] * r[(k + 1) % 3];
            REQUIRE(vf[k] == doctest::Approx(vm[k] + cross).epsilon(1e-5));
        }
    }
    CHECK(phys.welded(plant::graph::BodyId(main)));
    CHECK(phys.welded(plant::graph::BodyId(foot)));
    CHECK(phys.world().getNumCollisionObjects() == 2);  // the floor and the bottle: one Bullet body
    CHECK(phys.world().getNumConstraints() == 0);
    CHECK(peak > 0.01);  // the belt still pulls at the foot: the bottle tips
    CHECK(e.body_velocity(plant::graph::BodyId(main))[0] == doctest::Approx(1.0).epsilon(0.01));
    CHECK(e.body_velocity(plant::graph::BodyId(foot))[0] == doctest::Approx(1.0).epsilon(0.01));
    // The bottle's mass is both bodies': the belt pulls it to speed with M/(2k), not m/k.
    CHECK(phys.rb(plant::graph::BodyId(main)).getMass() == doctest::Approx(0.040));
    e.input(plant::graph::SlotId(b.S(b.g.joints[plant::graph::JointId(j)].comp.v, "disable")));
    for (int i = 0; i < 60; ++i) e.step();
    CHECK_FALSE(phys.welded(plant::graph::BodyId(foot)));
    CHECK(phys.world().getNumCollisionObjects() == 3);
    CHECK(phys.rb(plant::graph::BodyId(main)).getMass() == doctest::Approx(0.036));
    CHECK(e.body_com(plant::graph::BodyId(foot))[2] < -0.2);                    // no collisions: it falls through the floor
    CHECK(e.body_com(plant::graph::BodyId(main))[2] == doctest::Approx(0.0505).epsilon(0.01));  // the main body stands
}

TEST_CASE("runtime: collision_off lets a blocked body through, collision_on blocks again") {
    SceneBuilder b;
    b.g.settings.gravity = {0, 0, 0};
    int32_t wall = b.body(b.dobj("wall"), "body", BodyMode::Static, {box({0.1, 2, 2})}, 0, at(1, 0, 0));
    int32_t ball = b.body(b.dobj("ball"), "body", BodyMode::Dynamic, {sphere(0.05)}, 0.1, at(0, 0, 0));
    b.field(0, "push", {10, 10, 10}, at(0, 0, 0), {1, 0, 0}, 1.0, 5);
    Engine e(b.g);
    for (int i = 0; i < 300; ++i) e.step();
    CHECK(e.body_com(plant::graph::BodyId(ball))[0] < 0.95);  // blocked in front of the wall
    CHECK(e.body_com(plant::graph::BodyId(ball))[0] > 0.85);
    e.input(plant::graph::SlotId(b.S(b.body_comp(wall), "collision_off")));
    for (int i = 0; i < 150; ++i) e.step();
    CHECK(e.body_com(plant::graph::BodyId(ball))[0] > 1.2);  // passed through
    (void)wall;
}

TEST_CASE("runtime: a fixed constraint holds a heavy body under gravity, and lets go when disabled") {
    SceneBuilder b;
    int32_t d = b.dobj("crane");
    int32_t anchor = b.body(d, "anchor", BodyMode::Static, {box({0.1, 0.1, 0.1})}, 0, at(0, 0, 1));
    int32_t load = b.body(d, "load", BodyMode::Dynamic, {box({0.2, 0.2, 0.2})}, 5, at(0, 0, 0.8));
    int32_t j = b.joint(d, "hold", JointKind::Fixed, anchor, load, at(0, 0, -0.2), at(0, 0, 0));
    Engine e(b.g);
    for (int i = 0; i < 300; ++i) e.step();
    CHECK(std::abs(e.body_com(plant::graph::BodyId(load))[2] - 0.8) < 0.005);
    e.input(plant::graph::SlotId(b.S(b.g.joints[plant::graph::JointId(j)].comp.v, "disable")));
    for (int i = 0; i < 90; ++i) e.step();
    CHECK(e.body_com(plant::graph::BodyId(load))[2] < 0.0);  // free fall: 0.8 m in 0.4 s
    CHECK_FALSE(e.active(plant::graph::SlotId(b.S(b.g.joints[plant::graph::JointId(j)].comp.v, "enabled"))));
    CHECK(e.value(plant::graph::SlotId(b.S(b.g.joints[plant::graph::JointId(j)].comp.v, "enabled")))[0] == 0);
}

TEST_CASE("runtime: dynamics_off takes a body out of the simulation, set_velocity then moves it") {
    SceneBuilder b;
    int32_t body = b.body(b.dobj("box"), "body", BodyMode::Dynamic, {box({0.1, 0.1, 0.1})}, 1, at(0, 0, 1));
    const int32_t c = b.body_comp(body);
    Engine e(b.g);
    e.input(plant::graph::SlotId(b.S(c, "dynamics_off")));
    e.step();
    const double z = e.body_com(plant::graph::BodyId(body))[2];
    const std::array<double, 3> v{1, 0, 0};
    e.input(plant::graph::SlotId(b.S(c, "set_velocity")), v);
    for (int i = 0; i < 150; ++i) e.step();
    CHECK(e.body_com(plant::graph::BodyId(body))[2] == doctest::Approx(z));
    CHECK(e.body_com(plant::graph::BodyId(body))[0] == doctest::Approx(1.0).epsilon(0.01));
    e.input(plant::graph::SlotId(b.S(c, "dynamics_on")));
    for (int i = 0; i < 30; ++i) e.step();
    CHECK(e.body_com(plant::graph::BodyId(body))[2] < z - 0.1);  // falls again
}

TEST_CASE("runtime: a body declared with dynamics off starts still and falls after dynamics_on") {
    SceneBuilder b;
    int32_t body = b.body(b.dobj("box"), "body", BodyMode::Dynamic, {box({0.1, 0.1, 0.1})}, 1, at(0, 0, 1));
    b.g.bodies[plant::graph::BodyId(body)].dynamics = false;
    const int32_t c = b.body_comp(body);
    Engine e(b.g);
    for (int i = 0; i < 30; ++i) e.step();
    CHECK(e.body_com(plant::graph::BodyId(body))[2] == doctest::Approx(1.0));
    e.input(plant::graph::SlotId(b.S(c, "dynamics_on")));
    for (int i = 0; i < 30; ++i) e.step();
    CHECK(e.body_com(plant::graph::BodyId(body))[2] < 0.9);  // 0.2 s of free fall: 0.2 m
}

TEST_CASE("runtime: set_pose teleports a dynamic body, outputs report the body frame") {
    SceneBuilder b;
    b.g.settings.gravity = {0, 0, 0};
    // Centre of mass off the body frame, two shapes: a compound.
    int32_t body = b.body(b.dobj("odd"), "body", BodyMode::Dynamic,
                          {box({0.1, 0.1, 0.1}), sphere(0.05, at(0.2, 0, 0))}, 1, at(1, 2, 3), 0, {0.05, 0, 0});
    const int32_t c = b.body_comp(body);
    b.record(b.S(c, "position"), "p");
    Engine e(b.g);
    e.step();
    CHECK(e.value(plant::graph::SlotId(b.S(c, "position")))[0] == doctest::Approx(1));
    CHECK(e.body_com(plant::graph::BodyId(body))[0] == doctest::Approx(1.05));
    const std::array<double, 7> pose{5, 0, 0, 0, 0, 0, 1};
    e.input(plant::graph::SlotId(b.S(c, "set_pose")), pose);
    e.step();  // written in phase 5
    e.step();
    CHECK(e.value(plant::graph::SlotId(b.S(c, "position")))[0] == doctest::Approx(5));
    CHECK(e.body_pose(plant::graph::BodyId(body)).p[1] == doctest::Approx(0).epsilon(1e-6));
}

TEST_CASE("runtime: a hull without volume (the loader refuses it) neither crashes the contacts nor falls through") {
    // A graph built by hand skips the loader's check (graph/hull.h): the contact routine must
    // not trust the shape, and the body must still rest on the floor.
    const std::vector<std::vector<Vec3>> flat_hulls = {
        {{0, 0, 0}},                                                // one point
        {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}},               // four identical points
        {{0, 0, 0}, {0.01, 0, 0}, {0.02, 0, 0}, {0.03, 0, 0}},      // four on a line
        {{0, 0, 0}, {0.02, 0, 0}, {0, 0.02, 0}, {0.02, 0.02, 0}},   // four in a plane
    };
    for (const auto& points : flat_hulls) {
        CAPTURE(points.size());
        CAPTURE(points[1][0]);
        SceneBuilder b;
        b.body(0, "floor", BodyMode::Static, {box({2, 2, 0.2})}, 0, at(0, 0, -0.1));
        ShapeSpec hull{ShapeKind::Hull, {0, 0, 0}, {}, points};
        const int32_t blob = b.body(b.dobj("blob"), "body", BodyMode::Dynamic, {hull}, 0.1, at(0, 0, 0.05));
        Engine e(b.g);
        for (int i = 0; i < 300; ++i) e.step();  // 2 s: long enough to fall 5 cm and settle
        const double z = e.body_pose(plant::graph::BodyId(blob)).p[2];
        CHECK(std::isfinite(z));
        CHECK(z > -0.005);  // on the floor (its margin is 1 mm), not through it
        CHECK(z < 0.01);
    }
}

TEST_CASE("runtime: a place, velocity or belt speed out of range reaching an input is not applied, and counted") {
    // Events are refused when read (events.cpp); what else reaches these inputs (the plant's own
    // logic, a caller of Engine::input) is checked where they act, against graph/range.h.
    SceneBuilder b;
    const int32_t belt = floor_and_belt(b, 0.5, 16);
    const int32_t body = b.body(b.dobj("box"), "body", BodyMode::Dynamic, {box({0.05, 0.05, 0.05})}, 0.1, at(0, 0, 0.025));
    const int32_t c = b.body_comp(body), fc = b.field_comp(belt);
    Engine e(b.g);
    e.step();
    const double nan = std::nan("");
    const std::array<double, 7> far_pose{0, 2e5, 0, 0, 0, 0, 1};
    const std::array<double, 3> far{0, 0, 1e300}, fast{-2e5, 0, 0}, spin{0, 0, 2e6}, broken{0, nan, 0};
    const std::array<double, 1> speed{1e300}, speed_nan{nan};
    e.input(plant::graph::SlotId(b.S(c, "set_pose")), far_pose);
    e.input(plant::graph::SlotId(b.S(c, "set_position")), far);
    e.input(plant::graph::SlotId(b.S(fc, "set_speed")), speed);
    e.step();
    CHECK(e.warnings().out_of_range == 3);
    e.input(plant::graph::SlotId(b.S(c, "set_velocity")), fast);
    e.input(plant::graph::SlotId(b.S(c, "set_angular_velocity")), spin);
    e.step();
    e.input(plant::graph::SlotId(b.S(c, "set_velocity")), broken);
    e.input(plant::graph::SlotId(b.S(fc, "set_speed")), speed_nan);
    e.step();
    CHECK(e.warnings().out_of_range == 7);
    CHECK(e.field_speed(plant::graph::FieldId(belt)) == 0.5);
    const plant::graph::Vec3 p = e.body_com(plant::graph::BodyId(body));
    CHECK(std::abs(p[0]) < 0.1);
    CHECK(std::abs(p[1]) < 1e-3);
    CHECK(std::abs(e.body_velocity(plant::graph::BodyId(body))[0]) < 0.6);
    // In range, the same inputs apply.
    const std::array<double, 1> slower{0.25};
    e.input(plant::graph::SlotId(b.S(fc, "set_speed")), slower);
    const std::array<double, 3> near{0, 1e5 - 1, 0.025};
    e.input(plant::graph::SlotId(b.S(c, "set_position")), near);
    e.step();
    e.step();
    CHECK(e.warnings().out_of_range == 7);
    CHECK(e.field_speed(plant::graph::FieldId(belt)) == 0.25);
    CHECK(e.body_com(plant::graph::BodyId(body))[1] == doctest::Approx(1e5 - 1).epsilon(1e-6));
}

// A kinematic part that nothing writes is passed over by its world (Physics::writes): Bullet's
// saveKinematicState is not called for it and its broadphase box is not worked out again. Once
// something moves or places it, both follow it again: its box is the one Bullet works out from
// its pose in every step, and it pushes what is in its way.
TEST_CASE("runtime: a kinematic part at rest is passed over until something writes it") {
    SceneBuilder b;
    b.body(0, "floor", BodyMode::Static, {box({4, 4, 0.2})}, 0, at(0, 0, -0.1), 0.5);
    const int32_t pusher = b.body(b.dobj("pusher"), "body", BodyMode::Kinematic, {box({0.1, 0.1, 0.1})}, 0, at(0, 0, 0.05));
    const int32_t crate = b.body(b.dobj("crate"), "body", BodyMode::Dynamic, {box({0.1, 0.1, 0.1})}, 1, at(0.3, 0, 0.05), 0.5);
    const int32_t c = b.body_comp(pusher);
    Engine e(b.g);
    auto& phys = e.internals().phys;
    const plant::graph::BodyId p(pusher);
    // Steps after which the pusher's broadphase box is not the one of its pose (but for a step
    // that places it: that is done after the step's physics, and the box follows in the next).
    int stale = 0, misplaced = 0;
    auto step = [&](bool placing = false) {
        e.step();
        if (placing) return;
        const btRigidBody& rb = phys.rb(p);
        btVector3 lo, hi;
        rb.getCollisionShape()->getAabb(rb.getWorldTransform(), lo, hi);
        const btVector3 m(gContactBreakingThreshold, gContactBreakingThreshold, gContactBreakingThreshold);
        const btBroadphaseProxy& proxy = *rb.getBroadphaseHandle();
        stale += !((lo - m) == proxy.m_aabbMin && (hi + m) == proxy.m_aabbMax);
        // Handed the box it holds, its proxy is where Bullet's setAabb leaves it: in the dynamic
        // tree, in the list of this step's updates, which stays linked both ways (keep_box).
        const auto& bp = dynamic_cast<const btDbvtBroadphase&>(*phys.world().getBroadphase());
        const auto& dp = static_cast<const btDbvtProxy&>(proxy);
        const int last = (bp.m_stageCurrent + btDbvtBroadphase::STAGECOUNT - 1) % btDbvtBroadphase::STAGECOUNT;
        bool listed = false, linked = true;
        const btDbvtProxy* before = nullptr;
        int n = 0;  // the scene has three bodies: a longer list has gone wrong (a cycle)
        for (const btDbvtProxy* x = bp.m_stageRoots[last]; x != nullptr && linked; before = x, x = x->links[1]) {
            linked &= x->links[0] == before && x->stage == last && ++n <= 3;
            listed |= x == &dp;
        }
        misplaced += !(dp.stage == last && listed && linked);
    };
    for (int i = 0; i < 10; ++i) step();
    const uint32_t resting = phys.writes(p);
    for (int i = 0; i < 20; ++i) step();
    CHECK(phys.writes(p) == resting);  // passed over: nothing wrote it, not even Bullet's velocity
    const std::array<double, 3> v{1, 0, 0}, still{0, 0, 0};
    e.input(plant::graph::SlotId(b.S(c, "set_velocity")), v);
    for (int i = 0; i < 60; ++i) step();  // 0.4 m: 0.2 m to the crate, then 0.2 m pushing it
    e.input(plant::graph::SlotId(b.S(c, "set_velocity")), still);
    for (int i = 0; i < 30; ++i) step();
    CHECK(phys.writes(p) > resting);
    CHECK(e.body_com(p)[0] == doctest::Approx(0.4).epsilon(0.02));
    CHECK(e.body_com(plant::graph::BodyId(crate))[0] > 0.45);  // pushed
    CHECK(phys.rb(p).getLinearVelocity().length() == 0);    // Bullet's, from a pose that stands
    const uint32_t stopped = phys.writes(p);
    for (int i = 0; i < 20; ++i) step();
    CHECK(phys.writes(p) == stopped);
    const std::array<double, 7> pose{-1, 1, 0.05, 0, 0, 0, 1};
    e.input(plant::graph::SlotId(b.S(c, "set_pose")), pose);
    step(true);
    for (int i = 0; i < 5; ++i) step();
    CHECK(e.body_com(p)[0] == doctest::Approx(-1));
    CHECK(stale == 0);
    CHECK(misplaced == 0);
}
