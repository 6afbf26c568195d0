// Faults scheduled in the plant file (runtime/faults, docs/plc.md "Faults from the plant
// file"): each entry is the event an events file would give, applied the same way.
#include "paths.h"
#include "../compiler/compile_helper.h"
#include "app/run_flags.h"
#include "engine/run.h"
#include "engine/events.h"
#include "graph/text.h"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <sstream>

using namespace plant;

namespace {

// The summary's `forced:` section (wall time differs from run to run; this does not).
std::string forced_section(const std::string& summary) {
    const size_t at = summary.find("forced:");
    return at == std::string::npos ? "" : summary.substr(at);
}

}  // namespace

TEST_CASE("faults: each entry is the event its events-file line gives") {
    Compilation c;
    test::compile_repo_file("tests/golden/faults/drill.plant", c);
    REQUIRE(c.ok());
    const std::vector<engine::Event> planned = engine::plant_events(c.graph);
    // In time order; a force with `until` is followed (in time) by its release.
    const std::vector<std::string> lines = {
        "0s force t.running invert",  "1.5s force b1.stop stuck on",       "2s force sw.seen open",
        "3s release b1.stop",         "4s release sw.seen",                "5s force b1.set_speed stuck 0.2",
        "6s force sw.id stuck B-7",   "7s force sw.working stuck 2",       "8s release t.running",
    };
    REQUIRE(planned.size() == lines.size());
    const engine::SlotIndex index = engine::slot_index(c.graph);
    for (size_t i = 0; i < lines.size(); ++i) {
        CAPTURE(lines[i]);
        engine::Event given;
        std::string error;
        REQUIRE_MESSAGE(engine::parse_event(c.graph, index, lines[i], given, error), error);
        const engine::Event& p = planned[i];
        CHECK(p.planned);
        CHECK(p.time == given.time);
        CHECK(p.path == given.path);
        CHECK(p.slots == given.slots);
        CHECK(p.force == given.force);
        CHECK(p.mode == given.mode);
        CHECK(p.value == given.value);
        CHECK(p.text == given.text);
    }
}

TEST_CASE("faults: the loader runs the kind's check on a graph written by hand") {
    Compilation c;
    test::compile_repo_file("tests/golden/faults/drill.plant", c);
    REQUIRE(c.ok());
    const std::string good = graph::to_text(c.graph);
    // The loader's error for `good` with `from` replaced by `to`.
    auto refused = [&](const std::string& from, const std::string& to) {
        std::string text = good;
        const size_t at = text.find(from);
        REQUIRE(at != std::string::npos);
        text.replace(at, from.size(), to);
        std::istringstream in(text);
        graph::Graph g;
        std::string error;
        CHECK_FALSE(graph::read_text(in, g, error));
        return error;
    };
    // Entry 0 is `open 2 s => sw.seen(until = 4 s)`: its `until` (plugin_param 0) before it.
    const std::string early = refused("plugin_param 0 num=4 ", "plugin_param 0 num=1 ");
    CHECK_MESSAGE(early.find("until = 1 s is not after it") != std::string::npos, early);
    // A time key below 0.
    const std::string negative = refused("word=\"open\" key=2 ", "word=\"open\" key=-2 ");
    CHECK_MESSAGE(negative.find("key -2 is not a time of 0 s or more") != std::string::npos, negative);
}

// The drill of plants/bottling_faults.plant, and the same line without it but with the
// two --event lines it stands for: the same trace, bit for bit (one way in), and the same
// forces in the summary. And what the fault does: S2's reader cut, no bottle goes into
// lane B from 20 s to 100 s; after the release some do again. Under the sanitizers the cut
// is from 15 s to 40 s, in a run of 70 s (130 s took 41 s there).
TEST_CASE("faults: a drill in the plant file runs as its --event lines do") {
    const int cut_at = PLANT_SANITIZED ? 15 : 20, cut_until = PLANT_SANITIZED ? 40 : 100, until = PLANT_SANITIZED ? 70 : 130;
    const std::vector<std::string> times = {fmt::format("cut_at={}s", cut_at), fmt::format("cut_until={}s", cut_until)};
    const std::string dir = test::scratch_dir().string();
    auto run = [&](const std::vector<std::string>& sets, std::vector<std::string> extra, const std::string& trace,
                   std::string& summary) {
        CompileOptions opts;
        opts.stdlib_dir = PLANT_STDLIB_DIR;
        opts.overrides = times;
        opts.overrides.insert(opts.overrides.end(), sets.begin(), sets.end());
        Compilation c;
        compile_file(std::string(PLANT_SOURCE_DIR) + "/plants/bottling_faults.plant", opts, c);
        REQUIRE(c.ok());
        std::vector<std::string> args = {"--for", fmt::format("{}s", until), "--quiet", "--trace", trace, "--trace-rate", "10Hz"};
        args.insert(args.end(), extra.begin(), extra.end());
        std::ostringstream out, err;
        REQUIRE_MESSAGE(app::run_main(c.graph, args, out, err) == 0, err.str());
        summary = out.str();
    };
    std::string with_drill, with_events;
    run({}, {}, dir + "/drill.csv", with_drill);
    run({"drill=false"},
        {"--event", fmt::format("{}s force line[0].s2.bottle open", cut_at), "--event",
         fmt::format("{}s release line[0].s2.bottle", cut_until)},
        dir + "/events.csv", with_events);
    const std::string trace = test::slurp(dir + "/drill.csv");
    REQUIRE(trace.size() > 1000);
    CHECK(trace == test::slurp(dir + "/events.csv"));
    CHECK(forced_section(with_drill) == forced_section(with_events));
    CHECK(forced_section(with_drill).find(fmt::format("line[0].s2.bottle  open            from {}.000 s to {}.000 s",
                                                      cut_at, cut_until)) != std::string::npos);

    std::istringstream rows(trace);
    std::string line;
    std::getline(rows, line);
    std::vector<std::string> head;
    for (std::istringstream h(line); std::getline(h, line, ',');) head.push_back(line);
    const auto col = std::find(head.begin(), head.end(), std::string("s2 to lane B")) - head.begin();
    const auto forced = std::find(head.begin(), head.end(), std::string("forced")) - head.begin();
    REQUIRE(size_t(col) < head.size());
    REQUIRE(size_t(forced) < head.size());
    double before = 0, during = 0, after = 0;
    int marked = 0;
    while (std::getline(rows, line)) {
        std::vector<std::string> cells;
        for (std::istringstream r(line); std::getline(r, line, ',');) cells.push_back(line);
        if (cells.size() <= size_t(col)) continue;
        const double t = std::stod(cells[0]), n = std::stod(cells[size_t(col)]);
        // The row at cut_until counts the 15 steps up to it, and the last is the release's own
        // (an event applies in the step at its time): a bottle read then sends S2 to lane B, as
        // one did in the sanitizers' run since the curves turn. That row is neither.
        if (std::abs(t - cut_until) < 1e-6) continue;
        (t <= cut_at ? before : t < cut_until ? during : after) += n;
        if (t > cut_at + 0.05 && t < cut_until && size_t(forced) < cells.size() && cells[size_t(forced)].find("open") != std::string::npos)
            ++marked;
    }
    MESSAGE("into lane B: ", before, " before ", cut_at, " s, ", during, " while cut, ", after, " after the release");
    CHECK(during == 0);
    CHECK(after >= 1);
    CHECK(marked >= 10 * (cut_until - cut_at) - 10);  // every 10 Hz row in the window marks the force
}
