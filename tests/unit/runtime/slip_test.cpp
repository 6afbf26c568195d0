// The conveyor law's slip limit (a field's max_force, docs/semantics.md §2): a body the law
// would pull harder gets exactly the limit, a free body still reaches the belt speed without
// overshoot, a rigid group's members are each limited, and a held body presses with the limit.
#include "engine/engine.h"
#include "engine/runtime.h"
#include "scene_builder.h"

#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <doctest/doctest.h>

#include <cmath>

using namespace plant::test;
using plant::engine::Engine;

namespace {

// A frictionless floor (top at z = 0) and a belt field over it along +x at `speed`.
int32_t floor_and_belt(SceneBuilder& b, double speed, double gain, double max_force) {
    b.body(0, "floor", BodyMode::Static, {box({20, 20, 0.2})}, 0, at(0, 0, -0.1));
    const int32_t f = b.field(0, "belt", {20, 2, 0.5}, at(0, 0, 0.25), {1, 0, 0}, speed, gain);
    b.g.fields[plant::graph::FieldId(f)].max_force = max_force;
    return f;
}

}  // namespace

TEST_CASE("runtime: past the slip limit a body gets exactly the limit, and still reaches belt speed without overshoot") {
    const double mass = 0.04, gain = 16, cap = 0.1, speed = 0.5;
    SceneBuilder b;
    floor_and_belt(b, speed, gain, cap);
    const int32_t cube = b.body(b.dobj("cube"), "body", BodyMode::Dynamic, {box({0.05, 0.05, 0.05})}, mass, at(0, 0, 0.025));
    Engine e(b.g);
    const double dt = e.internals().dt;
    double last = 0, fastest = 0;
    int saturated = 0;
    for (int i = 0; i < 150; ++i) {
        e.step();
        const double v = e.body_velocity(plant::graph::BodyId(cube))[0];
        // While the exact step's force m·e·(1 − exp(−k·dt/m))/dt exceeds the limit, the law
        // saturates: Δv = cap·dt/m every step.
        if (mass * (speed - last) * -std::expm1(-gain * dt / mass) / dt > cap * 1.01) {
            CHECK(v - last == doctest::Approx(cap * dt / mass).epsilon(1e-4));
            ++saturated;
        }
        fastest = std::max(fastest, v);
        last = v;
    }
    MESSAGE("saturated for " << saturated << " steps (" << saturated * dt << " s); unlimited 95 % after "
                             << std::log(20.0) * mass / gain << " s");
    CHECK(saturated > 20);                              // 0.5 m/s at 2.5 m/s² takes 0.2 s
    CHECK(fastest <= speed + 1e-9);                     // never faster than the belt
    CHECK(last == doctest::Approx(speed).epsilon(1e-4));  // and at its speed at the end
}

TEST_CASE("runtime: the slip limit acts per member of a rigid group") {
    // Two bodies welded side by side, both in the field: the group's momentum grows by two
    // limits per step while both saturate.
    const double cap = 0.05;
    SceneBuilder b;
    floor_and_belt(b, 1.0, 16, cap);
    const int32_t d = b.dobj("pair");
    const int32_t m1 = b.body(d, "a", BodyMode::Dynamic, {box({0.04, 0.04, 0.04})}, 0.03, at(0, -0.03, 0.02));
    const int32_t m2 = b.body(d, "b", BodyMode::Dynamic, {box({0.04, 0.04, 0.04})}, 0.01, at(0, 0.03, 0.02));
    b.joint(d, "weld", JointKind::Fixed, m1, m2, at(0, 0.03, 0), at(0, -0.03, 0));
    Engine e(b.g);
    for (int i = 0; i < 15; ++i) e.step();  // 0.1 s: 0.25 m/s at 2·cap/M, far from saturation's end
    const double p = 0.03 * e.body_velocity(plant::graph::BodyId(m1))[0] + 0.01 * e.body_velocity(plant::graph::BodyId(m2))[0];
    CHECK(p == doctest::Approx(2 * cap * e.time()).epsilon(0.02));
    CHECK(e.warnings().total() == 0);
}

TEST_CASE("runtime: a body held against a wall presses on it with the slip limit") {
    const double cap = 0.2;
    SceneBuilder b;
    floor_and_belt(b, 0.5, 16, cap);
    const int32_t wall = b.body(0, "wall", BodyMode::Static, {box({0.02, 0.5, 0.2})}, 0, at(0.1, 0, 0.1));
    const int32_t cube = b.body(b.dobj("cube"), "body", BodyMode::Dynamic, {box({0.05, 0.05, 0.05})}, 0.04, at(0, 0, 0.025));
    Engine e(b.g);
    for (int i = 0; i < 150; ++i) e.step();
    CHECK(std::abs(e.body_velocity(plant::graph::BodyId(cube))[0]) < 1e-3);
    // The wall's contact impulses over one step, along x, are the limit times dt.
    e.step();
    auto& phys = e.internals().phys;
    const btCollisionObject* w = &phys.rb(plant::graph::BodyId(wall));
    double impulse = 0;
    btDispatcher* disp = phys.world().getDispatcher();
    for (int m = 0; m < disp->getNumManifolds(); ++m) {
        const btPersistentManifold* pm = disp->getManifoldByIndexInternal(m);
        if (pm->getBody0() != w && pm->getBody1() != w) continue;
        for (int c = 0; c < pm->getNumContacts(); ++c)
            impulse += pm->getContactPoint(c).m_appliedImpulse * std::abs(pm->getContactPoint(c).m_normalWorldOnB.x());
    }
    CHECK(impulse / e.internals().dt == doctest::Approx(cap).epsilon(0.02));
}
