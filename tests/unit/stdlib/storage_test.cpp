// std.storage: a Storage issues exactly the bar codes it is given, in order and round
// again, on bottles of its pool that an exit hands back. Run on a belt into an exit.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"

#include <doctest/doctest.h>

#include <map>
#include <set>
#include <string>
#include <vector>

using namespace plant;

TEST_CASE("std.storage: a Storage issues the codes given, in turn, from its pool") {
    // Five codes, a pool of two: the exit must hand bottles back for the codes to go on.
    const std::vector<std::string> codes{"K-7", "A-001", "Q", "A-001", "Z-99"};
    Compilation c;
    test::compile_text(R"(
import std.belts, std.stations, std.storage
plant Store {
    belt:  Belt(length = 80 cm) at (-10 cm, 0 m, 0 m)
    store: Storage(codes = ["K-7", "A-001", "Q", "A-001", "Z-99"], bottles = 2, mass = 30 g, rate = 1 Hz)
    done:  Commissioning at (40 cm, 0 m, 0 m)
}
)",
                       c, "storage.plant");
    REQUIRE(c.ok());
    const graph::Graph& g = c.graph;
    std::map<std::string, int32_t> slot;
    for (plant::graph::SlotId s : plant::graph::ids_of(g.slots)) slot[g.slot_path(s)] = s.v;
    const int32_t issued = slot.at("store.store.issued"), id = slot.at("store.store.id"),
                  bottle = slot.at("store.store.object"), taken = slot.at("done.away.taken");
    engine::Engine e(g);
    e.watch(plant::graph::SlotId(id));
    e.watch(plant::graph::SlotId(bottle));
    for (const char* label : {"store.store[0].label.value", "store.store[1].label.value"}) e.watch(plant::graph::SlotId(slot.at(label)));
    std::vector<std::string> got;
    std::set<std::string> bottles;
    int n_taken = 0;
    for (int i = 0; i < 12 * 150; ++i) {
        e.step();
        n_taken += e.active(plant::graph::SlotId(taken));
        if (!e.active(plant::graph::SlotId(issued))) continue;
        const std::string code(e.str(int32_t(e.value(plant::graph::SlotId(id))[0])));
        const int32_t d = int32_t(e.value(plant::graph::SlotId(bottle))[0]);
        REQUIRE(d >= 0);
        const std::string path(g.str(g.dos[graph::DoId(d)].path));
        bottles.insert(path);
        // The code is in the bottle's label too, where readers and routers look.
        INFO("issue " << got.size() << " on " << path << " at " << e.time() << " s");
        CHECK(code == codes[got.size() % codes.size()]);
        CHECK(e.str(int32_t(e.value(plant::graph::SlotId(slot.at(path + ".label.value")))[0])) == code);
        got.push_back(code);
    }
    CHECK(got.size() >= 10);  // every code twice: the list starts again after its last
    CHECK(bottles == std::set<std::string>{"store.store[0]", "store.store[1]"});
    CHECK(n_taken >= int(got.size()) - 2);
    CHECK(e.warnings().total() == 0);  // no empty pool, nothing lost
}
