// The session report (docs/training.md): what happened in a training session, per fault —
// when it was set and released, what the plant did meanwhile (throughput, objects stalled
// or lost), what each person did and when, how long diagnosis took — as Markdown and a
// printable HTML page with a plot.
//
// The report is computed from the session's events file alone, by replaying it headless
// with `plant run --events` (engine::run): its counters are the replay's, so a report that
// reads right is also the proof that the session replays. The events file carries who sent
// each event and when on the wall clock in comment lines, which a replay ignores:
//
//     # by page 2 (trainee) at 2026-11-27T14:03:05.120Z
//     20.000s force line[0].s2.reader.id open
//     ...
//     # end 312.000s
#pragma once

#include "engine/events.h"
#include "graph/graph.h"

#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace plant::view {

// The comment line put before an event in a session's events file: who sent it (`by`, as
// the page's log says it), their role ("" none: the plant file, the command line, a link)
// and the wall clock (Unix seconds).
std::string session_comment(std::string_view by, std::string_view role, double wall);
// The comment line that says a drill was scheduled (faults/drill.h): its number, who
// scheduled it, its line ("# drill 1 by page 3 (instructor): when … >= 10 force … open").
std::string session_drill_comment(int number, std::string_view by, std::string_view line);
// The comment line that says a waiting drill was cancelled before it fired, at plant time
// `time`, by whom (as session_comment says it): "# drill 2 cancelled at 12.340s by page 1
// (instructor) at 2026-11-27T14:03:05.120Z". A replay skips it: the drill set nothing.
std::string session_drill_cancel_comment(int number, double time, double dt, std::string_view by,
                                         std::string_view role, double wall);
// The comment line that ends a session's events file: the plant time it ended at.
std::string session_end_comment(double time, double dt);

// One event of the session, as applied in the replay.
struct SessionEvent {
    double time = 0;    // plant time it applied at (the end of the step it fed)
    std::string line;   // its events-file line
    std::string path;   // the slot, port or body it addresses
    std::string by;     // who sent it ("plant file" for the plant's own faults)
    std::string role;   // "instructor", "trainee", or "" (the plant file, the command line, a link)
    std::string wall;   // the wall clock, ISO 8601 UTC ("" when the file does not say)
    bool force = false;  // a force (mode not None) or a release (mode None)
    engine::ForceMode mode = engine::ForceMode::None;
    bool planned = false;  // the plant file's own
};

// The plant's material counters, sampled once a second of plant time in the replay.
struct SessionSample {
    double time = 0;
    int64_t issued = 0, taken = 0, on_line = 0, lost = 0, stalled = 0, removed = 0;
};

// A lamp of an operator panel changing state (0 off, 1 on, 2 blinking).
struct SessionLamp {
    double time = 0;
    std::string path, label;
    int state = 0;
};

// A fault: a slot forced from `set` to `released` (-1: still forced at the end).
struct SessionFault {
    std::string path, how, set_by, released_by;
    std::string drill;  // the drill that set it, as scheduled ("1 by page 3 (instructor): when …"; "" none)
    double set = 0, released = -1;
    double before = 0, during = 0, after = 0;  // throughput, objects a minute (-1: no window)
    int64_t lost = 0, stalled = 0;             // lost while it held, most stalled at once
    std::vector<size_t> actions;               // events by others while it held (indices)
    std::vector<size_t> lamps;                 // lamps that lit or blinked while it held (indices)
};

// A drill as the session's events file says it was scheduled (and cancelled).
struct SessionDrill {
    std::string text;          // "by WHO: LINE" ("" a number the file skips)
    double cancelled = -1;     // plant time it was cancelled at (-1: it was not)
    std::string cancelled_by;  // who, with their role ("page 1 (instructor)")
    std::string wall;          // when on the wall clock ("" when the file does not say)
};

struct Session {
    std::string plant;  // the plant file
    double dt = 0, end = 0;
    std::vector<SessionEvent> events;
    std::vector<SessionSample> samples;
    std::vector<SessionLamp> lamps;  // every change of a panel lamp, in time order
    std::vector<SessionFault> faults;
    std::vector<SessionDrill> drills;  // each drill as scheduled, by number - 1
};

// Replays `events_text` (a session's events file; `events_path` names it in messages) on
// the graph up to its `# end` time (or `until` when > 0) and gathers the session. False with
// `error` when the file does not replay (a bad line: the replay's own message).
bool replay_session(const graph::Graph& g, const std::string& plant, const std::string& events_path,
                    double until, Session& out, std::string& error);
// The same from the file's text (`events_path` names it in messages): a served session's
// events so far (`plant serve`'s /report).
bool replay_session_text(const graph::Graph& g, const std::string& plant, const std::string& events_path,
                         const std::string& text, double until, Session& out, std::string& error);

// The report, Markdown (`plot_png`: the plot's file name, "" none) and HTML (`plot_svg`:
// the plot's SVG text, inlined; "" none).
std::string report_markdown(const Session& s, const std::string& plot_png);
std::string report_html(const Session& s, const std::string& plot_svg);
// A gnuplot script drawing throughput, lost and stalled over time with the faults shaded,
// reading `data` (report_plot_data) and writing `stem`.png and `stem`.svg.
std::string report_plot_script(const Session& s, const std::string& data, const std::string& stem);
std::string report_plot_data(const Session& s);

// Writes DIR/report.md, DIR/report.html, DIR/session.events and the plot (gnuplot, when
// installed: DIR/throughput.png and .svg; otherwise the report says so). False with `error`
// when a file cannot be written.
bool write_report(const Session& s, const std::string& events_text, const std::string& dir, std::string& error);

// The printable HTML page with its plot inlined, as write_report makes it (in a temporary
// folder, removed after); "" with `error` when it cannot be made.
std::string report_page(const Session& s, const std::string& events_text, std::string& error);

// `plant report PLANT EVENTS`: replays the session and writes the report into `dir`; says
// where on `out`. Returns 0, or 1 with the message on `err`.
int report_main(const graph::Graph& g, const std::string& plant, const std::string& events_path,
                const std::string& dir, double until, std::ostream& out, std::ostream& err);

}  // namespace plant::view
