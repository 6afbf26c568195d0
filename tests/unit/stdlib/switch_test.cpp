// std.switch: the switch section routes bottles physically, driven through its ports.
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

// A line through a switch section: 4 bottles `a` pass first, 4 bottles `b` follow
// 1.9 m behind them; long belts on both exits, a binary sensor 20 cm into each.
std::string line_plant(int side, const std::string& speed) {
    const std::string s = std::to_string(side);
    return R"(
import std.belts, std.bottle, std.sensors, std.switch
plant Line {
    up: Belt(length = 3 m, speed = )" + speed + R"() at (-3 m, 0 m, 0 m)
    sw: Switch(side = )" + s + ", speed = " + speed + R"()
    ahead: Belt(length = 4 m, speed = )" + speed + R"() at (65 cm, 0 m, 0 m)
    aside: Belt(length = 4 m, speed = )" + speed + R"() at (65 cm, )" + s + R"( * 30 cm, 0 m) rotate z by )" + s + R"( * 90 deg
    ahead_eye: BinarySensor at (85 cm, 0 m, 0 m)
    aside_eye: BinarySensor at (65 cm, )" + s + R"( * 50 cm, 0 m) rotate z by )" + s + R"( * 90 deg
    for i in 0 .. 4 {
        a[i]: Bottle(mass = 20 g + i * 20 g) at (-25 cm - i * 25 cm, -1.5 cm + i * 1 cm, 0 m)
        b[i]: Bottle(mass = 80 g - i * 20 g) at (-215 cm - i * 25 cm, 1.5 cm - i * 1 cm, 0 m)
    }
}
)";
}

struct Run {
    double worst_tilt = 0;
    int64_t straight = 0, branch = 0;                    // bottles seen at each exit
    int32_t move_to_working = -1, working = -1, base = -1;  // after the second to_working
};

// Runs the line for `seconds` with the switch sent to working twice (two steps apart) at
// `switch_at`, between the two groups; belt_speed in m/s.
Run run_line(const plant::graph::Graph& g, double belt_speed, double switch_at, double seconds) {
    Run r;
    const int32_t to_working = slot_named(g, "sw.net.MoveToWorkingPos.put");
    REQUIRE(to_working >= 0);
    const int32_t ahead_eye = row_of_comp(g, g.triggers, "ahead_eye.volume"), aside_eye = row_of_comp(g, g.triggers, "aside_eye.volume");
    REQUIRE(ahead_eye >= 0);
    REQUIRE(aside_eye >= 0);
    std::vector<int32_t> bottles;
    for (int i = 0; i < 4; ++i)
        for (const char* grp : {"a", "b"}) bottles.push_back(row_of_comp(g, g.bodies, std::string(grp) + "[" + std::to_string(i) + "].main"));
    for (int32_t b : bottles) REQUIRE(b >= 0);

    Engine e(g);
    const int64_t send = std::lround(switch_at / e.dt());
    const int64_t steps = std::lround(seconds / e.dt());
    for (int64_t i = 0; i < steps; ++i) {
        if (i == send || i == send + 2) e.input(plant::graph::SlotId(to_working));
        e.step();
        if (i == send + 4) {
            r.move_to_working = e.tokens(plant::graph::PlaceId(place_named(g, "sw.net", "MoveToWorkingPos")));
            r.working = e.tokens(plant::graph::PlaceId(place_named(g, "sw.net", "WorkingPos")));
            r.base = e.tokens(plant::graph::PlaceId(place_named(g, "sw.net", "BasePos")));
        }
        for (int32_t b : bottles) r.worst_tilt = std::max(r.worst_tilt, tilt_deg(e.body_pose(plant::graph::BodyId(b)).q));
    }
    r.straight = e.trigger_enters(plant::graph::TriggerId(ahead_eye));
    r.branch = e.trigger_enters(plant::graph::TriggerId(aside_eye));
    CHECK(e.warnings().total() == 0);

    // Where every bottle is at the end, and that it still moves at belt speed.
    for (size_t k = 0; k < bottles.size(); ++k) {
        const auto p = e.body_pose(plant::graph::BodyId(bottles[k])).p;
        const auto v = e.body_velocity(plant::graph::BodyId(bottles[k]));
        CAPTURE(k);
        CAPTURE(p[0]);
        CAPTURE(p[1]);
        CHECK(std::abs(std::hypot(v[0], v[1]) - belt_speed) < 0.02);
        if (k % 2 == 0) {  // group a: straight on, between the rails of `ahead`
            CHECK(p[0] > 0.9);
            CHECK(std::abs(p[1]) < 0.021);
        } else {  // group b: on the branch belt `aside`, between its rails
            CHECK(std::abs(p[1]) > 0.55);
            CHECK(std::abs(p[0] - 0.65) < 0.021);
        }
    }
    return r;
}

}  // namespace

TEST_CASE("std.switch: base position runs bottles straight through, working position sends every bottle into the branch") {
    for (int side : {1, -1}) {
        CAPTURE(side);
        plant::Compilation c;
        compile_text(line_plant(side, "50 cm/s"), c, "switch_line.plant");
        INFO(plant::render_all_text(c.sink.all(), c.sources));
        REQUIRE(c.ok());
        // Group a reaches the blade within 1.5 s and has left it by 3 s; group b reaches it
        // after 4 s. Switch at 3 s; after 9 s every b bottle is 0.5 m or more into the branch.
        const Run r = run_line(c.graph, 0.5, 3.0, 9.0);
        CHECK(r.straight == 4);
        CHECK(r.branch == 4);
        CHECK(r.worst_tilt < 6);
        MESSAGE("side " << side << ": worst tilt " << r.worst_tilt << " deg");
        // to_working twice in a row: the second request is drained (tcw), not kept.
        CHECK(r.move_to_working == 0);
        CHECK(r.working == 1);
        CHECK(r.base == 0);
    }
}

TEST_CASE("std.switch: without a request every bottle runs straight on") {
    plant::Compilation c;
    compile_text(line_plant(1, "50 cm/s"), c, "switch_base.plant");
    INFO(plant::render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    // The switch is never sent to working: all 8 bottles take the straight exit.
    const int32_t ahead_eye = row_of_comp(c.graph, c.graph.triggers, "ahead_eye.volume"), aside_eye = row_of_comp(c.graph, c.graph.triggers, "aside_eye.volume");
    std::vector<int32_t> bottles;
    for (size_t b = 0; b < c.graph.bodies.size(); ++b)
        if (c.graph.comp_path(c.graph.bodies[plant::graph::BodyId(b)].comp).ends_with("].main")) bottles.push_back(int32_t(b));
    REQUIRE(bottles.size() == 8);
    Engine e(c.graph);
    double worst = 0;
    for (int i = 0; i < 150 * 9; ++i) {
        e.step();
        for (int32_t b : bottles) worst = std::max(worst, tilt_deg(e.body_pose(plant::graph::BodyId(b)).q));
    }
    CHECK(e.trigger_enters(plant::graph::TriggerId(ahead_eye)) == 8);
    CHECK(e.trigger_enters(plant::graph::TriggerId(aside_eye)) == 0);
    CHECK(worst < 6);
    CHECK(e.warnings().total() == 0);
    MESSAGE("base position: worst tilt " << worst << " deg");
}

TEST_CASE("std.switch: the blade's graphics swings out to the working position and back to the base position") {
    plant::Compilation c;
    compile_text("import std.switch\nplant P { sw: Switch(side = -1, blade_angle = 20 deg, swing = 200 ms) }\n", c,
                 "switch_blade.plant");
    INFO(plant::render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    const int32_t look = row_of_comp(c.graph, c.graph.graphics, "sw.look");
    REQUIRE(look >= 0);
    const int32_t to_working = slot_named(c.graph, "sw.net.MoveToWorkingPos.put");
    const int32_t to_base = slot_named(c.graph, "sw.net.MoveToBasePos.put");
    REQUIRE(to_working >= 0);
    REQUIRE(to_base >= 0);
    Engine e(c.graph);
    e.step();
    const plant::graph::Quat q0 = e.graphics_pose(plant::graph::GraphicsId(look)).q;
    const plant::graph::Vec3 p0 = e.graphics_pose(plant::graph::GraphicsId(look)).p;  // the blade turns about its own origin
    // The angle about z between the start pose and q (both rotations about z only).
    auto turned_deg = [&](const plant::graph::Quat& q) {
        const double a0 = 2 * std::atan2(q0[2], q0[3]), a = 2 * std::atan2(q[2], q[3]);
        double d = (a - a0) * 180 / std::numbers::pi;
        while (d > 180) d -= 360;
        while (d < -180) d += 360;
        return d;
    };
    auto run = [&](double seconds) {
        for (int i = 0; i < int(seconds * 150); ++i) e.step();
    };
    e.input(plant::graph::SlotId(to_working));
    run(0.1);
    const double halfway = turned_deg(e.graphics_pose(plant::graph::GraphicsId(look)).q);
    run(0.4);
    CHECK(turned_deg(e.graphics_pose(plant::graph::GraphicsId(look)).q) == doctest::Approx(-20).epsilon(1e-6));  // side −1: turned by −20°
    CHECK(halfway < -1);
    CHECK(halfway > -19);
    e.input(plant::graph::SlotId(to_base));
    run(0.1);
    const double back_halfway = turned_deg(e.graphics_pose(plant::graph::GraphicsId(look)).q);
    run(0.4);
    CHECK(back_halfway < -1);  // on its way back from the working position
    CHECK(back_halfway > -19);
    CHECK(std::abs(turned_deg(e.graphics_pose(plant::graph::GraphicsId(look)).q)) < 1e-6);  // back at the start pose
    for (int i = 0; i < 3; ++i) CHECK(e.graphics_pose(plant::graph::GraphicsId(look)).p[size_t(i)] == doctest::Approx(p0[size_t(i)]));
}
