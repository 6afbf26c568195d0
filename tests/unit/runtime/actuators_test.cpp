// Phase 5 (runtime/engine/actuators.cpp): the components with an active input act as one pass
// in id order has them act, though those that act alone (a kinematic body's place and
// orientation, KindBehaviour::acts_alone) move as the items of a job on the physics threads.
#include "engine/engine.h"
#include "engine/runtime.h"
#include "engine/workers.h"
#include "scene_builder.h"

#include <doctest/doctest.h>

#include <array>
#include <cstring>
#include <string>
#include <vector>

using namespace plant::test;
using namespace plant::engine;
using plant::graph::SlotId;

namespace {

// Two floors 50 m apart (two physics regions, so more than one thread), six kinematic pins
// over each, a dynamic cube, a timer and a graphics.
struct PinScene {
    SceneBuilder b;
    std::vector<int32_t> pins;
    int32_t cube = -1, timer = -1, look = -1;
};

PinScene pin_scene() {
    PinScene s;
    SceneBuilder& b = s.b;
    b.body(0, "floor_a", BodyMode::Static, {box({1.2, 1.2, 0.2})}, 0, at(0, 0, -0.1));
    b.body(0, "floor_b", BodyMode::Static, {box({1.2, 1.2, 0.2})}, 0, at(50, 0, -0.1));
    for (int i = 0; i < 12; ++i) {
        const double x = (i < 6 ? 0 : 50) + 0.15 * (i % 6) - 0.4;
        s.pins.push_back(b.body(b.dobj("pin" + std::to_string(i)), "body", BodyMode::Kinematic,
                                {box({0.05, 0.05, 0.2})}, 0, at(x, 0, 0.5)));
    }
    s.cube = b.body(b.dobj("cube"), "body", BodyMode::Dynamic, {box({0.1, 0.1, 0.1})}, 1.0, at(0, 0.4, 0.05));
    s.timer = b.timer(b.dobj("clock"), "t", 1.0, false, false);
    s.look = b.graphics(b.dobj("sign"), "look", at(0, -0.5, 1));
    return s;
}

}  // namespace

TEST_CASE("phase 5: only a kinematic body's place and orientation act alone") {
    PinScene s = pin_scene();
    Engine e(s.b.g);
    const Tables& t = e.internals().tab;
    const int32_t pin = s.b.body_comp(s.pins[0]), cube = s.b.body_comp(s.cube);
    for (const char* name : {"set_pose", "set_position", "set_orientation"}) {
        CAPTURE(name);
        CHECK(t.alone(SlotId(s.b.S(pin, name))));
        CHECK_FALSE(t.alone(SlotId(s.b.S(cube, name))));  // placing a dynamic body touches its world
    }
    for (const char* name : {"collision_off", "collision_on", "set_velocity", "dynamics_off"}) {
        CAPTURE(name);
        CHECK_FALSE(t.alone(SlotId(s.b.S(pin, name))));
    }
    CHECK_FALSE(t.alone(SlotId(s.b.S(s.b.g.timers[plant::graph::Id<plant::graph::Timer>(s.timer)].comp.v, "start"))));
}

TEST_CASE("phase 5: kinematic bodies moved in one step act on the physics threads, as in one pass in id order") {
    // The pins' poses set together, two of them out of range; in the same step a pin's collision
    // switched off (a component that does not act alone, between the others by id), a timer
    // started and a graphics placed (components that leave the physics alone).
    struct Result {
        std::vector<std::array<double, 7>> poses;
        int64_t out_of_range = 0;
        bool collision = true, running = false;
        double look_x = 0;
        int64_t jobs = 0;
    };
    auto run = [](int threads) {
        PinScene s = pin_scene();
        Options o;
        o.threads = threads;
        Engine e(s.b.g, o);
        const int32_t look = s.b.g.graphics[plant::graph::GraphicsId(s.look)].comp.v;
        e.watch(SlotId(s.b.S(look, "pose")));
        e.step();
        e.profile().on = true;
        for (size_t i = 0; i < s.pins.size(); ++i) {
            const double x = i == 4 || i == 9 ? 2e5 : 0.1 * double(i);  // 4 and 9 out of range (100 km)
            const std::array<double, 7> pose{x, 1.0, 0.5 + 0.01 * double(i), 0, 0, 0, 1};
            e.input(SlotId(s.b.S(s.b.body_comp(s.pins[i]), "set_pose")), pose);
        }
        e.input(SlotId(s.b.S(s.b.body_comp(s.pins[6]), "collision_off")));
        e.input(SlotId(s.b.S(s.b.g.timers[plant::graph::Id<plant::graph::Timer>(s.timer)].comp.v, "start")));
        const std::array<double, 7> sign{3, 0, 1, 0, 0, 0, 1};
        e.input(SlotId(s.b.S(look, "set_pose")), sign);
        e.step();  // acted in phase 5
        Result r;
        for (const StepJob& j : e.profile().jobs)
            if (j.name && std::strstr(j.name, "phase_actuators")) r.jobs += j.calls;
        e.profile().on = false;
        e.step();
        for (int32_t p : s.pins) {
            const plant::graph::Pose q = e.body_pose(plant::graph::BodyId(p));
            r.poses.push_back({q.p[0], q.p[1], q.p[2], q.q[0], q.q[1], q.q[2], q.q[3]});
        }
        r.out_of_range = e.warnings().out_of_range;
        r.collision = e.internals().phys.collision_on(plant::graph::BodyId(s.pins[6]));
        r.running = e.value(SlotId(s.b.S(s.b.g.timers[plant::graph::Id<plant::graph::Timer>(s.timer)].comp.v, "running")))[0] != 0;
        r.look_x = e.value(SlotId(s.b.S(look, "pose")))[0];
        return r;
    };
    const Result one = run(1), three = run(3);
    CHECK(three.jobs >= 2);  // the pins before the one switched off, and those after it
    for (const Result* r : {&one, &three}) {
        CHECK(r->out_of_range == 2);
        CHECK_FALSE(r->collision);
        CHECK(r->running);
        CHECK(r->look_x == 3);
        for (size_t i = 0; i < r->poses.size(); ++i) {
            CAPTURE(i);
            if (i == 4 || i == 9) {
                CHECK(r->poses[i][1] == 0);  // not moved
            } else {
                CHECK(r->poses[i][0] == doctest::Approx(0.1 * double(i)));
                CHECK(r->poses[i][1] == doctest::Approx(1.0));
            }
        }
    }
    CHECK(one.poses == three.poses);  // to the bit
}
