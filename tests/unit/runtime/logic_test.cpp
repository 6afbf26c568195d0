// The logic phase: execution conditions, singular flows, connectors, routers,
// labels, dynamic access flows, cycles.
#include "engine/engine.h"
#include "scene_builder.h"

#include <doctest/doctest.h>

#include <array>

using namespace plant::test;
using plant::engine::Engine;

namespace {

// Two triggers far from anything: their `count` outputs are sources we activate
// with external inputs; a field's `set_speed` input is the observable target.
struct CondScene {
    SceneBuilder b;
    int32_t t1, t3, f2;
    explicit CondScene(Cond cond) {
        t1 = b.g.triggers[plant::graph::TriggerId(b.trigger(0, "t1", {1, 1, 1}, at(0, 0, 50)))].comp.v;
        t3 = b.g.triggers[plant::graph::TriggerId(b.trigger(0, "t3", {1, 1, 1}, at(0, 0, 50)))].comp.v;
        f2 = b.g.fields[plant::graph::FieldId(b.field(0, "f2", {1, 1, 1}, at(0, 0, 50), {1, 0, 0}, 0, 1))].comp.v;
        b.g.values[b.g.slots[plant::graph::SlotId(b.S(t1, "count"))].value_adr.first()].v = 1;  // what each copies,
        b.g.values[b.g.slots[plant::graph::SlotId(b.S(t3, "count"))].value_adr.first()].v = 3;  // active or not
        b.flow(b.S(t1, "count"), b.S(f2, "set_speed"), cond);  // under test (flow 0)
        b.flow(b.S(t3, "count"), b.S(f2, "set_speed"));        // activates the target (flow 1)
    }
};

double run_cond(Cond cond, bool source, bool target) {
    CondScene s(cond);
    Engine e(s.b.g);
    if (source) e.input(plant::graph::SlotId(s.b.S(s.t1, "count")));
    if (target) e.input(plant::graph::SlotId(s.b.S(s.t3, "count")));
    e.step();
    return e.value(plant::graph::SlotId(s.b.S(s.f2, "set_speed")))[0];
}

}  // namespace

TEST_CASE("runtime: execution conditions over source and target activity") {
    // 1: the flow under test ran last; 3: the other flow ran last; 0: neither ran.
    // A flow reading its target's activity is scheduled after the source-only flows
    // into that target; two source-only flows keep their id order (the later wins).
    CHECK(run_cond(Cond::Source, true, false) == 1);
    CHECK(run_cond(Cond::Source, false, true) == 3);
    CHECK(run_cond(Cond::Source, true, true) == 3);
    CHECK(run_cond(Cond::Source, false, false) == 0);
    CHECK(run_cond(Cond::Target, true, false) == 0);
    CHECK(run_cond(Cond::Target, false, true) == 1);
    CHECK(run_cond(Cond::Both, true, false) == 0);
    CHECK(run_cond(Cond::Both, false, true) == 3);
    CHECK(run_cond(Cond::Both, true, true) == 1);
    CHECK(run_cond(Cond::Either, true, false) == 1);
    CHECK(run_cond(Cond::Either, false, true) == 1);
    CHECK(run_cond(Cond::Either, false, false) == 0);
}

TEST_CASE("runtime: a continuous flow runs every step, a singular one once until re-armed") {
    for (bool once : {false, true}) {
        SceneBuilder b;
        int32_t trig = b.g.triggers[plant::graph::TriggerId(b.trigger(0, "t", {1, 1, 1}, at(0, 0, 50)))].comp.v;
        int32_t p = b.net(0, "net", {{"p", 0}}, {});
        b.flow(b.S(trig, "on_enter"), b.put(p), Cond::Source, once);
        Engine e(b.g);
        // Source active in steps 1-3, idle in 4, active in 5.
        for (int step = 1; step <= 5; ++step) {
            if (step != 4) e.input(plant::graph::SlotId(b.S(trig, "on_enter")));
            e.step();
        }
        CHECK(e.tokens(plant::graph::PlaceId(p)) == (once ? 2 : 4));
    }
}

TEST_CASE("runtime: connector truth tables with negation") {
    for (LogicOp op : {LogicOp::And, LogicOp::Or})
        for (int neg = 0; neg < 4; ++neg)
            for (int in = 0; in < 4; ++in) {
                SceneBuilder b;
                const bool na = neg & 1, nb = neg & 2, a = in & 1, c = in & 2;
                int32_t l = b.logic(0, "l", op, {na, nb});
                int32_t p = b.net(0, "net", {{"p", 0}}, {});
                b.flow(b.g.logics[plant::graph::LogicId(l)].out_slot.v, b.put(p));
                Engine e(b.g);
                const auto& ins = b.g.logic_inputs;
                if (a) e.input(ins[b.g.logics[plant::graph::LogicId(l)].in_adr.first()].slot);
                if (c) e.input(ins[b.g.logics[plant::graph::LogicId(l)].in_adr + 1].slot);
                e.step();
                const bool x = a != na, y = c != nb;
                const bool want = op == LogicOp::And ? (x && y) : (x || y);
                CAPTURE(int(op));
                CAPTURE(neg);
                CAPTURE(in);
                CHECK(e.tokens(plant::graph::PlaceId(p)) == (want ? 1 : 0));
                CHECK(e.active(b.g.logics[plant::graph::LogicId(l)].out_slot) == want);
            }
}

TEST_CASE("runtime: flows into a connector run before it, flows from it after it, in one step") {
    SceneBuilder b;
    int32_t t1 = b.g.triggers[plant::graph::TriggerId(b.trigger(0, "t1", {1, 1, 1}, at(0, 0, 50)))].comp.v;
    int32_t l2 = b.logic(0, "second", LogicOp::Or, {false});
    int32_t l1 = b.logic(0, "first", LogicOp::Or, {false});
    int32_t p = b.net(0, "net", {{"p", 0}}, {});
    // Declared against the natural order on purpose.
    b.flow(b.g.logics[plant::graph::LogicId(l2)].out_slot.v, b.put(p));
    b.flow(b.g.logics[plant::graph::LogicId(l1)].out_slot.v, b.g.logic_inputs[b.g.logics[plant::graph::LogicId(l2)].in_adr.first()].slot.v);
    b.flow(b.S(t1, "on_enter"), b.g.logic_inputs[b.g.logics[plant::graph::LogicId(l1)].in_adr.first()].slot.v);
    Engine e(b.g);
    e.input(plant::graph::SlotId(b.S(t1, "on_enter")));
    e.step();
    CHECK(e.tokens(plant::graph::PlaceId(p)) == 1);
}

TEST_CASE("runtime: a cycle of flows and connectors is broken with one step delay") {
    SceneBuilder b;
    int32_t t1 = b.g.triggers[plant::graph::TriggerId(b.trigger(0, "t1", {1, 1, 1}, at(0, 0, 50)))].comp.v;
    // A latch: out = start OR out (through a flow back into its own input).
    int32_t l = b.logic(0, "latch", LogicOp::Or, {false, false});
    int32_t p = b.net(0, "net", {{"p", 0}}, {});
    const int32_t in0 = b.g.logic_inputs[b.g.logics[plant::graph::LogicId(l)].in_adr.first()].slot.v;
    const int32_t in1 = b.g.logic_inputs[b.g.logics[plant::graph::LogicId(l)].in_adr + 1].slot.v;
    b.flow(b.S(t1, "on_enter"), in0);
    b.flow(b.g.logics[plant::graph::LogicId(l)].out_slot.v, in1);  // the back edge
    b.flow(b.g.logics[plant::graph::LogicId(l)].out_slot.v, b.put(p));
    Engine e(b.g);
    e.input(plant::graph::SlotId(b.S(t1, "on_enter")));
    for (int i = 0; i < 5; ++i) e.step();
    CHECK(e.tokens(plant::graph::PlaceId(p)) == 5);  // latched: active in every step after the first
}

TEST_CASE("runtime: router activates the first route whose glob matches") {
    SceneBuilder b;
    int32_t r = b.router(0, "router", {"F-*", "C-?", "*"});
    int32_t p = b.net(0, "net", {{"fill", 0}, {"cap", 0}, {"loop", 0}}, {});
    for (int i = 0; i < 3; ++i) b.flow(b.S(r, "r" + std::to_string(i)), b.put(p + i));
    Engine e(b.g);
    auto query = [&](const char* id) {
        const std::array<double, 1> v{double(e.intern(id))};
        e.input(plant::graph::SlotId(b.S(r, "query")), v);
        e.step();
    };
    query("F-0012");
    query("C-7");
    query("C-77");
    query("X");
    query("F-");
    CHECK(e.tokens(plant::graph::PlaceId(p)) == 2);
    CHECK(e.tokens(plant::graph::PlaceId(p + 1)) == 1);
    CHECK(e.tokens(plant::graph::PlaceId(p + 2)) == 2);
}

TEST_CASE("runtime: label set passes its text on within the step") {
    SceneBuilder b;
    int32_t src = b.g.labels[plant::graph::Id<plant::graph::Label>(b.label(0, "a", "hello"))].comp.v;
    int32_t dst = b.g.labels[plant::graph::Id<plant::graph::Label>(b.label(0, "b", ""))].comp.v;
    b.flow(b.S(src, "value"), b.S(dst, "set"));
    Engine e(b.g);
    e.step();  // the initial publication of "hello"
    CHECK(e.str(int32_t(e.value(plant::graph::SlotId(b.S(dst, "value")))[0])) == "hello");
    CHECK(e.active(plant::graph::SlotId(b.S(dst, "value"))));
}

TEST_CASE("runtime: dynamic access flows address the slot of the object held in a reference") {
    SceneBuilder b;
    int32_t bottle = b.type("Bottle");
    int32_t other = b.type("Other");
    int32_t d0 = b.dobj("b0", 0, bottle);
    int32_t l0 = b.g.labels[plant::graph::Id<plant::graph::Label>(b.label(d0, "code", "A"))].comp.v;
    int32_t d1 = b.dobj("b1", 0, bottle);
    int32_t l1 = b.g.labels[plant::graph::Id<plant::graph::Label>(b.label(d1, "code", "B"))].comp.v;
    int32_t dx = b.dobj("x", 0, other);
    int32_t station = b.dobj("station");
    int32_t trig = b.g.triggers[plant::graph::TriggerId(b.trigger(station, "seen", {1, 1, 1}, at(0, 0, 50)))].comp.v;
    int32_t text = b.g.labels[plant::graph::Id<plant::graph::Label>(b.label(station, "text", "FILLED"))].comp.v;
    int32_t sink = b.g.labels[plant::graph::Id<plant::graph::Label>(b.label(station, "sink", ""))].comp.v;
    const int32_t obj = b.S(trig, "object");
    int32_t to_set = b.access(obj, bottle, {b.S(l0, "set"), b.S(l1, "set")});
    int32_t from_value = b.access(obj, bottle, {b.S(l0, "value"), b.S(l1, "value")});
    b.flow(b.S(text, "value"), obj, Cond::Source, false, -1, to_set);  // text -> object.code.set
    b.flow(obj, b.S(sink, "set"), Cond::Source, false, from_value, -1);          // object.code.value -> sink
    Engine e(b.g);
    e.step();  // initial publication: the reference is still -1
    CHECK(e.warnings().access_null == 1);  // the text flow would have run without an object

    const std::array<double, 1> ref1{double(d1)};
    e.input(plant::graph::SlotId(obj), ref1);
    e.input(plant::graph::SlotId(b.S(text, "value")));
    e.step();
    CHECK(e.str(int32_t(e.value(plant::graph::SlotId(b.S(l1, "value")))[0])) == "FILLED");
    CHECK(e.str(int32_t(e.value(plant::graph::SlotId(b.S(l0, "value")))[0])) == "A");
    // The reference was published this step: its object's label value reached the sink.
    CHECK(e.str(int32_t(e.value(plant::graph::SlotId(b.S(sink, "value")))[0])) == "FILLED");

    const std::array<double, 1> refx{double(dx)};
    e.input(plant::graph::SlotId(obj), refx);
    e.input(plant::graph::SlotId(b.S(text, "value")));
    e.step();
    // Both flows would run (the reference was published this step): two warnings.
    CHECK(e.warnings().access_type == 2);
}

TEST_CASE("runtime: external inputs on outputs and inputs arrive in the next logic phase") {
    SceneBuilder b;
    int32_t p = b.net(0, "net", {{"p", 0}}, {});
    Engine e(b.g);
    e.input(plant::graph::SlotId(b.put(p)));
    CHECK(e.tokens(plant::graph::PlaceId(p)) == 0);
    e.step();
    CHECK(e.tokens(plant::graph::PlaceId(p)) == 1);
    CHECK(e.active(plant::graph::SlotId(b.put(p))));
    e.step();
    CHECK_FALSE(e.active(plant::graph::SlotId(b.put(p))));
}
