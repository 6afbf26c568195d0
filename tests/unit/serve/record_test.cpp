// Recordings, plain and zstd-compressed, at the default and a lower frame rate: each plays
// back exactly the frames a live run of the same plant shows at those times (floats compared
// bit for bit), the events are all kept at any rate, and damaged or cut input is refused
// with a message, never a crash.
#include "paths.h"
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "app/run_flags.h"
#include "engine/run.h"
#include "engine/events.h"
#include "serve/record.h"

#include <doctest/doctest.h>

#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <sstream>

using namespace plant;

namespace {

graph::Graph compile_bottling() {
    Compilation c;
    test::compile_repo_file("plants/bottling.plant", c);
    REQUIRE(c.ok());
    return std::move(c.graph);
}

const std::vector<std::string> kEvents = {"2s line[0].b6.stop", "2.5s line[0].b6.go"};

// Records `seconds` of the plant with two events, as `plant run --record` does.
std::string record(const graph::Graph& g, const std::string& name, view::RecordOptions opt, double seconds) {
    const std::string path = (test::scratch_dir() / name).string();
    view::Recorder rec(g, path, {}, opt);
    REQUIRE(rec.ok());
    std::vector<std::string> args = {"--for", fmt::format("{}s", seconds), "--quiet"};
    for (const std::string& ev : kEvents) args.insert(args.end(), {"--event", ev});
    std::ostringstream out, err;
    REQUIRE(app::run_main(g, args, out, err, &rec) == 0);
    return path;
}

// The live run's frame at every step, from an engine fed the same events.
std::map<int64_t, view::Frame> live_frames(const graph::Graph& g, double seconds) {
    engine::Engine e(g);
    const engine::SlotIndex slots = engine::slot_index(g);
    std::vector<engine::Event> evs;
    for (const std::string& line : kEvents) {
        engine::Event ev;
        std::string error;
        REQUIRE(engine::parse_event(g, slots, line, ev, error));
        evs.push_back(ev);
    }
    view::FrameTracker t(g);
    std::map<int64_t, view::Frame> out;
    t.take(e);
    out[0] = t.frame();
    size_t next = 0;
    const auto steps = int64_t(std::llround(seconds / e.dt()));
    while (e.steps() < steps) {
        for (; next < evs.size() && engine::due(e, evs[next]); ++next) engine::apply_event(e, evs[next]);
        e.step();
        t.take(e);
        out[e.steps()] = t.frame();
    }
    return out;
}

// Plays the recording's frames in order and compares each with the live run's.
int check_against_live(const view::Recording& rec, const std::map<int64_t, view::Frame>& live, double rate) {
    view::Frame cur = view::Frame::sized(rec.bodies, rec.graphics);
    int compared = 0;
    for (const auto& f : rec.frames) {
        bool full = false;
        REQUIRE(view::decode_frame(f.data, cur, full));
        const auto it = live.find(cur.step);
        REQUIRE(it != live.end());
        const view::Frame& want = it->second;
        CHECK(cur.time == want.time);
        CHECK(cur.body_pose == want.body_pose);
        CHECK(cur.body_state == want.body_state);
        CHECK(cur.gfx_pose == want.gfx_pose);
        CHECK(cur.gfx_variant == want.gfx_variant);
        // On the recording's grid (the last frame, at the end of the run, is too).
        const double k = cur.time * rate;
        CHECK(std::abs(k - std::round(k)) < 1e-6);
        ++compared;
    }
    return compared;
}

void write(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

}  // namespace

TEST_CASE("record: plain and compressed recordings, at 30 and 10 Hz, replay the live run's frames") {
    const graph::Graph g = compile_bottling();
    const double seconds = 12;
    const std::string plain = record(g, "plain.rec", {30, false}, seconds);
    const std::string packed = record(g, "packed.rec", {30, true}, seconds);
    const std::string thin = record(g, "thin.rec", {10, true}, seconds);
    const auto live = live_frames(g, seconds);

    // The compressed file is recognised by zstd's magic bytes, the plain one by its own.
    CHECK(test::slurp(plain).rfind("plant-rec 1\n", 0) == 0);
    CHECK(test::slurp(packed).rfind("\x28\xB5\x2F\xFD", 0) == 0);
    CHECK(test::slurp(packed).size() * 3 < test::slurp(plain).size());
    CHECK(test::slurp(thin).size() < test::slurp(packed).size());

    view::Recording a, b, c;
    std::string err;
    REQUIRE_MESSAGE(view::load_recording(plain, a, err), err);
    REQUIRE_MESSAGE(view::load_recording(packed, b, err), err);
    REQUIRE_MESSAGE(view::load_recording(thin, c, err), err);
    // The round trip: the compressed recording holds exactly the plain one's chunks.
    CHECK(a.scene == b.scene);
    REQUIRE(a.frames.size() == b.frames.size());
    for (size_t i = 0; i < a.frames.size(); ++i) CHECK(a.frames[i].data == b.frames[i].data);
    REQUIRE(a.statuses.size() == b.statuses.size());
    for (size_t i = 0; i < a.statuses.size(); ++i) CHECK(a.statuses[i].data == b.statuses[i].data);
    CHECK(a.duration == doctest::Approx(seconds));
    CHECK(c.duration == doctest::Approx(seconds));

    CHECK(check_against_live(a, live, 30) == int(seconds * 30) + 2);  // t = 0, every 1/30 s, and the end again
    CHECK(check_against_live(b, live, 30) == int(seconds * 30) + 2);
    CHECK(check_against_live(c, live, 10) == int(seconds * 10) + 2);
    // A full frame each second at either rate.
    for (const view::Recording* r : {&a, &c}) {
        int full = 0;
        for (const auto& f : r->frames) full += f.full ? 1 : 0;
        CHECK(full == int(seconds) + 1);
    }
    // Every event, at any rate.
    for (const view::Recording* r : {&a, &b, &c}) {
        REQUIRE(r->events.size() == kEvents.size());
        CHECK(r->events[0].data.find("line[0].b6.stop") != std::string::npos);
        CHECK(r->events[1].time == doctest::Approx(2.5).epsilon(1e-3));
    }
}

TEST_CASE("record: a damaged or cut recording is refused with a message") {
    const graph::Graph g = compile_bottling();
    const std::string plain = test::slurp(record(g, "p.rec", {30, false}, 2));
    const std::string packed = test::slurp(record(g, "z.rec", {30, true}, 2));
    REQUIRE(packed.size() > 1000);
    auto refused = [](const std::string& bytes, const std::string& says) {
        view::Recording rec;
        std::string err;
        CHECK_FALSE(view::parse_recording(bytes, "x.rec", rec, err));
        INFO(err);
        CHECK(err.find(says) != std::string::npos);
    };
    refused(packed.substr(0, packed.size() / 2), "cut short");
    refused(packed.substr(0, 4), "cut short");
    std::string flipped = packed;
    for (size_t i = packed.size() / 2; i < packed.size() / 2 + 8; ++i) flipped[i] = char(flipped[i] ^ 0x5a);
    refused(flipped, "damaged");
    refused(packed + "trailing", "damaged");
    refused(plain.substr(0, plain.size() - 3), "cut short");
    refused("not a recording", "not a plant recording");
    // Compressed bytes that are not a recording inside.
    const std::string path = (test::scratch_dir() / "text.rec").string();
    {
        view::Recorder rec(g, path, {}, {});  // writes only what it is given: nothing but an ended zstd frame
        REQUIRE(rec.ok());
    }
    refused(test::slurp(path), "not a plant recording");
    // The file form too.
    write(path, packed.substr(0, 100));
    view::Recording rec;
    std::string err;
    CHECK_FALSE(view::load_recording(path, rec, err));
    CHECK(err.find(path) == 0);
}
