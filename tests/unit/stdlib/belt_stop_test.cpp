// std.belts Belt's stop and go (and std.transfers Corner's): a stopped belt brakes what
// rides on it to rest (its band holds still and pulls with the slip limit), go runs it again.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "lookup.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace plant::test;
using plant::engine::Engine;

namespace {

// The plant `text` compiled into c (it must compile) and its n bottles' main bodies.
std::vector<int32_t> compile_bottles(const std::string& text, const std::string& name, plant::Compilation& c, size_t n) {
    compile_text(text, c, name);
    INFO(plant::render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    std::vector<int32_t> bottles = bodies_ending(c.graph, ".main");
    REQUIRE(bottles.size() == n);
    return bottles;
}

}  // namespace

TEST_CASE("std.belts: a stopped belt brakes its bottles to rest, go starts them again") {
    plant::Compilation c;
    const std::vector<int32_t> bottles = compile_bottles(R"(
import std.belts, std.bottle
plant Stop {
    belt: Belt(length = 4 m)
    for i in 0 .. 5 { b[i]: Bottle at (20 cm + i * 20 cm, 0 m, -2 mm + (20 cm + i * 20 cm) / 4 m * 2 mm) }
    timer halt: oneshot { period = 1 s; autostart = true }
    timer restart: oneshot { period = 3 s; autostart = true }
    flow halt.tick -> belt.stop
    flow restart.tick -> belt.go
}
)",
                                                         "belt_stop.plant", c, 5);
    Engine e(c.graph);
    // The timers send stop at 1 s (every bottle rides at belt speed by then) and go at 3 s.
    for (int i = 0; i < 150; ++i) e.step();
    std::vector<double> at_stop;
    for (int32_t b : bottles) {
        CHECK(e.body_velocity(plant::graph::BodyId(b))[0] == doctest::Approx(0.5).epsilon(0.01));
        at_stop.push_back(e.body_com(plant::graph::BodyId(b))[0]);
    }
    double worst_tilt = 0, longest = 0;
    std::vector<double> rest_at(bottles.size(), -1);
    for (int i = 0; i < 150 * 2; ++i) {
        e.step();
        for (size_t k = 0; k < bottles.size(); ++k) {
            worst_tilt = std::max(worst_tilt, tilt_deg(e.body_pose(plant::graph::BodyId(bottles[k])).q));
            if (rest_at[k] < 0 && std::abs(e.body_velocity(plant::graph::BodyId(bottles[k]))[0]) < 1e-3) rest_at[k] = e.time() - 1;
        }
    }
    for (size_t k = 0; k < bottles.size(); ++k) {
        CAPTURE(k);
        const double moved = e.body_com(plant::graph::BodyId(bottles[k]))[0] - at_stop[k];
        longest = std::max(longest, moved);
        CHECK(rest_at[k] >= 0);
        CHECK(rest_at[k] < 0.12);  // at rest within 0.12 s of the stop (measured 0.107 s)
        CHECK(std::abs(e.body_velocity(plant::graph::BodyId(bottles[k]))[0]) < 1e-3);
        CHECK(moved > 0);
        CHECK(moved < 0.025);  // measured 23.3 mm at most (see the message); v²/(2·2F/M) = 25 mm
    }
    MESSAGE("stopped within " << longest * 1000 << " mm, worst tilt " << worst_tilt << " deg");
    CHECK(worst_tilt < 10);
    for (int i = 0; i < 150; ++i) e.step();
    for (int32_t b : bottles) {
        CHECK(e.body_velocity(plant::graph::BodyId(b))[0] == doctest::Approx(0.5).epsilon(0.01));
        CHECK(tilt_deg(e.body_pose(plant::graph::BodyId(b)).q) < 2);
    }
    CHECK(e.warnings().total() == 0);
}

// What a PLC reads of a belt: `running` (not stopped) and `speed_now` (the band's speed,
// 0 while stopped; before, the target's 0.5 m/s stayed after a stop), following stop, go and
// set_speed; plants/bottling_plc.plant maps both.
TEST_CASE("std.belts: running and speed_now follow stop, go and set_speed") {
    plant::Compilation c;
    compile_text(R"(
import std.belts
plant Ports {
    belt: Belt(length = 1 m)
    timer halt: oneshot { period = 1 s; autostart = true }
    timer restart: oneshot { period = 2 s; autostart = true }
    flow halt.tick -> belt.stop
    flow restart.tick -> belt.go
}
)",
                 c, "belt_ports.plant");
    INFO(plant::render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    const plant::graph::Graph& g = c.graph;
    const int32_t running = slot_named(g, "belt.drive.enabled"), speed = slot_named(g, "belt.drive.speed");
    REQUIRE(running >= 0);
    REQUIRE(speed >= 0);
    Engine e(g);
    e.watch(plant::graph::SlotId(running));
    e.watch(plant::graph::SlotId(speed));
    auto at = [&](double t) {
        while (e.time() < t - 1e-9) e.step();
    };
    at(0.5);
    CHECK(e.value(plant::graph::SlotId(running))[0] == 1);
    CHECK(e.value(plant::graph::SlotId(speed))[0] == doctest::Approx(0.5));
    at(1.5);
    CHECK(e.value(plant::graph::SlotId(running))[0] == 0);
    CHECK(e.value(plant::graph::SlotId(speed))[0] == 0);
    at(2.5);
    CHECK(e.value(plant::graph::SlotId(running))[0] == 1);
    CHECK(e.value(plant::graph::SlotId(speed))[0] == doctest::Approx(0.5));
}

// std.transfers Corner's stop: its band halts and brakes what is on it, as a Belt's (before,
// it only let go, and a bottle coasted on over the frictionless band); go runs it again.
TEST_CASE("std.transfers: a stopped Corner brakes the bottle on it to rest, go starts it again") {
    plant::Compilation c;
    const std::vector<int32_t> bottles = compile_bottles(R"(
import std.belts, std.bottle, std.transfers
plant CornerStop {
    in1:  Belt(length = 1 m)
    turn: Corner(left = true) at (1 m, 0 m, 0 m)
    out1: Belt(length = 1 m) at (1.04 m, 4 cm, 0 m) rotate z by 90 deg
    b:    Bottle at (1.04 m, 0 m, -1 mm)
    timer halt: oneshot { period = 60 ms; autostart = true }
    timer restart: oneshot { period = 1 s; autostart = true }
    flow halt.tick -> turn.stop
    flow restart.tick -> turn.go
}
)",
                                                         "corner_stop.plant", c, 1);
    const plant::graph::BodyId b(bottles[0]);
    Engine e(c.graph);
    while (e.time() < 0.06 - 1e-9) e.step();
    CHECK(e.body_velocity(b)[1] > 0.3);  // the band pulls it along +y, towards out1
    while (e.time() < 0.5 - 1e-9) e.step();
    CHECK(std::abs(e.body_velocity(b)[1]) < 1e-3);
    CHECK(e.body_com(b)[1] < 0.04);  // still on the corner's square
    while (e.time() < 1.5 - 1e-9) e.step();
    CHECK(e.body_velocity(b)[1] > 0.3);
    CHECK(e.body_com(b)[1] > 0.1);  // on out1
    CHECK(e.warnings().total() == 0);
}
