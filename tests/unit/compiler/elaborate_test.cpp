#include "paths.h"
#include "compile_helper.h"
#include "graph/kinds.h"
#include "graph/text.h"

#include <cmath>
#include <doctest/doctest.h>
#include <sstream>

using namespace plant;
using plant::test::compile_text;
using plant::test::has_code;

namespace {
const char* kSwitchPlant = R"(
object Sw {
    in to_base: void => net.MoveToBasePos.put, look.back.play
    in to_working: void => net.MoveToWorkingPos.put
    physics blade: kinematic { shape box(12 cm, 4 mm, 3 cm); collision = false }
    graphics look { animation back { duration = 400 ms; rotate z by -35 deg } }
    state net {
        place BasePos = 1, WorkingPos, MoveToBasePos, MoveToWorkingPos
        transition tw: BasePos + MoveToWorkingPos -> WorkingPos
        transition tb: WorkingPos + MoveToBasePos -> BasePos
        transition cw: WorkingPos + MoveToWorkingPos -> WorkingPos
        transition cb: BasePos + MoveToBasePos -> BasePos
    }
    flow net.WorkingPos.entered -> blade.collision_on
    flow net.BasePos.entered -> blade.collision_off
}
object Clock(p: time = 1 s) {
    out tick: void => t.tick
    timer t: periodic { period = p; autostart = true }
}
plant P {
    for i in 0 .. 3 { s[i]: Sw at (i * 50 cm, 0 m, 0 m) rotate z by 90 deg }
    c: Clock(p = 2 s)
    d: Clock
    flow c.tick -> s[1].to_working
    flow d.tick -> s[1].to_base
}
)";
}  // namespace

TEST_CASE("elaborate: instances get dotted paths, poses and contiguous components") {
    Compilation c;
    compile_text(kSwitchPlant, c);
    REQUIRE_MESSAGE(c.ok(), render_all_text(c.sink.sorted(), c.sources));
    const auto& g = c.graph;
    CHECK(g.str(g.plant) == "P");
    REQUIRE(g.dos.size() == 6);
    CHECK(g.str(g.dos[graph::DoId(1)].path) == "s[0]");
    CHECK(g.str(g.dos[graph::DoId(2)].path) == "s[1]");
    CHECK(g.dos[graph::DoId(2)].pose.p[0] == doctest::Approx(0.5));
    CHECK(g.dos[graph::DoId(2)].pose.q[2] == doctest::Approx(std::sqrt(0.5)));  // 90 deg about z
    for (graph::DoId d : graph::ids_of(g.dos))
        for (graph::CompId c : graph::children(g.dos[d].comp_adr, g.dos[d].comp_num)) CHECK(g.comps[c].owner == d);
    for (graph::CompId c : graph::ids_of(g.comps))
        for (graph::SlotId sl : graph::children(g.comps[c].slot_adr, g.comps[c].slot_num)) CHECK(g.slots[sl].comp == c);
    // Timer periods are SI seconds.
    REQUIRE(g.timers.size() == 2);
    CHECK(g.timers[graph::Id<graph::Timer>(0)].period == doctest::Approx(2.0));
    CHECK(g.timers[graph::Id<graph::Timer>(1)].period == doctest::Approx(1.0));
}

TEST_CASE("elaborate: an input port forwarding to two slots yields two flows") {
    Compilation c;
    compile_text(kSwitchPlant, c);
    REQUIRE(c.ok());
    const auto& g = c.graph;
    int into_s1 = 0;
    for (const auto& f : g.flows) {
        std::string to = g.slot_path(f.to);
        if (to.rfind("s[1].", 0) == 0 && g.slot_path(f.from).find(".t.tick") != std::string::npos) ++into_s1;
        if (to == "s[1].look.back.play") CHECK(g.slot_path(f.from) == "d.t.tick");
    }
    CHECK(into_s1 == 3);  // to_working -> 1 slot, to_base -> 2 slots
}

TEST_CASE("elaborate: the same source compiles to the same text, which round-trips") {
    Compilation a, b;
    compile_text(kSwitchPlant, a, "a.plant");
    compile_text(kSwitchPlant, b, "a.plant");
    REQUIRE(a.ok());
    std::string ta = graph::to_text(a.graph), tb = graph::to_text(b.graph);
    CHECK(ta == tb);
    graph::Graph loaded;
    std::istringstream in(ta);
    std::string err;
    REQUIRE(graph::read_text(in, loaded, err));
    CHECK(graph::to_text(loaded) == ta);
    CHECK(loaded.same_as(a.graph));
}

TEST_CASE("elaborate: dynamic access lists one target per object of the type, by ordinal") {
    Compilation c;
    compile_text(R"(
object B { label code { value = "x" } physics body { mass = 10 g; shape sphere(1 cm) } }
object Reader {
    out obj: ref => v.object
    out seen: void => v.on_enter
    trigger v { extent = (1 cm, 1 cm, 1 cm); filter = B }
}
plant P {
    b1: B
    r: Reader
    b2: B at (1 m, 0 m, 0 m)
    router q { "x*" => hit }
    flow (r.obj as B).code.value -> q.query
    flow q.hit -> (r.obj as B).body.collision_off
}
)", c);
    REQUIRE_MESSAGE(c.ok(), render_all_text(c.sink.sorted(), c.sources));
    const auto& g = c.graph;
    REQUIRE(g.accesses.size() == 2);
    const auto& a = g.accesses[graph::AccessId(0)];
    CHECK(g.str(a.member) == "code.value");
    REQUIRE(a.target_num == 2);
    CHECK(g.slot_path(g.access_targets[a.target_adr.first()].v) == "b1.code.value");
    CHECK(g.slot_path(g.access_targets[a.target_adr + 1].v) == "b2.code.value");
    int dynamic = 0;
    for (const auto& f : g.flows) dynamic += f.from_access.valid() || f.to_access.valid();
    CHECK(dynamic == 2);
}

TEST_CASE("elaborate: a source's pool is built at compile time, contiguous") {
    Compilation c;
    compile_text(R"(
object Item { physics body { mass = 10 g; shape sphere(1 cm) } }
plant P { source s at (0 m, 0 m, 1 m) { object = Item; pool = 4; rate = 1 Hz } }
)", c);
    REQUIRE_MESSAGE(c.ok(), render_all_text(c.sink.sorted(), c.sources));
    const auto& g = c.graph;
    REQUIRE(g.sources.size() == 1);
    const auto& s = g.sources[graph::SourceId(0)];
    CHECK(s.pool_num == 4);
    for (int32_t i = 0; i < 4; ++i) {
        const auto& d = g.dos[graph::DoId(s.pool_adr + i)];
        CHECK(d.pool == s.comp);
        CHECK(d.ordinal == i);
        CHECK(d.pose.p[2] == doctest::Approx(1.0));
    }
    CHECK(s.id_num == 4);
    CHECK(g.str(g.ids[s.id_adr.first()].v) == "s-1");
}

TEST_CASE("elaborate: several independent mistakes are all reported in one run") {
    Compilation c;
    compile_text(R"(
object T { timer t: periodic { period = 50 cm; autostart = true }
           state n { place A = 1
                     transition x: A + Nope -> A } }
plant P {
    a: T
    flow a.t.tik -> a.t.start
    flow a.t.elapsed -> a.t.start
}
)", c);
    CHECK(has_code(c, "E0203"));  // period in cm
    CHECK(has_code(c, "E0401"));  // arc to Nope
    CHECK(has_code(c, "E0104"));  // tik
    CHECK(has_code(c, "E0201"));  // real -> void
    CHECK(c.sink.count(Severity::Error) == 4);
}

TEST_CASE("elaborate: the switch without drains warns about accumulation") {
    Compilation c;
    compile_text(R"(
object Sw {
    in w: void => net.MoveToWorkingPos.put
    state net {
        place BasePos = 1, WorkingPos, MoveToWorkingPos
        transition tw: BasePos + MoveToWorkingPos -> WorkingPos
    }
}
object Clock { out tick: void => t.tick  timer t: periodic { period = 1 s; autostart = true } }
plant P { s: Sw  c: Clock  flow c.tick -> s.w }
)", c);
    CHECK(c.ok());
    CHECK(has_code(c, "W0401"));
}

TEST_CASE("elaborate: every bundled example compiles and its graph text round-trips") {
    namespace fs = std::filesystem;
    int seen = 0;
    for (const auto& e : fs::directory_iterator(fs::path(PLANT_SOURCE_DIR) / "examples")) {
        if (e.path().extension() != ".plant") continue;
        ++seen;
        Compilation c;
        CompileOptions opts;
        opts.stdlib_dir = PLANT_STDLIB_DIR;
        compile_file(e.path().string(), opts, c);
        INFO(e.path().string());
        REQUIRE_MESSAGE(c.ok(), render_all_text(c.sink.sorted(), c.sources));
        std::string text = graph::to_text(c.graph);
        graph::Graph loaded;
        std::istringstream in(text);
        std::string err;
        REQUIRE_MESSAGE(graph::read_text(in, loaded, err), err);
        CHECK(graph::to_text(loaded) == text);
        CHECK(loaded.same_as(c.graph));
    }
    CHECK(seen >= 6);
}

// The loop limit is an option (the compile fuzzer lowers it); both counts obey it: members
// produced, and iterations of loops whose bodies produce nothing.
TEST_CASE("elaborate: the loop limit is CompileOptions::max_members") {
    const std::string members = "object T { label tag { value = \"x\" } }\n"
                                "plant p { for i in 0..300 { t[i]: T() } }\n";
    const std::string empty = "plant p { for i in 0..20 { for j in 0..20 { } } }\n";
    for (const std::string& text : {members, empty}) {
        CAPTURE(text);
        CompileOptions opts;
        opts.stdlib_dir = PLANT_STDLIB_DIR;
        Compilation wide;
        compile_file(plant::test::temp_plant("limit.plant", text), opts, wide);
        CHECK_FALSE(has_code(wide, "E0310"));
        opts.max_members = 250;
        Compilation narrow;
        compile_file(plant::test::temp_plant("limit.plant", text), opts, narrow);
        CHECK(has_code(narrow, "E0310"));
    }
}

// A connector's output is named by the connector alone or as its slot `out` (the name
// `plant info --slots` lists, and std.switch uses): both are the one output slot.
TEST_CASE("elaborate: a connector's output written `go` and `go.out` is the same slot") {
    Compilation c;
    plant::test::compile_text(R"(
plant P {
    timer t: periodic { period = 1 s; autostart = true }
    timer u: oneshot { period = 1 s }
    logic go = t.tick
    flow go -> u.start
    flow go.out -> u.stop
}
)",
                              c);
    REQUIRE(c.ok());
    const auto& g = c.graph;
    REQUIRE(g.flows.size() >= 2);
    int from_go = 0;
    for (const auto& f : g.flows)
        if (g.slot_path(f.from) == "go.out") ++from_go;
    CHECK(from_go == 2);
}
