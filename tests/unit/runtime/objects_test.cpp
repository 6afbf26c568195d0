// Grippers, sources and exits.
#include "engine/engine.h"
#include "scene_builder.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace plant::test;
using plant::engine::Engine;

TEST_CASE("runtime: a gripper carries a body kinematically and releases it with its velocity") {
    SceneBuilder b;
    b.body(0, "floor", BodyMode::Static, {box({4, 4, 0.2})}, 0, at(0, 0, -0.1), 0.5);
    int32_t part = b.body(b.dobj("part"), "body", BodyMode::Dynamic, {box({0.05, 0.05, 0.05})}, 0.1,
                          at(0, 0, 0.025), 0.5);
    int32_t arm = b.dobj("arm");
    int32_t hand = b.body(arm, "hand", BodyMode::Kinematic, {box({0.1, 0.1, 0.02})}, 0, at(0, 0, 0.1));
    int32_t t = b.trigger(arm, "reach", {0.1, 0.1, 0.2}, at(0, 0, 0.05), -1, hand);
    const auto gc = b.g.comps[plant::graph::CompId(b.g.grippers[plant::graph::GripperId(b.gripper(arm, "grip", t, hand))].comp)].slot_adr;
    const int32_t gcomp = b.g.grippers.back().comp.v;
    Engine e(b.g);
    for (int i = 0; i < 10; ++i) e.step();
    e.input(plant::graph::SlotId(b.S(gcomp, "grip")));
    e.step();
    CHECK(e.value(plant::graph::SlotId(b.S(gcomp, "object")))[0] == b.g.comps[plant::graph::CompId(b.body_comp(part))].owner.v);
    const double dz = e.body_pose(plant::graph::BodyId(hand)).p[2] - e.body_pose(plant::graph::BodyId(part)).p[2];
    const std::array<double, 3> up{0, 0, 0.5};
    e.input(plant::graph::SlotId(b.S(b.body_comp(hand), "set_velocity")), up);
    for (int i = 0; i < 150; ++i) e.step();
    CHECK(e.active(plant::graph::SlotId(b.S(gcomp, "gripped"))) == false);
    CHECK(e.body_pose(plant::graph::BodyId(hand)).p[2] == doctest::Approx(0.6).epsilon(0.01));
    // Follows one step behind its gripper (carried in phase 2, the hand moves in phase 1).
    CHECK(e.body_pose(plant::graph::BodyId(hand)).p[2] - e.body_pose(plant::graph::BodyId(part)).p[2] == doctest::Approx(dz + 0.5 / 150).epsilon(0.01));
    e.input(plant::graph::SlotId(b.S(gcomp, "release")));
    e.step();
    CHECK(e.body_velocity(plant::graph::BodyId(part))[2] == doctest::Approx(0.5).epsilon(0.02));
    CHECK(e.value(plant::graph::SlotId(b.S(gcomp, "object")))[0] == -1);
    e.step();
    CHECK(e.active(plant::graph::SlotId(b.S(gcomp, "released"))));
    for (int i = 0; i < 150; ++i) e.step();
    CHECK(e.body_pose(plant::graph::BodyId(part)).p[2] == doctest::Approx(0.025).epsilon(0.05));  // fell back to the floor
    (void)gc;
}

TEST_CASE("runtime: sources issue pooled objects with bar codes, exits return them to the pool") {
    SceneBuilder b;
    b.g.settings.gravity = {0, 0, 0};
    int32_t bottle = b.type("Bottle");
    // Two pooled bottles (contiguous DO ids), each a body and a label.
    std::vector<int32_t> bodies;
    const int32_t pool = int32_t(b.g.dos.size());
    for (int i = 0; i < 2; ++i) {
        int32_t d = b.dobj("pool" + std::to_string(i), 0, bottle, at(0, 10 + i, 0));
        bodies.push_back(b.body(d, "body", BodyMode::Dynamic, {sphere(0.03)}, 0.05, at(0, 10 + i, 0)));
        b.label(d, "code", "");
    }
    int32_t plant_do = b.dobj("line");
    int32_t src = b.source(plant_do, "src", bottle, pool, 2, 0, at(0, 0, 0), {"F-1", "C-2", "F-3"});
    const int32_t sc = b.g.sources[plant::graph::SourceId(src)].comp.v;
    b.field(plant_do, "belt", {10, 1, 1}, at(0, 0, 0), {1, 0, 0}, 2.0, 10);
    int32_t t = b.trigger(plant_do, "end", {0.2, 1, 1}, at(1, 0, 0), bottle);
    const int32_t ec = b.g.exits[plant::graph::ExitId(b.exit(plant_do, "out", t))].comp.v;
    Engine e(b.g);
    CHECK_FALSE(e.body_in_world(plant::graph::BodyId(bodies[0])));  // pooled objects start outside the world
    e.step();
    CHECK(e.body_com(plant::graph::BodyId(bodies[0]))[1] == 10);  // untouched: not simulated

    auto issue = [&] {
        e.input(plant::graph::SlotId(b.S(sc, "issue")));
        e.step();
    };
    issue();
    CHECK(e.body_in_world(plant::graph::BodyId(bodies[0])));
    CHECK(e.value(plant::graph::SlotId(b.S(sc, "object")))[0] == pool);
    CHECK(e.str(int32_t(e.value(plant::graph::SlotId(b.S(sc, "id")))[0])) == "F-1");
    e.step();
    CHECK(e.active(plant::graph::SlotId(b.S(sc, "issued"))));
    issue();
    issue();  // the pool is empty: a warning, nothing issued
    CHECK(e.warnings().pool_empty == 1);
    CHECK(e.value(plant::graph::SlotId(b.S(sc, "count")))[0] == 2);
    // The label of the second bottle carries its bar code.
    CHECK(e.str(int32_t(e.value(plant::graph::SlotId(b.S(b.g.labels[plant::graph::Id<plant::graph::Label>(1)].comp.v, "value")))[0])) == "C-2");

    int taken = 0;
    for (int i = 0; i < 150; ++i) {
        e.step();
        if (e.active(plant::graph::SlotId(b.S(ec, "taken")))) ++taken;
    }
    CHECK(taken == 2);
    CHECK(e.value(plant::graph::SlotId(b.S(ec, "count")))[0] == 2);
    CHECK_FALSE(e.body_in_world(plant::graph::BodyId(bodies[0])));
    CHECK_FALSE(e.body_in_world(plant::graph::BodyId(bodies[1])));
    issue();  // back in the pool: issued again (first returned first), with the next code
    CHECK(e.body_in_world(plant::graph::BodyId(bodies[0])));
    CHECK(e.str(int32_t(e.value(plant::graph::SlotId(b.S(sc, "id")))[0])) == "F-3");
    CHECK(e.body_com(plant::graph::BodyId(bodies[0]))[0] < 0.1);
}

TEST_CASE("runtime: a source with a rate issues on its own") {
    SceneBuilder b;
    int32_t bottle = b.type("Bottle");
    const int32_t pool = int32_t(b.g.dos.size());
    for (int i = 0; i < 5; ++i) {
        int32_t d = b.dobj("p" + std::to_string(i), 0, bottle, at(0, 0, 0));
        b.body(d, "body", BodyMode::Dynamic, {sphere(0.03)}, 0.05, at(0, 0, 0));
    }
    int32_t src = b.source(b.dobj("line"), "src", bottle, pool, 5, 2, at(0, 0, 1), {});
    Engine e(b.g);
    // 2 per second: in the steps at or just past 0 s, 0.5 s and 1 s (the 150th step).
    for (int i = 0; i < 149; ++i) e.step();
    CHECK(e.value(plant::graph::SlotId(b.S(b.g.sources[plant::graph::SourceId(src)].comp.v, "count")))[0] == 2);
    e.step();
    CHECK(e.value(plant::graph::SlotId(b.S(b.g.sources[plant::graph::SourceId(src)].comp.v, "count")))[0] == 3);
    // Without bar codes, an object's id is its path.
    CHECK(e.str(int32_t(e.value(plant::graph::SlotId(b.S(b.g.sources[plant::graph::SourceId(src)].comp.v, "id")))[0])) == "p2");
}
