// Operator panels (runtime/panel, docs/language.md "panel"): elements compile to components
// of their own kinds with ordinary slots, and are worked by events (the one way in).
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/events.h"
#include "graph/plugin.h"
#include "graph/text.h"

#include <doctest/doctest.h>

#include <sstream>

using namespace plant;

namespace {

constexpr const char* kDeskPlant = R"(plant Desk {
    panel ops {
        title = "Desk"
        button start { label = "Start"; color = "green" }
        button stop { label = "Stop"; color = "red" }
        estop halt { label = "Emergency stop" }
        selector mode { label = "Mode"; positions = 3; names = "Hand/Off/Auto"; initial = 2 }
        lamp running { label = "Running" }
        display count { label = "Count"; digits = 0 }
    }
    state line {
        place Stopped = 1, Running, Go, Halt
        transition go: Stopped + Go -> Running
        transition halt: Running + Halt -> Stopped
        transition drop_go: Go ->
        transition drop_halt: Halt ->
    }
    flow ops.start.pressed -> line.Go.put
    flow ops.stop.pressed -> line.Halt.put
    flow line.Running.tokens -> ops.running.set
    flow line.Running.tokens -> ops.count.count
}
)";

int32_t desk_slot(const graph::Graph& g, std::string_view path) {
    for (plant::graph::SlotId s : plant::graph::ids_of(g.slots))
        if (g.slot_path(s) == path) return s.v;
    FAIL("no slot " << path);
    return -1;
}

std::string panel_diagnostics(const std::string& text) {
    Compilation c;
    test::compile_text(text, c, "panel_bad.plant");
    std::string out;
    for (const auto& d : c.sink.all()) out += std::string(info(d.id).code) + " " + d.message + "\n";
    return out;
}

struct DeskRun {
    graph::Graph g;
    engine::SlotIndex index;
    std::unique_ptr<engine::Engine> e;
    explicit DeskRun(const graph::Graph& graph) : g(graph), index(engine::slot_index(g)), e(new engine::Engine(g)) {}
    void input(std::string_view text) {
        engine::Event ev;
        std::string error;
        REQUIRE_MESSAGE(engine::parse_input(g, index, text, ev, error), error);
        engine::apply_event(*e, ev);
    }
    double value(std::string_view path) { return e->value(graph::SlotId(desk_slot(g, path)))[0]; }
    // Emitted in this step's phase 5 (the logic sees it in the next step).
    bool active(std::string_view path) { return e->emitted(graph::SlotId(desk_slot(g, path))); }
};

}  // namespace

TEST_CASE("panel: elements are components of their own kinds, named panel.element") {
    Compilation c;
    test::compile_text(kDeskPlant, c, "desk.plant");
    REQUIRE(c.ok());
    const graph::Graph& g = c.graph;
    std::vector<std::string> kinds;
    for (const auto& p : g.plugins) kinds.emplace_back(std::string(g.str(g.comps[graph::CompId(p.comp.v)].name)) + ":" + std::string(g.str(p.kind)));
    CHECK(kinds == std::vector<std::string>{"ops:panel", "ops.start:button", "ops.stop:button", "ops.halt:estop",
                                            "ops.mode:selector", "ops.running:lamp", "ops.count:display"});
    // Saved and loaded, the loader runs the elements' checks and keeps them.
    const std::string text = graph::to_text(g);
    graph::Graph loaded;
    std::string error;
    std::istringstream in(text);
    REQUIRE_MESSAGE(graph::read_text(in, loaded, error), error);
    CHECK(loaded.same_as(g));
}

TEST_CASE("panel: a graph whose element names no panel of its object is refused on loading") {
    Compilation c;
    test::compile_text(kDeskPlant, c, "desk.plant");
    REQUIRE(c.ok());
    graph::Graph g = c.graph;
    for (graph::CompId k : graph::ids_of(g.comps))
        if (g.str(g.comps[k].name) == "ops") g.comps[k].name = g.intern("desk");  // the panel renamed
    const std::string text = graph::to_text(g);
    graph::Graph loaded;
    std::string error;
    std::istringstream in(text);
    CHECK_FALSE(graph::read_text(in, loaded, error));
    CHECK_MESSAGE(error.find("a button belongs inside a panel: 'ops.start' is in none") != std::string::npos, error);
}

TEST_CASE("panel: a button pressed by an event drives the logic, lamps and displays follow") {
    Compilation c;
    test::compile_text(kDeskPlant, c, "desk.plant");
    REQUIRE(c.ok());
    DeskRun d(c.graph);
    d.e->step();
    CHECK(d.value("ops.mode.position") == 2);  // the selector starts at `initial`
    CHECK(d.value("ops.running.state") == 0);
    d.input("ops.start.press");
    d.e->step();  // the press: pressed emitted in phase 5
    CHECK(d.value("ops.start.down") == 1);
    CHECK(d.active("ops.start.pressed"));
    d.e->step();  // logic puts the token; the net fires
    d.e->step();  // the tokens reach the lamp and the display
    d.e->step();
    CHECK(d.value("ops.running.state") == 1);
    CHECK(d.value("ops.count.value") == 1);
    d.input("ops.start.release");
    d.e->step();
    CHECK(d.value("ops.start.down") == 0);
    CHECK(d.active("ops.start.released"));
    // A coil's bool: hold true presses, false lets go.
    d.input("ops.stop.hold true");
    d.e->step();
    CHECK(d.value("ops.stop.down") == 1);
    d.input("ops.stop.hold false");
    for (int i = 0; i < 4; ++i) d.e->step();
    CHECK(d.value("ops.stop.down") == 0);
    CHECK(d.value("ops.running.state") == 0);
    // Blinking is the lamp's state 2, from `blink` or `set 2`; a number that is no state is ignored.
    d.input("ops.running.blink");
    d.e->step();
    CHECK(d.value("ops.running.state") == 2);
    d.input("ops.running.set 7");
    d.e->step();
    CHECK(d.value("ops.running.state") == 2);
    d.input("ops.running.lit false");
    d.e->step();
    CHECK(d.value("ops.running.state") == 0);
}

TEST_CASE("panel: the emergency stop latches until a reset, a selector takes only its positions") {
    Compilation c;
    test::compile_text(kDeskPlant, c, "desk.plant");
    REQUIRE(c.ok());
    DeskRun d(c.graph);
    d.input("ops.halt.press");
    d.e->step();
    CHECK(d.active("ops.halt.pressed"));
    CHECK(d.value("ops.halt.engaged") == 1);
    d.input("ops.halt.press");  // struck again: still latched, nothing new
    d.e->step();
    CHECK_FALSE(d.active("ops.halt.pressed"));
    CHECK(d.value("ops.halt.engaged") == 1);
    d.e->step();
    CHECK(d.value("ops.halt.engaged") == 1);
    d.input("ops.halt.reset");
    d.e->step();
    CHECK(d.active("ops.halt.cleared"));
    CHECK(d.value("ops.halt.engaged") == 0);

    d.input("ops.mode.turn 0");
    d.e->step();
    CHECK(d.value("ops.mode.position") == 0);
    CHECK(d.active("ops.mode.to0"));
    CHECK(d.active("ops.mode.changed"));
    d.e->step();  // from then on at0 is active in every step, seen by the logic
    CHECK(d.e->active(graph::SlotId(desk_slot(d.g, "ops.mode.at0"))));
    CHECK_FALSE(d.e->active(graph::SlotId(desk_slot(d.g, "ops.mode.at2"))));
    d.input("ops.mode.turn 3");  // no fourth position
    d.e->step();
    CHECK(d.value("ops.mode.position") == 0);
    CHECK_FALSE(d.active("ops.mode.changed"));
}

TEST_CASE("panel: the compiler checks elements like every kind") {
    auto in_panel = [](const std::string& body) { return "plant P {\n    panel ops {\n" + body + "    }\n}\n"; };
    CHECK(panel_diagnostics(in_panel("        knob k { }\n")).find("E0") != std::string::npos);
    CHECK(panel_diagnostics(in_panel("        knob k { }\n")).find("a panel holds no 'knob'") != std::string::npos);
    CHECK(panel_diagnostics(in_panel("        button a { }\n        lamp a { }\n")).find("declared twice") != std::string::npos);
    CHECK(panel_diagnostics(in_panel("        selector m { positions = 4 }\n")).find("2 or 3 positions, not 4") != std::string::npos);
    CHECK(panel_diagnostics(in_panel("        selector m { names = \"A/B/C\" }\n")).find("name 3 positions, but it has 2") != std::string::npos);
    CHECK(panel_diagnostics(in_panel("        lamp l { color = \"purple\" }\n")).find("not 'purple'") != std::string::npos);
    CHECK(panel_diagnostics("plant P {\n    button b { }\n}\n").find("a button is written inside a panel component") != std::string::npos);
    CHECK(panel_diagnostics(in_panel("        button b { }\n") + "").empty());
    const std::string wrong_dir = "plant P {\n    panel ops {\n        lamp l { }\n    }\n    timer t: periodic { period = 1 s }\n"
                                  "    flow ops.l.state -> t.tick\n}\n";
    CHECK(panel_diagnostics(wrong_dir).find("E0") != std::string::npos);
}
