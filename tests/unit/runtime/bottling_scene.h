// A small bottling line built by hand, used by the determinism, allocation and
// scene-file tests: a belt with guard rails, bottles (hull body with cylinder
// inertia plus a foot joined by a fixed constraint, a graphics, a label) from a
// source pool, a sensor whose object is read by an ID reader flow into a router,
// a separator-like net paced by a timer, and an exit at the end of the belt.
#pragma once

#include "scene_builder.h"

#include <cmath>

namespace plant::test {

// One line at y0; its DOs are named "line", "bottle0", ... (with a prefix for more lines).
inline void bottling_line(SceneBuilder& b, const std::string& prefix, double y0, int bottles, double belt_speed) {
    auto at = [y0](double x, double y, double z) { return plant::test::at(x, y0 + y, z); };
    const int32_t line = b.dobj(prefix + "line");
    b.body(line, "floor", BodyMode::Static, {box({4, 1, 0.02})}, 0, at(1.5, 0, -0.01));
    b.body(line, "rail_l", BodyMode::Static, {box({4, 0.01, 0.05})}, 0, at(1.5, 0.05, 0.025));
    b.body(line, "rail_r", BodyMode::Static, {box({4, 0.01, 0.05})}, 0, at(1.5, -0.05, 0.025));
    b.field(line, "belt", {4, 0.09, 0.04}, at(1.5, 0, 0.02), {1, 0, 0}, belt_speed, 16);

    int32_t bottle = -1;  // one type for the bottles of every line
    for (size_t t = 0; t < b.g.do_types.size(); ++t)
        if (b.g.do_types[graph::DoTypeId(t)].name.id == b.name("Bottle").id) bottle = int32_t(t);
    if (bottle < 0) bottle = b.type("Bottle");
    const int32_t pool = int32_t(b.g.dos.size());
    std::vector<Vec3> hull;
    for (int i = 0; i < 12; ++i) {
        const double a = 2 * M_PI * i / 12;
        for (double z : {-0.05, 0.05}) hull.push_back({0.03 * std::cos(a), 0.03 * std::sin(a), z});
    }
    for (int i = 0; i < bottles; ++i) {
        const double y = 2 + i;  // parked away from the line
        const int32_t d = b.dobj(prefix + "bottle" + std::to_string(i), 0, bottle, at(0, y, 0));
        ShapeSpec h{ShapeKind::Hull, {}, {}, hull};
        const int32_t main = b.body(d, "main", BodyMode::Dynamic, {h}, 0.02, at(0, y, 0.051));
        b.g.bodies[graph::BodyId(main)].inertia_set = true;  // a homogeneous cylinder's
        const double ixx = 0.02 * (3 * 0.03 * 0.03 + 0.1 * 0.1) / 12, izz = 0.02 * 0.03 * 0.03 / 2;
        b.g.bodies[graph::BodyId(main)].inertia = {ixx, ixx, izz};
        const int32_t foot = b.body(d, "foot", BodyMode::Dynamic, {sphere(0.004)}, 0.002, at(0, y, 0.005));
        b.joint(d, "fix", JointKind::Fixed, main, foot, at(0, 0, -0.046), at(0, 0, 0));
        b.graphics(d, "look", at(0, y, 0.051), main, {}, {"empty", "filled"});
        b.label(d, "code", "");
    }
    const int32_t src = b.source(line, "source", bottle, pool, bottles, 1.0, at(0, 0, 0.001),
                                 {"F-1", "C-2", "F-3", "X-4"});
    (void)src;

    // An ID reader: the sensor's object's code goes to the router.
    const int32_t reader = b.g.triggers[graph::TriggerId(b.trigger(line, "reader", {0.02, 0.1, 0.1}, at(1, 0, 0.05), bottle))].comp.v;
    std::vector<int32_t> codes;
    for (auto l : graph::ids_of(b.g.labels)) codes.push_back(b.S(b.g.labels[l].comp.v, "value"));
    const int32_t acc = b.access(b.S(reader, "object"), bottle, codes);
    const int32_t router = b.router(line, "router", {"F-*", "C-*", "*"});
    b.flow(b.S(reader, "object"), b.S(router, "query"), Cond::Source, false, acc, -1);

    // A net counting routed bottles, a connector, a paced gate.
    const int32_t p = b.net(line, "state", {{"filling", 0}, {"capping", 0}, {"other", 0}, {"gate", 1}, {"open", 0}},
                            {{"pass", {{3, 1}}, {{4, 1}}}, {"close", {{4, 1}}, {{3, 1}}}});
    for (int i = 0; i < 3; ++i) b.flow(b.S(router, "r" + std::to_string(i)), b.put(p + i));
    const int32_t clock = b.g.timers[graph::Id<graph::Timer>(b.timer(line, "clock", 0.4, true, true))].comp.v;
    const int32_t l = b.logic(line, "go", LogicOp::And, {false, true});
    b.flow(b.S(clock, "tick"), b.g.logic_inputs[b.g.logics[graph::LogicId(l)].in_adr.first()].slot.v);
    b.flow(b.S(reader, "on_stay"), b.g.logic_inputs[b.g.logics[graph::LogicId(l)].in_adr + 1].slot.v);
    b.flow(b.g.logics[graph::LogicId(l)].out_slot.v, b.put(p + 3), Cond::Source, true);

    const int32_t end = b.trigger(line, "end", {0.1, 0.2, 0.2}, at(3.2, 0, 0.05), bottle);
    b.exit(line, "exit", end);
}

// `lines` copies of the line, 20 m apart (each a physics region of its own).
inline Graph bottling_scene(int bottles = 6, double belt_speed = 0.5, int lines = 1) {
    SceneBuilder b;
    for (int k = 0; k < lines; ++k)
        bottling_line(b, k ? "l" + std::to_string(k) + "_" : "", 20.0 * k, bottles, belt_speed);
    return b.g;
}

}  // namespace plant::test
