// Drills (runtime/faults/drill.h, docs/training.md "Drills"): the line syntax, its errors,
// and the scheduler — a condition fires at the boundary after the step it first holds in,
// as an ordinary timed event, and a repair rule releases the fault after its input is
// operated.
#include "paths.h"
#include "../compiler/compile_helper.h"
#include "engine/events.h"
#include "engine/times.h"
#include "faults/drill.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

using namespace plant;

namespace {

const char* kDrillPlant = R"(import std.belts
plant P {
    b1: Belt(length = 1 m)
    timer t: periodic { period = 200 ms; autostart = true }
    record t.elapsed
}
)";

struct DrillFixture {
    Compilation c;
    engine::SlotIndex slots;
    DrillFixture() {
        test::compile_text(kDrillPlant, c, "drill_plant.plant");
        REQUIRE(c.ok());
        slots = engine::slot_index(c.graph);
    }
    std::string refused(const std::string& line) {
        faults::Drill d;
        std::string error;
        CHECK_FALSE(faults::parse_drill(c.graph, slots, line, d, error));
        return error;
    }
};

}  // namespace

TEST_CASE("drill: the three triggers, hidden or shown, and a repair rule") {
    DrillFixture f;
    faults::Drill d;
    std::string error;
    REQUIRE_MESSAGE(faults::parse_drill(f.c.graph, f.slots, "2s force b1.stop stuck on", d, error), error);
    CHECK(d.trigger == faults::Drill::Trigger::At);
    CHECK(d.at == doctest::Approx(2));
    CHECK_FALSE(d.shown);
    REQUIRE_MESSAGE(faults::parse_drill(f.c.graph, f.slots, "shown now force b1.stop stuck on", d, error), error);
    CHECK(d.trigger == faults::Drill::Trigger::Now);
    CHECK(d.shown);
    REQUIRE_MESSAGE(faults::parse_drill(f.c.graph, f.slots,
                                        "hidden when t.tick >= 3 force b1.stop stuck on repaired by b1.set_speed", d,
                                        error),
                    error);
    CHECK(d.trigger == faults::Drill::Trigger::When);
    CHECK(d.when_void);
    CHECK(d.threshold == 3);
    CHECK(d.event.force);
    CHECK(d.repair_path == "b1.set_speed");
    CHECK_FALSE(d.repair_slots.empty());
    REQUIRE_MESSAGE(faults::parse_drill(f.c.graph, f.slots, "when t.elapsed >= 0.5 b1.set_speed 0.1", d, error), error);
    CHECK_FALSE(d.when_void);
    CHECK_FALSE(d.event.force);
}

TEST_CASE("drill: a bad line says what is wrong") {
    DrillFixture f;
    CHECK(f.refused("when t.tik >= 3 force b1.stop stuck on").find("no slot 't.tik' in the plant (did you mean 't.tick'?)") !=
          std::string::npos);
    CHECK(f.refused("when t.tick > 3 force b1.stop stuck on").find("'when PATH >= NUMBER'") != std::string::npos);
    CHECK(f.refused("when t.tick >= three force b1.stop stuck on").find("'three' is not a number") != std::string::npos);
    CHECK(f.refused("when t.tick >= 3").find("the event that fires is missing") != std::string::npos);
    CHECK(f.refused("now b1.set_speed 0.1 repaired by b1.stop").find("this drill forces nothing") != std::string::npos);
    CHECK(f.refused("now force b1.stop stuck on repaired by b1.nope").find("no slot 'b1.nope'") != std::string::npos);
    CHECK_FALSE(f.refused("soon force b1.stop stuck on").empty());
    // A file's error: FILE:LINE:COL.
    const std::string path = test::temp_plant("bad.drill", "# a drill\n\n  when t.tick >= x force b1.stop stuck on\n");
    std::vector<faults::Drill> drills;
    std::string error;
    CHECK_FALSE(faults::load_drills(f.c.graph, f.slots, path, drills, error));
    CHECK_MESSAGE(error.find("bad.drill:3:3: ") != std::string::npos, error);
}

TEST_CASE("drill: a condition fires at the boundary after the step it first holds in, and a repair releases") {
    DrillFixture f;
    engine::Engine e(f.c.graph);
    const graph::SlotId tick(f.slots.at("t.tick").slots[0]);
    e.watch(tick);
    faults::Drills drills;
    faults::Drill d;
    std::string error;
    REQUIRE(faults::parse_drill(f.c.graph, f.slots, "when t.tick >= 3 force b1.stop stuck on repaired by b1.set_speed",
                                d, error));
    drills.add(d);
    REQUIRE(faults::parse_drill(f.c.graph, f.slots, "when t.elapsed >= 0.5 force b1.set_speed stuck 0.1", d, error));
    drills.add(d);
    const graph::SlotId stop(f.slots.at("b1.stop").slots[0]);
    engine::Event operate;
    REQUIRE(engine::parse_event(f.c.graph, f.slots, "1s b1.set_speed 0.3", operate, error));
    int64_t ticks = 0, third = -1;  // the step in which t.tick was active the third time
    double elapsed_at = -1;         // the end of the first step with t.elapsed >= 0.5
    std::vector<faults::Drills::Fired> fired;
    std::vector<std::pair<double, std::string>> log;
    const graph::SlotId elapsed(f.slots.at("t.elapsed").slots[0]);
    e.watch(elapsed);
    while (e.time() < 1.5) {
        fired.clear();
        drills.due(e, fired);
        for (faults::Drills::Fired& x : fired) {
            CHECK(x.event.time == doctest::Approx(double(e.steps() + 1) * e.dt()));
            engine::apply_event(e, x.event);
            log.emplace_back(x.event.time, engine::format_event(f.c.graph, x.event, e.dt()));
        }
        if (engine::due(e, operate) && operate.time >= 0) {
            engine::apply_event(e, operate);
            operate.time = -1e9;  // once
        }
        e.step();
        if (e.active(tick) && ++ticks == 3) third = e.steps();
        if (elapsed_at < 0 && e.value(elapsed)[0] >= 0.5) elapsed_at = e.time();
    }
    REQUIRE(third > 0);
    REQUIRE(elapsed_at > 0);
    REQUIRE(log.size() == 3);
    // The numeric condition: at the end of the step after the first that saw it hold.
    CHECK(log[0].first == doctest::Approx(elapsed_at + e.dt()));
    CHECK(log[0].second.find("force b1.set_speed stuck 0.1") != std::string::npos);
    // The count: the third tick was in step `third`; the force applies before step third+1.
    CHECK(log[1].first == doctest::Approx(double(third + 1) * e.dt()));
    CHECK(log[1].second.find("force b1.stop stuck") != std::string::npos);
    // b1.set_speed operated at 1 s (applied before the step ending at 1 s): the release
    // comes before the step after it.
    CHECK(log[2].first == doctest::Approx(1.0 + e.dt()));
    CHECK(log[2].second.find("release b1.stop") != std::string::npos);
    CHECK(e.forced(stop) == engine::ForceMode::None);
    CHECK(drills.list()[0].state == faults::Drill::State::Repaired);
    CHECK(drills.list()[1].state == faults::Drill::State::Holding);
    // A restart: every drill waits again.
    drills.reset();
    CHECK(drills.list()[0].state == faults::Drill::State::Waiting);
    CHECK(drills.list()[0].count == 0);
}

TEST_CASE("drill: a fault released by someone else ends its drill") {
    DrillFixture f;
    engine::Engine e(f.c.graph);
    faults::Drills drills;
    faults::Drill d;
    std::string error;
    REQUIRE(faults::parse_drill(f.c.graph, f.slots, "0.1s force b1.stop stuck on repaired by b1.set_speed", d, error));
    drills.add(d);
    engine::Event release;
    REQUIRE(engine::parse_event(f.c.graph, f.slots, "0.3s release b1.stop", release, error));
    std::vector<faults::Drills::Fired> fired;
    int applied = 0;
    while (e.time() < 0.5) {
        fired.clear();
        drills.due(e, fired);
        for (auto& x : fired) engine::apply_event(e, x.event), ++applied;
        if (engine::due(e, release) && release.time >= 0) {
            engine::apply_event(e, release);
            release.time = -1e9;
        }
        e.step();
    }
    CHECK(applied == 1);
    CHECK(drills.list()[0].state == faults::Drill::State::Released);
}

TEST_CASE("drill: a waiting drill cancelled never fires, one that fired or no such drill is not cancelled") {
    DrillFixture f;
    engine::Engine e(f.c.graph);
    faults::Drills drills;
    faults::Drill d;
    std::string error;
    REQUIRE(faults::parse_drill(f.c.graph, f.slots, "0.2s force b1.stop stuck on", d, error));
    drills.add(d);
    REQUIRE(faults::parse_drill(f.c.graph, f.slots, "now force b1.set_speed stuck 0.1", d, error));
    drills.add(d);
    CHECK_FALSE(drills.cancel(3, 0, "page 1 (instructor)", error));
    CHECK(error == "no drill 3 (they are 1 to 2)");
    CHECK_FALSE(drills.cancel(0, 0, "page 1 (instructor)", error));
    std::vector<faults::Drills::Fired> fired;
    int applied = 0;
    bool cancelled = false;
    const graph::SlotId stop(f.slots.at("b1.stop").slots[0]);
    while (e.time() < 0.5) {
        if (!cancelled && e.time() >= 0.1) {  // before drill 1's time; drill 2 fired at the first step
            CHECK_FALSE(drills.cancel(2, e.time(), "page 1 (instructor)", error));
            CHECK(error.find("drill 2 has fired (its fault holds)") != std::string::npos);
            REQUIRE_MESSAGE(drills.cancel(1, e.time(), "page 1 (instructor)", error), error);
            cancelled = true;
            CHECK_FALSE(drills.cancel(1, e.time(), "page 1 (instructor)", error));
            CHECK(error == "drill 1 is cancelled: only a waiting drill can be cancelled");
        }
        fired.clear();
        drills.due(e, fired);
        for (auto& x : fired) {
            CHECK(x.drill == 1);
            engine::apply_event(e, x.event), ++applied;
        }
        e.step();
    }
    CHECK(applied == 1);
    CHECK(e.forced(stop) == engine::ForceMode::None);
    CHECK(drills.list()[0].state == faults::Drill::State::Cancelled);
    CHECK(faults::word(drills.list()[0].state) == "cancelled");
    CHECK(drills.list()[0].ended == doctest::Approx(0.1).epsilon(0.1));
    CHECK(drills.list()[0].cancelled_by == "page 1 (instructor)");
    CHECK(drills.list()[0].fired < 0);
    // A restart: the others wait again, a cancelled drill stays dropped.
    drills.reset();
    CHECK(drills.list()[0].state == faults::Drill::State::Cancelled);
    CHECK(drills.list()[1].state == faults::Drill::State::Waiting);
}

TEST_CASE("drill: repaired by hand, the fault is released once a hand has let go of the part it held") {
    Compilation c;
    test::compile_text(R"(
object Crate {
    physics body: dynamic { mass = 1 kg; shape box(10 cm, 10 cm, 10 cm) }
}
plant P {
    timer t: periodic { period = 200 ms; autostart = true }
    box1: Crate at (0 m, 0 m, 5 cm)
    box2: Crate at (1 m, 0 m, 5 cm)
    physics floor: static { shape box(4 m, 4 m, 2 cm) at (0 m, 0 m, -1 cm) }
}
)",
                       c, "hand_drill.plant");
    REQUIRE_MESSAGE(c.ok(), render_all_text(c.sink.sorted(), c.sources));
    const engine::SlotIndex slots = engine::slot_index(c.graph);
    faults::Drill d;
    std::string error;
    REQUIRE_MESSAGE(faults::parse_drill(c.graph, slots, "now force t.stop stuck on repaired by hand box1", d, error), error);
    CHECK(d.repair_hand);
    CHECK(d.repair_path == "box1");
    CHECK(d.repair_bodies.size() == 1);
    REQUIRE(faults::parse_drill(c.graph, slots, "now force t.stop stuck on repaired by hand box2.body", d, error));
    CHECK(d.repair_bodies.size() == 1);
    REQUIRE(faults::parse_drill(c.graph, slots, "now force t.stop stuck on repaired by hand box", d, error) == false);
    CHECK(error.find("'repaired by hand box': no object or body of that path has a dynamic body") != std::string::npos);
    CHECK_FALSE(faults::parse_drill(c.graph, slots, "now force t.stop stuck on repaired by hand floor", d, error));
    CHECK_FALSE(faults::parse_drill(c.graph, slots, "now t.stop repaired by hand box1", d, error));
    CHECK(error.find("'repaired by hand box1': a repair rule ends a fault") != std::string::npos);

    faults::Drills drills;
    REQUIRE(faults::parse_drill(c.graph, slots, "now force t.stop stuck on repaired by hand box1", d, error));
    drills.add(d);
    REQUIRE(faults::parse_drill(c.graph, slots, "now force t.start stuck on repaired by hand box2", d, error));
    drills.add(d);
    engine::Engine e(c.graph);
    std::vector<engine::Event> hand;  // box1 taken at 0.2 s and put back at 0.5 s; box2 never
    for (const char* line : {"0.2s grab box1.body at 0,0,0.08", "0.3s move box1.body to 0,0.2,0.15", "0.5s drop box1.body"}) {
        engine::Event ev;
        REQUIRE_MESSAGE(engine::parse_event(c.graph, slots, line, ev, error), error);
        hand.push_back(ev);
    }
    std::vector<faults::Drills::Fired> fired;
    std::vector<std::pair<double, std::string>> log;
    size_t next = 0;
    const graph::SlotId stop(slots.at("t.stop").slots[0]);
    while (e.time() < 1.0) {
        fired.clear();
        drills.due(e, fired);
        for (auto& x : fired) {
            engine::apply_event(e, x.event);
            log.emplace_back(x.event.time, engine::format_event(c.graph, x.event, e.dt()));
        }
        for (; next < hand.size() && engine::due(e, hand[next]); ++next) engine::apply_event(e, hand[next]);
        e.step();
        if (e.time() < 0.5 - 1e-9) CHECK(e.forced(stop) != engine::ForceMode::None);  // held, not yet let go
    }
    REQUIRE(log.size() == 3);
    CHECK(log[2].second.find("release t.stop") != std::string::npos);
    // The drop applied before the step ending at 0.5 s: let go of at the boundary after it.
    CHECK(log[2].first == doctest::Approx(0.5 + e.dt()));
    CHECK(e.forced(stop) == engine::ForceMode::None);
    CHECK(drills.list()[0].state == faults::Drill::State::Repaired);
    CHECK(drills.list()[1].state == faults::Drill::State::Holding);  // nobody took box2

    // One way in: the hand's events and what the drills fired, replayed as timed events
    // without any drill, leave the plant where the drilled run did.
    engine::Engine replay(c.graph);
    std::vector<engine::Event> timed = hand;
    for (const auto& [time, line] : log) {
        engine::Event ev;
        REQUIRE_MESSAGE(engine::parse_event(c.graph, slots, engine::time_text(time, e.dt()) + "s " + line.substr(line.find(' ') + 1), ev,
                                            error),
                        error);
        timed.push_back(ev);
    }
    std::stable_sort(timed.begin(), timed.end(), [](const auto& a, const auto& b) { return a.time < b.time; });
    next = 0;
    while (replay.time() < 1.0) {
        for (; next < timed.size() && engine::due(replay, timed[next]); ++next) engine::apply_event(replay, timed[next]);
        replay.step();
    }
    CHECK(next == timed.size());
    CHECK(replay.forced(stop) == engine::ForceMode::None);
    const graph::SlotId pose(slots.at("box1.body.pose").slots[0]);
    e.watch(pose);
    replay.watch(pose);
    e.step();
    replay.step();
    for (int k = 0; k < 7; ++k) CHECK(replay.value(pose)[size_t(k)] == e.value(pose)[size_t(k)]);
}
