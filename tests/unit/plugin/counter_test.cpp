// A plugin kind through the whole path: descriptor, compile (properties checked against
// its parameters), graph text form and loader, runtime hooks in phases 2 and 5.
#include "counter_kind.h"
#include "graph_edit.h"

#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "graph/plugin.h"
#include "graph/text.h"

#include <doctest/doctest.h>

#include <sstream>

using namespace plant;

namespace {

constexpr const char* kPlant = R"(plant Counting {
    timer t: periodic { period = 100 ms; autostart = true }
    counter c { start = 2; limit = 5; idle_after = 1 s }
    flow t.tick -> c.add
    flow c.reached -> t.stop
}
)";

int32_t slot(const graph::Graph& g, std::string_view path) {
    for (plant::graph::SlotId s : plant::graph::ids_of(g.slots))
        if (g.slot_path(s) == path) return s.v;
    FAIL("no slot " << path);
    return -1;
}

std::string counter_diagnostics(const std::string& text) {
    Compilation c;
    test::compile_text(text, c, "counter_bad.plant");
    std::string out;
    for (const auto& d : c.sink.all()) out += std::string(info(d.id).code) + " " + d.message + "\n";
    return out;
}

}  // namespace

TEST_CASE("plugin kind: a counter compiles, saves, loads and runs") {
    test::register_counter_kind();
    Compilation c;
    test::compile_text(kPlant, c, "counter.plant");
    REQUIRE(c.ok());
    const graph::Graph& g = c.graph;
    REQUIRE(g.plugins.size() == 1);
    CHECK(g.str(g.plugins[graph::PluginId(0)].kind) == "counter");
    REQUIRE(g.plugins[graph::PluginId(0)].param_num == 3);
    CHECK(g.plugin_params[graph::Id<graph::PluginParam>(0)].num == 2);   // start
    CHECK(g.plugin_params[graph::Id<graph::PluginParam>(1)].num == 5);   // limit
    CHECK(g.plugin_params[graph::Id<graph::PluginParam>(2)].num == 1.0);  // idle_after, in seconds

    // The text form carries it, and reads back the same.
    const std::string text = graph::to_text(g);
    CHECK(text.find("count plugins 1\nplugin 0 comp=1 kind=\"counter\" param_adr=0 param_num=3 entry_adr=0 entry_num=0 placed=false pose=(0 0 0|0 0 0 1)\n") != std::string::npos);
    graph::Graph loaded;
    std::string error;
    std::istringstream in(text);
    REQUIRE_MESSAGE(graph::read_text(in, loaded, error), error);
    CHECK(loaded.same_as(g));
    CHECK(graph::to_text(loaded) == text);

    // Runs: ticks at 0.1, 0.2, 0.3 s count 3, 4, 5; 5 is the limit, which stops the timer;
    // a second after the last tick, idle.
    engine::Engine e(loaded);
    const int32_t value = slot(loaded, "c.value"), reached = slot(loaded, "c.reached"),
                  idle = slot(loaded, "c.idle");
    e.watch(plant::graph::SlotId(value));
    int reached_n = 0, idle_n = 0;
    double idle_at = -1;
    for (int i = 0; i < 2 * 150; ++i) {
        e.step();
        reached_n += e.active(plant::graph::SlotId(reached));
        if (e.active(plant::graph::SlotId(idle))) idle_at = e.time(), ++idle_n;
    }
    CHECK(e.value(plant::graph::SlotId(value))[0] == 5);
    CHECK(reached_n == 1);
    CHECK(idle_n == 1);
    CHECK(idle_at == doctest::Approx(1.3).epsilon(0.02));
    // An event reaches it like any input: reset, then one add.
    e.input(plant::graph::SlotId(slot(loaded, "c.reset")));
    e.step();
    CHECK(e.value(plant::graph::SlotId(value))[0] == 2);
}

TEST_CASE("plugin kind: its properties are checked like a built-in kind's") {
    test::register_counter_kind();
    CHECK(counter_diagnostics("plant P { counter c { start = 2 } }\n").find("E0304 counter 'c' needs the property 'limit'") !=
          std::string::npos);
    const std::string dim = counter_diagnostics("plant P { counter c { limit = 3; idle_after = 2 m } }\n");
    CHECK(dim.find("E0203") != std::string::npos);
    CHECK(dim.find("idle_after") != std::string::npos);
    CHECK(counter_diagnostics("plant P { counter c { limit = 3; limt = 4 } }\n").find("E0106 counter has no property 'limt'") !=
          std::string::npos);
    CHECK(counter_diagnostics("plant P { counter c { limit = 3; start = 1.5 } }\n").find("E0") != std::string::npos);
    Compilation ms;
    test::compile_text("plant P { counter c { limit = 3; idle_after = 500 ms } }\n", ms, "counter_ms.plant");
    REQUIRE(ms.ok());
    CHECK(ms.graph.plugin_params[graph::Id<graph::PluginParam>(2)].num == 0.5);  // stored in the descriptor's unit, seconds
    CHECK(counter_diagnostics("plant P { countr c { limit = 3 } }\n").find("unknown component kind 'countr'") !=
          std::string::npos);
    const std::string slot_error = counter_diagnostics("plant P { counter c { limit = 3 }\n flow c.value -> c.ad }\n");
    CHECK(slot_error.find("counter component 'c' has no slot 'ad'") != std::string::npos);
}

TEST_CASE("plugin kind: the loader refuses what this program cannot run") {
    test::register_counter_kind();
    Compilation c;
    test::compile_text(kPlant, c, "counter.plant");
    REQUIRE(c.ok());
    const std::string text = graph::to_text(c.graph);
    auto load = [](std::string t) {
        graph::Graph g;
        std::string error;
        std::istringstream in(t);
        graph::read_text(in, g, error);
        return error;
    };
    auto replaced = [&](std::string_view from, std::string_view to) {
        std::string t = text;
        const size_t at = t.find(from);
        REQUIRE(at != std::string::npos);
        return t.replace(at, from.size(), to);
    };
    CHECK(load(replaced("kind=\"counter\"", "kind=\"meter\"")).find("kind 'meter', which this program does not have") !=
          std::string::npos);
    CHECK(load(replaced("param_num=3", "param_num=2")).find("a counter has 3 parameters") != std::string::npos);
    CHECK(load(replaced("plugin_param 1 num=5", "plugin_param 1 num=5.5")).find("'limit' of a counter is not a valid int") !=
          std::string::npos);
    // Built-in kinds' words are not for plugins, nor is a word twice.
    static constexpr graph::KindDesc timer_again{"timer", "", {}, {}};
    CHECK_FALSE(graph::register_kind(timer_again));
    static constexpr graph::KindDesc physics_again{"physics", "", {}, {}};
    CHECK_FALSE(graph::register_kind(physics_again));
    CHECK_FALSE(graph::register_kind(*graph::find_plugin("counter")));
}

TEST_CASE("plugin kind: entries name slots anywhere in the plant, checked and carried to the runtime") {
    test::register_counter_kind();
    constexpr const char* kTapped = R"(object Gate {
    in open: void => t.start, t2.start
    timer t: oneshot { period = 1 s }
    timer t2: oneshot { period = 2 s }
}
plant Tapped {
    timer fast: periodic { period = 100 ms; autostart = true }
    timer slow: periodic { period = 250 ms; autostart = true }
    g: Gate
    counter c {
        limit = 1000
        tap 1 => fast.tick (weight = 2)
        tap 2 => slow.tick
        notify 7 => g.open
    }
}
)";
    Compilation c;
    test::compile_text(kTapped, c, "tapped.plant");
    REQUIRE(c.ok());
    const graph::Graph& g = c.graph;
    REQUIRE(g.plugin_entries.size() == 3);
    CHECK(g.plugins[graph::PluginId(0)].entry_num == 3);
    CHECK(g.str(g.plugin_entries[graph::Id<graph::PluginEntry>(0)].word) == "tap");
    CHECK(g.plugin_entries[graph::Id<graph::PluginEntry>(1)].key == 2);
    CHECK(g.plugin_params[g.plugin_entries[graph::Id<graph::PluginEntry>(0)].param_adr.first()].num == 2);
    CHECK(g.plugin_params[g.plugin_entries[graph::Id<graph::PluginEntry>(1)].param_adr.first()].num == 1);  // the default weight
    // An input port stands for every input it forwards to.
    const graph::PluginEntry& notify = g.plugin_entries[graph::Id<graph::PluginEntry>(2)];
    REQUIRE(notify.slot_num == 2);
    CHECK(g.slot_path(g.plugin_entry_slots[notify.slot_adr + 0].v) == "g.t.start");
    CHECK(g.slot_path(g.plugin_entry_slots[notify.slot_adr + 1].v) == "g.t2.start");

    // Through the text form and the loader, then run for 1 s: fast ticks 10 times (x2), slow 4.
    const std::string text = graph::to_text(g);
    graph::Graph loaded;
    std::string error;
    std::istringstream in(text);
    REQUIRE_MESSAGE(graph::read_text(in, loaded, error), error);
    CHECK(loaded.same_as(g));
    engine::Engine e(loaded);
    const int32_t value = slot(loaded, "c.value");
    e.watch(plant::graph::SlotId(value));
    for (int i = 0; i < 150; ++i) e.step();
    CHECK(e.value(plant::graph::SlotId(value))[0] == 2 * 10 + 4);

    // The loader checks entries as the compiler does.
    auto load = [&](std::string_view from, std::string_view to) { return test::load_edited(text, from, to); };
    CHECK(load("word=\"notify\"", "word=\"poke\"").find("a counter takes no entry 'poke'") != std::string::npos);
    CHECK(load("key=7", "key=100").find("key 100 is not a whole number between 0 and 99") != std::string::npos);
    CHECK(load("plugin_entry_slot 0 v=", "plugin_entry_slot 0 v=1").find("which a 'tap' entry cannot name") !=
          std::string::npos);
}

TEST_CASE("plugin kind: bad entries get the diagnostics of their kind") {
    test::register_counter_kind();
    auto diag = [](const std::string& entry) {
        return counter_diagnostics("plant P {\n timer t: periodic { period = 1 s }\n counter c {\n limit = 3\n " + entry +
                           "\n }\n}\n");
    };
    CHECK(diag("tapp 1 => t.tick").find("E0106 a counter takes no entry 'tapp'") != std::string::npos);
    CHECK(diag("tap 100 => t.tick").find("E0308 the key of a 'tap' entry is between 0 and 99, not 100") !=
          std::string::npos);
    CHECK(diag("tap 1.5 => t.tick").find("E0204") != std::string::npos);
    CHECK(diag("tap 1 => t.start").find("E0202 a 'tap' entry names an output, but 't.start' is an input") !=
          std::string::npos);
    CHECK(diag("tap 1 => t.elapsed").find("E0201 a 'tap' entry takes a void slot, but 't.elapsed' is real") !=
          std::string::npos);
    CHECK(diag("notify 1 => t.tick").find("E0202 a 'notify' entry names an input") != std::string::npos);
    CHECK(diag("tap 1 => t.tick (wieght = 2)").find("E0303 a 'tap' entry has no option 'wieght'") != std::string::npos);
    CHECK(diag("tap 1 => t.tick (weight = 2, weight = 3)").find("E0305 option 'weight' is given twice") !=
          std::string::npos);
    CHECK(diag("tap 1 => t.tick (weight = 2 s)").find("E0204") != std::string::npos);
    CHECK(diag("tap 1 => t.tick (2)").find("E0303 an entry's options are named") != std::string::npos);
    CHECK(diag("tap 1 => t.tock").find("E0104") != std::string::npos);
    // A kind without entries holds none.
    CHECK(counter_diagnostics("plant P {\n timer t: periodic { period = 1 s\n tap 1 => t.tick }\n}\n").find("E0311") !=
          std::string::npos);
}
