// Fault forcing: a slot stuck at a value, cut (open) or inverted, set and released by
// events, on examples/switch.plant (a reader before a switch; "F-*" bottles go aside,
// every other one straight on).
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/events.h"

#include <doctest/doctest.h>

#include <string>

using namespace plant;

namespace {

struct SwitchRun {
    Compilation c;
    engine::SlotIndex idx;
    SwitchRun() {
        test::compile_repo_file("examples/switch.plant", c);
        REQUIRE(c.ok());
        idx = engine::slot_index(c.graph);
    }
    const graph::Graph& g() const { return c.graph; }
    int32_t exit_of(const std::string& path) const {
        for (size_t i = 0; i < g().exits.size(); ++i)
            if (g().comp_path(g().exits[graph::ExitId(i)].comp) == path) return int32_t(i);
        FAIL("no exit ", path);
        return -1;
    }
    graph::SlotId slot_of(const std::string& path) const {
        auto it = idx.find(path);
        REQUIRE_MESSAGE(it != idx.end(), path);
        return it->second.slots[0];
    }
    engine::Event event(const std::string& line) const {
        engine::Event ev;
        std::string err;
        REQUIRE_MESSAGE(engine::parse_event(g(), idx, line, ev, err), err);
        return ev;
    }
    // Runs `seconds`, applying the events at their times (as plant run does).
    void run(engine::Engine& e, double seconds, std::vector<engine::Event> events = {}) const {
        size_t next = 0;
        const int64_t steps = int64_t(seconds / e.dt() + 0.5);
        for (int64_t i = 0; i < steps; ++i) {
            for (; next < events.size() && engine::due(e, events[next]); ++next) engine::apply_event(e, events[next]);
            e.step();
        }
    }
};

}  // namespace

TEST_CASE("forces: the reader's output cut open sends every bottle straight on, released, routing resumes") {
    SwitchRun s;
    const int32_t aside = s.exit_of("aside_exit"), ahead = s.exit_of("ahead_exit");
    {  // unforced: the F bottles go aside
        engine::Engine e(s.g());
        s.run(e, 15);
        CHECK(e.taken(plant::graph::ExitId(aside)) >= 2);
        CHECK(e.taken(plant::graph::ExitId(ahead)) >= 2);
    }
    engine::Engine e(s.g());
    s.run(e, 15, {s.event("0s force sw.id open")});
    CHECK(e.taken(plant::graph::ExitId(aside)) == 0);
    CHECK(e.taken(plant::graph::ExitId(ahead)) >= 6);
    CHECK(e.forced(s.slot_of("sw.id")) == engine::ForceMode::Open);
    const int64_t before = e.taken(plant::graph::ExitId(aside));
    s.run(e, 15, {s.event("0s release sw.id")});
    CHECK(e.forced(s.slot_of("sw.id")) == engine::ForceMode::None);
    CHECK(e.taken(plant::graph::ExitId(aside)) > before);
}

TEST_CASE("forces: a switch held in its working position sends every bottle aside") {
    SwitchRun s;
    const int32_t aside = s.exit_of("aside_exit"), ahead = s.exit_of("ahead_exit");
    engine::Engine e(s.g());
    // The control's "back to base" wire cut, then the switch sent to working once.
    s.run(e, 15, {s.event("0s force sw.to_base open"), s.event("0s sw.to_working")});
    CHECK(e.taken(plant::graph::ExitId(ahead)) == 0);
    CHECK(e.taken(plant::graph::ExitId(aside)) >= 6);
}

TEST_CASE("forces: a string output stuck at a value is what the logic reads, the component goes on underneath") {
    SwitchRun s;
    const int32_t aside = s.exit_of("aside_exit"), ahead = s.exit_of("ahead_exit");
    const graph::SlotId id = s.slot_of("sw.id");
    engine::Engine e(s.g());
    s.run(e, 15, {s.event("0s force sw.id stuck \"F-99\"")});
    CHECK(e.str(int32_t(e.value(id)[0])) == "F-99");  // readers after the step see it too
    CHECK(e.taken(plant::graph::ExitId(ahead)) == 0);
    CHECK(e.taken(plant::graph::ExitId(aside)) >= 6);
    // Released: the reader's own last value shows again (a bar code of this run).
    s.run(e, 0.1, {s.event("0s release sw.id")});
    const std::string natural(e.str(int32_t(e.value(id)[0])));
    CHECK(natural != "F-99");
    CHECK(natural.size() == 3);
}

TEST_CASE("forces: a void output stuck on is active every step, invert negates a bool") {
    SwitchRun s;
    const graph::SlotId seen = s.slot_of("ahead_end.seen");
    engine::Engine e(s.g());
    s.run(e, 0.5, {s.event("0s force ahead_end.seen stuck on")});
    CHECK(e.active(seen));
    s.run(e, 0.1);
    CHECK(e.active(seen));
    s.run(e, 0.1, {s.event("0s force ahead_end.seen stuck off")});
    CHECK_FALSE(e.active(seen));
    CHECK(e.forced(seen) == engine::ForceMode::Open);  // stuck off is kept as open
    s.run(e, 0.1, {s.event("0s release ahead_end.seen")});
    CHECK(e.forced(seen) == engine::ForceMode::None);

    // A bool output inverted reads the negation of the component's value.
    graph::SlotId occupied;
    for (const auto& [path, t] : s.idx)
        if (t.type == graph::SlotType::Bool && t.dir == graph::Dir::Out && !t.port) occupied = t.slots[0];
    REQUIRE(occupied.valid());
    const std::string path = s.g().slot_path(occupied);
    engine::Engine f(s.g());
    s.run(f, 1);
    const double natural = f.value(occupied)[0];
    s.run(f, 0.01, {s.event("0s force " + path + " invert")});
    CHECK(f.value(occupied)[0] == (natural != 0 ? 0 : 1));
    s.run(f, 0.01, {s.event("0s release " + path)});
    CHECK(f.value(occupied)[0] == natural);
}

TEST_CASE("forces: the events-file lines replay as they went out, bad forces are refused") {
    SwitchRun s;
    for (const char* line : {"1.000s force sw.id open", "2.000s release sw.id", "3.000s force sw.id stuck \"F-1\"",
                             "4.000s force ahead_end.seen stuck on", "5.000s force feed.set_speed stuck 0.25",
                             "6.000s force sw.to_base open"}) {
        const engine::Event ev = s.event(line);
        CHECK(ev.force);
        CHECK(engine::format_event(s.g(), ev) == line);
    }
    engine::Event ev;
    std::string err;
    auto refused = [&](const std::string& line, const std::string& part) {
        CHECK_FALSE(engine::parse_event(s.g(), s.idx, line, ev, err));
        CHECK_MESSAGE(err.find(part) != std::string::npos, err);
    };
    refused("1s force sw.id invert", "only a bool slot can be inverted");
    refused("1s force sw.id", "which way?");
    refused("1s force sw.id sideways", "'sideways' is not a way to force");
    refused("1s force sw.i open", "did you mean 'sw.id'");
    refused("1s release sw.id now", "unexpected 'now'");
    refused("1s force ahead_end.seen stuck maybe", "stuck on or off");
    refused("1s force feed.set_speed stuck fast", "is not a real value");
    // Forced like an event: within the range of the physics it moves (graph/range.h).
    refused("1s force feed.set_speed stuck 2e5", "'2e5' is out of range for 'feed.set_speed': it takes a speed within 100 km/s");
    CHECK(engine::parse_event(s.g(), s.idx, "1s force feed.set_speed stuck -1e5", ev, err));
}
