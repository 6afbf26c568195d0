// Triggers, timers, graphics.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/runtime.h"
#include "scene_builder.h"

#include <doctest/doctest.h>

#include <cmath>
#include <string>

using namespace plant::test;
using plant::engine::Engine;

namespace {

// A slot and a graphics of a compiled plant by path (the test fails where there is none).
plant::graph::SlotId slot_at(const plant::graph::Graph& g, std::string_view path) {
    for (plant::graph::SlotId s : plant::graph::ids_of(g.slots))
        if (g.slot_path(s) == path) return s;
    FAIL("no slot " << path);
    return plant::graph::SlotId{};
}

plant::graph::GraphicsId graphics_at(const plant::graph::Graph& g, std::string_view path) {
    for (plant::graph::GraphicsId i : plant::graph::ids_of(g.graphics))
        if (g.comp_path(g.graphics[i].comp) == path) return i;
    FAIL("no graphics " << path);
    return plant::graph::GraphicsId{};
}

}  // namespace

TEST_CASE("runtime: trigger enter/stay/leave with two objects, and its type filter") {
    SceneBuilder b;
    b.g.settings.gravity = {0, 0, 0};
    int32_t bottle = b.type("Bottle");
    int32_t crate = b.type("Crate");
    int32_t a = b.dobj("a", 0, bottle);
    int32_t ba = b.body(a, "body", BodyMode::Dynamic, {sphere(0.05)}, 0.1, at(-0.5, 0, 0));
    int32_t c = b.dobj("c", 0, bottle);
    int32_t bc = b.body(c, "body", BodyMode::Dynamic, {sphere(0.05)}, 0.1, at(-1.0, 0, 0));
    int32_t x = b.dobj("x", 0, crate);
    int32_t bx = b.body(x, "body", BodyMode::Dynamic, {sphere(0.05)}, 0.1, at(-0.7, 0, 0));
    int32_t t = b.trigger(0, "sensor", {0.5, 1, 1}, at(0, 0, 0), bottle);
    const int32_t tc = b.g.triggers[plant::graph::TriggerId(t)].comp.v;
    Engine e(b.g);
    const std::array<double, 3> v{1.5, 0, 0};
    for (int32_t body : {ba, bc, bx}) e.input(plant::graph::SlotId(b.S(b.body_comp(body), "set_velocity")), v);

    // Record the sequence of events as they happen.
    std::string seq;
    int max_count = 0;
    for (int i = 0; i < 150; ++i) {
        e.step();
        const int n = int(e.value(plant::graph::SlotId(b.S(tc, "count")))[0]);
        max_count = std::max(max_count, n);
        if (e.active(plant::graph::SlotId(b.S(tc, "on_enter")))) seq += "E" + std::to_string(int(e.value(plant::graph::SlotId(b.S(tc, "object")))[0]));
        if (e.active(plant::graph::SlotId(b.S(tc, "on_leave")))) seq += "L";
        if (e.active(plant::graph::SlotId(b.S(tc, "on_stay"))) != (n > 0)) seq += "!";
    }
    // a enters, then c; a leaves, then c; the crate x is filtered out.
    CHECK(seq == "E" + std::to_string(a) + "E" + std::to_string(c) + "LL");
    CHECK(max_count == 2);
    CHECK(e.trigger_enters(plant::graph::TriggerId(t)) == 2);
}

TEST_CASE("runtime: two objects entering in the same step: one on_enter, count 2, lowest id reported") {
    SceneBuilder b;
    b.g.settings.gravity = {0, 0, 0};
    int32_t d1 = b.dobj("one");
    b.body(d1, "body", BodyMode::Dynamic, {sphere(0.05)}, 0.1, at(0, 0.2, 0));
    int32_t d2 = b.dobj("two");
    b.body(d2, "body", BodyMode::Dynamic, {sphere(0.05)}, 0.1, at(0, -0.2, 0));
    const int32_t tc = b.g.triggers[plant::graph::TriggerId(b.trigger(0, "t", {1, 1, 1}, at(0, 0, 0)))].comp.v;
    Engine e(b.g);
    e.step();
    CHECK(e.active(plant::graph::SlotId(b.S(tc, "on_enter"))));
    CHECK(e.value(plant::graph::SlotId(b.S(tc, "count")))[0] == 2);
    CHECK(e.value(plant::graph::SlotId(b.S(tc, "object")))[0] == d1);
    e.step();
    CHECK_FALSE(e.active(plant::graph::SlotId(b.S(tc, "on_enter"))));
    CHECK(e.active(plant::graph::SlotId(b.S(tc, "on_stay"))));
}

TEST_CASE("runtime: periodic and one-shot timers") {
    SceneBuilder b(100);
    const int32_t periodic = b.g.timers[plant::graph::Id<plant::graph::Timer>(b.timer(0, "clock", 0.1, true, true))].comp.v;
    const int32_t once = b.g.timers[plant::graph::Id<plant::graph::Timer>(b.timer(0, "delay", 0.25, false, false))].comp.v;
    Engine e(b.g);
    std::vector<int> ticks, shots;
    e.input(plant::graph::SlotId(b.S(once, "start")));  // starts in step 1's phase 5
    for (int i = 1; i <= 100; ++i) {
        e.step();
        if (e.active(plant::graph::SlotId(b.S(periodic, "tick")))) ticks.push_back(i);
        if (e.active(plant::graph::SlotId(b.S(once, "tick")))) shots.push_back(i);
    }
    CHECK(ticks == std::vector<int>{10, 20, 30, 40, 50, 60, 70, 80, 90, 100});
    CHECK(shots == std::vector<int>{26});  // started after step 1: 25 steps later
    CHECK(e.value(plant::graph::SlotId(b.S(once, "running")))[0] == 0);
    e.input(plant::graph::SlotId(b.S(periodic, "stop")));
    for (int i = 0; i < 20; ++i) e.step();
    CHECK_FALSE(e.active(plant::graph::SlotId(b.S(periodic, "tick"))));
    CHECK(e.value(plant::graph::SlotId(b.S(periodic, "running")))[0] == 0);
}

TEST_CASE("runtime: graphics animations play relative to the start pose and report finished") {
    SceneBuilder b(100);
    Pose turned = at(0, 0, 0);
    turned.q = {0, 0, std::sin(M_PI / 8), std::cos(M_PI / 8)};  // 45 deg about z
    Pose moved = at(1, 0, 0);
    int32_t gi = b.graphics(0, "blade", at(2, 0, 0), -1,
                            {{"swing", 0.5, {{0, Pose{}}, {0.5, turned}}}, {"slide", 0.2, {{0, Pose{}}, {0.2, moved}}}},
                            {"empty", "filled"});
    const int32_t gc = b.g.graphics[plant::graph::GraphicsId(gi)].comp.v;
    Engine e(b.g);
    e.watch(plant::graph::SlotId(b.S(gc, "pose")));
    e.input(plant::graph::SlotId(b.S(gc, "swing.play")));
    int finished_at = -1;
    for (int i = 1; i <= 80; ++i) {
        e.step();
        if (i == 26) {  // halfway (started in step 1's phase 5, advancing from step 2)
            const auto q = e.graphics_pose(plant::graph::GraphicsId(gi)).q;
            CHECK(2 * std::atan2(q[2], q[3]) == doctest::Approx(M_PI / 8).epsilon(0.001));
        }
        if (e.active(plant::graph::SlotId(b.S(gc, "swing.finished")))) finished_at = i;
    }
    CHECK(finished_at == 51);
    const auto q = e.graphics_pose(plant::graph::GraphicsId(gi)).q;
    CHECK(2 * std::atan2(q[2], q[3]) == doctest::Approx(M_PI / 4));  // holds the last key
    CHECK(e.graphics_pose(plant::graph::GraphicsId(gi)).p[0] == doctest::Approx(2));

    e.input(plant::graph::SlotId(b.S(gc, "filled.select")));
    e.step();
    e.step();
    CHECK(e.str(int32_t(e.value(plant::graph::SlotId(b.S(gc, "shown")))[0])) == "filled");
    CHECK(e.active(plant::graph::SlotId(b.S(gc, "shown"))));
}

TEST_CASE("runtime: each graphics starts with the variant its `show` names") {
    // The second graphics' variants follow the first's in the variants table: its `show`
    // is an index among its own variants, not a row of the table.
    plant::Compilation c;
    compile_text(R"(
plant P {
    graphics a { model = "a.glb"; variant x = "ax.glb"; variant y = "ay.glb"; show = "y" }
    graphics b { model = "b.glb"; variant p = "bp.glb"; variant q = "bq.glb"; variant r = "br.glb"; show = "r" }
    graphics c { model = "c.glb"; variant u = "cu.glb" }
}
)", c, "variants.plant");
    INFO(plant::render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    Engine e(c.graph);
    auto shown = [&](const char* path) {
        for (plant::graph::SlotId s : plant::graph::ids_of(c.graph.slots))
            if (c.graph.slot_path(s) == path) return std::string(e.str(int32_t(e.value(s)[0])));
        FAIL("no slot " << path);
        return std::string();
    };
    e.step();
    CHECK(shown("a.shown") == "y");
    CHECK(shown("b.shown") == "r");
    CHECK(shown("c.shown") == "c.glb");
}

// Graphics the runtime stops visiting while nothing can change them (kinds/graphics/run.cpp:
// those on a parked body, and those on a static body standing as it stood) are visited again
// when an animation plays on them, and when the static body is placed.
TEST_CASE("runtime: an animation plays on the graphics of a parked body and of a standing static body") {
    plant::Compilation c;
    compile_text(R"(
object Crate {
    physics main: dynamic {
        mass = 1 kg
        shape box(10 cm, 10 cm, 10 cm)
    }
    graphics look on main {
        model = "crate.glb"
        animation nod { duration = 200 ms; move (0 m, 0 m, 1 cm) }
    }
}
plant P {
    physics ground: static { shape box(1 m, 1 m, 1 cm) at (0 m, 0 m, -5 mm) }
    graphics sign on ground at (0 m, 0 m, 1 m) {
        model = "sign.glb"
        animation wave { duration = 200 ms; rotate z by 90 deg }
    }
    source store { object = Crate; pool = 2 }
}
)", c, "still.plant");
    INFO(plant::render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    const plant::graph::Graph& g = c.graph;
    auto slot = [&g](std::string_view path) { return slot_at(g, path); };
    auto graphics = [&g](std::string_view path) { return graphics_at(g, path); };
    const plant::graph::GraphicsId look = graphics("store[1].look"), sign = graphics("sign");
    Engine e(g);
    for (int i = 0; i < 10; ++i) e.step();  // both settled: store[1] in its pool, the ground standing
    const plant::graph::Pose parked = e.graphics_pose(look), standing = e.graphics_pose(sign);

    e.input(slot("store[1].look.nod.play"));
    e.input(slot("sign.wave.play"));
    bool nodded = false, waved = false;
    for (int i = 0; i < 60; ++i) {
        e.step();
        nodded = nodded || e.active(slot("store[1].look.nod.finished"));
        waved = waved || e.active(slot("sign.wave.finished"));
    }
    CHECK(nodded);
    CHECK(waved);
    CHECK(e.graphics_pose(look).p[2] == doctest::Approx(parked.p[2] + 0.01));
    const auto q = e.graphics_pose(sign).q;
    CHECK(2 * std::atan2(q[2], q[3]) == doctest::Approx(M_PI / 2));
    CHECK(e.graphics_pose(sign).p[2] == doctest::Approx(standing.p[2]));

    // The static body placed 2 m along x: its graphics follow, the animation's last key held.
    e.input(slot("ground.set_position"), std::vector<double>{2, 0, -0.005});
    for (int i = 0; i < 3; ++i) e.step();
    CHECK(e.graphics_pose(sign).p[0] == doctest::Approx(standing.p[0] + 2));
    CHECK(2 * std::atan2(e.graphics_pose(sign).q[2], e.graphics_pose(sign).q[3]) == doctest::Approx(M_PI / 2));
}

// A graphics on no body that stands still is passed over (kinds/graphics/run.cpp, kFixed) until
// something moves it: its set_pose, an animation, and a source issuing the object it belongs to
// (which sets its base). Each must still move it after it stood still for a while.
TEST_CASE("runtime: a graphics on no body left standing still moves again on set_pose, an animation, an issue") {
    plant::Compilation c;
    compile_text(R"(
object Tag {
    physics main: dynamic {
        mass = 1 kg
        shape box(10 cm, 10 cm, 10 cm)
    }
    graphics flag at (0 m, 0 m, 50 cm) { model = "flag.glb" }
}
plant P {
    physics ground: static { shape box(4 m, 4 m, 1 cm) at (0 m, 0 m, -5 mm) }
    graphics pin at (1 m, 0 m, 0 m) {
        model = "pin.glb"
        animation lift { duration = 100 ms; move (0 m, 0 m, 3 cm) }
    }
    source store at (1 m, 1 m, 10 cm) { object = Tag; pool = 1 }
}
)", c, "fixed.plant");
    INFO(plant::render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    const plant::graph::Graph& g = c.graph;
    auto slot = [&g](std::string_view path) { return slot_at(g, path); };
    auto graphics = [&g](std::string_view path) { return graphics_at(g, path); };
    const plant::graph::GraphicsId pin = graphics("pin"), flag = graphics("store[0].flag");
    REQUIRE_FALSE(g.graphics[pin].body.valid());
    REQUIRE_FALSE(g.graphics[flag].body.valid());
    Engine e(g);
    for (int i = 0; i < 10; ++i) e.step();
    CHECK(e.graphics_pose(pin).p[0] == doctest::Approx(1));
    const double flag_x = e.graphics_pose(flag).p[0];

    e.input(slot("pin.set_pose"), std::vector<double>{2, 0.5, 0, 0, 0, 0, 1});
    for (int i = 0; i < 10; ++i) e.step();
    CHECK(e.graphics_pose(pin).p[0] == doctest::Approx(2));
    CHECK(e.graphics_pose(pin).p[1] == doctest::Approx(0.5));

    e.input(slot("pin.lift.play"));
    for (int i = 0; i < 40; ++i) e.step();
    CHECK(e.graphics_pose(pin).p[2] == doctest::Approx(0.03));
    CHECK(e.graphics_pose(pin).p[0] == doctest::Approx(2));

    // The pooled object's flag moved away and left standing there; issuing the object puts it
    // back at the source, 50 cm above the object's origin.
    e.input(slot("store[0].flag.set_pose"), std::vector<double>{-1, -1, 0, 0, 0, 0, 1});
    for (int i = 0; i < 10; ++i) e.step();
    CHECK(e.graphics_pose(flag).p[0] == doctest::Approx(-1));
    e.input(slot("store.issue"));
    for (int i = 0; i < 3; ++i) e.step();
    CHECK(e.graphics_pose(flag).p[0] == doctest::Approx(flag_x));
    CHECK(e.graphics_pose(flag).p[0] == doctest::Approx(1));
    CHECK(e.graphics_pose(flag).p[1] == doctest::Approx(1));
    CHECK(e.graphics_pose(flag).p[2] == doctest::Approx(0.6));
}

// Whether a graphics' pose output is watched is kept beside the graphics (kinds/graphics/run.cpp)
// and read again when a watch is added: a graphics watched after the start publishes its pose
// from the next step on.
TEST_CASE("runtime: a graphics watched after the start publishes its pose from then on") {
    SceneBuilder b;
    int32_t d = b.dobj("thing");
    int32_t body = b.body(d, "body", BodyMode::Dynamic, {box({0.1, 0.1, 0.1})}, 1, at(0, 0, 1));
    int32_t gi = b.graphics(d, "look", at(0, 0, 1.2), body);
    const plant::graph::SlotId pose(b.S(b.g.graphics[plant::graph::GraphicsId(gi)].comp.v, "pose"));
    Engine e(b.g);
    for (int i = 0; i < 5; ++i) {  // falling: its pose changes every step, unwatched
        e.step();
        CHECK_FALSE(e.active(pose));
    }
    e.watch(pose);
    for (int i = 0; i < 5; ++i) {
        e.step();
        CHECK(e.active(pose));
        REQUIRE(e.value(pose).size() == 7);
        CHECK(e.value(pose)[2] == doctest::Approx(e.graphics_pose(plant::graph::GraphicsId(gi)).p[2]));
    }
}

TEST_CASE("runtime: graphics attached to a body track it") {
    SceneBuilder b;
    int32_t d = b.dobj("thing");
    int32_t body = b.body(d, "body", BodyMode::Dynamic, {box({0.1, 0.1, 0.1})}, 1, at(0, 0, 1));
    int32_t gi = b.graphics(d, "look", at(0, 0, 1.2), body);
    Engine e(b.g);
    for (int i = 0; i < 30; ++i) e.step();
    CHECK(e.graphics_pose(plant::graph::GraphicsId(gi)).p[2] == doctest::Approx(e.body_pose(plant::graph::BodyId(body)).p[2] + 0.2));
}

// A graphics that only its pose output reads (on a moving body, no child, no gripper following
// it), with that output not watched, is not kept up step by step (GraphicsState::stale):
// Engine::graphics_pose computes it from its body's frame at the visit. It reads the same bits
// as when kept up (a bottle moved later in the step by a pusher too), in the world and parked,
// and once watched its output is published as before.
TEST_CASE("runtime: a bottle's graphics not kept up read the same pose as kept up, and publish once watched") {
    plant::Compilation c;
    compile_repo_file("plants/bottling.plant", c);
    REQUIRE(c.ok());
    const plant::graph::Graph& g = c.graph;
    Engine lazy(g), kept(g);
    std::vector<plant::graph::GraphicsId> looks;
    for (plant::graph::GraphicsId i : ids_of(g.graphics))
        if (g.graphics[i].body.valid() && g.bodies[g.graphics[i].body].mode == plant::graph::BodyMode::Dynamic) {
            looks.push_back(i);
            kept.watch(plant::graph::SlotId(g.comps[g.graphics[i].comp].slot_adr.v + plant::graph::graphicsslot::pose));
        }
    REQUIRE(looks.size() >= 40);  // the pools of its sources
    size_t compared = 0, in_world = 0, mismatched = 0;
    for (int step = 0; step < 1500; ++step) {  // 10 s: bottles issued, carried, some taken
        lazy.step();
        kept.step();
        if (step % 50 != 49) continue;
        for (plant::graph::GraphicsId i : looks) {
            const plant::graph::Pose a = lazy.graphics_pose(i), b = kept.graphics_pose(i);
            const plant::graph::BodyId body = g.graphics[i].body;
            ++compared;
            in_world += lazy.body_in_world(body);
            if (a.p != b.p || a.q != b.q) ++mismatched;
        }
    }
    CHECK(mismatched == 0);
    CHECK(in_world > 50);  // of 1,200 looks, 69: most bottles are in their pools
    // Watched from now on: its output carries the pose a visit computes.
    plant::graph::GraphicsId moving{};
    for (plant::graph::GraphicsId i : looks)
        if (lazy.body_in_world(g.graphics[i].body) && lazy.body_velocity(g.graphics[i].body)[0] != 0) moving = i;
    REQUIRE(moving.valid());
    const plant::graph::SlotId out(g.comps[g.graphics[moving].comp].slot_adr.v + plant::graph::graphicsslot::pose);
    lazy.watch(out);
    lazy.step();
    kept.step();
    const auto v = lazy.value(out), w = kept.value(out);
    REQUIRE(v.size() == 7);
    CHECK(std::equal(v.begin(), v.end(), w.begin()));
    CHECK(lazy.graphics_pose(moving).p == kept.graphics_pose(moving).p);
}

TEST_CASE("runtime: many timers, ticked in slices on two threads, tick and stop as on one") {
    // More than 256 timers: their job has several slices, each noting which of its timers made
    // an output active, which the calling thread then lists (kinds/timer/run.cpp). Two floors
    // far apart are two regions, so the plant steps on two threads.
    SceneBuilder b(100);
    b.body(0, "floor_a", BodyMode::Static, {box({1, 1, 0.2})}, 0, at(0, 0, -0.1));
    b.body(0, "floor_b", BodyMode::Static, {box({1, 1, 0.2})}, 0, at(50, 0, -0.1));
    std::vector<int32_t> comps;
    for (int i = 0; i < 700; ++i) {
        const int32_t t = b.timer(0, "t" + std::to_string(i), 0.01 * (1 + i % 13), i % 3 != 0, i % 5 != 0);
        comps.push_back(b.g.timers[plant::graph::Id<plant::graph::Timer>(t)].comp.v);
    }
    plant::engine::Options one, two;
    one.threads = 1;
    two.threads = 2;
    Engine a(b.g, one), c(b.g, two);
    REQUIRE(c.internals().phys.threads() == 2);
    int64_t ticks = 0, stops = 0, differ = 0;
    for (int step = 1; step <= 150; ++step) {
        if (step == 40)  // the timers that did not start by themselves, on both
            for (size_t i = 0; i < comps.size(); i += 5) {
                a.input(plant::graph::SlotId(b.S(comps[i], "start")));
                c.input(plant::graph::SlotId(b.S(comps[i], "start")));
            }
        a.step();
        c.step();
        for (int32_t comp : comps) {
            const auto tick = plant::graph::SlotId(b.S(comp, "tick")), running = plant::graph::SlotId(b.S(comp, "running"));
            differ += a.active(tick) != c.active(tick) || a.active(running) != c.active(running) ||
                      a.value(running)[0] != c.value(running)[0];
            ticks += a.active(tick);
            stops += a.active(running) && a.value(running)[0] == 0;
        }
    }
    CHECK(differ == 0);
    CHECK(ticks > 2000);
    CHECK(stops > 100);  // the one-shots that ran out
}
