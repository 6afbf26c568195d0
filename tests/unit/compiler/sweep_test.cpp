// plant sweep: the spec reader's values and located errors, the checks against the plant,
// the order of runs, and the reading of `plant run`'s summary.
#include "paths.h"
#include "app/summary.h"
#include "app/sweep/sweep.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace plant::sweep;

namespace {

// A spec file beside the bottling plant's folder (so `plant: ../bottling.plant` resolves).
struct SpecFile {
    std::string path;
    explicit SpecFile(const std::string& text) {
        path = std::string(PLANT_SOURCE_DIR) + "/plants/sweeps/unit-test-" + std::to_string(::getpid()) + ".sweep";
        std::ofstream(path) << text;
    }
    ~SpecFile() { std::filesystem::remove(path); }
};

std::vector<SpecError> errors_of(const std::string& text, bool check = false) {
    SpecFile f(text);
    Spec s;
    std::vector<SpecError> e;
    if (load_spec(f.path, s, e) && check) check_spec(s, PLANT_STDLIB_DIR, e);
    return e;
}

}  // namespace

TEST_CASE("sweep spec: lists, ranges with a step and seeded random samples") {
    SpecFile f("plant: ../bottling.plant\nfor: 5 s\nvary:\n  feed_every: {from: 1000 ms, to: 2000 ms, step: 250 ms}\n"
               "  belt_speed: [40 cm/s, 0.5 m/s]\n  bottles: {random: 3, from: 10, to: 20, seed: 7}\nreplicates: 2\n");
    Spec s;
    std::vector<SpecError> e;
    REQUIRE(load_spec(f.path, s, e));
    REQUIRE(s.params.size() == 3);
    CHECK(s.run_for == "5 s");
    REQUIRE(s.params[0].values.size() == 5);
    CHECK(s.params[0].values[0].text == "1000 ms");
    CHECK(s.params[0].values[4].text == "2000 ms");
    CHECK(s.params[1].values[1].text == "0.5 m/s");
    REQUIRE(s.params[2].values.size() == 3);
    Spec again;
    REQUIRE(load_spec(f.path, again, e));
    for (size_t i = 0; i < 3; ++i) {
        CHECK(s.params[2].values[i].text == again.params[2].values[i].text);  // the seed decides
        const double v = std::stod(s.params[2].values[i].text);
        CHECK(v >= 10);
        CHECK(v < 20);
    }
    CHECK(s.params[2].values[0].text != s.params[2].values[1].text);
    // Default outputs: the summary's counters.
    REQUIRE(s.outputs.size() == 5);
    CHECK(s.outputs[1].column() == "commissioned");
    // 5 x 2 x 3 combinations, 2 replicates each, the first parameter slowest, replicates innermost.
    const auto runs = expand(s);
    REQUIRE(runs.size() == 60);
    CHECK(runs[0].replicate == 0);
    CHECK(runs[1].replicate == 1);
    CHECK(runs[1].values == runs[0].values);
    CHECK(runs[2].values[2] != runs[0].values[2]);
    CHECK(runs[59].values[0] == "2000 ms");
    CHECK(runs[59].sets[0] == "feed_every=2000 ms");
    CHECK(runs[59].index == 59);
}

TEST_CASE("sweep spec: a replicate perturbs one varied parameter by a step") {
    SpecFile f("plant: ../bottling.plant\nvary:\n  feed_every: [1000 ms]\nreplicates: {count: 3, perturb: feed_every, by: 10 ms}\n");
    Spec s;
    std::vector<SpecError> e;
    REQUIRE(load_spec(f.path, s, e));
    REQUIRE(check_spec(s, PLANT_STDLIB_DIR, e));
    const auto runs = expand(s);
    REQUIRE(runs.size() == 3);
    CHECK(runs[0].sets[0] == "feed_every=1000 ms");
    CHECK(runs[2].sets[0] == "feed_every=(1000 ms) + 2 * (10 ms)");
    CHECK(runs[2].values[0] == "1000 ms");
}

TEST_CASE("sweep spec: errors point at the line and column") {
    auto e = errors_of("plant: ../bottling.plant\nvary:\n  feed_every: {from: 3 s, to: 1 s, step: 1 s}\n");
    REQUIRE(e.size() == 1);
    CHECK(e[0].loc.line == 3);
    CHECK(e[0].loc.col == 15);
    CHECK(e[0].message.find("empty range") != std::string::npos);

    e = errors_of("plant: ../bottling.plant\nvary:\n  feed_every: {from: 1 s, to: 3000 ms, step: 1 s}\n");
    REQUIRE(e.size() == 1);
    CHECK(e[0].message.find("one unit") != std::string::npos);

    e = errors_of("plant: ../bottling.plant\nvary:\n  feed_every: []\n");
    REQUIRE(e.size() == 1);
    CHECK(e[0].message.find("empty list") != std::string::npos);

    e = errors_of("plant: ../bottling.plant\nvary:\n  feed_every: {from: 1 s, to: 2 s, random: 3}\n");
    REQUIRE(e.size() == 1);
    CHECK(e[0].message.find("need a seed") != std::string::npos);

    e = errors_of("plant: ../bottling.plant\nfor: 5 furlongs\nspeed: 3\n");
    REQUIRE(e.size() == 2);
    CHECK(e[0].loc.line == 3);  // unknown keys first, then each key's own checks
    CHECK(e[0].message.find("unknown key 'speed'") != std::string::npos);
    CHECK(e[1].loc.line == 2);
    CHECK(e[1].loc.col == 6);

    e = errors_of("plant: ../bottling.plant\noutputs: [issued, throughput]\n");
    REQUIRE(e.size() == 1);
    CHECK(e[0].loc.col == 19);

    e = errors_of("plant: nowhere.plant\n");
    REQUIRE(e.size() == 1);
    CHECK(e[0].message.find("no plant file") != std::string::npos);

    e = errors_of("plant: [unclosed\n");  // YAML's own syntax error, with its place
    REQUIRE(e.size() == 1);
    CHECK(e[0].loc.line >= 1);
}

TEST_CASE("sweep check: names, units and records against the plant") {
    auto e = errors_of("plant: ../bottling.plant\nvary:\n  feed_evry: [1 s]\n", true);
    REQUIRE(e.size() == 1);
    CHECK(e[0].loc.line == 3);
    CHECK(e[0].loc.col == 3);
    CHECK(e[0].message.find("no parameter 'feed_evry'") != std::string::npos);

    e = errors_of("plant: ../bottling.plant\nvary:\n  belt_speed: [40 cm/s, 40 kg]\n", true);
    REQUIRE(e.size() == 1);
    CHECK(e[0].loc.col == 25);
    CHECK(e[0].message.find("E0203") != std::string::npos);

    // A good value the plant refuses elsewhere (a loop over the limit) is the run's failure,
    // not the spec's; a value that breaks the parameter's own constraint is the spec's.
    e = errors_of("plant: ../bottling.plant\nvary:\n  lines: [3000000, 1]\n", true);
    CHECK(e.empty());
    e = errors_of("plant: ../bottling.plant\nvary:\n  bottles: [0, 4]\n", true);
    REQUIRE(e.size() == 1);
    CHECK(e[0].message.find("E0314") != std::string::npos);

    e = errors_of("plant: ../bottling.plant\noutputs: [{rate: filled}, {total: flled}]\n", true);
    REQUIRE(e.size() == 1);
    CHECK(e[0].message.find("records nothing as 'flled'") != std::string::npos);

    e = errors_of("plant: ../bottling.plant\nvary:\n  bottles: [4]\nreplicates: {count: 2, perturb: bottles, by: 1 s}\n", true);
    REQUIRE(e.size() == 1);
    CHECK(e[0].loc.line == 4);
}

TEST_CASE("sweep: the summary of plant run (--summary=json), counters and records") {
    // The summary as `plant run --summary=json` writes it (app/summary.cpp), read back.
    plant::engine::RunSummary r;
    r.time = 10;
    r.dt = 1.0 / 150;
    r.steps = 1500;
    r.wall = 0.5;
    r.objects.shown = true;
    r.objects.issued = 5;
    r.objects.taken = 2;
    r.objects.on_line = 3;
    r.objects.lost = 1;
    r.records = {{"issued", true, 5, 30, 0, false}, {"commissioned A", true, 2, 12.5, 0, false},
                 {"level", false, 0, 0, 0.25, true}};
    r.warning_counts = {{"nan_state", "objects with a NaN state", 1}};
    r.warnings = 1;
    std::ostringstream json;
    plant::app::write_summary_json(r, json);
    Summary s;
    REQUIRE(parse_summary(json.str(), s));
    CHECK(s.counters["issued"] == 5);
    CHECK(s.counters["commissioned"] == 2);
    CHECK(s.counters["on_line"] == 3);
    CHECK(s.counters["lost"] == 1);
    CHECK(s.counters["stalled"] == 0);
    CHECK(s.counters["rtf"] == 20);
    CHECK(s.totals["commissioned A"] == 2);
    CHECK(s.rates["commissioned A"] == 12.5);  // not rounded as the text's 12.5 -> "12.5", 12.46 -> "12.5"
    CHECK(s.totals["issued"] == 5);
    CHECK(s.totals["level"] == 0.25);
    CHECK(s.nan);
    // A plant without sources or exits has no such counters (an empty CSV cell).
    r.objects.issued.reset();
    r.objects.taken.reset();
    r.warning_counts.clear();
    json.str("");
    plant::app::write_summary_json(r, json);
    Summary without;
    REQUIRE(parse_summary(json.str(), without));
    CHECK(without.counters.count("issued") == 0);
    CHECK(without.counters.count("commissioned") == 0);
    CHECK_FALSE(without.nan);
    Summary none;
    CHECK_FALSE(parse_summary("plant run: error: unknown flag\n", none));
    CHECK_FALSE(parse_summary("simulated time:   10 s\n", none));  // the text summary is not read
}

TEST_CASE("sweep: --resume keeps finished rows and runs lost ones again") {
    CHECK(is_final("ok"));
    CHECK(is_final("compile_error"));
    CHECK(is_final("timeout"));
    CHECK_FALSE(is_final("lost"));
    CHECK_FALSE(is_final(""));
}

TEST_CASE("sweep: progress on a terminal is one line rewritten, in a log lines at most every 10 s and the last") {
    std::ostringstream tty;
    Progress on_tty(tty, true, 4, 1, 1);  // --resume kept one run, not ok
    CHECK(on_tty.line(2) == "1/4 runs done, 1 not ok, 2 running, time left not known before the first run ends");
    on_tty.finished(true, 2);
    CHECK(tty.str().rfind("\r\033[Kplant sweep: 2/4 runs done, 1 not ok, 2 running, about ", 0) == 0);
    CHECK(tty.str().find('\n') == std::string::npos);
    on_tty.clear();  // before another message: the line is wiped
    CHECK(tty.str().substr(tty.str().size() - 4) == "\r\033[K");
    on_tty.finished(false, 1);
    on_tty.finished(true, 0);
    CHECK(on_tty.failed() == 2);
    on_tty.end();
    CHECK(tty.str().find("4/4 runs done, 2 not ok, in ") != std::string::npos);
    CHECK(tty.str().back() == '\n');

    std::ostringstream log;
    Progress in_log(log, false, 3, 0, 0);
    in_log.finished(true, 2);
    in_log.tick(2);            // nothing between lines in a log
    in_log.finished(false, 1);  // less than 10 s later: no line
    in_log.finished(true, 0);  // the last: always
    CHECK(log.str().find("\r") == std::string::npos);
    CHECK(log.str().rfind("plant sweep: 1/3 runs done, 0 not ok, 2 running, about ", 0) == 0);
    CHECK(log.str().find("2/3") == std::string::npos);
    CHECK(log.str().find("\nplant sweep: 3/3 runs done, 1 not ok, in ") != std::string::npos);
}

TEST_CASE("sweep: durations for people") {
    CHECK(format_duration(0.4) == "0 s");
    CHECK(format_duration(59) == "59 s");
    CHECK(format_duration(250) == "4 min 10 s");
    CHECK(format_duration(3 * 3600 + 65) == "3 h 01 min");
    CHECK(format_duration(-1) == "?");
}

TEST_CASE("sweep: a warning when every ok run gave the plotted output the same value") {
    Spec s;
    s.run_for = "2 s";
    s.params.push_back({"feed_every", {}, {}});
    s.outputs.push_back({Output::Counter, "rtf", {}});
    s.outputs.push_back({Output::Counter, "commissioned", {}});
    s.outputs.push_back({Output::Counter, "issued", {}});
    std::map<int, std::string> rows = {{0, "0,0,1 s,40.5,0,3,ok,,0.1"},
                                       {1, "1,0,2 s,80.1,0,2,ok,,0.1"},
                                       {2, "2,0,3 s,,,,failed,bad,0.1"}};
    // The plot shows `commissioned` (the first output that is not rtf): 0 in both ok runs.
    const auto w = flat_plot_warning(s, rows);
    REQUIRE(w);
    CHECK(*w == "commissioned is 0 in every run that ended ok (2 runs): a plot of it is flat and shows nothing about "
                "the parameters; is the simulated time per run (2 s, --for) long enough for anything to happen?");
    s.plot = "issued";  // 3 and 2: not flat
    CHECK_FALSE(flat_plot_warning(s, rows));
    rows[1] = "1,0,2 s,80.1,0,3,ok,,0.1";  // 3 in both: flat, but not 0, so no word about --for
    const auto same = flat_plot_warning(s, rows);
    REQUIRE(same);
    CHECK(same->find("issued is 3 in every run") == 0);
    CHECK(same->find("--for") == std::string::npos);
    rows.erase(1);  // one ok run says nothing
    CHECK_FALSE(flat_plot_warning(s, rows));
}
