// Events address every declared input by its dotted path: component slots and the ports
// object types declare (an input port feeds every slot it forwards to).
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/events.h"

#include <doctest/doctest.h>

using namespace plant;

TEST_CASE("runtime: an event on an object's port drives what the port forwards to") {
    Compilation c;
    test::compile_repo_file("examples/switch.plant", c);
    REQUIRE(c.ok());
    const graph::Graph& g = c.graph;
    const engine::SlotIndex idx = engine::slot_index(g);
    engine::Event ev;
    std::string err;
    REQUIRE(engine::parse_event(g, idx, "0.1s sw.to_working", ev, err));
    REQUIRE(ev.slots.size() == 1);
    CHECK(g.slot_path(ev.slots[0]) == "sw.net.MoveToWorkingPos.put");
    int32_t working = -1;
    for (size_t p = 0; p < g.places.size(); ++p)
        if (g.comp_path(g.places[graph::PlaceId(p)].comp) == "sw.net" && g.str(g.places[graph::PlaceId(p)].name) == "WorkingPos") working = int32_t(p);
    REQUIRE(working >= 0);
    engine::Engine e(g);
    for (int i = 0; i < 30; ++i) e.step();
    CHECK(e.tokens(plant::graph::PlaceId(working)) == 0);
    engine::apply_event(e, ev);
    for (int i = 0; i < 3; ++i) e.step();
    CHECK(e.tokens(plant::graph::PlaceId(working)) == 1);
    // The logged line replays it.
    ev.time = 0.5;
    CHECK(engine::format_event(g, ev) == "0.500s sw.to_working");
    engine::Event back;
    REQUIRE(engine::parse_event(g, idx, engine::format_event(g, ev), back, err));
    CHECK(back.slots == ev.slots);
}

TEST_CASE("runtime: events refuse outputs and suggest a near path") {
    Compilation c;
    test::compile_repo_file("examples/switch.plant", c);
    REQUIRE(c.ok());
    const engine::SlotIndex idx = engine::slot_index(c.graph);
    engine::Event ev;
    std::string err;
    CHECK_FALSE(engine::parse_event(c.graph, idx, "1s sw.in_working", ev, err));
    CHECK(err.find("is an output") != std::string::npos);
    CHECK_FALSE(engine::parse_event(c.graph, idx, "1s sw.to_wrking", ev, err));
    CHECK(err.find("did you mean 'sw.to_working'") != std::string::npos);
    CHECK_FALSE(engine::parse_event(c.graph, idx, "1s nothing.like.this.at.all", ev, err));
    CHECK(err.find("plant info --slots") != std::string::npos);
    // Values of every kind come back as they went out.
    for (const char* line : {"1.500s feed.set_speed 0.25", "2.000s feed.drive.enable"}) {
        REQUIRE_MESSAGE(engine::parse_event(c.graph, idx, line, ev, err), err);
        CHECK(engine::format_event(c.graph, ev) == line);
    }
}

// Text that is not UTF-8 never becomes an event: a string slot's value would reach traces
// and the viewer's JSON as is (every way in parses through parse_event or parse_input).
TEST_CASE("runtime: an event line that is not UTF-8 is refused with the byte and its column") {
    Compilation c;
    test::compile_repo_file("examples/switch.plant", c);
    REQUIRE(c.ok());
    const graph::Graph& g = c.graph;
    const engine::SlotIndex idx = engine::slot_index(g);
    engine::Event ev;
    std::string err;
    REQUIRE(engine::parse_event(g, idx, "0.5s control.query \"A-1\"", ev, err));
    CHECK_FALSE(engine::parse_event(g, idx, "0.5s control.query \"A-\xff\"", ev, err));
    CHECK(err == "not valid UTF-8: byte 0xFF at column 23");
    CHECK_FALSE(engine::parse_event(g, idx, "0.5s force control.query stuck \xc3\x28", ev, err));  // a broken pair
    CHECK(err == "not valid UTF-8: byte 0xC3 at column 32");
    CHECK_FALSE(engine::parse_input(g, idx, "control.query \xed\xa0\x80", ev, err));  // a UTF-16 surrogate
    CHECK(err == "not valid UTF-8: byte 0xED at column 15");
    REQUIRE(engine::parse_event(g, idx, "0.5s control.query \"\xc3\xa4\"", ev, err));  // 'ä' is fine
    CHECK(ev.text == "\xc3\xa4");
}
