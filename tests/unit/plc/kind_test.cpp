// The link declared in a plant (plc/kind.h): the `modbus` kind's entries become the map,
// its check reports what check_map finds at the entry, and the loader refuses a graph
// whose map is broken.
#include "../compiler/compile_helper.h"
#include "graph/validate.h"
#include "plc/map.h"

#include <doctest/doctest.h>
#include <fmt/format.h>

using namespace plant;

namespace {

constexpr const char* kLinked = R"(import std.belts, std.switch
plant Linked {
    b1: Belt(length = 1 m)
    sw: Switch(side = 1) at (1 m, 0 m, 0 m)
    modbus plc {
        port = 1502
        host = "127.0.0.2"
        coil 3 => sw.to_working
        discrete 0 => sw.seen
        input 0 => sw.seen
        input 4 => sw.id(registers = 4)
        input 8 => b1.speed_now(scale = 1000, unit = "mm/s")
        input 9 => b1.speed_now(encoding = "float32")
        holding 10 => b1.set_speed(scale = 1000)
    }
}
)";

std::string link_diagnostics(const std::string& link) {
    Compilation c;
    test::compile_text("import std.belts\nplant P {\n    b1: Belt(length = 1 m)\n" + link + "\n}\n", c, "link_bad.plant");
    std::string out;
    for (const auto& d : c.sink.all())
        out += fmt::format("{}:{} {} {}\n", c.sources.line_col(d.span.file, d.span.begin).line, 
                           c.sources.line_col(d.span.file, d.span.begin).col, info(d.id).code, d.message);
    return out;
}

}  // namespace

TEST_CASE("plc link kind: the declared entries are the map the server serves") {
    Compilation c;
    test::compile_text(kLinked, c, "linked.plant");
    for (const auto& d : c.sink.all()) INFO(d.message);
    REQUIRE(c.ok());
    int links = 0;
    const plc::Map m = plc::map_from_graph(c.graph, &links);
    CHECK(links == 1);
    CHECK(m.port == 1502);
    CHECK(m.host == "127.0.0.2");
    REQUIRE(m.entries.size() == 7);
    CHECK(plc::check_map(m, c.graph).empty());
    CHECK(m.entries[0].table == plc::Table::Coil);
    CHECK(m.entries[0].address == 3);
    CHECK(m.entries[0].path == "sw.to_working");
    CHECK(m.entries[1].encoding == plc::Encoding::Bit);    // a void output as a discrete input
    CHECK(m.entries[2].encoding == plc::Encoding::Count);  // ... as an input register
    CHECK(m.entries[3].encoding == plc::Encoding::String);
    CHECK(m.entries[3].length == 4);
    CHECK(m.entries[4].encoding == plc::Encoding::Scaled);
    CHECK(m.entries[4].scale == 1000);
    CHECK(m.entries[4].unit == "mm/s");
    CHECK(m.entries[5].encoding == plc::Encoding::Float32);
    CHECK(m.entries[6].table == plc::Table::HoldingRegister);
    CHECK(m.entries[6].dir == graph::Dir::In);
    // A plant without a link has an empty map.
    Compilation none;
    test::compile_text("import std.belts\nplant P { b1: Belt(length = 1 m) }\n", none, "unlinked.plant");
    REQUIRE(none.ok());
    CHECK(plc::map_from_graph(none.graph, &links).entries.empty());
    CHECK(links == 0);
}

TEST_CASE("plc link kind: cross-entry problems are E0315 at the entry, entry problems their own codes") {
    CHECK(link_diagnostics("modbus plc {\n input 0 => b1.speed_now(encoding = \"float32\")\n input 1 => b1.speed_now(scale = 1000)\n}") ==
          "6:2 E0315 'b1.speed_now': input register 1 overlaps 'b1.speed_now' at 0\n");
    CHECK(link_diagnostics("modbus plc {\n input 59999 => b1.speed_now(encoding = \"float32\")\n}").find(
              "5:2 E0315 'b1.speed_now': input register address 59999..60000 is out of range") == 0);
    CHECK(link_diagnostics("modbus plc { holding 60000 => b1.set_speed }").find("E0308") != std::string::npos);
    CHECK(link_diagnostics("modbus plc { input 0 => b1.speed_now(encoding = \"int16\") }").find(
              "E0315 'b1.speed_now': a real slot cannot be encoded as int16") != std::string::npos);
    CHECK(link_diagnostics("modbus plc { input 0 => b1.speed_now(unit = \"mm/s\") }").find(
              "E0315 'b1.speed_now': a unit belongs to a scaled register, not to float32") != std::string::npos);
    CHECK(link_diagnostics("modbus plc { input 0 => b1.speed_now(encoding = \"double\") }").find(
              "no encoding 'double'") != std::string::npos);
    CHECK(link_diagnostics("modbus plc { coil 0 => b1.speed_now }").find("E0202") != std::string::npos);
    CHECK(link_diagnostics("modbus plc { coil 0 => b1.set_speed }").find("E0201") != std::string::npos);
    CHECK(link_diagnostics("modbus a { port = 1502 }\nmodbus b {\n port = 1502\n}") ==
          "5:8 E0315 port 1502 is taken by the link 'a': two links cannot serve one port\n");
    CHECK(link_diagnostics("modbus a { port = 1502 }\nmodbus b { port = 1503 }").empty());
}

TEST_CASE("plc link kind: the loader runs the kind's check") {
    Compilation c;
    test::compile_text(kLinked, c, "linked.plant");
    REQUIRE(c.ok());
    graph::Graph g = c.graph;
    graph::GraphProblem problem;
    CHECK(graph::validate(g, problem));
    g.plugin_entries[graph::Id<graph::PluginEntry>(5)].key = 8;  // the float32 onto the scaled register
    REQUIRE_FALSE(graph::validate(g, problem));
    CHECK(problem.message.find("plugin entry 5: 'b1.speed_now': input register 8 overlaps") != std::string::npos);
}
