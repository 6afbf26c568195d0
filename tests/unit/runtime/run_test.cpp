// The run API of the `plant` command.
#include "app/run_flags.h"
#include "engine/run.h"
#include "engine/events.h"
#include "bottling_scene.h"
#include "../compiler/compile_helper.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <sstream>

using namespace plant::test;
using namespace plant::engine;

namespace {

int run(const Graph& g, std::vector<std::string> args, std::string& out, std::string& err) {
    std::ostringstream o, e;
    int rc = plant::app::run_main(g, args, o, e);
    out = o.str();
    err = e.str();
    return rc;
}


}  // namespace

TEST_CASE("runtime: durations and frequencies") {
    double v = 0;
    std::string err;
    CHECK(parse_duration("10s", v, err));
    CHECK(v == 10);
    CHECK(parse_duration("250ms", v, err));
    CHECK(v == 0.25);
    CHECK(parse_duration("1.5min", v, err));
    CHECK(v == 90);
    CHECK_FALSE(parse_duration("10", v, err));
    CHECK(err.find("unit") != std::string::npos);
    CHECK_FALSE(parse_duration("ten s", v, err));
    CHECK(parse_frequency("150Hz", v, err));
    CHECK(v == 150);
    CHECK(parse_frequency("1kHz", v, err));
    CHECK(v == 1000);
    CHECK_FALSE(parse_frequency("0Hz", v, err));
    CHECK_FALSE(parse_frequency("150", v, err));
}

TEST_CASE("runtime: duration and frequency errors say what is wrong") {
    double v = 0;
    std::string err;
    CHECK(parse_duration("1h", v, err));
    CHECK(v == 3600);
    CHECK_FALSE(parse_duration("2d", v, err));
    CHECK(err == "'2d': unknown unit 'd'; a duration takes s, ms, min or h");
    CHECK_FALSE(parse_duration("10", v, err));
    CHECK(err == "'10': a duration needs a unit: s, ms, min or h");
    CHECK_FALSE(parse_duration("-1s", v, err));
    CHECK(err == "'-1s': a duration must not be negative");
    CHECK_FALSE(parse_frequency("0Hz", v, err));
    CHECK(err == "'0Hz': a frequency must be above 0");
    CHECK_FALSE(parse_frequency("150MHz", v, err));
    CHECK(err == "'150MHz': unknown unit 'MHz'; a frequency takes Hz or kHz");
    CHECK_FALSE(parse_frequency("150", v, err));
    CHECK(err == "'150': a frequency needs a unit: Hz or kHz");
}

TEST_CASE("runtime: --events given a folder and a trace that cannot be written are errors") {
    const Graph g = bottling_scene(2);
    std::string out, err;
    CHECK(run(g, {"--events", "/tmp", "--quiet"}, out, err) == 2);
    CHECK(err.find("/tmp: is a folder, not an events file") != std::string::npos);
    CHECK(run(g, {"--for", "0.1s", "--quiet", "--trace", "/dev/full"}, out, err) == 1);
    CHECK(err.find("--trace: writing '/dev/full' failed") != std::string::npos);
}

// Every time printed for people sits on the step grid with a fixed number of decimals, the
// fewest that keep steps apart (times.h), and reads back to its step; the trace's time column
// has three more, at 150 Hz, 600 Hz and 10 Hz; an event at either printed time is due in
// that step.
TEST_CASE("runtime: a trace's time is the step on the grid with fixed decimals, and reads back to its step") {
    const Graph g = bottling_scene(2);
    const std::string path = "/tmp/plant_runtime_test_time.csv";
    for (const auto& [rate, decimals] : {std::pair{150, 3}, {600, 4}, {10, 2}}) {
        CAPTURE(rate);
        std::string out, err;
        REQUIRE(run(g, {"--for", "2s", "--rate", std::to_string(rate) + "Hz", "--trace", path, "--quiet"}, out, err) == 0);
        std::istringstream lines(slurp(path));
        std::string line;
        std::getline(lines, line);  // the header
        int k = 0;
        for (; std::getline(lines, line); ++k) {
            const std::string time = line.substr(0, line.find(','));
            CHECK(time == fmt::format("{:.{}f}", k / double(rate), decimals + 3));
            const std::string said = plant::engine::time_text(k / double(rate), 1.0 / rate);
            CHECK(said == fmt::format("{:.{}f}", k / double(rate), decimals));
            // Read back as an event's time, each is due in step k (the step that ends at it).
            for (const std::string& printed : {time, said}) {
                CAPTURE(printed);
                plant::engine::Engine e(g, plant::engine::Options{.rate = double(rate)});
                for (int i = 0; i + 1 < k; ++i) e.step();
                plant::engine::Event ev;
                ev.time = std::stod(printed);
                if (k > 0) CHECK(plant::engine::due(e, ev));  // before step k
                if (k > 1) {
                    plant::engine::Engine f(g, plant::engine::Options{.rate = double(rate)});
                    for (int i = 0; i + 2 < k; ++i) f.step();
                    CHECK_FALSE(plant::engine::due(f, ev));  // not before step k - 1
                }
            }
            if (k >= 12) break;  // a few steps make the point; engines are not free
        }
        CHECK(k >= 12);
    }
    CHECK(plant::engine::time_decimals(1.0 / 150) == 3);
    CHECK(plant::engine::time_text(183.41333333333333, 1.0 / 150) == "183.413");  // an interrupted run's last row
    CHECK(plant::engine::time_decimals(1.0 / 50) == 2);  // 10 ms steps: 0.01 apart is enough
    CHECK(plant::engine::trace_time_decimals(1.0 / 150) == 6);
    std::remove(path.c_str());
}

TEST_CASE("runtime: run_main rejects bad flags with exit code 2") {
    const Graph g = bottling_scene(2);
    std::string out, err;
    CHECK(run(g, {"--for", "ten"}, out, err) == 2);
    CHECK(err.find("duration") != std::string::npos);
    CHECK(run(g, {"--rate", "fast"}, out, err) == 2);
    CHECK(run(g, {"--frobnicate"}, out, err) == 2);
    CHECK(err.find("unknown flag") != std::string::npos);
    CHECK(run(g, {"--for"}, out, err) == 2);
    CHECK(run(g, {"--event", "1s no.such.slot"}, out, err) == 2);
    CHECK(err.find("no slot 'no.such.slot'") != std::string::npos);
    CHECK(run(g, {"--event", "1s line.belt.set_speed"}, out, err) == 2);  // needs a value
    CHECK(run(g, {"--events", "/nonexistent/events.txt"}, out, err) == 2);
    CHECK(run(g, {"--broadphase", "octree"}, out, err) == 2);
    CHECK(run(g, {"--threads", "0"}, out, err) == 2);
    CHECK(err.find("--threads: '0' is not a number of threads") != std::string::npos);
    CHECK(run(g, {"--threads", "two"}, out, err) == 2);
    CHECK(run(g, {"--threads", "+2"}, out, err) == 2);  // digits only (app::whole_number)
    CHECK(run(g, {"--threads", " 2"}, out, err) == 2);
    CHECK(err.find("--threads: ' 2' is not a number of threads") != std::string::npos);
    // Numbers that parse but cannot run: refused, not run as 0 steps or forever.
    CHECK(run(g, {"--rate", "1e-300Hz"}, out, err) == 2);
    CHECK(err.find("the physics rate must lie between 1 Hz and 1 MHz") != std::string::npos);
    CHECK(run(g, {"--rate", "2000kHz"}, out, err) == 2);
    CHECK(run(g, {"--trace-rate", "2000kHz"}, out, err) == 2);
    CHECK(err.find("at most 1 MHz") != std::string::npos);
    CHECK(run(g, {"--for", "1e308s", "--quiet"}, out, err) == 2);
    CHECK(err.find("more than 1e18 steps") != std::string::npos);
    out.clear();
    CHECK(run(g, {"--for", "0.1s", "--quiet", "--trace-rate", "1e-300Hz"}, out, err) == 0);  // a row at the start and the end
    // Event values: finite numbers; rotations unit quaternions (to a typed precision); places within 100 km.
    CHECK(run(g, {"--event", "0.05s bottle0.main.set_velocity (nan 0 0)"}, out, err) == 2);
    CHECK(err.find("is not a vec3 value for 'bottle0.main.set_velocity'") != std::string::npos);
    CHECK(run(g, {"--event", "0.05s bottle0.main.set_pose (0 0 0.1|0 0 0 0)"}, out, err) == 2);
    CHECK(err.find("a unit quaternion") != std::string::npos);
    // A place as far as a plant may lie (graph/range.h), not further.
    CHECK(run(g, {"--event", "0.05s bottle0.main.set_pose (0 -2e5 0.1|0 0 0 1)"}, out, err) == 2);
    CHECK(err.find("is not a pose value for 'bottle0.main.set_pose' (a place within 100 km") != std::string::npos);
    CHECK(run(g, {"--event", "0.05s bottle0.main.set_pose (0 -1e5 0.1|0 0 0 1)", "--for", "0.1s", "--quiet"}, out, err) == 0);
    CHECK(run(g, {"--event", "0.05s bottle0.main.set_orientation (0 0 0.7071 0.7071)", "--for", "0.1s", "--quiet"},
              out, err) == 0);
    // Whatever else moves the physics stays in its range too: a place set alone, velocities, a belt's speed.
    const std::pair<const char*, const char*> far[] = {
        {"0.05s bottle0.main.set_position (0 0 1e300)", "it takes a place within 100 km"},
        {"0.05s bottle0.main.set_velocity (-2e5 0 0)", "it takes a velocity within 100 km/s on each axis"},
        {"0.05s bottle0.main.set_angular_velocity (0 2e6 0)", "it takes an angular velocity within 1e6 rad/s"},
        {"0.05s line.belt.set_speed 1e300", "'1e300' is out of range for 'line.belt.set_speed': it takes a speed"},
    };
    for (const auto& [event, words] : far) {
        CAPTURE(event);
        CHECK(run(g, {"--event", event}, out, err) == 2);
        CHECK_MESSAGE(err.find(words) != std::string::npos, err);
    }
    // A static body takes no velocity, whatever the value (E0316 for a flow): refused when
    // read, as an event and as a forced value.
    for (const char* event : {"0.05s line.floor.set_velocity (0 0 0)", "0.05s line.rail_l.set_angular_velocity (0 0 1)",
                              "0.05s force line.rail_r.set_velocity stuck (0.1 0 0)"}) {
        CAPTURE(event);
        CHECK(run(g, {"--event", event}, out, err) == 2);
        CHECK_MESSAGE(err.find("it takes no value: the body is static and does not move") != std::string::npos, err);
    }
    for (const char* event : {"0.05s bottle0.main.set_position (0 0 1e5)", "0.05s bottle0.main.set_velocity (-1e5 0 0)",
                              "0.05s bottle0.main.set_angular_velocity (0 1e6 0)", "0.05s line.belt.set_speed -1e5"}) {
        CAPTURE(event);
        CHECK(run(g, {"--event", event, "--for", "0.1s", "--quiet"}, out, err) == 0);
    }
}

TEST_CASE("runtime: run_main names the physics regions and their threads in the summary") {
    std::string out, err;
    CHECK(run(bottling_scene(2, 0.5, 2), {"--for", "0.1s", "--quiet", "--threads", "2"}, out, err) == 0);
    CHECK(out.find("physics regions:  2 (a Bullet world each), on 2 threads") != std::string::npos);
    CHECK(run(bottling_scene(2), {"--for", "0.1s", "--quiet", "--threads", "2"}, out, err) == 0);
    CHECK(out.find("physics regions") == std::string::npos);  // one region: as before
}

TEST_CASE("runtime: --summary=json says what the text summary says, for programs") {
    // A plant that loses bottles: a belt speed far beyond the line's end throws them off.
    const Graph g = bottling_scene(4);
    std::string text, json, err;
    const std::vector<std::string> args = {"--for", "3s", "--quiet", "--event", "0.1s line.belt.set_speed 3",
                                           "--event", "0.2s force line.belt.set_speed stuck 3"};
    REQUIRE(run(g, args, text, err) == 0);
    std::vector<std::string> as_json = args;
    as_json.push_back("--summary=json");
    REQUIRE(run(g, as_json, json, err) == 0);
    const nlohmann::json j = nlohmann::json::parse(json);
    CHECK(j["format"] == "plant-run-summary 1");
    CHECK(j["steps"] == 450);
    CHECK(j["simulated_time_s"].get<double>() == doctest::Approx(3.0));
    CHECK(j["interrupted_by"].is_null());
    const auto& o = j["objects"];
    auto count = [&](const std::string& line) {  // "  lost (left the world): 2 (...)" -> 2
        const size_t at = text.find(line);
        REQUIRE_MESSAGE(at != std::string::npos, line);
        return std::stoll(text.substr(at + line.size()));
    };
    CHECK(o["on_line"].get<int64_t>() == count("on the line:"));
    CHECK(o["lost"].get<int64_t>() == count("lost (left the world):"));
    CHECK(o["lost_objects"].size() == o["lost"].get<size_t>());
    CHECK(j["warnings"]["total"].get<int64_t>() == count("warnings:"));
    CHECK(j["warnings"]["left_world"].get<int64_t>() == o["lost"].get<int64_t>());
    REQUIRE(j["forced"].size() == 1);
    CHECK(j["forced"][0]["path"] == "line.belt.set_speed");
    CHECK(j["forced"][0]["until_s"].is_null());
    for (const auto& lost : o["lost_objects"])
        CHECK(text.find(lost["object"].get<std::string>() + ": " + lost["where"].get<std::string>()) != std::string::npos);
    CHECK(run(g, {"--summary=yaml"}, json, err) == 2);
    CHECK(err.find("--summary takes text or json, not 'yaml'") != std::string::npos);
}

TEST_CASE("runtime: run_main runs, traces and summarises") {
    const Graph g = bottling_scene(4);
    const std::string path = "/tmp/plant_runtime_test_trace.csv";
    std::string out, err;
    CHECK(run(g, {"--for", "2s", "--rate", "100Hz", "--trace", path, "--quiet", "--event",
                  "0.5s line.belt.set_speed 0.25", "--event", "1s line.state.other.put"},
              out, err) == 0);
    CHECK(err.empty());
    CHECK(out.find("simulated time:   2.000 s") != std::string::npos);
    CHECK(out.find("steps:            200 at 100 Hz") != std::string::npos);
    CHECK(out.find("real-time factor") != std::string::npos);
    const std::string csv = slurp(path);
    std::istringstream lines(csv);
    std::string header, line;
    std::getline(lines, header);
    CHECK(header.rfind("time,bottle0.main.x,bottle0.main.y,bottle0.main.z,bottle0.main.speed", 0) == 0);
    CHECK(header.find("line.state.other.tokens") != std::string::npos);
    CHECK(header.find("line.reader.on_enter") != std::string::npos);
    int rows = 0;
    while (std::getline(lines, line)) ++rows;
    CHECK(rows == 201);  // t = 0 and every step
    std::remove(path.c_str());
}

TEST_CASE("runtime: records choose the trace columns, --trace-places selects a default group") {
    SceneBuilder b;
    const int32_t p = b.net(0, "net", {{"p", 2}}, {});
    const int32_t t = b.g.timers[plant::graph::Id<plant::graph::Timer>(b.timer(0, "clock", 0.1, true, true))].comp.v;
    b.record(b.S(t, "tick"), "tick");
    b.record(b.S(t, "elapsed"), "");
    b.record(b.g.places[plant::graph::PlaceId(p)].tokens_slot.v, "tokens");
    const std::string path = "/tmp/plant_runtime_test_records.csv";
    std::string out, err;
    CHECK(run(b.g, {"--for", "0.2s", "--rate", "10Hz", "--trace", path}, out, err) == 0);
    std::string csv = slurp(path);
    CHECK(csv == "time,tick,clock.elapsed,tokens\n0.00000,0,0,2\n0.10000,1,0.1,2\n0.20000,1,0.2,2\n");
    CHECK(run(b.g, {"--for", "0.1s", "--rate", "10Hz", "--trace", path, "--trace-places"}, out, err) == 0);
    csv = slurp(path);
    CHECK(csv == "time,net.p.tokens\n0.00000,2\n0.10000,2\n");
    std::remove(path.c_str());
}

// #19 §3b: a sampled trace never hides an event, and the summary's records count what the
// last step produced.
TEST_CASE("runtime: a 10 Hz trace counts a 30 Hz timer's ticks, records agree with the sources' count") {
    plant::Compilation c;
    plant::test::compile_text(R"(import std.bottle
plant Ticks {
    timer clock: periodic { period = 1 s / 30; autostart = true }
    source store at (0 m, 0 m, 5 cm) { object = Bottle; pool = 20; rate = 3 Hz }
    record clock.tick as "ticks"
    record store.issued as "issued"
}
)", c, "ticks.plant");
    REQUIRE(c.ok());
    const Graph& g = c.graph;
    const std::string csv = (plant::test::scratch_dir() / "ticks.csv").string();
    for (const char* duration : {"1s", "2s", "0.34s", "1.6667s", "3s"}) {
        const std::string for_time = duration;
        CAPTURE(for_time);
        std::string out, err;
        REQUIRE(run(g, {"--for", duration, "--quiet", "--trace", csv, "--trace-rate", "10Hz"}, out, err) == 0);
        // The summary: ticks and issues as records, issues as the sources' count.
        auto number_after = [&](const std::string& what) {
            const size_t at = out.find(what);
            REQUIRE_MESSAGE(at != std::string::npos, what, " in ", out);
            return std::stoll(out.substr(at + what.size()));
        };
        const long long ticks = number_after("ticks   "), issued = number_after("issued  ");
        CHECK(issued == number_after("issued by sources: "));
        // The trace: the sum of each void column is the summary's count.
        std::istringstream rows(slurp(csv));
        std::string line;
        std::getline(rows, line);
        REQUIRE(line == "time,ticks,issued,lost");  // a plant with dynamic bodies: the `lost` column
        long long sum_ticks = 0, sum_issued = 0;
        int n = 0;
        while (std::getline(rows, line)) {
            const size_t a = line.find(','), b = line.find(',', a + 1);
            sum_ticks += std::stoll(line.substr(a + 1, b - a - 1));
            sum_issued += std::stoll(line.substr(b + 1));
            ++n;
        }
        CHECK(n >= 4);
        CHECK(sum_ticks == ticks);
        CHECK(sum_issued == issued);
        CHECK(ticks >= 10);
    }
}

TEST_CASE("runtime: an event after the end of the run is reported") {
    const Graph g = bottling_scene(2);
    std::string out, err;
    REQUIRE(run(g, {"--for", "1s", "--quiet", "--event", "5s line.state.other.put"}, out, err) >= 0);
    CHECK(err.find("after the end of the run") != std::string::npos);
}

namespace {

// A link (engine::RunLink) that forces a slot before step `at` and grants `steps` steps.
struct ScriptedLink : RunLink {
    Event force;
    int64_t at = 0, steps = 0, waits = 0;
    std::vector<const Event*> now;
    bool wait(std::string& error) override {
        if (waits++ < steps) return true;
        error = "no more steps granted";
        return false;
    }
    void before_step(Engine& e) override {
        now.clear();
        if (e.steps() + 1 != at) return;
        apply_event(e, force);
        now.push_back(&force);
    }
    std::span<const Event* const> applied() const override { return now; }
    void after_step(const Engine&) override {}
};

}  // namespace

TEST_CASE("runtime: a link's forces are listed in the summary, a link that stops granting ends the run with its error") {
    const Graph g = bottling_scene(2);
    ScriptedLink link;
    std::string error;
    REQUIRE(parse_input(g, slot_index(g), "force line.reader.on_enter stuck on", link.force, error));
    link.at = 50;
    link.steps = 1000;
    std::ostringstream out, err;
    CHECK(plant::app::run_main(g, {"--for", "1s", "--rate", "100Hz", "--quiet"}, out, err, nullptr, &link) == 0);
    CHECK(out.str().find("forced:           1\n  line.reader.on_enter  stuck on        from 0.500 s to the end (1.000 s)") !=
          std::string::npos);
    link.steps = 30;
    link.waits = 0;
    std::ostringstream out2, err2;
    CHECK(plant::app::run_main(g, {"--for", "1s", "--rate", "100Hz", "--quiet"}, out2, err2, nullptr, &link) == 1);
    CHECK(out2.str().find("steps:            30 at 100 Hz") != std::string::npos);
    CHECK(err2.str() == "plant run: error: no more steps granted\n");
}
