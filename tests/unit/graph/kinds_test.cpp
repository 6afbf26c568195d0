// The runtime indexes fixed slots through the *slot enums of kinds.h; they must
// agree with the slot tables the compiler checks flows against.
#include "graph/kinds.h"

#include <doctest/doctest.h>

#include <set>
#include <string>

using namespace plant::graph;

namespace {

constexpr CompKind kAllKinds[] = {
    CompKind::Graphics, CompKind::Body,    CompKind::Field,  CompKind::Constraint,
    CompKind::State,    CompKind::Trigger, CompKind::Timer,  CompKind::Gripper,
    CompKind::Source,   CompKind::Exit,    CompKind::Router, CompKind::Logic,
    CompKind::Label,    CompKind::Plugin,
};

size_t slot_count(CompKind k) { return fixed_slots(k).size(); }

}  // namespace

// Entry `e` of namespace `ns` is the slot named `name` of `kind`.
#define CHECK_SLOT_AS(ns, kind, e, name) CHECK(int(ns::e) == fixed_slot_index(CompKind::kind, name))
#define CHECK_SLOT(ns, kind, e) CHECK_SLOT_AS(ns, kind, e, #e)
#define CHECK_COUNT(ns, kind) CHECK(size_t(ns::count) == slot_count(CompKind::kind))

TEST_SUITE("kinds") {

TEST_CASE("bodyslot") {
    CHECK_SLOT(bodyslot, Body, set_pose);
    CHECK_SLOT(bodyslot, Body, set_position);
    CHECK_SLOT(bodyslot, Body, set_orientation);
    CHECK_SLOT(bodyslot, Body, set_velocity);
    CHECK_SLOT(bodyslot, Body, set_angular_velocity);
    CHECK_SLOT(bodyslot, Body, collision_on);
    CHECK_SLOT(bodyslot, Body, collision_off);
    CHECK_SLOT(bodyslot, Body, dynamics_on);
    CHECK_SLOT(bodyslot, Body, dynamics_off);
    CHECK_SLOT(bodyslot, Body, pose);
    CHECK_SLOT(bodyslot, Body, position);
    CHECK_SLOT(bodyslot, Body, orientation);
    CHECK_SLOT(bodyslot, Body, velocity);
    CHECK_SLOT(bodyslot, Body, angular_velocity);
    CHECK_COUNT(bodyslot, Body);
}

TEST_CASE("graphicsslot") {
    CHECK_SLOT(graphicsslot, Graphics, set_pose);
    CHECK_SLOT(graphicsslot, Graphics, pose);
    CHECK_SLOT(graphicsslot, Graphics, shown);
    CHECK_COUNT(graphicsslot, Graphics);
}

TEST_CASE("fieldslot") {
    CHECK_SLOT(fieldslot, Field, set_speed);
    CHECK_SLOT(fieldslot, Field, enable);
    CHECK_SLOT(fieldslot, Field, disable);
    CHECK_SLOT(fieldslot, Field, speed);
    CHECK_COUNT(fieldslot, Field);
}

TEST_CASE("jointslot") {
    CHECK_SLOT(jointslot, Constraint, enable);
    CHECK_SLOT(jointslot, Constraint, disable);
    CHECK_SLOT(jointslot, Constraint, enabled);
    CHECK_COUNT(jointslot, Constraint);
}

TEST_CASE("triggerslot") {
    CHECK_SLOT(triggerslot, Trigger, on_enter);
    CHECK_SLOT(triggerslot, Trigger, on_stay);
    CHECK_SLOT(triggerslot, Trigger, on_leave);
    CHECK_SLOT(triggerslot, Trigger, object);
    CHECK_SLOT_AS(triggerslot, Trigger, count_inside, "count");
    CHECK_COUNT(triggerslot, Trigger);
}

TEST_CASE("timerslot") {
    CHECK_SLOT(timerslot, Timer, start);
    CHECK_SLOT(timerslot, Timer, stop);
    CHECK_SLOT(timerslot, Timer, tick);
    CHECK_SLOT(timerslot, Timer, elapsed);
    CHECK_SLOT(timerslot, Timer, running);
    CHECK_COUNT(timerslot, Timer);
}

TEST_CASE("gripperslot") {
    CHECK_SLOT(gripperslot, Gripper, grip);
    CHECK_SLOT(gripperslot, Gripper, release);
    CHECK_SLOT(gripperslot, Gripper, gripped);
    CHECK_SLOT(gripperslot, Gripper, released);
    CHECK_SLOT(gripperslot, Gripper, object);
    CHECK_COUNT(gripperslot, Gripper);
}

TEST_CASE("sourceslot") {
    CHECK_SLOT(sourceslot, Source, issue);
    CHECK_SLOT(sourceslot, Source, issued);
    CHECK_SLOT(sourceslot, Source, object);
    CHECK_SLOT(sourceslot, Source, id);
    CHECK_SLOT_AS(sourceslot, Source, issued_count, "count");
    CHECK_COUNT(sourceslot, Source);
}

TEST_CASE("exitslot") {
    CHECK_SLOT(exitslot, Exit, taken);
    CHECK_SLOT(exitslot, Exit, object);
    CHECK_SLOT(exitslot, Exit, id);
    CHECK_SLOT_AS(exitslot, Exit, taken_count, "count");
    CHECK_COUNT(exitslot, Exit);
}

TEST_CASE("routerslot, logicslot, labelslot") {
    CHECK_SLOT(routerslot, Router, query);
    CHECK_COUNT(routerslot, Router);
    CHECK_SLOT(logicslot, Logic, out);
    CHECK_COUNT(logicslot, Logic);
    CHECK_SLOT(labelslot, Label, set);
    CHECK_SLOT(labelslot, Label, value);
    CHECK_COUNT(labelslot, Label);
}

TEST_CASE("state has no fixed slots") { CHECK(slot_count(CompKind::State) == 0); }

TEST_CASE("kAllKinds lists every kind") {
    size_t n = 0;
    while (word(static_cast<CompKind>(n)) != "?") ++n;
    CHECK(n == std::size(kAllKinds));
}

TEST_CASE("every kind: names unique, index finds each, unknown is -1") {
    for (CompKind k : kAllKinds) {
        CAPTURE(word(k));
        auto slots = fixed_slots(k);
        std::set<std::string_view> seen;
        for (size_t i = 0; i < slots.size(); ++i) {
            CAPTURE(slots[i].name);
            CHECK(seen.insert(slots[i].name).second);
            CHECK(fixed_slot_index(k, slots[i].name) == int(i));
            CHECK(!slots[i].doc.empty());
        }
        CHECK(fixed_slot_index(k, "no_such_slot") == -1);
        CHECK(fixed_slot_index(k, "") == -1);
    }
}

}  // TEST_SUITE
