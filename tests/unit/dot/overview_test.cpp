// `plant graph`'s overview and `--object PATH` on the bottling plant.
#include "../compiler/compile_helper.h"
#include "dot/dot.h"

#include <doctest/doctest.h>

#include <sstream>

namespace {

size_t count(const std::string& s, const std::string& what) {
    size_t n = 0;
    for (size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
    return n;
}

}  // namespace

TEST_CASE("dot: the overview shows a line's objects as nodes and bundles their flows") {
    plant::Compilation c;
    plant::test::compile_repo_file("plants/bottling.plant", c);
    REQUIRE(c.ok());
    std::ostringstream o;
    plant::dot::write_overview(c.graph, o);
    const std::string dot = o.str();
    // The plant wraps one line: the line's children are the nodes, one each.
    CHECK(dot.find("line[0]: BottlingLine") != std::string::npos);
    for (const char* n : {"\"s1: RoutedSwitch\"", "\"s5: RoutedSwitch\"", "\"sep1: Separator\"", "\"b1: Belt\"", "\"arm: Arm\""})
        CHECK_MESSAGE(count(dot, n) == 1, n);
    CHECK(count(dot, "shape=doublecircle") == 2);  // the feed net and the run net (the panel's), collapsed
    CHECK(dot.find("<TABLE") == std::string::npos);  // no slot tables
    CHECK(count(dot, " -> ") < 80);
    std::ostringstream full;
    plant::dot::write_dot(c.graph, full);
    CHECK(full.str().size() > 20 * dot.size());
}

TEST_CASE("dot: --object draws one object in full, and only it") {
    plant::Compilation c;
    plant::test::compile_repo_file("plants/bottling.plant", c);
    REQUIRE(c.ok());
    std::ostringstream o;
    REQUIRE(plant::dot::write_dot_object(c.graph, "line[0].s1", o));
    const std::string dot = o.str();
    CHECK(dot.find("label=\"line[0].s1\"") != std::string::npos);
    CHECK(dot.find("line[0].s2") == std::string::npos);
    CHECK(dot.find("MoveToWorkingPos") != std::string::npos);  // its net, in full
    std::ostringstream none;
    CHECK_FALSE(plant::dot::write_dot_object(c.graph, "line[0].nope", none));
}

TEST_CASE("dot: a faults component is drawn with an edge to every slot it forces, in every view") {
    plant::Compilation c;
    plant::test::compile_repo_file("tests/golden/faults/drill.plant", c);
    REQUIRE(c.ok());
    // The overview: the drill's node by its kind's word, one bundle to each object it forces.
    std::ostringstream o;
    plant::dot::write_overview(c.graph, o);
    const std::string overview = o.str();
    CHECK(overview.find("label=\"faults\\ndrill\"") != std::string::npos);
    CHECK(overview.find("without flows") == std::string::npos);  // nothing left unconnected
    CHECK(count(overview, "\"c1\" -> ") == 3);                    // b1, sw and the timer t
    CHECK(overview.find("\"c1\" -> \"c0\" [label=\"invert 0 s running, release 8 s running\"") != std::string::npos);
    // In full: one edge per entry and slot, labelled with its word and time, into the slot.
    std::ostringstream full;
    plant::dot::write_dot(c.graph, full);
    const std::string dot = full.str();
    CHECK(dot.find("faults drill</TD>") != std::string::npos);
    CHECK(count(dot, "\"c1\" -> ") == 8);  // 7 entries; `stuck 1500 ms => b1.stop` reaches two inputs
    CHECK(dot.find("[label=\"open 2 s\", style=dashed") != std::string::npos);
    CHECK(dot.find("[label=\"stuck 1.5 s\", style=dashed") != std::string::npos);
    // One object: the entries into it are drawn only with the drill inside the drawing.
    std::ostringstream sw;
    REQUIRE(plant::dot::write_dot_object(c.graph, "sw", sw));
    CHECK(sw.str().find("\"c1\"") == std::string::npos);
}

TEST_CASE("dot: a PLC link's entries are edges: coils into the inputs they drive, outputs into the link") {
    plant::Compilation c;
    plant::test::compile_repo_file("plants/bottling_plc.plant", c);
    REQUIRE(c.ok());
    std::ostringstream o;
    plant::dot::write_overview(c.graph, o);
    const std::string overview = o.str();
    CHECK(overview.find("label=\"modbus") != std::string::npos);
    CHECK(count(overview, "entries\", penwidth=2, style=dashed") == 2);  // one bundle each way
}
