// std.transfers: bottles cross a right-angle Corner, compiled from the standard library
// and run on Bullet.
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

struct CornerRun {
    double peak_tilt = 0;     // degrees, over all bottles until each reached the end line
    double worst_out = 0;     // m, how far a bottom body strayed beyond 2 cm of a lane's centre line
    double last_arrival = -1; // s, when the last bottle reached the end line; -1: some never did
};

// A 60 cm belt, a Corner, an 80 cm outgoing belt; `count` bottles of `mass_g` touching
// in a queue, the first 20 cm before the corner. Runs until every bottle has come 70 cm
// along the outgoing belt, or 5 s.
CornerRun run_corner(int mass_g, int speed_cm_s, bool left, int count) {
    const double L = 0.60, w = 0.08, side = left ? 1 : -1;
    std::string src = "import std.belts\nimport std.bottle\nimport std.transfers\nplant T {\n";
    const std::string v = std::to_string(speed_cm_s) + " cm/s";
    src += "    in1: Belt(length = 60 cm, speed = " + v + ")\n";
    src += "    turn: Corner(left = " + std::string(left ? "true" : "false") + ", speed = " + v +
           ") at (60 cm, 0 m, 0 m)\n";
    src += "    out1: Belt(length = 80 cm, speed = " + v + ") at (64 cm, " + (left ? "4" : "-4") +
           " cm, 0 m) rotate z by " + (left ? "90" : "-90") + " deg\n";
    for (int i = 0; i < count; ++i)
        src += "    bottle" + std::to_string(i) + ": Bottle(mass = " + std::to_string(mass_g) + " g) at (" +
               std::to_string(40 - i * 4.05) + " cm, 0 m, 0 m)\n";
    src += "}\n";
    plant::Compilation c;
    compile_text(src, c, "corner.plant");
    REQUIRE(c.ok());
    const std::vector<int32_t> mains = bodies_ending(c.graph, ".main");
    const std::vector<int32_t> bottoms = bodies_ending(c.graph, ".bottom");
    REQUIRE(mains.size() == size_t(count));
    REQUIRE(bottoms.size() == size_t(count));
    Engine e(c.graph);
    CornerRun r;
    std::vector<double> arrived(size_t(count), -1);
    for (int step = 1; step <= 150 * 5; ++step) {
        e.step();
        for (size_t i = 0; i < mains.size(); ++i) {
            if (arrived[i] >= 0) continue;
            r.peak_tilt = std::max(r.peak_tilt, tilt_deg(e.body_pose(mains[i]).q));
            const auto p = e.body_pose(bottoms[i]).p;
            // The incoming lane and the corner square, or the outgoing lane.
            const double in_lane = p[0] <= L + w ? std::abs(p[1]) - 0.02 : 1;
            const double out_lane = side * p[1] >= -w / 2 ? std::abs(p[0] - (L + w / 2)) - 0.02 : 1;
            r.worst_out = std::max(r.worst_out, std::min(in_lane, out_lane));
            CHECK(p[2] > -0.01);  // still on the band
            if (side * p[1] > 0.04 + 0.70) arrived[i] = step / 150.0;
        }
    }
    if (std::all_of(arrived.begin(), arrived.end(), [](double t) { return t >= 0; }))
        r.last_arrival = *std::max_element(arrived.begin(), arrived.end());
    CHECK(e.warnings().total() == 0);
    return r;
}

}  // namespace

TEST_CASE("std.transfers: 20-80 g bottles at 50 and 100 cm/s cross a left and a right Corner upright, inside the rails") {
    // Measured (ci build): peak tilt 4.1° (20-40 g at 100 cm/s, the band's sideways pull
    // at the corner), 2.3° at 50 cm/s; bottom bodies at most 6.5 mm beyond 2 cm of a lane's
    // centre line (the 1 m/s impact on the end rail), i.e. inside the 4 cm half-width.
    for (int mass : {20, 40, 80})
        for (int speed : {50, 100})
            for (bool left : {true, false})
                for (int count : {1, 4}) {
                    CAPTURE(mass);
                    CAPTURE(speed);
                    CAPTURE(left);
                    CAPTURE(count);
                    const CornerRun r = run_corner(mass, speed, left, count);
                    CHECK(r.peak_tilt < (speed == 50 ? 3.0 : 5.0));
                    CHECK(r.worst_out < 0.008);
                    // None stuck: 94 cm of track for the first bottle, 4 cm more for each
                    // in the queue; measured 1.89-2.14 s at 50 cm/s, 0.95-1.08 s at 100 cm/s.
                    CHECK(r.last_arrival > 0);
                    CHECK(r.last_arrival < (speed == 50 ? 2.5 : 1.3));
                }
}
