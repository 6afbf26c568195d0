// A plugin kind's parameters of every type of the one property vocabulary (graph/plugin.h:
// ParamType): a vec3 with its unit, a string list, an object type and a component reference
// are checked like a built-in kind's, stored in the graph, carried by the text form, checked
// by the loader and read by the runtime hooks.
#include "probe_kind.h"

#include "graph_edit.h"

#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "graph/plugin.h"
#include "graph/text.h"

#include <doctest/doctest.h>

#include <sstream>

using namespace plant;

namespace {

constexpr const char* kPlant = R"(object Bottle {
    timer t: oneshot { period = 1 s }
}
plant Probing {
    timer t: periodic { period = 100 ms; autostart = true }
    flow t.tick -> t.stop
    probe p { offset = (1 cm, 2 cm, 30 mm); names = ["ab", "cde"]; object = Bottle; watch = t; label = "front" }
}
)";

std::string probe_diagnostics(const std::string& text) {
    Compilation c;
    test::compile_text(text, c, "probe_bad.plant");
    std::string out;
    for (const auto& d : c.sink.all()) out += std::string(info(d.id).code) + " " + d.message + "\n";
    return out;
}

double output(engine::Engine& e, const graph::Graph& g, std::string_view path) {
    return e.value(test::slot_of(g, path))[0];
}

}  // namespace

TEST_CASE("plugin kind: vec3, string list, type and component reference parameters") {
    test::register_probe_kind();
    Compilation c;
    test::compile_text(kPlant, c, "probe.plant");
    REQUIRE_MESSAGE(c.ok(), probe_diagnostics(kPlant));
    const graph::Graph& g = c.graph;
    REQUIRE(g.plugins.size() == 1);
    const graph::Plugin& p = g.plugins[graph::PluginId(0)];
    REQUIRE(p.param_num == 5);
    const graph::PluginParam& offset = g.plugin_params[p.param_adr + 0];
    CHECK(offset.vec == graph::Vec3{0.01, 0.02, 0.03});  // in SI units
    const graph::PluginParam& names = g.plugin_params[p.param_adr + 1];
    REQUIRE(names.list_num == 2);
    CHECK(g.str(g.plugin_strings[names.list_adr + 1].v) == "cde");
    const graph::PluginParam& object = g.plugin_params[p.param_adr + 2];
    REQUIRE(object.type.valid());
    CHECK(g.str(g.do_types[object.type].name) == "Bottle");
    const graph::PluginParam& watch = g.plugin_params[p.param_adr + 3];
    REQUIRE(watch.comp.valid());
    CHECK(g.comp_path(watch.comp) == "t");
    CHECK(g.str(g.plugin_params[p.param_adr + 4].text) == "front");

    // The text form carries them and reads back the same; the runtime reads them at the start.
    const std::string text = graph::to_text(g);
    CHECK(text.find("count plugin_strings 2\nplugin_string 0 v=\"ab\"\n") != std::string::npos);
    graph::Graph loaded;
    std::string error;
    std::istringstream in(text);
    REQUIRE_MESSAGE(graph::read_text(in, loaded, error), error);
    CHECK(loaded.same_as(g));
    CHECK(graph::to_text(loaded) == text);
    engine::Engine e(loaded);
    e.step();
    CHECK(output(e, loaded, "p.z") == doctest::Approx(0.03));
    CHECK(output(e, loaded, "p.names") == 2);
    CHECK(output(e, loaded, "p.chars") == 2 + 3 + 5);
    CHECK(output(e, loaded, "p.watches_timer") == 1);
    CHECK(output(e, loaded, "p.typed") == 1);

    // Not given: a vec3 is (0, 0, 0), a list empty, a type none; a reference to another kind.
    constexpr const char* kBare = R"(plant Bare {
    timer t: periodic { period = 100 ms; autostart = true }
    trigger v { extent = (1 m, 1 m, 1 m) }
    flow t.tick -> t.stop
    probe p { watch = v }
}
)";
    Compilation bare;
    test::compile_text(kBare, bare, "bare.plant");
    REQUIRE_MESSAGE(bare.ok(), probe_diagnostics(kBare));
    engine::Engine b(bare.graph);
    b.step();
    CHECK(output(b, bare.graph, "p.z") == 0);
    CHECK(output(b, bare.graph, "p.names") == 0);
    CHECK(output(b, bare.graph, "p.chars") == 0);
    CHECK(output(b, bare.graph, "p.watches_timer") == 0);
    CHECK(output(b, bare.graph, "p.typed") == 0);
}

TEST_CASE("plugin kind: a vec3, list, type or reference parameter is checked like a built-in kind's") {
    test::register_probe_kind();
    auto with = [](const std::string& probe) {
        return probe_diagnostics("object Bottle { timer t: oneshot { period = 1 s } }\nplant P {\n"
                                 "    timer t: periodic { period = 1 s; autostart = true }\n    flow t.tick -> t.stop\n"
                                 "    probe p { " + probe + " }\n}\n");
    };
    CHECK(with("offset = (1 cm, 2 cm, 3 cm); watch = t").empty());
    CHECK(with("offset = (1 s, 2 s, 3 s); watch = t").find("E0203") != std::string::npos);  // not a length
    CHECK(with("offset = 1 cm; watch = t").find("'offset'") != std::string::npos);
    CHECK(with("names = \"ab\"; watch = t").find("'names' must be a list of strings") != std::string::npos);
    CHECK(with("object = Botle; watch = t").find("unknown object type 'Botle'") != std::string::npos);
    CHECK(with("watch = nothere").find("no component 'nothere' in this object") != std::string::npos);
    CHECK(with("watch = 3").find("'watch' must name a component of this object") != std::string::npos);
    CHECK(with("offset = (0 m, 0 m, 0 m)").find("E0304 probe 'p' needs the property 'watch'") != std::string::npos);
}

TEST_CASE("plugin kind: the loader checks a reference parameter names a component of its own object") {
    test::register_probe_kind();
    constexpr const char* kTwo = R"(object Box {
    timer inner: periodic { period = 1 s; autostart = true }
    flow inner.tick -> inner.stop
}
plant Two {
    timer t: periodic { period = 100 ms; autostart = true }
    flow t.tick -> t.stop
    b: Box
    probe p { watch = t }
}
)";
    Compilation c;
    test::compile_text(kTwo, c, "two.plant");
    REQUIRE_MESSAGE(c.ok(), probe_diagnostics(kTwo));
    const graph::Graph& g = c.graph;
    const graph::PluginParam& watch = g.plugin_params[g.plugins[graph::PluginId(0)].param_adr + 3];
    REQUIRE(watch.comp.valid());
    graph::CompId inner;
    for (graph::CompId k : graph::ids_of(g.comps))
        if (g.comp_path(k) == "b.inner") inner = k;
    REQUIRE(inner.valid());
    const std::string text = graph::to_text(g);
    auto load = [&](std::string_view from, std::string_view to) { return test::load_edited(text, from, to); };
    const std::string was = fmt::format("comp={} list_adr", watch.comp.v);
    CHECK(load(was, fmt::format("comp={} list_adr", inner.v)).find("parameter 'watch' of a probe is not a valid component reference") !=
          std::string::npos);
    CHECK(load(was, "comp=-1 list_adr").find("parameter 'watch' of a probe is not a valid component reference") !=
          std::string::npos);
}
