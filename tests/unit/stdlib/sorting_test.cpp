// examples/sorting.plant: three RoutedSwitches (std.switch) sort bottles by bar code. Every
// bottle is checked where it leaves: the lane whose exit takes it must be the one its code
// names (A-*, B-*, C-*, anything else straight on), and none is lost.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"

#include <doctest/doctest.h>

#include <map>

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
    for (const Lane& l : lanes) e.watch(slot.at(l.exit + ".away.id"));
    std::map<char, int> sorted;
    int wrong = 0;
    for (int i = 0; i < 90 * 150; ++i) {
        e.step();
        for (const Lane& l : lanes) {
            if (!e.active(slot.at(l.exit + ".away.taken"))) continue;
            const std::string id(e.str(int32_t(e.value(slot.at(l.exit + ".away.id"))[0])));
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
    for (size_t d = 0; d < g.dos.size(); ++d) lost += e.lost_at(int32_t(d)) >= 0 ? 1 : 0;
    CHECK(lost == 0);
    CHECK(e.warnings().pool_empty == 0);
}
