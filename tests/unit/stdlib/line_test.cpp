// std.arm and std.stations, through examples/line.plant: an arm sets bottles from the
// storage onto a belt, a filling and a capping station process them, an exit takes them.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "graph/kinds.h"
#include "lookup.h"

#include <doctest/doctest.h>

#include <string>
#include <vector>

using namespace plant::test;
using plant::engine::Engine;

TEST_CASE("std.arm and std.stations: every bottle is set down, filled, capped and commissioned") {
    plant::Compilation c;
    compile_repo_file("examples/line.plant", c);
    REQUIRE(c.ok());
    const auto& g = c.graph;
    const int32_t placed = slot_named(g, "arm.hand.released"), filled = slot_named(g, "fill.core.work.tick"),
                  capped = slot_named(g, "cap.core.work.tick"), taken = slot_named(g, "done.away.taken");
    // The bottle the exit takes: its variant must be the filled and capped one.
    const int32_t taken_obj = slot_named(g, "done.away.object");
    REQUIRE(placed >= 0);
    REQUIRE(taken_obj >= 0);
    plant::graph::IdVector<plant::graph::DoId, plant::graph::SlotId> shown_of(g.dos.count());
    for (const plant::graph::Graphics& gr : g.graphics) {
        const plant::graph::Comp& c = g.comps[gr.comp];
        shown_of[c.owner] = c.slot_adr + plant::graph::graphicsslot::shown;
    }
    Engine e(g);
    for (plant::graph::SlotId s : shown_of)
        if (s.valid()) e.watch(s);
    int n_placed = 0, n_filled = 0, n_capped = 0, n_taken = 0, unfinished = 0;
    for (int i = 0; i < 150 * 40; ++i) {
        e.step();
        n_placed += e.active(plant::graph::SlotId(placed));
        n_filled += e.active(plant::graph::SlotId(filled));
        n_capped += e.active(plant::graph::SlotId(capped));
        if (e.active(plant::graph::SlotId(taken))) {
            ++n_taken;
            const int32_t d = int32_t(e.value(plant::graph::SlotId(taken_obj))[0]);
            REQUIRE(d >= 0);
            unfinished += e.str(int32_t(e.value(shown_of[plant::graph::DoId(d)])[0])) != "filled_capped";
        }
    }
    CHECK(n_taken >= 5);
    CHECK(n_placed >= n_filled);
    CHECK(n_filled >= n_capped);
    CHECK(n_capped >= n_taken);
    CHECK(unfinished == 0);
    CHECK(e.warnings().total() == 0);  // nothing dropped, nothing lost
}
