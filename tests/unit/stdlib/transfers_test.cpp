// std.transfers: bottles cross a right-angle Corner and a TJunction, compiled from the standard library
// and run on Bullet.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "lookup.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

using namespace plant::test;
using plant::engine::Engine;

namespace {

struct TransferRun {
    double peak_tilt = 0;     // degrees, over all bottles until each reached the end line
    double worst_out = 0;     // m, how far a bottom body strayed beyond 2 cm of a lane's centre line
    double last_arrival = -1; // s, when the last bottle reached the end line; -1: some never did
};

// A track around a transfer at (60 cm, 0, 0): its belts and `count` touching bottles of
// `mass_g` (from `bottles(i, mass)`), run for at most 5 s until every bottle is done.
// `excess(p)` says how far a bottom body at p lies beyond 2 cm of the nearest lane's
// centre line (≤ 0 inside); `input` is a slot sent at the start, if any.
struct Track {
    std::string belts;
    std::function<std::string(int, int)> bottle;
    std::function<double(const plant::graph::Vec3&)> excess;
    std::function<bool(const plant::graph::Vec3&)> done;
    std::string input;
};

TransferRun run_track(const Track& t, int mass_g, int count) {
    std::string src = "import std.belts\nimport std.bottle\nimport std.transfers\nplant T {\n" + t.belts;
    for (int i = 0; i < count; ++i) src += "    b" + std::to_string(i) + ": " + t.bottle(i, mass_g) + "\n";
    src += "}\n";
    CAPTURE(src);
    plant::Compilation c;
    compile_text(src, c, "transfer.plant");
    REQUIRE(c.ok());
    const std::vector<int32_t> mains = bodies_ending(c.graph, ".main");
    const std::vector<int32_t> bottoms = bodies_ending(c.graph, ".bottom");
    REQUIRE(mains.size() == size_t(count));
    REQUIRE(bottoms.size() == size_t(count));
    Engine e(c.graph);
    if (!t.input.empty()) {
        const int32_t slot = slot_named(c.graph, t.input);
        REQUIRE(slot >= 0);
        e.input(plant::graph::SlotId(slot));
    }
    TransferRun r;
    std::vector<double> arrived(size_t(count), -1);
    // Until every bottle is done, before they ride off the end of the last belt.
    for (int step = 1; step <= 150 * 5 && std::count(arrived.begin(), arrived.end(), -1.0) > 0; ++step) {
        e.step();
        for (size_t i = 0; i < mains.size(); ++i) {
            if (arrived[i] >= 0) continue;
            r.peak_tilt = std::max(r.peak_tilt, tilt_deg(e.body_pose(plant::graph::BodyId(mains[i])).q));
            const auto p = e.body_pose(plant::graph::BodyId(bottoms[i])).p;
            r.worst_out = std::max(r.worst_out, t.excess(p));
            CHECK(p[2] > -0.01);  // still on the band
            if (t.done(p)) arrived[i] = step / 150.0;
        }
    }
    if (std::all_of(arrived.begin(), arrived.end(), [](double a) { return a >= 0; }))
        r.last_arrival = *std::max_element(arrived.begin(), arrived.end());
    CHECK(e.warnings().total() == 0);
    return r;
}

std::string speed_text(int cm_s) { return std::to_string(cm_s) + " cm/s"; }

// Bottles touching in a queue on the incoming belt, the first 20 cm before the transfer.
std::string queued_bottle(int i, int mass_g) {
    return "Bottle(mass = " + std::to_string(mass_g) + " g) at (" + std::to_string(40 - i * 4.05) + " cm, 0 m, 0 m)";
}

// Beyond 2 cm of the incoming lane (y = 0, up to the transfer's far side x = 68 cm) and of
// a lane leaving towards `side` · y at x = 64 cm; the smaller of the two.
double excess_turn(const plant::graph::Vec3& p, double side) {
    const double in_lane = p[0] <= 0.68 ? std::abs(p[1]) - 0.02 : 1;
    const double out_lane = side * p[1] >= -0.04 ? std::abs(p[0] - 0.64) - 0.02 : 1;
    return std::min(in_lane, out_lane);
}

// The measured bounds, shared by every transfer: see the test cases.
void check_bounds(const TransferRun& r, int speed) {
    CHECK(r.peak_tilt < (speed == 50 ? 4.5 : 10.0));
    CHECK(r.worst_out < 0.008);
    CHECK(r.last_arrival > 0);
    CHECK(r.last_arrival < (speed == 50 ? 2.5 : 1.4));
}

// Runs `make(speed, side)` for 20, 40, 80 g, 50 and 100 cm/s, both sides, 1 and 4 bottles.
void sweep(const std::function<Track(int, double)>& make) {
    for (int mass : {20, 40, 80})
        for (int speed : {50, 100})
            for (double side : {1.0, -1.0})
                for (int count : {1, 4}) {
                    CAPTURE(mass);
                    CAPTURE(speed);
                    CAPTURE(side);
                    CAPTURE(count);
                    check_bounds(run_track(make(speed, side), mass, count), speed);
                }
}

// An 80 cm belt leaving the transfer towards side · y, as after a Corner.
std::string turn_belt(const char* name, int speed, double side) {
    return std::string("    ") + name + ": Belt(length = 80 cm, speed = " + speed_text(speed) + ") at (64 cm, " +
           (side > 0 ? "4" : "-4") + " cm, 0 m) rotate z by " + (side > 0 ? "90" : "-90") + " deg\n";
}

}  // namespace

// Measured (plant run, 150 Hz), 20-80 g, one bottle or four touching, both sides: peak tilt
// 2.3° at 50 cm/s and 4.1° at 100 cm/s (20-40 g; the band's sudden sideways pull, the
// same for end rails 2-8 cm high) with unlimited belts; with std.belts' slip limit
// (0.3 N per body) on the belts before and after, 3.6° at 50 cm/s and 8.9° at 100 cm/s
// (20 g; 40 g: 6.3°); bottom bodies at most 6.6 mm beyond 2 cm of a lane's
// centre line (the 1 m/s impact on the end rail), inside the 4 cm half-width. Every bottle
// is done (70 cm along the belt after the transfer) at most 2.3 s (50 cm/s) or 1.15 s
// (100 cm/s) after starting 20 cm before it: nobody waits at the transfer. With std.belts'
// limit at 0.1 N per body (since issue 34) the bottles take longer to come up to 100 cm/s:
// 1.35 s at most. The bounds: tilt 4.5° / 10°, 8 mm, 2.5 s / 1.4 s.

TEST_CASE("std.transfers: 20-80 g bottles at 50 and 100 cm/s cross a left and a right Corner upright, inside the rails") {
    sweep([](int speed, double side) {
        const std::string v = speed_text(speed);
        return Track{"    in1: Belt(length = 60 cm, speed = " + v + ")\n    turn: Corner(left = " +
                         (side > 0 ? "true" : "false") + ", speed = " + v + ") at (60 cm, 0 m, 0 m)\n" +
                         turn_belt("out1", speed, side),
                     queued_bottle, [side](const plant::graph::Vec3& p) { return excess_turn(p, side); },
                     [side](const plant::graph::Vec3& p) { return side * p[1] > 0.74; }, ""};
    });
}

// A TJunction with its incoming belt, straight exit and branch.
std::string t_belts(int speed, double side) {
    const std::string v = speed_text(speed);
    return "    in1: Belt(length = 60 cm, speed = " + v + ")\n    t: TJunction(side = " + (side > 0 ? "1" : "-1") +
           ", speed = " + v + ") at (60 cm, 0 m, 0 m)\n    ahead: Belt(length = 80 cm, speed = " + v +
           ") at (68 cm, 0 m, 0 m)\n";
}

TEST_CASE("std.transfers: a TJunction lets bottles through, turns them into its branch, and merges its side belt") {
    SUBCASE("straight on") {
        sweep([](int speed, double side) {
            return Track{t_belts(speed, side) + turn_belt("branch", speed, side), queued_bottle,
                         [](const plant::graph::Vec3& p) { return std::abs(p[1]) - 0.02; },
                         [](const plant::graph::Vec3& p) { return p[0] > 1.38; }, ""};
        });
    }
    SUBCASE("into the branch") {
        sweep([](int speed, double side) {
            return Track{t_belts(speed, side) + turn_belt("branch", speed, side), queued_bottle,
                         [side](const plant::graph::Vec3& p) { return excess_turn(p, side); },
                         [side](const plant::graph::Vec3& p) { return side * p[1] > 0.74; }, "t.net.MoveToBranch.put"};
        });
    }
    SUBCASE("merging from the side belt") {
        sweep([](int speed, double side) {
            const std::string sy = side > 0 ? "" : "-";
            const std::string turn = side > 0 ? "-90" : "90";
            return Track{t_belts(speed, side) + "    side1: Belt(length = 60 cm, speed = " + speed_text(speed) +
                             ") at (64 cm, " + sy + "64 cm, 0 m) rotate z by " + turn + " deg\n",
                         [sy, turn](int i, int mass_g) {
                             return "Bottle(mass = " + std::to_string(mass_g) + " g) at (64 cm, " + sy +
                                    std::to_string(44 - i * 4.05) + " cm, 0 m) rotate z by " + turn + " deg";
                         },
                         [side](const plant::graph::Vec3& p) {
                             const double side_lane = side * p[1] >= -0.04 ? std::abs(p[0] - 0.64) - 0.02 : 1;
                             const double out_lane = p[0] >= 0.60 ? std::abs(p[1]) - 0.02 : 1;
                             return std::min(side_lane, out_lane);
                         },
                         [](const plant::graph::Vec3& p) { return p[0] > 1.38; }, ""};
        });
    }
}
