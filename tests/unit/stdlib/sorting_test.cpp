// examples/sorting.plant: three RoutedSwitches (std.switch) sort bottles by bar code. Every
// bottle is checked where it leaves: the lane whose exit takes it must be the one its code
// names (A-*, B-*, C-*, anything else straight on), and none is lost.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

using namespace plant;

TEST_CASE("stdlib: a sorting line of RoutedSwitches sends every bottle into the lane its code names") {
    Compilation c;
    test::compile_repo_file("examples/sorting.plant", c);
    REQUIRE(c.ok());
    const graph::Graph& g = c.graph;
    std::map<std::string, int32_t> slot;
    for (size_t s = 0; s < g.slots.size(); ++s) slot[g.slot_path(int32_t(s))] = int32_t(s);
    struct Lane {
        std::string exit;
        char code;  // the first letter its bottles carry; 0: none of A, B, C
    };
    const Lane lanes[] = {{"lane_end[0]", 'A'}, {"lane_end[1]", 'B'}, {"lane_end[2]", 'C'}, {"line_end", 0}};
    engine::Engine e(g);
    for (const Lane& l : lanes) e.watch(plant::graph::SlotId(slot.at(l.exit + ".away.id")));
    std::map<char, int> sorted;
    int wrong = 0;
    for (int i = 0; i < 90 * 150; ++i) {
        e.step();
        for (const Lane& l : lanes) {
            if (!e.active(plant::graph::SlotId(slot.at(l.exit + ".away.taken")))) continue;
            const std::string id(e.str(int32_t(e.value(plant::graph::SlotId(slot.at(l.exit + ".away.id")))[0])));
            const char first = id.empty() ? '?' : id[0];
            const bool right = l.code ? first == l.code : (first != 'A' && first != 'B' && first != 'C');
            CHECK_MESSAGE(right, "bottle " << id << " left by " << l.exit << " at " << e.time() << " s");
            wrong += right ? 0 : 1;
            ++sorted[l.code ? l.code : 'X'];
        }
    }
    CHECK(wrong == 0);
    for (char k : {'A', 'B', 'C', 'X'}) CHECK_MESSAGE(sorted[k] >= 10, k << ": " << sorted[k]);
    int lost = 0;
    for (size_t d = 0; d < g.dos.size(); ++d) lost += e.lost_at(plant::graph::DoId(int32_t(d))) >= 0 ? 1 : 0;
    CHECK(lost == 0);
    CHECK(e.warnings().pool_empty == 0);
}

// A long run, run once at full length (the ci build); the sanitizer build runs its first
// 120 s, the queue full from about 30 s on (docs/testing.md, "How long the suite takes").
TEST_CASE("stdlib: a sorting line fed twice as fast as its filling station loses no bottle in 600 s") {
    const int seconds = PLANT_SANITIZED ? 120 : 600;
    // examples/sorting.plant with a separator and a filling station on its feed belt, fed a
    // bottle a second: the queue in front of the separator grows until the source's pool is
    // empty and stays there, pressed by the belt (whose band slips under held bottles).
    Compilation c;
    test::compile_text(R"(
import std.belts, std.bottle, std.switch, std.stations, std.separator
plant Overfed {
    feed: Belt(length = 3 m) at (-3 m, 0 m, 0 m)
    sep: Separator(behind = 32 cm, further = 60 cm) at (-1.2 m, 0 m, 0 m)
    fill: FillingStation(process = 1500 ms) at (-85 cm, 0 m, 0 m)
    for i in 0 .. 3 {
        ahead[i]: Belt(length = 1 m) at (i * 1.65 m + 65 cm, 0 m, 0 m)
        lane[i]:  Belt(length = 1 m) at (i * 1.65 m + 65 cm, 30 cm, 0 m) rotate z by 90 deg
        lane_end[i]: Commissioning at (i * 1.65 m + 65 cm, 1.25 m, 0 m) rotate z by 90 deg
    }
    sa: RoutedSwitch(codes = ["A-*"]) at (0 m, 0 m, 0 m)
    sb: RoutedSwitch(codes = ["B-*"]) at (1.65 m, 0 m, 0 m)
    sc: RoutedSwitch(codes = ["C-*"]) at (3.3 m, 0 m, 0 m)
    line_end: Commissioning at (4.9 m, 0 m, 0 m)
    source store at (-2.9 m, 0 m, 0 m) {
        object = Bottle
        pool = 16
        rate = 1 / 1 s
        ids = ["A-1", "B-2", "C-3", "X-4", "B-5", "A-6", "C-7", "X-8", "C-9", "A-10"]
    }
}
)",
                       c, "overfed_sorting.plant");
    INFO(render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    const graph::Graph& g = c.graph;
    std::map<std::string, int32_t> slot;
    for (size_t s = 0; s < g.slots.size(); ++s) slot[g.slot_path(int32_t(s))] = int32_t(s);
    engine::Engine e(g);
    const plant::graph::SlotId tick(slot.at("fill.core.work.tick"));
    std::vector<plant::graph::SlotId> exits;
    for (const char* exit : {"lane_end[0]", "lane_end[1]", "lane_end[2]", "line_end"})
        exits.emplace_back(slot.at(std::string(exit) + ".away.taken"));
    int filled = 0, taken = 0;
    for (int i = 0; i < seconds * 150; ++i) {
        e.step();
        filled += e.active(tick);
        for (const plant::graph::SlotId exit : exits) taken += e.active(exit);
    }
    const int64_t issued = e.issued(plant::graph::SourceId(0));
    int lost = 0;
    for (size_t d = 0; d < g.dos.size(); ++d) lost += e.lost_at(plant::graph::DoId(int32_t(d))) >= 0 ? 1 : 0;
    MESSAGE(seconds << " s: " << issued << " issued, " << filled << " filled (" << double(seconds) / std::max(filled, 1)
                    << " s per bottle at the station), " << taken << " taken by the exits, " << lost << " lost");
    CHECK(lost == 0);
    CHECK(filled > seconds / 4);                   // the station works all the time
    CHECK(taken >= filled - 6);                    // every filled bottle reaches an exit (12 s on the way)
    CHECK(double(seconds) / filled > 2 * 1.0 * 0.95);  // fed once a second, at least twice its pace
    CHECK(e.warnings().total() - e.warnings().pool_empty == 0);
}
