// Hands (docs/runtime.md, "Hands"): a trainee grabs a bottle on one belt, lifts it, carries
// it to a second belt and sets it down there; takes one out of the plant. Every act is an
// event (grab / move / drop / remove): parsed, formatted and replayed like any other.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/pose.h"
#include "engine/run.h"
#include "engine/events.h"

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace plant;

namespace {

// Two belts side by side, 30 cm apart, both running along +x; a source puts a bottle on
// the first at t = 0 and another at t = 5 s.
constexpr const char* kHandsPlant = R"(
import std.belts, std.bottle

plant Hands {
    rate = 150 Hz
    a: Belt(length = 3 m) at (0 m, 0 m, 0 m)
    b: Belt(length = 3 m) at (0 m, 30 cm, 0 m)
    source store at (10 cm, 0 m, 0 m) {
        object = Bottle
        pool = 2
        rate = 0.2 Hz
    }
}
)";

struct HandsRun {
    Compilation c;
    engine::SlotIndex idx;
    HandsRun() {
        test::compile_text(kHandsPlant, c, "hands.plant");
        REQUIRE(c.ok());
        idx = engine::slot_index(c.graph);
    }
    const graph::Graph& g() const { return c.graph; }
    // The main body of the first pooled bottle (the one issued first).
    graph::BodyId bottle() const {
        for (size_t b = 0; b < g().bodies.size(); ++b)
            if (g().bodies[graph::BodyId(b)].mode == graph::BodyMode::Dynamic && g().str(g().comps[g().bodies[graph::BodyId(b)].comp].name) == "main")
                return graph::BodyId(int32_t(b));
        FAIL("no bottle");
        return graph::BodyId(-1);
    }
    std::string path(graph::BodyId b) const { return g().comp_path(g().bodies[b].comp); }
    engine::Event event(const std::string& line) const {
        engine::Event ev;
        std::string err;
        REQUIRE_MESSAGE(engine::parse_event(g(), idx, line, ev, err), err);
        return ev;
    }
    // Runs to `until`, applying the events from `next` on at their times (as plant run does).
    void run(engine::Engine& e, double until, const std::vector<engine::Event>& evs, size_t& next) const {
        while (e.time() < until - 1e-9) {
            for (; next < evs.size() && engine::due(e, evs[next]); ++next) engine::apply_event(e, evs[next]);
            e.step();
        }
    }
    void run(engine::Engine& e, double until, const std::vector<engine::Event>& evs) const {
        size_t next = 0;
        run(e, until, evs, next);
    }
};

// The carry: at 1 s grab the bottle's top, lift it 10 cm, carry it over belt b, lower it
// onto b's band and let go.
std::vector<std::string> carry_lines(const std::string& body, double x) {
    auto at = [&](double px, double py, double pz) { return std::to_string(px) + "," + std::to_string(py) + "," + std::to_string(pz); };
    return {"1s grab " + body + " at " + at(x, 0, 0.08),
            "1.05s move " + body + " to " + at(x, 0, 0.18),
            "1.5s move " + body + " to " + at(x + 0.1, 0.3, 0.18),
            "2.2s move " + body + " to " + at(x + 0.1, 0.3, 0.075),
            "2.7s drop " + body};
}

}  // namespace

TEST_CASE("hands: grab, move, drop and remove parse, format back and refuse what is wrong") {
    HandsRun s;
    const std::string body = s.path(s.bottle());
    const engine::Event grab = s.event("1.5s grab " + body + " at 0.5,0,0.08");
    CHECK(grab.hand == engine::HandAct::Grab);
    CHECK(grab.body == s.bottle());
    CHECK(grab.slots.empty());
    CHECK(grab.value == std::vector<double>{0.5, 0, 0.08});
    // Times as engine/times.h prints them at the plant's rate (three decimals at 150 Hz).
    for (const std::string& line : {"1.500s grab " + body + " at 0.5,0,0.08", "2.000s move " + body + " to 0.125,0.3,0.1875",
                                   "3.000s drop " + body, "4.000s remove " + body.substr(0, body.rfind('.'))}) {
        const engine::Event ev = s.event(line);
        CHECK(engine::format_event(s.g(), ev) == line);
        const engine::Event back = s.event(engine::format_event(s.g(), ev));
        CHECK(back.hand == ev.hand);
        CHECK(back.body == ev.body);
        CHECK(back.object == ev.object);
        CHECK(back.value == ev.value);
    }
    // A body's path to remove names its object.
    CHECK(engine::format_event(s.g(), s.event("4s remove " + body)) == "4.000s remove " + body.substr(0, body.rfind('.')));
    engine::Event ev;
    std::string err;
    CHECK_FALSE(engine::parse_event(s.g(), s.idx, "1s grab a.band at 0,0,0", ev, err));
    CHECK(err.find("only a dynamic body") != std::string::npos);
    CHECK_FALSE(engine::parse_event(s.g(), s.idx, "1s grab " + body + "x at 0,0,0", ev, err));
    CHECK(err.find("did you mean '" + body + "'") != std::string::npos);
    CHECK_FALSE(engine::parse_event(s.g(), s.idx, "1s grab " + body + " to 0,0,0", ev, err));
    CHECK(err.find("expected 'at X,Y,Z'") != std::string::npos);
    CHECK_FALSE(engine::parse_event(s.g(), s.idx, "1s move " + body + " to 0,0", ev, err));
    CHECK_FALSE(engine::parse_event(s.g(), s.idx, "1s move " + body + " to 0,0,1e9", ev, err));
    CHECK(err.find("within 100 km") != std::string::npos);
    CHECK_FALSE(engine::parse_event(s.g(), s.idx, "1s drop " + body + " now", ev, err));
    CHECK_FALSE(engine::parse_event(s.g(), s.idx, "1s remove nothing_here", ev, err));
    CHECK(err.find("no object") != std::string::npos);
}

TEST_CASE("hands: a bottle lifted off one belt and set down on the other rides on upright, and replays bit for bit") {
    HandsRun s;
    const graph::BodyId b = s.bottle();
    std::vector<engine::Event> evs;
    {
        // Where the bottle is when the hand takes it: from a run to that time.
        engine::Engine probe(s.g());
        s.run(probe, 1.0, {});
        const double x = probe.body_pose(b).p[0];
        CHECK(x > 0.4);  // the belt carried it
        for (const std::string& l : carry_lines(s.path(b), x)) evs.push_back(s.event(l));
    }
    engine::Engine e(s.g());
    size_t next = 0;
    s.run(e, 1.3, evs, next);
    CHECK(e.held(b));
    CHECK(e.body_pose(b).p[2] > 0.1);  // lifted: the main body's centre was at 4 cm
    s.run(e, 2.6, evs, next);
    CHECK(std::abs(e.body_pose(b).p[1] - 0.3) < 0.01);  // over belt b
    s.run(e, 4.5, evs, next);
    CHECK_FALSE(e.held(b));
    const graph::Pose p = e.body_pose(b);
    CHECK(std::abs(p.p[1] - 0.3) < 0.015);  // on belt b, between its rails
    CHECK(std::abs(p.p[2] - 0.04) < 0.005);  // standing on its band
    const graph::Vec3 axis = engine::qrot(p.q, graph::Vec3{0, 0, 1});
    CHECK(axis[2] > 0.99);  // upright
    CHECK(e.body_velocity(b)[0] > 0.4);  // carried along by belt b
    const engine::MaterialCounts m = engine::material_counts(e);
    CHECK(m.lost == 0);
    CHECK(e.warnings().total() == 0);

    // The same events through their events-file lines: the same run, bit for bit.
    std::vector<engine::Event> again;
    for (const engine::Event& ev : evs) again.push_back(s.event(engine::format_event(s.g(), ev)));
    engine::Engine e2(s.g());
    s.run(e2, 4.5, again);
    for (size_t k = 0; k < s.g().bodies.size(); ++k) {
        const graph::BodyId id{int32_t(k)};
        CHECK(e2.body_pose(id).p == e.body_pose(id).p);
        CHECK(e2.body_pose(id).q == e.body_pose(id).q);
    }
}

TEST_CASE("hands: a bottle taken out by hand goes back to its pool, counted as removed, not lost") {
    HandsRun s;
    const graph::BodyId b = s.bottle();
    const std::string obj = s.path(b).substr(0, s.path(b).rfind('.'));
    engine::Engine e(s.g());
    s.run(e, 1.0, {s.event("0.5s grab " + s.path(b) + " at 0.3,0,0.06"), s.event("1s remove " + obj)});
    CHECK_FALSE(e.body_in_world(b));
    CHECK_FALSE(e.held(b));  // the hand let go of what left the plant
    CHECK(e.removed() == 1);
    engine::MaterialCounts m = engine::material_counts(e);
    CHECK(m.removed == 1);
    CHECK(m.lost == 0);
    CHECK(m.on_line == 0);
    // Back in the pool: the source issues it again (two issues from a pool of two at 5 s and
    // 10 s take both bottles; at 10 s one of them is the removed one).
    s.run(e, 10.1, {});  // (the events above are all in the past)
    CHECK(e.body_in_world(b));
    m = engine::material_counts(e);
    CHECK(m.issued == 3);
    CHECK(m.on_line == 2);
    CHECK(e.warnings().pool_empty == 0);
    // What is not in the world cannot be grabbed or removed again: refused, counted.
    engine::Engine fresh(s.g());
    engine::apply_event(fresh, s.event("0s grab " + s.path(b) + " at 0,0,0"));
    CHECK_FALSE(fresh.held(b));
    CHECK(fresh.warnings().hand_refused == 1);
}
