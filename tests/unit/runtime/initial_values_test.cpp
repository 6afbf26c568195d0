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
        const graph::CompKind kind = g.comps[size_t(s.comp)].kind;
        if (s.value_adr < 0 || kind == graph::CompKind::Label || kind == graph::CompKind::Field ||
            kind == graph::CompKind::State)
            continue;
        const double* v = &g.values[size_t(s.value_adr)].v;
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
    int32_t id_slot = -1, object_slot = -1;
    for (size_t s = 0; s < g.slots.size(); ++s) {
        if (g.slot_path(int32_t(s)) == "store.id") id_slot = int32_t(s);
        if (g.slot_path(int32_t(s)) == "store.object") object_slot = int32_t(s);
    }
    REQUIRE(id_slot >= 0);
    e.watch(plant::graph::SlotId(id_slot));
    for (int i = 0; i < 10; ++i) e.step();
    CHECK(e.str(int32_t(e.value(plant::graph::SlotId(id_slot))[0])).empty());
    CHECK(e.value(plant::graph::SlotId(object_slot))[0] == -1);
}
