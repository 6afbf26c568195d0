// Petri nets: all enabled transitions fire together; puts first; entered outputs.
#include "engine/engine.h"
#include "scene_builder.h"

#include <doctest/doctest.h>

using namespace plant::test;
using plant::engine::Engine;

TEST_CASE("runtime: forward conflict: both transitions fire on one token") {
    SceneBuilder b;
    int32_t p = b.net(0, "net", {{"a", 1}, {"b", 0}, {"c", 0}},
                      {{"t1", {{0, 1}}, {{1, 1}}}, {"t2", {{0, 1}}, {{2, 1}}}});
    Engine e(b.g);
    e.step();
    CHECK(e.tokens(plant::graph::PlaceId(p)) == 0);
    CHECK(e.tokens(plant::graph::PlaceId(p + 1)) == 1);
    CHECK(e.tokens(plant::graph::PlaceId(p + 2)) == 1);
    e.step();  // nothing enabled any more
    CHECK(e.tokens(plant::graph::PlaceId(p + 1)) == 1);
    CHECK(e.tokens(plant::graph::PlaceId(p + 2)) == 1);
}

TEST_CASE("runtime: arc weights and the clamped marking") {
    SceneBuilder b;
    // t1 needs 2 of a and makes 3 b; t2 needs 1 of a: with a = 2 both fire, a -> max(0, 2-3) = 0.
    int32_t p = b.net(0, "net", {{"a", 2}, {"b", 0}, {"c", 0}},
                      {{"t1", {{0, 2}}, {{1, 3}}}, {"t2", {{0, 1}}, {{2, 1}}}});
    Engine e(b.g);
    e.step();
    CHECK(e.tokens(plant::graph::PlaceId(p)) == 0);
    CHECK(e.tokens(plant::graph::PlaceId(p + 1)) == 3);
    CHECK(e.tokens(plant::graph::PlaceId(p + 2)) == 1);

    SceneBuilder b2;  // weight above the marking: not enabled
    int32_t q = b2.net(0, "net", {{"a", 1}, {"b", 0}}, {{"t", {{0, 2}}, {{1, 1}}}});
    Engine e2(b2.g);
    e2.step();
    CHECK(e2.tokens(plant::graph::PlaceId(q)) == 1);
    e2.input(plant::graph::SlotId(b2.put(q)));
    e2.step();  // the put comes first, then t fires in the same step
    CHECK(e2.tokens(plant::graph::PlaceId(q)) == 0);
    CHECK(e2.tokens(plant::graph::PlaceId(q + 1)) == 1);
}

TEST_CASE("runtime: tokens put by flows are added before firing, entered is seen next step") {
    SceneBuilder b;
    std::vector<int32_t> tr;
    int32_t p = b.net(0, "net", {{"in", 0}, {"out", 0}, {"echo", 0}}, {{"move", {{0, 1}}, {{1, 1}}}}, &tr);
    b.flow(b.entered(p + 1), b.put(p + 2));  // out.entered -> echo.put
    Engine e(b.g);
    e.input(plant::graph::SlotId(b.put(p)));
    e.step();  // put on `in`, `move` fires at once
    CHECK(e.tokens(plant::graph::PlaceId(p)) == 0);
    CHECK(e.tokens(plant::graph::PlaceId(p + 1)) == 1);
    CHECK(e.tokens(plant::graph::PlaceId(p + 2)) == 0);
    CHECK_FALSE(e.active(plant::graph::SlotId(b.entered(p + 1))));  // produced in phase 4: not yet seen by logic
    e.step();
    CHECK(e.active(plant::graph::SlotId(b.entered(p + 1))));
    CHECK(e.active(plant::graph::SlotId(b.entered(p))));  // the put of step 1 made `in` entered too
    CHECK(e.active(b.g.transitions[plant::graph::TransitionId(tr[0])].fired_slot));
    CHECK(e.tokens(plant::graph::PlaceId(p + 2)) == 1);  // the flow ran in this step's logic phase
    e.step();
    CHECK_FALSE(e.active(plant::graph::SlotId(b.entered(p + 1))));
    CHECK(e.active(plant::graph::SlotId(b.entered(p + 2))));
    CHECK(e.tokens(plant::graph::PlaceId(p + 2)) == 1);
}

TEST_CASE("runtime: two puts in one step add one token, a transition without inputs fires every step") {
    SceneBuilder b;
    int32_t t1 = b.g.triggers[plant::graph::TriggerId(b.trigger(0, "t1", {1, 1, 1}, at(0, 0, 50)))].comp.v;
    int32_t t2 = b.g.triggers[plant::graph::TriggerId(b.trigger(0, "t2", {1, 1, 1}, at(0, 0, 50)))].comp.v;
    int32_t p = b.net(0, "net", {{"a", 0}, {"gen", 0}}, {{"src", {}, {{1, 1}}}});
    b.flow(b.S(t1, "on_enter"), b.put(p));
    b.flow(b.S(t2, "on_enter"), b.put(p));
    Engine e(b.g);
    e.input(plant::graph::SlotId(b.S(t1, "on_enter")));
    e.input(plant::graph::SlotId(b.S(t2, "on_enter")));
    for (int i = 0; i < 4; ++i) e.step();
    CHECK(e.tokens(plant::graph::PlaceId(p)) == 1);
    CHECK(e.tokens(plant::graph::PlaceId(p + 1)) == 4);
}

TEST_CASE("runtime: the track switch net from the mission moves and drains surplus requests") {
    SceneBuilder b;
    // Places: 0 BasePos, 1 WorkingPos, 2 MoveToBasePos, 3 MoveToWorkingPos,
    // 4 BaseStartAnim, 5 WorkingStartAnim, 6 BaseAnimCtrl, 7 WorkingAnimCtrl.
    int32_t p = b.net(0, "sw",
                      {{"BasePos", 1}, {"WorkingPos", 0}, {"MoveToBasePos", 0}, {"MoveToWorkingPos", 0},
                       {"BasePosStartAnim", 0}, {"WorkingPosStartAnim", 0}, {"BasePosAnimCtrl", 0},
                       {"WorkingPosAnimCtrl", 1}},
                      {{"tw", {{0, 1}, {3, 1}, {7, 1}}, {{1, 1}, {5, 1}, {6, 1}}},
                       {"tb", {{1, 1}, {2, 1}, {6, 1}}, {{0, 1}, {4, 1}, {7, 1}}},
                       {"tcw", {{1, 1}, {3, 1}}, {{1, 1}}},
                       {"tcb", {{0, 1}, {2, 1}}, {{0, 1}}},
                       {"aw", {{5, 1}}, {}},
                       {"ab", {{4, 1}}, {}}});
    Engine e(b.g);
    e.input(plant::graph::SlotId(b.put(p + 3)));
    e.step();
    CHECK(e.tokens(plant::graph::PlaceId(p + 1)) == 1);  // WorkingPos
    CHECK(e.tokens(plant::graph::PlaceId(p + 0)) == 0);
    CHECK(e.tokens(plant::graph::PlaceId(p + 5)) == 1);  // the start-animation token, drained next step
    e.step();
    CHECK(e.tokens(plant::graph::PlaceId(p + 5)) == 0);
    e.input(plant::graph::SlotId(b.put(p + 3)));  // already working: tcw drains the request
    e.step();
    CHECK(e.tokens(plant::graph::PlaceId(p + 3)) == 0);
    CHECK(e.tokens(plant::graph::PlaceId(p + 1)) == 1);
    CHECK(e.tokens(plant::graph::PlaceId(p + 5)) == 0);
}

TEST_CASE("runtime: a place counts past 32 bits exactly, never wraps") {
    // A pump of the largest arc weight: 1,000,000 tokens a step, 2^31 passed after 2,148 steps
    // (a 32-bit count wrapped to about -2.1e9 there).
    SceneBuilder b;
    int32_t p = b.net(0, "net", {{"run", 1}, {"count", 0}}, {{"pump", {{0, 1}}, {{0, 1}, {1, 1'000'000}}}});
    Engine e(b.g);
    for (int i = 0; i < 3000; ++i) e.step();
    CHECK(e.tokens(plant::graph::PlaceId(p + 1)) == int64_t(3000) * 1'000'000);
    CHECK(e.tokens(plant::graph::PlaceId(p)) == 1);
}
