// Physics regions (runtime/engine/regions.cpp): a Bullet world per group of static bodies far
// from the others, bodies moving between them, and results that do not depend on the threads.
#include "paths.h"
#include "engine/engine.h"
#include "graph/text.h"
#include "engine/runtime.h"
#include "engine/trace.h"
#include "engine/workers.h"
#include "bottling_scene.h"
#include "trace_of.h"

#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>


using namespace plant::test;
using namespace plant::engine;

namespace {

Options on_threads(int n) {
    Options o;
    o.threads = n;
    return o;
}

// Two frictional floors 1.2 m square, their tops at z = 0, centred at x = 0 and x = `far`.
void two_floors(SceneBuilder& b, double far) {
    b.body(0, "floor_a", BodyMode::Static, {box({1.2, 1.2, 0.2})}, 0, at(0, 0, -0.1), 1.0);
    b.body(0, "floor_b", BodyMode::Static, {box({1.2, 1.2, 0.2})}, 0, at(far, 0, -0.1), 1.0);
}

// A 10 cm frictional cube of 1 kg.
int32_t cube_at(SceneBuilder& b, double x, double z) {
    return b.body(b.dobj("cube"), "body", BodyMode::Dynamic, {box({0.1, 0.1, 0.1})}, 1.0, at(x, 0, z), 1.0);
}

}  // namespace

TEST_CASE("runtime: lines far apart are physics regions, a Bullet world each, and a void's") {
    const Graph g = bottling_scene(6, 0.5, 3);
    Engine e(g, on_threads(1));
    auto& phys = e.internals().phys;
    CHECK(e.regions() == 3);
    CHECK(phys.worlds() == 4);
    auto body = [&](std::string_view line, std::string_view name) {
        for (plant::graph::BodyId b : plant::graph::ids_of(g.bodies))
            if (g.comp_path(g.bodies[b].comp) == std::string(line) + "." + std::string(name)) return b;
        FAIL("no body ", line, ".", name);
        return plant::graph::BodyId{};
    };
    const plant::graph::BodyId f0 = body("line", "floor"), f1 = body("l1_line", "floor"), f2 = body("l2_line", "floor");
    CHECK(phys.world_of(f0) != phys.world_of(f1));
    CHECK(phys.world_of(f1) != phys.world_of(f2));
    CHECK(phys.world_of(body("line", "rail_l")) == phys.world_of(f0));
    CHECK(phys.world_of(body("l2_line", "rail_r")) == phys.world_of(f2));
    for (int i = 0; i < 600; ++i) e.step();
    // A body joins its region's world in the physics phase; one issued in the last step's
    // actuator phase is still in the void's. So: the bodies in the world before and after a step.
    std::vector<char> was(g.bodies.size());
    for (size_t b = 0; b < g.bodies.size(); ++b) was[b] = phys.in_world(plant::graph::BodyId(b));
    e.step();
    // Bottles on each line are in that line's world; pooled ones wait in the void's.
    int on_lines = 0, parked = 0;
    for (size_t b = 0; b < g.bodies.size(); ++b) {
        if (g.bodies[plant::graph::BodyId(b)].mode != BodyMode::Dynamic || was[b] != phys.in_world(plant::graph::BodyId(b))) continue;
        const int32_t w = phys.world_of(plant::graph::BodyId(b));
        if (!phys.in_world(plant::graph::BodyId(b))) {
            CHECK(w == phys.worlds() - 1);
            ++parked;
            continue;
        }
        const double y = e.body_pose(plant::graph::BodyId(b)).p[1];
        const plant::graph::BodyId floor = y < 10 ? f0 : y < 30 ? f1 : f2;
        CHECK(w == phys.world_of(floor));
        ++on_lines;
    }
    CHECK(on_lines > 6);
    CHECK(parked > 0);
    CHECK(phys.world(phys.worlds() - 1).getNumCollisionObjects() >= parked);
}

TEST_CASE("runtime: a plant of several regions gives the same trace on one thread and on two") {
    const Graph g = bottling_scene(6, 0.5, 3);
    const TraceSelect bodies_and_places{true, true, false};
    const std::string one = trace_of(g, 900, on_threads(1), bodies_and_places),
                      two = trace_of(g, 900, on_threads(2), bodies_and_places);
    CHECK(one.size() > 10000);
    CHECK(one == two);
    CHECK(one.find(",1,") != std::string::npos);  // alive: bottles issued, routed, taken
}

TEST_CASE("runtime: the step profile splits a step into serial parts and one job of the worlds") {
    const Graph g = bottling_scene(6, 0.5, 3);
    Engine e(g, on_threads(2));
    StepProfile& p = e.profile();
    for (int i = 0; i < 150; ++i) e.step();  // bottles on the lines
    p.on = true;
    p.reset();
    CHECK(p.on);  // reset keeps it on
    for (int i = 0; i < 150; ++i) e.step();
    CHECK(p.steps == 150);
    CHECK(p.step_ns > 0);
    CHECK(p.work_ns > 0);  // the worlds' items
    CHECK(p.serial_ns[StepProfile::Logic] > 0);
    CHECK(p.serial_ns[StepProfile::Triggers] > 0);
    CHECK(p.serial_total() > 0);
    // One job per step: the worlds stepped, each with its law and its passengers; the items
    // laid out on 1 thread are their sum.
    CHECK(p.projected_ns[0] == doctest::Approx(p.work_ns));
    for (int i = 1; i < StepProfile::kProjected; ++i) {
        CHECK(p.projected_ns[i] <= p.projected_ns[i - 1]);
        CHECK(p.speedup(i) >= p.speedup(i - 1));
        CHECK(p.speedup(i) < StepProfile::threads_of(i) + 1e-9);
        CHECK(p.share(i) >= p.share(i - 1));
    }
    CHECK(p.share(0) > 0);
    CHECK(p.share(0) < 1);
    CHECK(std::string(StepProfile::name(StepProfile::Logic)) == "logic");
    // Timing changes nothing: every body where an engine without the profile has it.
    Engine f(g, on_threads(2));
    for (int i = 0; i < 300; ++i) f.step();
    int moving = 0;
    for (size_t b = 0; b < g.bodies.size(); ++b) {
        const plant::graph::BodyId id{int32_t(b)};
        const auto x = e.body_pose(id), y = f.body_pose(id);
        for (int k = 0; k < 3; ++k) CHECK(x.p[k] == y.p[k]);
        for (int k = 0; k < 4; ++k) CHECK(x.q[k] == y.q[k]);
        moving += g.bodies[plant::graph::BodyId(b)].mode == BodyMode::Dynamic && e.body_in_world(id);
    }
    CHECK(moving > 6);
}

TEST_CASE("runtime: a body thrown from one region over the void lands on the other region's floor") {
    SceneBuilder b;
    two_floors(b, 4);
    const int32_t cube = cube_at(b, 0, 0.05);
    Engine e(b.g, on_threads(2));
    auto& phys = e.internals().phys;
    REQUIRE(e.regions() == 2);
    const int void_world = phys.worlds() - 1;
    CHECK(phys.world_of(plant::graph::BodyId(cube)) == phys.world_of(plant::graph::BodyId(0)));
    // 4 m in about 0.8 s of flight: up at 4 m/s, along at 5 m/s.
    phys.write(plant::graph::BodyId(cube)).setLinearVelocity(btVector3(5, 0, 4));
    bool crossed_void = false;
    for (int i = 0; i < 450; ++i) {
        e.step();
        crossed_void |= phys.world_of(plant::graph::BodyId(cube)) == void_world;
    }
    CHECK(crossed_void);
    CHECK(phys.world_of(plant::graph::BodyId(cube)) == phys.world_of(plant::graph::BodyId(1)));
    const auto p = e.body_pose(plant::graph::BodyId(cube)).p;
    CHECK(p[0] > 3.4);
    CHECK(p[0] < 4.6);
    CHECK(p[2] == doctest::Approx(0.05).epsilon(0.05));  // resting on floor b, not fallen through
}

TEST_CASE("runtime: a body in the void collides with a body of a region that reaches out of it") {
    SceneBuilder b;
    two_floors(b, 8);
    // A plank lying on floor a, 40 cm of it over the edge (x = 0.6); a ball dropped on that end.
    const int32_t plank = b.body(b.dobj("plank"), "body", BodyMode::Dynamic, {box({1.0, 0.2, 0.05})}, 5.0,
                                 at(0.5, 0, 0.025), 0.8);
    const int32_t ball = b.body(b.dobj("ball"), "body", BodyMode::Dynamic, {sphere(0.04)}, 0.05,
                                at(0.9, 0, 0.5), 0.8);
    Engine e(b.g, on_threads(1));
    auto& phys = e.internals().phys;
    REQUIRE(e.regions() == 2);
    CHECK(phys.world_of(plant::graph::BodyId(ball)) == phys.worlds() - 1);  // starts in the void, over no floor
    for (int i = 0; i < 300; ++i) e.step();
    CHECK(phys.world_of(plant::graph::BodyId(ball)) == phys.world_of(plant::graph::BodyId(plank)));
    CHECK(phys.world_of(plant::graph::BodyId(plank)) == phys.world_of(plant::graph::BodyId(0)));
    CHECK(e.body_pose(plant::graph::BodyId(ball)).p[2] > 0.05);  // on the plank, not fallen past it
    CHECK(e.warnings().missed_contacts == 0);
}

TEST_CASE("runtime: a static body placed outside its region's box merges every world into one") {
    SceneBuilder b;
    two_floors(b, 4);
    const int32_t cube = cube_at(b, 8, 0.5);
    Engine e(b.g, on_threads(2));
    auto& phys = e.internals().phys;
    REQUIRE(e.regions() == 2);
    for (int i = 0; i < 10; ++i) e.step();
    CHECK(phys.world_of(plant::graph::BodyId(cube)) == phys.worlds() - 1);  // falling in the void
    phys.place(plant::graph::BodyId(1), btTransform(btQuaternion::getIdentity(), btVector3(8, 0, -0.1)));  // floor b under the cube
    CHECK(e.regions() == 1);
    CHECK(phys.worlds() == 1);
    for (int i = 0; i < 150; ++i) e.step();
    CHECK(e.body_pose(plant::graph::BodyId(cube)).p[2] == doctest::Approx(0.05).epsilon(0.05));  // caught by floor b
    CHECK(phys.world(0).getNumCollisionObjects() == 3);
}

// Bodies off the solver (steady transport: docs/runtime.md) when the worlds merge: a lone
// frictionless cube at rest on floor b coasts, and two touching cubes beside it rest (each still
// beside the other); floor a is placed out of its region, and they move into its world.
// They join the one world as bodies Bullet simulates once they land: thrown up, each flies and
// comes down again.
TEST_CASE("runtime: bodies off the solver when the worlds merge are simulated again once they land") {
    SceneBuilder b;
    two_floors(b, 4);
    // The lone one frictionless: on a frictional floor it would be held by friction, and rest.
    const int32_t lone = b.body(b.dobj("cube"), "body", BodyMode::Dynamic, {box({0.1, 0.1, 0.1})}, 1.0, at(3.7, 0, 0.05), 0.0);
    const int32_t first = cube_at(b, 4.2, 0.05), second = cube_at(b, 4.3, 0.05);
    Engine e(b.g, on_threads(2));
    auto& phys = e.internals().phys;
    REQUIRE(e.regions() == 2);
    const plant::graph::BodyId L(lone), A(first), B(second);
    for (int i = 0; i < 150; ++i) e.step();
    CHECK(phys.coasting(L));
    CHECK_FALSE(phys.resting(L));
    CHECK(phys.resting(A));
    CHECK(phys.resting(B));
    CHECK(phys.world_of(A) != 0);  // floor b's world: they move into floor a's
    phys.place(plant::graph::BodyId(0), btTransform(btQuaternion::getIdentity(), btVector3(-8, 0, -0.1)));  // floor a far out
    REQUIRE(phys.worlds() == 1);
    for (int i = 0; i < 3; ++i) e.step();
    const double z0 = e.body_pose(L).p[2];
    phys.write(L).setLinearVelocity(btVector3(0, 0, 2));
    phys.write(A).setLinearVelocity(btVector3(0, 0, 2));
    double top_l = 0, top_a = 0, top_b = 0;
    for (int i = 0; i < 150; ++i) {
        e.step();
        top_l = std::max(top_l, e.body_pose(L).p[2]);
        top_a = std::max(top_a, e.body_pose(A).p[2]);
        top_b = std::max(top_b, e.body_pose(B).p[2]);
    }
    CHECK(top_l > z0 + 0.1);  // up about 20 cm
    CHECK(top_a > z0 + 0.1);
    CHECK(top_b < z0 + 0.01);  // the other one stays where it stood
    CHECK(e.body_pose(L).p[2] == doctest::Approx(0.05).epsilon(0.05));  // and down again
    CHECK(e.body_pose(A).p[2] == doctest::Approx(0.05).epsilon(0.05));
}

TEST_CASE("runtime: with sweep-and-prune a plant of lines far apart keeps one Bullet world") {
    const Graph g = bottling_scene(6, 0.5, 3);
    Options o = on_threads(2);
    o.broadphase = Broadphase::Sap;
    Engine e(g, o);
    CHECK(e.regions() == 1);
    CHECK(e.internals().phys.worlds() == 1);
    for (int i = 0; i < 300; ++i) e.step();
    CHECK(e.warnings().total() == 0);
}

namespace {

// An input of tests/fuzz/regressions/graph/ (found by the graph target's libFuzzer campaigns).
// The loader now refuses each (a place beyond graph/range.h's 100 km, which no compiled plant
// has either), so it is read in form only and that refusal checked; the region finder keeps
// its guards for boxes that far, and these inputs check them.
plant::graph::Graph regression_graph(const std::string& name) {
    const std::string path = std::string(PLANT_SOURCE_DIR) + "/tests/fuzz/regressions/graph/" + name;
    plant::graph::Graph g;
    std::string error;
    CHECK_FALSE(plant::graph::load_text_file(path, g, error));
    CHECK_MESSAGE(error.find("beyond 100 km") != std::string::npos, error);
    REQUIRE_MESSAGE(plant::graph::load_text_file(path, g, error, plant::graph::Check::Form), error);
    return g;
}

// The regression input `name` holds what made it one (`far`, asked of the loaded graph);
// the engine is built from it and steps.
template <class Far>
void far_regression_builds_and_steps(const std::string& name, Far&& far) {
    const plant::graph::Graph g = regression_graph(name);
    REQUIRE(far(g));
    plant::engine::Engine e(g);
    for (int i = 0; i < 10; ++i) e.step();
    CHECK(e.steps() == 10);
    CHECK(e.regions() >= 1);
}

bool any_body(const plant::graph::Graph& g, auto&& pred) {
    return std::any_of(g.bodies.begin(), g.bodies.end(), pred);
}

}  // namespace

// A static box whose shape sits 1e19 m out overflowed the region finder's cell index
// (undefined behaviour, caught by UBSan).
TEST_CASE("runtime: a static body 1e19 m out is filed into regions without overflow") {
    far_regression_builds_and_steps("static_box_at_1e19.graph", [](const plant::graph::Graph& g) {
        return std::any_of(g.shapes.begin(), g.shapes.end(), [](const auto& s) { return std::abs(s.local.p[0]) > 1e18; });
    });
}

// A kinematic body whose centre of mass lies 1e32 m off has an infinite bounding sphere,
// and the region finder grew boxes by that infinity (inf - inf: a NaN cell index, undefined
// behaviour). Its margin is now finite.
TEST_CASE("runtime: a centre of mass 1e32 m off its body is filed into regions without NaN") {
    far_regression_builds_and_steps("kinematic_com_at_1e32.graph", [](const plant::graph::Graph& g) {
        return any_body(g, [](const auto& b) { return std::abs(b.com.p[0]) > 1e31; });
    });
}

// A static body whose centre of mass lies 1e308 m off (beyond float's range) has a box Bullet
// computes as inf - inf: NaN, and the region finder cast it to a cell index (undefined
// behaviour). A box that is not finite is now compared with every box instead of filed.
TEST_CASE("runtime: a centre of mass 1e308 m off a static body is filed into regions without NaN") {
    far_regression_builds_and_steps("static_com_at_1e308.graph", [](const plant::graph::Graph& g) {
        return any_body(g, [](const auto& b) { return b.mode == plant::graph::BodyMode::Static && std::abs(b.com.p[1]) > 1e307; });
    });
}
