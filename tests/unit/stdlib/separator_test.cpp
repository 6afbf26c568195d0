// std.separator: the gates hold a queue of bottles on a running belt and let exactly one
// pass per cycle.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "lookup.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

using namespace plant::test;
using plant::engine::Engine;

namespace {

// A 6 m belt at 50 cm/s with the separator's WP at x = 1.5 m and 4 bottles queued
// upstream, touching (0.5 mm apart), slightly off the centre line.
//
const char* queue_plant = R"(
import std.belts, std.bottle, std.separator

plant Queue {
    belt: Belt(length = 6 m)
    sep: Separator at (1.5 m, 0 m, 0 m)
    for i in 0 .. 4 { b[i]: Bottle at (1 m - i * 4.05 cm, -1.5 cm + i * 7 mm, 0 m) }
}
)";

struct Queue {
    plant::Compilation c;
    std::vector<int32_t> bottles;  // main bodies, b[0] first in the queue
    int32_t released = -1, hold = -1, free = -1, b327 = -1;
    Queue() {
        compile_text(queue_plant, c, "separator_queue.plant");
        INFO(plant::render_all_text(c.sink.all(), c.sources));
        REQUIRE(c.ok());
        const auto& g = c.graph;
        for (int i = 0; i < 4; ++i)
            for (size_t b = 0; b < g.bodies.size(); ++b)
                if (g.comp_path(g.bodies[plant::graph::BodyId(b)].comp) == "b[" + std::to_string(i) + "].main") bottles.push_back(int32_t(b));
        REQUIRE(bottles.size() == 4);
        // The port `released` forwards to BP's `closed`, the end of its close animation.
        released = slot_named(g, "sep.bp.left.look.close.finished");
        hold = slot_named(g, "sep.holding.start");
        free = slot_named(g, "sep.holding.stop");
        b327 = row_of_comp(g, g.triggers, "sep.b327.volume");
        REQUIRE(released >= 0);
        REQUIRE(hold >= 0);
        REQUIRE(free >= 0);
        REQUIRE(b327 >= 0);
    }
};

constexpr double wp_x = 1.5;

}  // namespace

TEST_CASE("std.separator: a queue of touching bottles on a running belt leaves one bottle per cycle") {
    Queue q;
    Engine e(q.c.graph);
    std::vector<double> release_times;
    std::vector<int64_t> b327_at_release;          // bottles B327 had seen at each release
    std::vector<int> passed_at_release;            // bottles past WP at each release
    std::vector<double> passed_at(4, -1);          // when each bottle's centre passed WP + 3 cm
    double worst_tilt = 0;
    for (int i = 0; i < 150 * 9; ++i) {
        e.step();
        if (e.active(plant::graph::SlotId(q.released))) {
            release_times.push_back(e.time());
            b327_at_release.push_back(e.trigger_enters(plant::graph::TriggerId(q.b327)));
            passed_at_release.push_back(int(std::count_if(passed_at.begin(), passed_at.end(), [](double t) { return t >= 0; })));
        }
        for (size_t k = 0; k < 4; ++k) {
            const auto pose = e.body_pose(plant::graph::BodyId(q.bottles[k]));
            worst_tilt = std::max(worst_tilt, tilt_deg(pose.q));
            if (passed_at[k] < 0 && pose.p[0] > wp_x + 0.03) passed_at[k] = e.time();
        }
    }
    MESSAGE("releases at " << (release_times.size() > 0 ? release_times[0] : -1.0) << " s ... "
                           << (release_times.empty() ? -1.0 : release_times.back()) << " s, worst tilt " << worst_tilt << " deg");
    REQUIRE(release_times.size() == 4);
    for (size_t k = 0; k < 4; ++k) {
        CAPTURE(k);
        // Before the k-th release exactly k bottles had passed, and B327 had seen k of
        // them: one bottle per cycle, the next one held.
        CHECK(passed_at_release[k] == int(k));
        CHECK(b327_at_release[k] == int64_t(k));
        // Bottles leave in queue order, each in its own cycle.
        CHECK(passed_at[k] > release_times[k]);
        if (k + 1 < 4) CHECK(passed_at[k] < release_times[k + 1]);
    }
    // Cycles are paced: settle (0.1 s) + BP in (0.1 s) + pitch (0.6 s) and the move-up.
    for (size_t k = 1; k < 4; ++k) CHECK(release_times[k] - release_times[k - 1] > 0.75);
    CHECK(e.trigger_enters(plant::graph::TriggerId(q.b327)) == 4);
    CHECK(worst_tilt < 10);
    CHECK(e.warnings().total() == 0);
    // All downstream, on the belt's centre line, at belt speed.
    for (int32_t b : q.bottles) {
        const auto p = e.body_pose(plant::graph::BodyId(b)).p;
        CHECK(p[0] > wp_x + 0.5);
        CHECK(std::abs(p[1]) < 0.021);
        CHECK(std::abs(e.body_velocity(plant::graph::BodyId(b))[0] - 0.5) < 0.01);
    }
}

TEST_CASE("std.separator: hold keeps it closed, free lets the queue go") {
    Queue q;
    Engine e(q.c.graph);
    int releases = 0;
    double worst_tilt = 0;
    e.input(plant::graph::SlotId(q.hold));
    for (int i = 0; i < 150 * 3; ++i) {  // 3 s held: the queue arrives and waits
        e.step();
        releases += e.active(plant::graph::SlotId(q.released));
        for (int32_t b : q.bottles) worst_tilt = std::max(worst_tilt, tilt_deg(e.body_pose(plant::graph::BodyId(b)).q));
    }
    CHECK(releases == 0);
    // The first bottle waits at WP (its face at x = wp_x - 3 mm), the others behind it.
    const double first = e.body_pose(plant::graph::BodyId(q.bottles[0])).p[0];
    CHECK(first < wp_x - 0.02);
    CHECK(first > wp_x - 0.03);
    for (size_t k = 1; k < 4; ++k) CHECK(e.body_pose(plant::graph::BodyId(q.bottles[k])).p[0] < e.body_pose(plant::graph::BodyId(q.bottles[k - 1])).p[0] - 0.03);
    CHECK(std::abs(e.body_velocity(plant::graph::BodyId(q.bottles[3]))[0]) < 0.02);

    e.input(plant::graph::SlotId(q.free));
    for (int i = 0; i < 150 * 5; ++i) {
        e.step();
        releases += e.active(plant::graph::SlotId(q.released));
        for (int32_t b : q.bottles) worst_tilt = std::max(worst_tilt, tilt_deg(e.body_pose(plant::graph::BodyId(b)).q));
    }
    CHECK(releases == 4);
    CHECK(e.trigger_enters(plant::graph::TriggerId(q.b327)) == 4);
    CHECK(worst_tilt < 10);
    MESSAGE("held queue: worst tilt " << worst_tilt << " deg");
}

TEST_CASE("std.separator: a gate's pin graphics goes up on open and back down to its start pose on close") {
    plant::Compilation c;
    compile_text("import std.separator\nplant P { g: Gate(lift = 100 ms) }\n", c, "gate_look.plant");
    INFO(plant::render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    const int32_t look = row_of_comp(c.graph, c.graph.graphics, "g.look");
    const int32_t open = slot_named(c.graph, "g.look.raise.play"), close = slot_named(c.graph, "g.look.lower.play");
    REQUIRE(look >= 0);
    REQUIRE(open >= 0);
    REQUIRE(close >= 0);
    Engine e(c.graph);
    e.step();
    const double z0 = e.graphics_pose(plant::graph::GraphicsId(look)).p[2];
    auto run = [&](int steps) {
        for (int i = 0; i < steps; ++i) e.step();
    };
    e.input(plant::graph::SlotId(open));
    run(30);
    CHECK(e.graphics_pose(plant::graph::GraphicsId(look)).p[2] == doctest::Approx(z0 + 0.06));
    e.input(plant::graph::SlotId(close));
    run(8);  // about halfway down
    CHECK(e.graphics_pose(plant::graph::GraphicsId(look)).p[2] > z0 + 0.01);
    CHECK(e.graphics_pose(plant::graph::GraphicsId(look)).p[2] < z0 + 0.05);
    run(30);
    CHECK(e.graphics_pose(plant::graph::GraphicsId(look)).p[2] == doctest::Approx(z0));
}
