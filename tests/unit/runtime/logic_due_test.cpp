// The logic phase runs only the nodes that are due (engine/schedule.h): every slot's activity
// and every value are, step by step, what running every node gives (Options::logic_every_node),
// on the plants that use flows, connectors (negated inputs too), routers, labels, `once`
// flows and dynamic ends.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/events.h"
#include "engine/runtime.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

using namespace plant;

namespace {

// Steps g with only the due nodes and with every node, side by side; the first step at
// which the slots' activity or values differ (-1: none). `only_due`: the due nodes even in a
// step with many active slots (schedule.h's dense_at), so small plants test them too.
int64_t first_difference(const graph::Graph& g, int64_t steps, const std::vector<std::string>& events = {},
                         bool only_due = true) {
    engine::Options every;
    every.logic_every_node = true;
    engine::Engine due(g, engine::Options{}), all(g, every);
    if (only_due) due.internals().sched.dense_at = SIZE_MAX;
    const engine::SlotIndex index = engine::slot_index(g);
    std::vector<engine::Event> planned;
    for (const std::string& line : events) {
        engine::Event ev;
        std::string error;
        REQUIRE_MESSAGE(engine::parse_event(g, index, line, ev, error), error);
        planned.push_back(ev);
    }
    for (int64_t i = 0; i < steps; ++i) {
        for (const engine::Event& ev : planned)
            if (ev.time <= due.time() + 0.5 / due.rate() && ev.time > due.time() - 0.5 / due.rate()) {
                engine::apply_event(due, ev);
                engine::apply_event(all, ev);
            }
        due.step();
        all.step();
        const engine::State& a = due.internals().st;
        const engine::State& b = all.internals().st;
        if (a.act != b.act || a.values != b.values || a.tokens != b.tokens) return i;
    }
    return -1;
}

// A plant of the tree, compiled with `sets`, stepped `steps` times by a case below.
struct Case {
    std::string file;
    std::vector<std::string> sets;
    int64_t steps;
};

graph::Graph compiled(const Case& c) {
    CompileOptions opts;
    opts.stdlib_dir = PLANT_STDLIB_DIR;
    opts.overrides = c.sets;
    Compilation comp;
    compile_file(std::string(PLANT_SOURCE_DIR) + "/" + c.file, opts, comp);
    REQUIRE(comp.ok());
    return comp.graph;
}

}  // namespace

TEST_CASE("logic: the nodes due give each step what every node gives") {
    const std::vector<Case> cases = {
        {"plants/bottling.plant", {"lines=2", "feed_every=1s"}, 4500},  // 30 s: routers, labels, dynamic ends
        {"examples/loops.plant", {}, 1500},                           // latches: connectors, a cycle cut
        {"examples/routing.plant", {}, 1500},
        {"examples/sorting.plant", {}, 1500},
        {"examples/switch.plant", {}, 1500},
        {"examples/separator.plant", {}, 1500},
        {"tests/golden/flows/conditions_and_once.plant", {}, 600},   // target, both, either; once
        {"tests/golden/flows/schedule.plant", {}, 600},
    };
    for (const Case& c : cases) {
        CAPTURE(c.file);
        CHECK(first_difference(compiled(c), c.steps) == -1);
    }
}

TEST_CASE("logic: a flow through a dynamic end is due when the slot its reference names becomes active") {
    // The trigger saw t1 once; later t1's code is set by an event. The flow from the seen
    // object's code runs then, its reference not republished: only the slot it names is active.
    Compilation c;
    test::compile_text(R"(object Tag(text: string = "x") {
    physics body {
        mass = 10 g
        shape box(2 cm, 2 cm, 2 cm)
    }
    label code { value = text }
}
object Floor {
    physics slab: static { shape box(1 m, 1 m, 2 cm) at (0 m, 0 m, -1 cm) }
}
plant P {
    ground: Floor
    t1: Tag(text = "F-1") at (0 m, 0 m, 1 cm)
    trigger seen at (0 m, 0 m, 1 cm) { extent = (10 cm, 10 cm, 10 cm); filter = Tag }
    router r { "F-*" => f; * => other }
    flow (seen.object as Tag).code.value -> r.query
    timer x: oneshot { period = 1 s }
    timer y: oneshot { period = 1 s }
    flow r.f -> x.start
    flow r.other -> y.start
}
)",
                       c, "dynamic_due.plant");
    REQUIRE(c.ok());
    CHECK(first_difference(c.graph, 450, {"1s t1.code.set \"C-9\"", "2s t1.code.set \"F-7\""}) == -1);
}

TEST_CASE("logic: a node left out of the due ones shows as a difference") {
    // The check above can fail: a connector with a negated input is on while that input is
    // off, so it is due every step; taken out of `always`, its output goes missing at once.
    Compilation c;
    test::compile_text(R"(plant P {
    trigger a { extent = (1 cm, 1 cm, 1 cm) }
    timer t: oneshot { period = 1 s }
    logic idle = not a.on_stay
    flow idle -> t.start
}
)",
                       c, "negated.plant");
    REQUIRE(c.ok());
    engine::Engine e(c.graph, engine::Options{});
    engine::Schedule& sc = e.internals().sched;
    sc.dense_at = SIZE_MAX;  // a plant this small is dense in every step
    bool was_always = false;
    for (uint64_t& w : sc.always) {
        was_always = was_always || w != 0;
        w = 0;
    }
    CHECK(was_always);
    engine::Options every;
    every.logic_every_node = true;
    engine::Engine all(c.graph, every);
    e.step();
    all.step();
    CHECK(e.internals().st.act != all.internals().st.act);
}

TEST_CASE("logic: a step with many active slots runs every node, with the same results") {
    // The logic bench's cells (bench/runtime_bench.cpp): every cell's connector and flows are
    // active each step, so nearly every step has dense_at or more active slots.
    Compilation c;
    test::compile_text(R"(object Cell {
    in  start: void => net.Req.put
    out done:  void => net.serve.fired
    timer t: periodic { period = 20 ms; autostart = true }
    state net {
        place Ready = 1, Req
        transition serve: Ready + Req -> Ready
    }
    logic go = t.tick or net.Ready.entered
    flow go -> net.Req.put
    flow t.tick -> net.Req.put
}
plant P {
    for i in 0 .. 40 {
        cell[i]: Cell
    }
    for i in 0 .. 39 {
        flow cell[i].done -> cell[i + 1].start
    }
}
)",
                       c, "cells.plant");
    REQUIRE(c.ok());
    engine::Engine e(c.graph, engine::Options{});
    const size_t dense_at = e.internals().sched.dense_at;
    CHECK(dense_at == e.internals().sched.ops.size() / 8 + 1);
    int dense_steps = 0;
    for (int i = 0; i < 100; ++i) {
        e.step();
        // What the next logic phase starts from, less what phase 1 adds: a lower bound.
        const engine::State& st = e.internals().st;
        if (st.out_list.size() + st.in_list.size() >= dense_at) ++dense_steps;
    }
    CHECK(dense_steps > 50);
    // Due nodes with the switch (the default) and every node: the same, step by step.
    CHECK(first_difference(c.graph, 300, {}, false) == -1);
    // And the due nodes alone, as the other cases.
    CHECK(first_difference(c.graph, 300) == -1);
}

namespace {

// Steps g on one thread and in the logic phase's lanes on `threads` (schedule.h), due nodes
// only; the first step at which activity, values, warnings or the activity lists, in their
// order, differ (-1: none). `most`: the most records the lanes joined in one step.
int64_t first_lane_difference(const graph::Graph& g, int64_t steps, int threads, size_t* most = nullptr) {
    engine::Options one, many;
    one.threads = 1;
    many.threads = threads;
    engine::Engine a(g, one), b(g, many);
    a.internals().sched.dense_at = b.internals().sched.dense_at = SIZE_MAX;
    REQUIRE(a.internals().st.lane_runs.empty());
    REQUIRE(b.internals().st.lane_runs.size() > 1);
    for (int64_t i = 0; i < steps; ++i) {
        a.step();
        b.step();
        const engine::State& x = a.internals().st;
        const engine::State& y = b.internals().st;
        if (most) {
            size_t joined = 0;
            for (const engine::LaneRun& l : y.lane_runs) joined += l.out.size() + l.in.size();
            *most = std::max(*most, joined);
        }
        if (x.act != y.act || x.values != y.values || x.tokens != y.tokens || x.in_list != y.in_list ||
            x.out_list != y.out_list || x.seen_list != y.seen_list || x.warn.access_null != y.warn.access_null ||
            x.warn.access_type != y.warn.access_type)
            return i;
    }
    return -1;
}

}  // namespace

TEST_CASE("logic: the program in lanes on the physics threads gives each step's lists in one pass's order") {
    // The ops that share no slot a step changes run in lanes, each on whichever thread takes it;
    // what they activate is joined by program position, so the lists (which order what the
    // actuators and the nets do next) are the same, in the same order, as on one thread.
    const std::vector<Case> cases = {
        // 30 s: routers, labels, dynamic ends; a region per line, so as many threads (a plant of
        // one region steps on one thread, and its logic in one pass)
        {"plants/bottling.plant", {"lines=3", "feed_every=1s"}, 4500},
        {"plants/bottling.plant", {"lines=2", "feed_every=0.5s"}, 3000},
    };
    for (const Case& c : cases) {
        CAPTURE(c.file);
        const graph::Graph g = compiled(c);
        for (int threads : {2, 3}) {
            CAPTURE(threads);
            CHECK(first_lane_difference(g, c.steps, threads) == -1);
        }
    }
    // Lanes that join more records in a step than the join reads at once (64 positions a chunk)
    // and than one slice of its job takes (128 records at least: logic.cpp, join_lanes).
    const Case many{"plants/bottling.plant", {"lines=36", "feed_every=0.5s"}, 600};
    size_t most = 0;
    CHECK(first_lane_difference(compiled(many), many.steps, 2, &most) == -1);
    CHECK(most > 256);
}

namespace {

// An engine of the graph on two threads: its program split into lanes.
std::unique_ptr<engine::Engine> on_two_threads(const graph::Graph& g) {
    engine::Options two;
    two.threads = 2;
    return std::make_unique<engine::Engine>(g, two);
}

}  // namespace

TEST_CASE("logic: lanes split the ops that share no slot a step changes, and only those") {
    Compilation c;
    test::compile_text(R"(plant P {
    trigger a { extent = (1 cm, 1 cm, 1 cm) }
    trigger b { extent = (1 cm, 1 cm, 1 cm) }
    timer t: oneshot { period = 1 s }
    timer u: oneshot { period = 1 s }
    logic both = a.on_stay and b.on_stay
    flow both -> t.start
    flow a.on_enter -> u.start
    flow b.on_enter -> u.start
}
)",
                       c, "lanes.plant");
    REQUIRE(c.ok());
    const auto e = on_two_threads(c.graph);
    const engine::Schedule& sc = e->internals().sched;
    // Two sets: the connector and its flow into t.start (one writes what the other reads), and
    // the two flows into u.start (both write it). a.on_stay, b.on_stay, a.on_enter and
    // b.on_enter are written by no op: reading them joins nothing.
    REQUIRE(sc.lanes() == 2);
    auto lane_of = [&](int32_t pos) {
        for (size_t k = 0; k < sc.lanes(); ++k)
            for (int32_t p = sc.lane_adr[k]; p < sc.lane_adr[k + 1]; ++p)
                if (sc.lane_op_pos[p] == pos) return int(k);
        return -1;
    };
    std::vector<int> lane(sc.ops.size());
    for (size_t i = 0; i < sc.ops.size(); ++i) lane[i] = lane_of(int32_t(i));
    // The ops by what they write: the connector's out, t.start (by its flow), u.start (two flows).
    std::map<std::string, std::set<int>> lanes_by_target;
    for (size_t i = 0; i < sc.ops.size(); ++i) {
        const engine::Op& op = sc.ops[i];
        std::string target;
        if (op.kind == engine::OpKind::Logic) target = "both";
        else target = c.graph.slot_path(sc.flows[op.flow()].to);
        lanes_by_target[target].insert(lane[i]);
    }
    CHECK(lanes_by_target["u.start"].size() == 1);  // the two flows into u.start: one lane
    CHECK(lanes_by_target["both"] == lanes_by_target["t.start"]);  // the connector and its flow
    CHECK(lanes_by_target["u.start"] != lanes_by_target["t.start"]);
}

TEST_CASE("logic: lanes join the ops through a dynamic end with those that write the slots it may be") {
    // `(seen.object as Tag).code.value` may be any tag's code: both routers' query flows read
    // through it, and each tag's label op writes a code, so the flows, the label ops and the
    // routers are one set, in one lane. `.clock.tick` is written by no op (the timers' sensing
    // writes it): the two flows that read through it share nothing and go to lanes of their own.
    Compilation c;
    test::compile_text(R"(object Tag {
    label code { value = "x" }
    timer clock: periodic { period = 1 s }
}
plant P {
    t1: Tag
    t2: Tag
    t3: Tag
    trigger seen { extent = (5 cm, 5 cm, 5 cm); filter = Tag }
    trigger other { extent = (5 cm, 5 cm, 5 cm); filter = Tag }
    router r { "F-*" => f; * => g }
    router q { "F-*" => f; * => g }
    flow (seen.object as Tag).code.value -> r.query
    flow (other.object as Tag).code.value -> q.query
    timer x: oneshot { period = 1 s }
    timer y: oneshot { period = 1 s }
    flow (seen.object as Tag).clock.tick -> x.start
    flow (other.object as Tag).clock.tick -> y.start
}
)",
                       c, "lanes_dynamic.plant");
    REQUIRE(c.ok());
    const auto e = on_two_threads(c.graph);
    const engine::Schedule& sc = e->internals().sched;
    REQUIRE(sc.lanes() >= 2);
    // The ops by kind and what they write: the flows by their target, the label ops, the routers.
    std::map<std::string, std::set<int>> lanes_of;
    for (size_t i = 0; i < sc.ops.size(); ++i) {
        const engine::Op& op = sc.ops[i];
        std::string what;
        if (op.kind == engine::OpKind::Label) what = "labels";
        else if (op.kind == engine::OpKind::Router) what = "routers";
        else if (op.kind == engine::OpKind::Flow || op.kind == engine::OpKind::Pulse)
            what = c.graph.slot_path(sc.flows[op.flow()].to);
        else continue;
        lanes_of[what].insert(sc.lane_of[i]);
    }
    REQUIRE(lanes_of.count("labels"));
    CHECK(lanes_of["labels"].size() == 1);  // three label ops, one lane
    CHECK(lanes_of["r.query"] == lanes_of["labels"]);
    CHECK(lanes_of["q.query"] == lanes_of["labels"]);
    CHECK(lanes_of["routers"] == lanes_of["labels"]);
    REQUIRE(lanes_of["x.start"].size() == 1);
    REQUIRE(lanes_of["y.start"].size() == 1);
    CHECK(lanes_of["x.start"] != lanes_of["y.start"]);
    CHECK(lanes_of["x.start"] != lanes_of["labels"]);
    // The lane's room for what it activates: every slot its ops may write, each once (the three
    // codes' values, and the two routers' outputs, two each; the two query slots).
    const int lane = *lanes_of["labels"].begin();
    CHECK(sc.lane_writes[size_t(lane)] == 3 + 4 + 2);
}
