// Queues that hold: a long queue of touching bottles waits at a held std.separator on a
// running std.belts belt (whose band slips under held bottles) without climbing or losing
// any, and the separator then still lets exactly one pass per cycle.
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

TEST_CASE("std.separator: 12 touching bottles held for 120 s stay on the band, none lost, then one passes per cycle") {
    constexpr int n = 12;
    constexpr double wp_x = 1.5;
    plant::Compilation c;
    compile_text(R"(
import std.belts, std.bottle, std.separator
plant LongQueue {
    belt: Belt(length = 6 m)
    sep: Separator at (1.5 m, 0 m, 0 m)
    trigger out_volume at (5.8 m, 0 m, 4 cm) { extent = (4 cm, 10 cm, 10 cm) }
    exit done { trigger = out_volume }
    for i in 0 .. 12 { b[i]: Bottle at (1.25 m - i * 4.05 cm, -1 mm + (i % 3) * 1 mm, -2 mm + (1.25 m - i * 4.05 cm) / 6 m * 2 mm) }
}
)",
                 c, "long_queue.plant");
    INFO(plant::render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    const auto& g = c.graph;
    std::vector<int32_t> mains, feet;
    for (int i = 0; i < n; ++i)
        for (size_t b = 0; b < g.bodies.size(); ++b) {
            const std::string p = g.comp_path(g.bodies[plant::graph::BodyId(b)].comp), name = "b[" + std::to_string(i) + "].";
            if (p == name + "main") mains.push_back(int32_t(b));
            if (p == name + "bottom") feet.push_back(int32_t(b));
        }
    REQUIRE(mains.size() == n);
    REQUIRE(feet.size() == n);
    const int32_t released = slot_named(g, "sep.bp.left.look.close.finished");
    const int32_t hold = slot_named(g, "sep.holding.start"), free = slot_named(g, "sep.holding.stop");
    REQUIRE(released >= 0);
    REQUIRE(hold >= 0);
    REQUIRE(free >= 0);

    Engine e(g);
    e.input(plant::graph::SlotId(hold));
    // The foot's centre rests 3 mm above the band's top (z = −2 mm … 0 mm along the belt),
    // so at most 3 mm; a bottle leaning 10° on its bottom edge lifts it 3.5 mm more; one
    // climbing onto its neighbour lifts it by centimetres. Every foot stays below 6.5 mm.
    constexpr double foot_top = 0.0065;
    double highest = -1, worst_tilt = 0;
    int releases = 0;
    for (int i = 0; i < 150 * 120; ++i) {
        e.step();
        releases += e.active(plant::graph::SlotId(released));
        for (int k = 0; k < n; ++k) {
            highest = std::max(highest, e.body_com(plant::graph::BodyId(feet[size_t(k)]))[2]);
            worst_tilt = std::max(worst_tilt, tilt_deg(e.body_pose(plant::graph::BodyId(mains[size_t(k)])).q));
        }
    }
    MESSAGE("held 120 s: highest foot at " << highest * 1000 << " mm, worst tilt " << worst_tilt << " deg");
    CHECK(releases == 0);
    CHECK(highest < foot_top);
    CHECK(worst_tilt < 10);
    // All waiting behind WP (its face at wp_x − 3 mm), the first at it. (In the guides'
    // funnel and on the wider belt behind it they stand zigzag, so x order is not queue order.)
    CHECK(e.body_com(plant::graph::BodyId(mains[0]))[0] < wp_x - 0.02);
    CHECK(e.body_com(plant::graph::BodyId(mains[0]))[0] > wp_x - 0.03);
    for (int k = 1; k < n; ++k) CHECK(e.body_com(plant::graph::BodyId(mains[size_t(k)]))[0] < e.body_com(plant::graph::BodyId(mains[0]))[0] - 0.03);

    // Let them go: one bottle past WP per cycle; the exit at 5.8 m takes them off the belt.
    e.input(plant::graph::SlotId(free));
    std::vector<int> passed_at_release;
    std::vector<double> passed_at(n, -1);
    for (int i = 0; i < 150 * 25; ++i) {
        e.step();
        int passed = 0;
        for (int k = 0; k < n; ++k) {
            const auto p = e.body_com(plant::graph::BodyId(mains[size_t(k)]));
            if (passed_at[size_t(k)] < 0 && p[0] > wp_x + 0.03) passed_at[size_t(k)] = e.time();
            passed += passed_at[size_t(k)] >= 0 ? 1 : 0;
            highest = std::max(highest, e.body_com(plant::graph::BodyId(feet[size_t(k)]))[2]);
        }
        if (e.active(plant::graph::SlotId(released))) passed_at_release.push_back(passed);
    }
    REQUIRE(passed_at_release.size() == n);
    for (int k = 0; k < n; ++k) CHECK(passed_at_release[size_t(k)] == k);
    CHECK(highest < foot_top);
    for (size_t d = 0; d < g.dos.size(); ++d) CHECK(e.lost_at(plant::graph::DoId(int32_t(d))) < 0);
    CHECK(e.warnings().total() == 0);
}
