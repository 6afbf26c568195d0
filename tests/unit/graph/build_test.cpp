// graph/build.h: the layout rules the compiler and the runtime tests' SceneBuilder share.
#include "graph/build.h"
#include "graph/kinds.h"
#include "graph/validate.h"

#include <doctest/doctest.h>

#include <vector>

using namespace plant::graph;

namespace {

Graph plant_graph() {
    Graph g;
    g.settings.rate = 150;
    g.plant = g.intern("Test");
    add_do(g, "", DoId{}, DoTypeId{}, {});
    return g;
}

std::vector<double> values_of(const Graph& g, SlotId slot) {
    const Slot& s = g.slots[slot];
    std::vector<double> out;
    for (int i = 0; i < slot_width(s.type); ++i) out.push_back(g.values[s.value_adr + i].v);
    return out;
}

}  // namespace

TEST_SUITE("graph build") {

TEST_CASE("add_comp: the kind's fixed slots, in declaration order, contiguous") {
    Graph g = plant_graph();
    const Src at{0, 3, 5};
    const CompId c = add_comp(g, DoId(0), CompKind::Timer, "t", at);
    const Comp& rec = g[c];
    CHECK(g.str(rec.name) == "t");
    CHECK(rec.kind == CompKind::Timer);
    CHECK(rec.owner == DoId(0));
    CHECK(!rec.detail.valid());
    CHECK(rec.slot_adr == Adr<Slot>(0));
    REQUIRE(rec.slot_num == int32_t(fixed_slots(CompKind::Timer).size()));
    for (int32_t i = 0; i < rec.slot_num; ++i) {
        const Slot& s = g.slots[SlotId(rec.slot_adr + i)];
        const SlotSpec& spec = fixed_slots(CompKind::Timer)[size_t(i)];
        CAPTURE(spec.name);
        CHECK(g.str(s.name) == spec.name);
        CHECK(s.type == spec.type);
        CHECK(s.dir == spec.dir);
        CHECK(s.comp == c);
        CHECK(s.src == at);
    }
    CHECK(g.str(g.slots[SlotId(rec.slot_adr + timerslot::running)].name) == "running");
}

TEST_CASE("add_slot: after the fixed ones, value storage by type with its start value") {
    Graph g = plant_graph();
    const CompId c = add_comp(g, DoId(0), CompKind::Label, "l");
    const int32_t fixed = g.comps[CompId(c)].slot_num;
    const SlotId v = add_slot(g, c, "v", SlotType::Void, Dir::In);
    const SlotId b = add_slot(g, c, "b", SlotType::Bool, Dir::Out);
    const SlotId r = add_slot(g, c, "r", SlotType::Ref, Dir::Out);
    const SlotId q = add_slot(g, c, "q", SlotType::Quat, Dir::Out);
    const SlotId p = add_slot(g, c, "p", SlotType::Pose, Dir::Out);
    CHECK(v == g.comps[CompId(c)].slot_adr + fixed);
    CHECK(g.comps[CompId(c)].slot_num == fixed + 5);
    CHECK(!g[v].value_adr.valid());
    CHECK(values_of(g, b) == std::vector<double>{0});
    CHECK(values_of(g, r) == std::vector<double>{-1});  // no object
    CHECK(values_of(g, q) == std::vector<double>{0, 0, 0, 1});
    CHECK(values_of(g, p) == std::vector<double>{0, 0, 0, 0, 0, 0, 1});
    // The label's fixed string slots read no text until written.
    CHECK(values_of(g, g.comps[CompId(c)].slot_adr + labelslot::value) == std::vector<double>{-1});
    slot_value(g, b) = 1;
    CHECK(values_of(g, b) == std::vector<double>{1});
    // Value storage is contiguous in slot order.
    CHECK(g[p].value_adr + 7 == next_id(g.values));
}

TEST_CASE("add_do, add_comp: a DO's components are its range, ordinals count per type") {
    Graph g = plant_graph();
    g.do_types.push_back({g.intern("Box"), 0, {}});
    const DoId a = add_do(g, "a", DoId(0), DoTypeId(0), {});
    const CompId c1 = add_comp(g, a, CompKind::Timer, "t1");
    const CompId c2 = add_comp(g, a, CompKind::Label, "l");
    const DoId empty = add_do(g, "e", DoId(0), DoTypeId(0), {});
    const DoId b = add_do(g, "b", DoId(0), DoTypeId{}, {});
    add_comp(g, b, CompKind::Exit, "x");
    CHECK(g.dos[DoId(a)].comp_adr.first() == c1);
    CHECK(g.dos[DoId(a)].comp_num == 2);
    CHECK(c2 == CompId(c1.v + 1));
    CHECK(g.dos[DoId(empty)].comp_num == 0);
    CHECK(g.dos[DoId(b)].comp_adr.first() == CompId(c2.v + 1));
    CHECK(g.dos[DoId(b)].comp_num == 1);
    CHECK(g.dos[DoId(a)].ordinal == 0);
    CHECK(g.dos[DoId(empty)].ordinal == 1);
    CHECK(g.do_types[DoTypeId(0)].instance_num == 2);
    CHECK(g.dos[DoId(b)].ordinal == 0);
    CHECK(g.dos[DoId(a)].pool == CompId{});
}

TEST_CASE("a graph built through the API keeps the loader's promises") {
    Graph g = plant_graph();
    const CompId t = add_comp(g, DoId(0), CompKind::Timer, "t");
    g.timers.push_back({t, 0.5, true, true});
    g[t].detail = Detail(Id<Timer>(0));
    const CompId l = add_comp(g, DoId(0), CompKind::Label, "l");
    g.labels.push_back({l, g.intern("")});
    g[l].detail = Detail(Id<Label>(0));
    const SlotId tick(g[t].slot_adr + timerslot::tick);
    const SlotId stop(g[t].slot_adr + timerslot::stop);
    const FlowId f = add_flow(g, tick, stop, Cond::Source, true);
    CHECK(g.flows[FlowId(f)].from == tick);
    CHECK(g.flows[FlowId(f)].to == stop);
    CHECK(g.flows[FlowId(f)].once);
    CHECK(g.flows[FlowId(f)].from_access == AccessId{});
    GraphProblem problem;
    CHECK_MESSAGE(validate(g, problem), problem.table << " " << problem.row << ": " << problem.message);
}

}  // TEST_SUITE
