// What a slot reads before anything wrote it (docs/semantics.md §3, "initial values"):
// string "" (no text), ref none, numbers 0, rotations the identity.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"

#include <doctest/doctest.h>

using namespace plant;

TEST_CASE("runtime: every slot type starts at its documented value") {
    Compilation c;
    test::compile_text(R"(import std.bottle
plant Sorter {
    source store at (0 m, 0 m, 0 m) { object = Bottle; pool = 2; ids = ["A-1", "B-2"] }
    timer t: periodic { period = 1 s }
    trigger zone at (1 m, 0 m, 0 m) { extent = (1 cm, 1 cm, 1 cm) }
}
)",
                       c, "initial_values.plant");
    REQUIRE(c.ok());
    const graph::Graph& g = c.graph;
    int strings = 0, refs = 0;
    for (const graph::Slot& s : g.slots) {
        // Labels publish their text, fields their speed, places their tokens from the start.
        const graph::CompKind kind = g.comps[graph::CompId(s.comp)].kind;
        if (!s.value_adr.valid() || kind == graph::CompKind::Label || kind == graph::CompKind::Field ||
            kind == graph::CompKind::State)
            continue;
        const double* v = &g.values[s.value_adr.first()].v;
        switch (s.type) {
        case graph::SlotType::String: CHECK(v[0] == -1); ++strings; break;
        case graph::SlotType::Ref: CHECK(v[0] == -1); ++refs; break;
        case graph::SlotType::Quat: CHECK(v[3] == 1); break;
        case graph::SlotType::Pose: CHECK(v[6] == 1); break;
        default: CHECK(v[0] == 0); break;
        }
    }
    CHECK(strings > 0);
    CHECK(refs > 0);
    // The source's id before its first bottle: "", not the plant's name (names[0]).
    engine::Engine e(g);
    plant::graph::SlotId id_slot, object_slot;
    for (plant::graph::SlotId s : plant::graph::ids_of(g.slots)) {
        if (g.slot_path(s) == "store.id") id_slot = s;
        if (g.slot_path(s) == "store.object") object_slot = s;
    }
    REQUIRE(id_slot.valid());
    e.watch(id_slot);
    for (int i = 0; i < 10; ++i) e.step();
    CHECK(e.str(int32_t(e.value(id_slot)[0])).empty());
    CHECK(e.value(object_slot)[0] == -1);
}
