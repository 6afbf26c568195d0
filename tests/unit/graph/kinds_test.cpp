// The slot tables of kinds.h: the runtime indexes fixed slots through the *slot
// constants, the compiler checks flows against fixed_slots().
#include "engine/plugin.h"
#include "graph/kinds.h"
#include "graph/plugin.h"
#include "sema/kinds/lowering.h"
#include "sema/schema.h"

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

TEST_SUITE("kinds") {

// The index constants and the tables come from one declaration per kind (kinds.h); what
// can still go wrong is fixed_slots() handing out another kind's table.
TEST_CASE("fixed_slots(kind) is the table its index constants count") {
    CHECK(slot_count(CompKind::Body) == size_t(bodyslot::count));
    CHECK(slot_count(CompKind::Graphics) == size_t(graphicsslot::count));
    CHECK(slot_count(CompKind::Field) == size_t(fieldslot::count));
    CHECK(slot_count(CompKind::Constraint) == size_t(constraintslot::count));
    CHECK(slot_count(CompKind::Trigger) == size_t(triggerslot::count));
    CHECK(slot_count(CompKind::Timer) == size_t(timerslot::count));
    CHECK(slot_count(CompKind::Gripper) == size_t(gripperslot::count));
    CHECK(slot_count(CompKind::Source) == size_t(sourceslot::count));
    CHECK(slot_count(CompKind::Exit) == size_t(exitslot::count));
    CHECK(slot_count(CompKind::Router) == size_t(routerslot::count));
    CHECK(slot_count(CompKind::Logic) == size_t(logicslot::count));
    CHECK(slot_count(CompKind::Label) == size_t(labelslot::count));
}

// Where the constant's name differs from the slot's (`count` ends each enum).
TEST_CASE("renamed index constants name the slot 'count'") {
    CHECK(fixed_slot_index(CompKind::Trigger, "count") == triggerslot::count_inside);
    CHECK(fixed_slot_index(CompKind::Source, "count") == sourceslot::issued_count);
    CHECK(fixed_slot_index(CompKind::Exit, "count") == exitslot::taken_count);
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

// The kind table (graph/plugin.h): each row names its own CompKind and graph table, and the
// generic code reads the row, not a switch.
TEST_CASE("the kind table: one row per kind on it, found by its CompKind, with its slots and table") {
    REQUIRE(!builtin_kinds().empty());
    std::set<CompKind> seen;
    for (const KindDesc* d : builtin_kinds()) {
        CAPTURE(d->word);
        CHECK(seen.insert(d->kind).second);
        CHECK(d->kind != CompKind::Plugin);
        CHECK(builtin_kind(d->kind) == d);
        // The graph's word for the CompKind is the plant file's, but for the body's (`physics`).
        CHECK((word(d->kind) == d->word) == (d->kind != CompKind::Body));
        CHECK(kind_word(d->kind) == d->word);
        CHECK(fixed_slots(d->kind).data() == d->slots.data());
        CHECK(!d->doc.empty());
        // A table of its own, or none at all (a router, a state: its components' detail is -1).
        CHECK(d->table.empty() == !d->rows);
        CHECK(d->table.empty() == !d->comp_of);
        if (d->rows) CHECK(d->rows(Graph{}) == 0);
        CHECK((d->idle_input < 0 || size_t(d->idle_input) < d->slots.size()));
        CHECK((d->idle_input < 0) == d->idle_warning.empty());
        CHECK(!find_plugin(d->word));  // not a plugin: register_kind refuses the word
    }
    CHECK(builtin_kind(CompKind::Plugin) == nullptr);
    const KindDesc* body = builtin_kind(CompKind::Body);
    REQUIRE(body);
    CHECK(body->word == "physics");  // the one place that says so
    CHECK(word(CompKind::Body) == "body");  // the graph's text form
    CHECK(body->blocks == kShapes);
    CHECK(body->placed);
    CHECK(bool(body->check_tables));  // its shapes
    // The connector: declared by its own form (`logic go = a and b`), its bare name its `out`.
    const KindDesc* logic = builtin_kind(CompKind::Logic);
    REQUIRE(logic);
    CHECK(logic->own_form);
    CHECK(logic->word == "logic");
    CHECK(logic->table == "logics");
    CHECK(logic->bare_slot == logicslot::out);
    CHECK(logic->idle_output == logicslot::out);
    CHECK(logic->noun == "connector");
    CHECK(plant::sema::find_kind("logic") == nullptr);  // no component word: `logic go { }` is not a connector
    for (const KindDesc* d : builtin_kinds())
        CHECK(d->own_form == (d->kind == CompKind::Logic));
    const KindDesc* timer = builtin_kind(CompKind::Timer);
    REQUIRE(timer);
    CHECK(timer->table == "timers");
    CHECK(timer->slots[timerslot::elapsed].unit == "s");
    const KindDesc* label = builtin_kind(CompKind::Label);
    REQUIRE(label);
    CHECK(label->table == "labels");
    const KindDesc* gripper = builtin_kind(CompKind::Gripper);
    REQUIRE(gripper);
    CHECK(gripper->on);  // written `gripper g on BODY`
    CHECK_FALSE(timer->on);
    const KindDesc* trigger = builtin_kind(CompKind::Trigger);
    REQUIRE(trigger);
    CHECK(trigger->table == "triggers");
    CHECK(trigger->on);
    CHECK(trigger->placed);  // its box stands where it is placed
    CHECK(trigger->blocks == 0);
    for (CompKind k : {CompKind::State, CompKind::Router}) {
        const KindDesc* d = builtin_kind(k);
        REQUIRE(d);
        CHECK(d->table.empty());
        CHECK(bool(d->check_tables));  // its places, transitions and arcs; its routes
    }
    CHECK(builtin_kind(CompKind::State)->blocks == kPlaces);
    CHECK(builtin_kind(CompKind::Router)->blocks == kRoutes);
    CHECK(!builtin_kind(CompKind::Router)->unused_output.empty());  // a route that drives nothing
    const KindDesc* field = builtin_kind(CompKind::Field);
    REQUIRE(field);
    CHECK(field->table == "fields");
    CHECK(field->on);      // `field f on BODY`
    CHECK(field->placed);  // its box stands where it is placed
    CHECK(field->slots[fieldslot::set_speed].unit == "m/s");  // what the OPC UA link states
    CHECK(field->slots[fieldslot::speed].unit == "m/s");
    const KindDesc* graphics = builtin_kind(CompKind::Graphics);
    REQUIRE(graphics);
    CHECK(graphics->table == "graphics");
    CHECK(graphics->blocks == (kAnimations | kVariants | kChildren));  // its sub-blocks, child graphics
}

// Each row's other two parts (kinds/list.h): the compiler's lowering and the runtime's
// behaviour, found by the row's CompKind; a kind whose inputs a phase other than 5 reads
// (the label's `set`, phase 3) has no act hook.
TEST_CASE("the kind table: every row has its lowering and its behaviour") {
    for (const KindDesc* d : builtin_kinds()) {
        CAPTURE(d->word);
        const plant::sema::KindLowering* lw = plant::sema::builtin_lowering(d->kind);
        REQUIRE(lw);
        CHECK(bool(lw->lower) != d->own_form);  // a connector is made by its own form
        const plant::engine::KindBehaviour* b = plant::engine::builtin_behaviour(d->kind);
        REQUIRE(b);
        CHECK_FALSE(bool(b->start));  // the per-component hooks are a plugin's
        CHECK_FALSE(bool(b->sense));
        CHECK_FALSE(bool(b->act));
        CHECK(b->state_size == 0);
    }
    CHECK_FALSE(bool(plant::engine::builtin_behaviour(CompKind::Label)->act_one));
    CHECK(bool(plant::engine::builtin_behaviour(CompKind::Timer)->act_one));
    CHECK(bool(plant::engine::builtin_behaviour(CompKind::Source)->act_all));  // a rate's issues
    // The trigger has no inputs; its sensing is timed apart (StepProfile::Triggers).
    CHECK_FALSE(bool(plant::engine::builtin_behaviour(CompKind::Trigger)->act_one));
    CHECK(plant::engine::builtin_behaviour(CompKind::Trigger)->sense_segment >= 0);
    CHECK(plant::engine::builtin_behaviour(CompKind::Timer)->sense_segment < 0);
    // The graphics: the order it poses in is its own state; set_pose, play, select act.
    CHECK(bool(plant::engine::builtin_behaviour(CompKind::Graphics)->make_state));
    CHECK(bool(plant::engine::builtin_behaviour(CompKind::Graphics)->act_one));
    CHECK(plant::engine::builtin_behaviour(CompKind::Graphics)->sense_segment >= 0);
    // The connector: a node of the logic network, read by phase 3, no hooks of its own.
    const plant::engine::KindBehaviour* logic = plant::engine::builtin_behaviour(CompKind::Logic);
    CHECK_FALSE(bool(logic->act_one));
    CHECK_FALSE(bool(logic->sense_all));
    CHECK(plant::engine::builtin_behaviour(CompKind::Body)->sense_segment >= 0);  // StepProfile::Bodies
    CHECK(bool(plant::engine::builtin_behaviour(CompKind::Body)->act_one));
}

TEST_CASE("register_kind refuses a table kind's word, a table kind's CompKind, sub-blocks, table checks and a Value parameter") {
    constexpr SlotSpec slots[] = {{"in", SlotType::Void, Dir::In, "an input"}};
    const KindDesc timer_word{"timer", "a second timer", slots, {}};
    CHECK_FALSE(register_kind(timer_word));
    const KindDesc as_table{.word = "kinds_test_table", .doc = "claims a CompKind", .slots = slots, .params = {}, .kind = CompKind::Timer};
    CHECK_FALSE(register_kind(as_table));
    // The built-in sub-blocks (a graphics' animations) are read by a table kind's lowering only.
    const KindDesc with_blocks{.word = "kinds_test_blocks", .doc = "holds animations", .slots = slots, .params = {},
                               .blocks = kAnimations};
    CHECK_FALSE(register_kind(with_blocks));
    CHECK(find_plugin("kinds_test_blocks") == nullptr);
    // So are the checks of other tables and the warning about unused own outputs.
    const KindDesc with_tables{.word = "kinds_test_tables", .doc = "checks tables", .slots = slots, .params = {},
                               .check_tables = [](const Graph&, GraphProblem&) { return true; }};
    CHECK_FALSE(register_kind(with_tables));
    const KindDesc with_unused{.word = "kinds_test_unused", .doc = "warns", .slots = slots, .params = {},
                               .unused_output = "'{}' of '{}'"};
    CHECK_FALSE(register_kind(with_unused));
    // And a grammar form of its own, a bare name's slot, a noun, an output that must drive.
    const KindDesc own_form{.word = "kinds_test_form", .doc = "its own form", .slots = slots, .params = {},
                            .own_form = true};
    CHECK_FALSE(register_kind(own_form));
    const KindDesc bare{.word = "kinds_test_bare", .doc = "a bare name", .slots = slots, .params = {}, .bare_slot = 0};
    CHECK_FALSE(register_kind(bare));
    const KindDesc noun{.word = "kinds_test_noun", .doc = "a noun", .slots = slots, .params = {}, .noun = "thing"};
    CHECK_FALSE(register_kind(noun));
    const KindDesc idle{.word = "kinds_test_idle", .doc = "an output", .slots = slots, .params = {}, .idle_output = 0};
    CHECK_FALSE(register_kind(idle));
    // A Value takes its type from an entry's slot; a component's parameter has none. Every
    // other type a plugin stores (tests/unit/plugin/probe_test.cpp).
    const ParamSpec value_param[] = {{"p", ParamType::Value, "", false, 0, "a parameter"}};
    const KindDesc d{"kinds_test_param", "takes one parameter", slots, value_param};
    CHECK_FALSE(register_kind(d));
    CHECK(find_plugin("kinds_test_param") == nullptr);
}

}  // TEST_SUITE
