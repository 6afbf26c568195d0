// The session report (serve/report.h): computed by replaying a session's events file
// headless, it finds each fault, the throughput before, while and after it held, what each
// person did and when, and how long the diagnosis took.
#include "../compiler/compile_helper.h"

#include "serve/report.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

using namespace plant;

namespace {

// A bottle a second onto a belt whose end takes it: about 60 a minute while the timer ticks.
const char* kLine = R"(
import std.belts, std.bottle, std.stations
plant Line {
    timer t: periodic { period = 1 s; autostart = true }
    feed: Belt(length = 1 m) at (0 m, 0 m, 0 m)
    done: Commissioning at (1.1 m, 0 m, 0 m)
    source store at (0.1 m, 0 m, 0 m) {
        object = Bottle
        pool = 10
    }
    flow t.tick -> store.issue
    panel ops { lamp alarm { label = "Alarm"; color = "red" } }
}
)";

std::string write_events(const std::string& name, const std::string& text) {
    const auto path = test::scratch_dir() / name;
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
}

}  // namespace

TEST_CASE("session report: a fault, what a trainee did while it held, and the throughput dip, from the replay") {
    Compilation c;
    test::compile_text(kLine, c, "report_line.plant");
    INFO(render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    // As plant serve writes it: who sent each event and when on the wall clock, then the end.
    const std::string events = "# events of a plant serve session: plant run FILE --events THIS_FILE replays it\n" +
                               view::session_comment("page 1", "instructor", 1795700000.25) + "\n" +
                               "30.000s force t.tick open\n" +
                               view::session_comment("page 2", "trainee", 1795700012.5) + "\n" +
                               "42.000s t.stop\n" +
                               view::session_comment("page 2", "trainee", 1795700014.0) + "\n" +
                               "44.000s t.start\n" +
                               view::session_comment("page 2", "trainee", 1795700015.0) + "\n" +
                               "45.000s ops.alarm.blink\n" + "90.000s ops.alarm.off\n" +
                               view::session_comment("page 1", "instructor", 1795700030.0) + "\n" +
                               "60.000s release t.tick\n" + view::session_end_comment(120, 1.0 / 150) + "\n";
    CHECK(view::session_comment("page 2", "trainee", 1795700012.5) == "# by page 2 (trainee) at 2026-11-26T13:33:32.500Z");
    const std::string path = write_events("report_session.events", events);
    view::Session s;
    std::string error;
    REQUIRE_MESSAGE(view::replay_session(c.graph, "report_line.plant", path, 0, s, error), error);
    CHECK(s.end == doctest::Approx(120));
    REQUIRE(s.events.size() == 6);
    CHECK(s.events[1].by == "page 2");
    CHECK(s.events[1].role == "trainee");
    CHECK(s.events[1].wall == "2026-11-26T13:33:32.500Z");
    CHECK(s.events[1].time == doctest::Approx(42).epsilon(1e-9));
    REQUIRE(s.faults.size() == 1);
    const view::SessionFault& f = s.faults[0];
    CHECK(f.path == "t.tick");
    CHECK(f.how == "open");
    CHECK(f.set == doctest::Approx(30).epsilon(1e-9));
    CHECK(f.released == doctest::Approx(60).epsilon(1e-9));
    CHECK(f.set_by == "page 1");
    CHECK(f.released_by == "page 1");
    // The trainee's three events, not the fault's own set and release, nor what came after.
    REQUIRE(f.actions.size() == 3);
    // The lamp the trainee set blinking while the fault held, and off after it.
    REQUIRE(s.lamps.size() == 2);
    CHECK(s.lamps[0].path == "ops.alarm");
    CHECK(s.lamps[0].state == 2);
    CHECK(s.lamps[1].state == 0);
    REQUIRE(f.lamps.size() == 1);
    CHECK(s.events[f.actions[0]].line.find("t.stop") != std::string::npos);
    // The dip: about a bottle a second before and after, none while the timer's tick was cut
    // (the bottles already on the belt arrive in its first second or two).
    MESSAGE("throughput before " << f.before << ", during " << f.during << ", after " << f.after << " a minute");
    CHECK(f.before > 45);
    CHECK(f.during < 10);
    CHECK(f.after > 45);
    CHECK(f.lost == 0);
    const std::string md = view::report_markdown(s, "throughput.png");
    CHECK(md.find("### 1. `t.tick` open") != std::string::npos);
    CHECK(md.find("| released | 60.000 s by page 1 |") != std::string::npos);
    CHECK(md.find("| lamps that lit | ops.alarm (Alarm) blinking at 45.000 s |") != std::string::npos);
    CHECK(md.find("| diagnosis took | 30.000 s of plant time |") != std::string::npos);
    CHECK(md.find("| 42.000 s | 2026-11-26T13:33:32.500Z | page 2 (trainee) | `42.000s t.stop` |") != std::string::npos);
    CHECK(md.find("plant run report_line.plant --events session.events --for 120.000s") != std::string::npos);
    const std::string html = view::report_html(s, "<?xml version=\"1.0\"?>\n<svg id=\"plot\"></svg>");
    CHECK(html.find("<svg id=\"plot\">") != std::string::npos);
    CHECK(html.find("<?xml") == std::string::npos);
    CHECK(html.find("<h3>page 2 (trainee)</h3>") != std::string::npos);

    // The files, with the plot when gnuplot is installed (scripts/setup.sh installs it).
    const auto dir = test::scratch_dir() / "report_out";
    std::filesystem::remove_all(dir);
    REQUIRE_MESSAGE(view::write_report(s, events, dir.string(), error), error);
    CHECK(test::slurp((dir / "session.events").string()) == events);
    CHECK(test::slurp((dir / "report.md").string()) .find("### 1. `t.tick` open") != std::string::npos);
    if (std::filesystem::exists("/usr/bin/gnuplot")) {
        CHECK(std::filesystem::file_size(dir / "throughput.png") > 1000);
        CHECK(test::slurp((dir / "report.html").string()).find("<svg") != std::string::npos);
    }
}

TEST_CASE("session report: a session that does not replay, or does not say when it ended, is refused with where") {
    Compilation c;
    test::compile_text(kLine, c, "report_line.plant");
    REQUIRE(c.ok());
    view::Session s;
    std::string error;
    const std::string bad = write_events("report_bad.events", "5.000s t.nothing\n# end 10s\n");
    CHECK_FALSE(view::replay_session(c.graph, "report_line.plant", bad, 0, s, error));
    CHECK(error.find("t.nothing") != std::string::npos);
    const std::string endless = write_events("report_endless.events", "5.000s t.stop\n");
    CHECK_FALSE(view::replay_session(c.graph, "report_line.plant", endless, 0, s, error));
    CHECK(error.find("no '# end TIME' line") != std::string::npos);
    CHECK(view::replay_session(c.graph, "report_line.plant", endless, 8, s, error));
    CHECK(s.end == doctest::Approx(8));
    const std::string bad_end = write_events("report_bad_end.events", "# end soon\n");
    CHECK_FALSE(view::replay_session(c.graph, "report_line.plant", bad_end, 0, s, error));
    CHECK(error.find("report_bad_end.events:1:1: the session's end") != std::string::npos);
}

TEST_CASE("session report: a drill cancelled before it fired is a comment: listed in the report, the replay unchanged") {
    Compilation c;
    test::compile_text(kLine, c, "report_line.plant");
    REQUIRE(c.ok());
    const std::string body = "42.000s t.stop\n";
    const std::string with = view::session_drill_comment(1, "page 1 (instructor)", "50s force t.tick open") + "\n" +
                             view::session_drill_comment(2, "page 1 (instructor)", "now force t.start open") + "\n" +
                             view::session_drill_cancel_comment(1, 12.34, 1.0 / 150, "page 1", "instructor",
                                                                1795700012.5) +
                             "\n" + view::session_comment("page 2", "trainee", 1795700014.0) + "\n" + body +
                             view::session_end_comment(60, 1.0 / 150) + "\n";
    CHECK(view::session_drill_cancel_comment(1, 12.34, 1.0 / 150, "page 1", "instructor", 1795700012.5) ==
          "# drill 1 cancelled at 12.340s by page 1 (instructor) at 2026-11-26T13:33:32.500Z");
    view::Session s, plain;
    std::string error;
    REQUIRE_MESSAGE(view::replay_session_text(c.graph, "report_line.plant", "with.events", with, 0, s, error), error);
    REQUIRE_MESSAGE(view::replay_session_text(c.graph, "report_line.plant", "plain.events", body + "# end 60s\n", 0,
                                              plain, error),
                    error);
    REQUIRE(s.drills.size() == 2);
    CHECK(s.drills[0].text == "by page 1 (instructor): 50s force t.tick open");
    CHECK(s.drills[0].cancelled == doctest::Approx(12.34));
    CHECK(s.drills[0].cancelled_by == "page 1 (instructor)");
    CHECK(s.drills[0].wall == "2026-11-26T13:33:32.500Z");
    CHECK(s.drills[1].cancelled < 0);
    // The replay is the one without the drills: the same events, the same counters.
    REQUIRE(s.events.size() == 1);
    CHECK(s.events[0].by == "page 2");  // the cancellation took no event's "# by" note
    REQUIRE(s.samples.size() == plain.samples.size());
    for (size_t i = 0; i < s.samples.size(); ++i) {
        CHECK(s.samples[i].taken == plain.samples[i].taken);
        CHECK(s.samples[i].issued == plain.samples[i].issued);
    }
    // `plant run --events` reads the file as it reads one without the comments.
    const std::string path = write_events("report_cancel.events", with);
    std::vector<engine::Event> events;
    REQUIRE_MESSAGE(engine::load_events(c.graph, engine::slot_index(c.graph), path, events, error), error);
    CHECK(events.size() == 1);
    const std::string md = view::report_markdown(s, "");
    CHECK(md.find("## Drills") != std::string::npos);
    CHECK(md.find("| 1. by page 1 (instructor): 50s force t.tick open | cancelled before it fired, at 12.340 s by page 1 "
                  "(instructor) at 2026-11-26T13:33:32.500Z |") != std::string::npos);
    CHECK(md.find("| 2. by page 1 (instructor): now force t.start open | had not fired when the session ended |") !=
          std::string::npos);
    CHECK(view::report_html(s, "").find("<h2>Drills</h2>") != std::string::npos);
    // A cancellation whose time does not read is refused with where.
    CHECK_FALSE(view::replay_session_text(c.graph, "report_line.plant", "bad.events", "# drill 1 cancelled at soon\n# end 1s\n",
                                          0, s, error));
    CHECK(error.find("bad.events:1:1: a drill's cancellation") != std::string::npos);
}
