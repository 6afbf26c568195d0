#include "serve/report.h"

#include "engine/run.h"
#include "engine/times.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cerrno>
#include <cstring>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>

extern char** environ;

namespace plant::view {
namespace {

constexpr std::string_view kBy = "# by ";
constexpr std::string_view kEnd = "# end ";
constexpr std::string_view kDrill = "# drill ";

std::string trim(std::string_view s) { return std::string(engine::trim(s)); }

// Who sent the next event: "# by NAME (ROLE) at WALL", role and wall optional.
struct Meta {
    std::string by, role, wall;
};
Meta parse_meta(std::string_view l) {
    Meta m;
    std::string_view rest = l.substr(kBy.size());
    if (const size_t at = rest.rfind(" at "); at != std::string_view::npos) {
        m.wall = trim(rest.substr(at + 4));
        rest = rest.substr(0, at);
    }
    if (rest.ends_with(')'))
        if (const size_t open = rest.rfind(" ("); open != std::string_view::npos) {
            m.role = trim(rest.substr(open + 2, rest.size() - open - 3));
            rest = rest.substr(0, open);
        }
    m.by = trim(rest);
    return m;
}

// Gathers the session while engine::run replays it.
class Gather : public engine::RunObserver {
public:
    Gather(const graph::Graph& g, Session& s, std::vector<Meta> metas) : g_(g), s_(s), metas_(std::move(metas)) {}
    void started(const engine::Engine& e) override {
        s_.dt = e.dt();
        sample(e);
        // The panels' lamps (runtime/panel): their `state` output, and their label.
        for (const graph::Plugin& p : g_.plugins) {
            if (g_.str(p.kind) != "lamp") continue;
            const graph::Comp& c = g_.comps[p.comp];
            for (graph::SlotId k : graph::children(c.slot_adr, c.slot_num))
                if (g_.str(g_.slots[k].name) == "state") {
                    const std::string label =
                        p.param_num > 0 ? std::string(g_.str(g_.plugin_params[p.param_adr.first()].text)) : "";
                    lamps_.push_back({k, g_.comp_path(p.comp), label, int(e.value(k)[0])});
                }
        }
    }
    void event(const engine::Engine& e, const engine::Event& ev) override {
        SessionEvent se;
        se.time = double(e.steps() + 1) * e.dt();
        se.line = engine::format_event(g_, ev, e.dt());
        se.path = ev.path;
        se.force = ev.force;
        se.mode = ev.mode;
        se.planned = ev.planned;
        if (ev.planned) {
            se.by = "plant file";
        } else if (next_ < metas_.size()) {
            const Meta& m = metas_[next_++];
            se.by = m.by.empty() ? "events file" : m.by;
            se.role = m.role;
            se.wall = m.wall;
        }
        s_.events.push_back(std::move(se));
    }
    void stepped(const engine::Engine& e, const engine::RecordTally&) override {
        if (e.steps() % every_ == 0) sample(e);
        for (Lamp& l : lamps_)
            if (const int now = int(e.value(l.slot)[0]); now != l.state) {
                l.state = now;
                s_.lamps.push_back({e.time(), l.path, l.label, now});
            }
    }
    bool finished(const engine::Engine& e, const engine::RecordTally&, std::string&) override {
        if (s_.samples.empty() || s_.samples.back().time < e.time()) sample(e);
        s_.end = e.time();
        return true;
    }
    void set_every(int64_t steps) { every_ = std::max<int64_t>(steps, 1); }

private:
    void sample(const engine::Engine& e) {
        const engine::MaterialCounts m = engine::material_counts(e);
        s_.samples.push_back({e.time(), m.issued, m.taken, m.on_line, m.lost, m.stalled, m.removed});
    }
    struct Lamp {
        graph::SlotId slot;
        std::string path, label;
        int state = 0;
    };
    const graph::Graph& g_;
    Session& s_;
    std::vector<Meta> metas_;
    std::vector<Lamp> lamps_;
    size_t next_ = 0;
    int64_t every_ = 150;
};

// The sample at or before t (the first one when t is before it).
const SessionSample& at(const Session& s, double t) {
    auto it = std::upper_bound(s.samples.begin(), s.samples.end(), t + 1e-9,
                               [](double x, const SessionSample& p) { return x < p.time; });
    return it == s.samples.begin() ? s.samples.front() : *(it - 1);
}
// Objects taken by the exits per minute between a and b (-1 when the window is under a second).
double rate(const Session& s, double a, double b) {
    if (s.samples.empty() || b - a < 1 - 1e-9) return -1;
    const SessionSample &x = at(s, a), &y = at(s, b);
    return y.time - x.time < 1 - 1e-9 ? -1 : double(y.taken - x.taken) * 60 / (y.time - x.time);
}

void find_faults(Session& s) {
    std::map<std::string, size_t> open;  // path -> its fault
    for (size_t i = 0; i < s.events.size(); ++i) {
        const SessionEvent& ev = s.events[i];
        if (!ev.force) continue;
        if (auto it = open.find(ev.path); it != open.end()) {  // released, or forced anew
            SessionFault& f = s.faults[it->second];
            f.released = ev.time;
            f.released_by = ev.by;
            open.erase(it);
        }
        if (ev.mode == engine::ForceMode::None) continue;
        SessionFault f;
        f.path = ev.path;
        const size_t p = ev.line.find(ev.path);
        f.how = p == std::string::npos ? "" : trim(std::string_view(ev.line).substr(p + ev.path.size()));
        f.set = ev.time;
        f.set_by = ev.by;
        // "drill N" (its repair's release is "drill N repair"): the drill's line as scheduled.
        if (int n = 0; ev.by.starts_with("drill ") && std::sscanf(ev.by.c_str() + 6, "%d", &n) == 1 && n >= 1 &&
                       size_t(n) <= s.drills.size() && !s.drills[size_t(n - 1)].text.empty())
            f.drill = fmt::format("{} {}", n, s.drills[size_t(n - 1)].text);
        open[ev.path] = s.faults.size();
        s.faults.push_back(std::move(f));
    }
    for (SessionFault& f : s.faults) {
        const double end = f.released < 0 ? s.end : f.released;
        const double w = std::min(60.0, f.set);
        f.before = rate(s, f.set - w, f.set);
        f.during = rate(s, f.set, end);
        f.after = f.released < 0 ? -1 : rate(s, f.released, std::min(s.end, f.released + 60));
        f.lost = at(s, end).lost - at(s, f.set).lost;
        for (const SessionSample& x : s.samples)
            if (x.time >= f.set - 1e-9 && x.time <= end + 1e-9) f.stalled = std::max(f.stalled, x.stalled);
        for (size_t i = 0; i < s.events.size(); ++i) {
            const SessionEvent& ev = s.events[i];
            if (ev.planned || ev.time < f.set - 1e-9 || ev.time > end + 1e-9) continue;
            if (ev.force && ev.path == f.path) continue;  // the fault's own set and release
            f.actions.push_back(i);
        }
        for (size_t i = 0; i < s.lamps.size(); ++i)
            if (s.lamps[i].state != 0 && s.lamps[i].time >= f.set - 1e-9 && s.lamps[i].time <= end + 1e-9)
                f.lamps.push_back(i);
    }
}

std::string lamp_text(const SessionLamp& l) {
    const char* how = l.state == 2 ? "blinking" : l.state == 1 ? "lit" : "off";
    return l.label.empty() ? fmt::format("{} {}", l.path, how) : fmt::format("{} ({}) {}", l.path, l.label, how);
}

std::string per_min(double r) { return r < 0 ? "—" : fmt::format("{:.1f}/min", r); }
std::string who(const SessionEvent& ev) { return ev.role.empty() ? ev.by : fmt::format("{} ({})", ev.by, ev.role); }
std::string esc(std::string_view s) {
    std::string out;
    for (char c : s) {
        if (c == '&') out += "&amp;";
        else if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '"') out += "&quot;";
        else out += c;
    }
    return out;
}
// Markdown table cells: a pipe would end the cell.
std::string cell(std::string_view s) {
    std::string out;
    for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
    return out;
}
std::string dash(std::string_view s) { return s.empty() ? "—" : std::string(s); }

// People (events with a role or sent by a page, a link, the command line), in order of their first event.
std::vector<std::string> people(const Session& s) {
    std::vector<std::string> out;
    for (const SessionEvent& ev : s.events)
        if (!ev.planned && std::find(out.begin(), out.end(), who(ev)) == out.end()) out.push_back(who(ev));
    return out;
}

// The report's facts as rows, shared by both renderings.
struct Row {
    std::string key, value;
};
std::vector<Row> fault_rows(const Session& s, const SessionFault& f) {
    const std::string t0 = engine::time_text(f.set, s.dt);
    std::vector<Row> rows = {{"set", fmt::format("{} s by {}", t0, f.set_by)}};
    if (!f.drill.empty()) rows.push_back({"drill", f.drill});
    if (f.released < 0) {
        rows.push_back({"released", fmt::format("not in the session (it ended at {} s, {} s after)",
                                                engine::time_text(s.end, s.dt), engine::time_text(s.end - f.set, s.dt))});
    } else {
        rows.push_back({"released", fmt::format("{} s by {}", engine::time_text(f.released, s.dt), f.released_by)});
        rows.push_back({"diagnosis took", fmt::format("{} s of plant time", engine::time_text(f.released - f.set, s.dt))});
    }
    rows.push_back({"throughput", fmt::format("{} in the minute before, {} while it held, {} in the minute after",
                                              per_min(f.before), per_min(f.during), per_min(f.after))});
    rows.push_back({"lost while it held", std::to_string(f.lost)});
    rows.push_back({"most stalled at once", std::to_string(f.stalled)});
    std::string lit;
    for (size_t i : f.lamps)
        lit += fmt::format("{}{} at {} s", lit.empty() ? "" : "; ", lamp_text(s.lamps[i]), engine::time_text(s.lamps[i].time, s.dt));
    rows.push_back({"lamps that lit", lit.empty() ? "none" : lit});
    return rows;
}

// Each drill and what became of it: the fault it set, an event it fired, its cancellation,
// or nothing yet.
std::vector<Row> drill_rows(const Session& s) {
    std::vector<Row> rows;
    for (size_t i = 0; i < s.drills.size(); ++i) {
        const SessionDrill& d = s.drills[i];
        if (d.text.empty() && d.cancelled < 0) continue;
        const std::string by = fmt::format("drill {}", i + 1);
        std::string what;
        for (size_t k = 0; k < s.faults.size() && what.empty(); ++k)
            if (s.faults[k].set_by == by)
                what = fmt::format("set fault {} at {} s", k + 1, engine::time_text(s.faults[k].set, s.dt));
        for (size_t k = 0; k < s.events.size() && what.empty(); ++k)
            if (s.events[k].by == by)
                what = fmt::format("fired `{}` at {} s", s.events[k].line, engine::time_text(s.events[k].time, s.dt));
        if (what.empty() && d.cancelled >= 0)
            what = fmt::format("cancelled before it fired, at {} s by {}{}", engine::time_text(d.cancelled, s.dt),
                               dash(d.cancelled_by), d.wall.empty() ? "" : " at " + d.wall);
        if (what.empty()) what = "had not fired when the session ended";
        rows.push_back({fmt::format("{}. {}", i + 1, d.text), what});
    }
    return rows;
}

std::string replay_command(const Session& s) {
    return fmt::format("plant run {} --events session.events --for {}s", s.plant, engine::time_text(s.end, s.dt));
}

}  // namespace

std::string session_comment(std::string_view by, std::string_view role, double wall) {
    const auto secs = static_cast<std::time_t>(std::floor(wall));
    const int ms = std::clamp(static_cast<int>(std::lround((wall - std::floor(wall)) * 1000)), 0, 999);
    std::tm tm{};
    gmtime_r(&secs, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
    return role.empty() ? fmt::format("# by {} at {}.{:03}Z", by, buf, ms)
                        : fmt::format("# by {} ({}) at {}.{:03}Z", by, role, buf, ms);
}

std::string session_drill_comment(int number, std::string_view by, std::string_view line) {
    return fmt::format("# drill {} by {}: {}", number, by, line);
}

std::string session_drill_cancel_comment(int number, double time, double dt, std::string_view by,
                                         std::string_view role, double wall) {
    // "# by WHO (ROLE) at WALL" without its "# ".
    return fmt::format("# drill {} cancelled at {}s {}", number, engine::time_text(time, dt),
                       session_comment(by, role, wall).substr(2));
}

std::string session_end_comment(double time, double dt) { return fmt::format("# end {}s", engine::time_text(time, dt)); }

bool replay_session(const graph::Graph& g, const std::string& plant, const std::string& events_path, double until,
                    Session& out, std::string& error) {
    std::ifstream in(events_path, std::ios::binary);
    if (!in) {
        error = fmt::format("{}: cannot read the session's events file", events_path);
        return false;
    }
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return replay_session_text(g, plant, events_path, text, until, out, error);
}

bool replay_session_text(const graph::Graph& g, const std::string& plant, const std::string& events_path,
                         const std::string& text, double until, Session& out, std::string& error) {
    std::istringstream in(text);
    std::vector<SessionDrill> drills;  // "by WHO: LINE", by number - 1
    std::vector<engine::Event> given;  // as engine::load_events reads them
    std::vector<Meta> metas;
    std::vector<std::pair<double, Meta>> timed;
    const engine::SlotIndex slots = engine::slot_index(g);
    Meta pending;
    double end = -1;
    std::string l;
    for (int n = 1; std::getline(in, l); ++n) {
        const std::string t = trim(l);
        if (t.starts_with(kBy)) {
            pending = parse_meta(t);
        } else if (t.starts_with(kDrill)) {  // "# drill N by WHO: LINE", "# drill N cancelled at T by WHO at WALL"
            int number = 0;
            const std::string_view rest = std::string_view(t).substr(kDrill.size());
            auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), number);
            if (ec == std::errc() && number >= 1 && number <= 100000) {
                if (drills.size() < size_t(number)) drills.resize(size_t(number));
                SessionDrill& d = drills[size_t(number - 1)];
                const std::string_view after = engine::trim(std::string_view(end, size_t(rest.data() + rest.size() - end)));
                constexpr std::string_view kCancelled = "cancelled at ";
                if (after.starts_with(kCancelled)) {
                    std::string_view when = after.substr(kCancelled.size());
                    const size_t sp = when.find(' ');
                    double seconds = 0;
                    std::string why;
                    if (!engine::parse_duration(when.substr(0, sp), seconds, why)) {
                        error = fmt::format("{}:{}:1: a drill's cancellation: {}", events_path, n, why);
                        return false;
                    }
                    d.cancelled = seconds;
                    if (sp != std::string_view::npos) {
                        const Meta m = parse_meta("# " + std::string(engine::trim(when.substr(sp))));
                        d.cancelled_by = m.role.empty() ? m.by : fmt::format("{} ({})", m.by, m.role);
                        d.wall = m.wall;
                    }
                } else {
                    d.text = std::string(after);
                }
            }
        } else if (t.starts_with(kEnd)) {
            double seconds = 0;
            std::string why;
            if (!engine::parse_duration(trim(std::string_view(t).substr(kEnd.size())), seconds, why)) {
                error = fmt::format("{}:{}:1: the session's end: {}", events_path, n, why);
                return false;
            }
            end = seconds;
        } else if (!t.empty() && t.front() != '#') {
            // The replay applies the file's events in time order (stable): so do their notes.
            engine::Event ev;
            std::string why;
            if (!engine::parse_event(g, slots, t, ev, why)) {
                error = fmt::format("{}:{}: {}", events_path, n, why);
                return false;
            }
            timed.emplace_back(ev.time, std::move(pending));
            given.push_back(std::move(ev));
            pending = {};
        }
    }
    std::stable_sort(timed.begin(), timed.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (auto& [time, meta] : timed) metas.push_back(std::move(meta));
    if (until > 0) end = until;
    if (end <= 0) {
        error = fmt::format("{}: no '# end TIME' line says when the session ended: give the report's length (--for)",
                            events_path);
        return false;
    }
    out = Session{};
    out.plant = plant;
    Gather gather(g, out, std::move(metas));
    const double rate = g.settings.rate > 0 ? g.settings.rate : 150;
    gather.set_every(std::llround(rate));
    // As `plant run PLANT --events FILE --for END --quiet` runs it.
    engine::RunOptions run;
    run.duration = end;
    run.quiet = true;
    run.events = engine::run_events(g, std::move(given));
    std::ostringstream err;
    if (engine::run(g, run, err, &gather, nullptr, [](const engine::RunSummary&) {}) != 0) {
        error = trim(err.str());
        if (error.empty()) error = fmt::format("{}: the replay failed", events_path);
        return false;
    }
    out.drills = std::move(drills);
    find_faults(out);
    return true;
}

std::string report_markdown(const Session& s, const std::string& plot_png) {
    std::string md = fmt::format("# Session report: {}\n\n", s.plant);
    const SessionSample& last = s.samples.empty() ? SessionSample{} : s.samples.back();
    md += fmt::format("Plant time 0 to {} s; {} events, {} faults. Replayed headless from the session's events file:\n\n"
                      "    {}\n\n",
                      engine::time_text(s.end, s.dt), s.events.size(), s.faults.size(), replay_command(s));
    md += fmt::format("At the end: {} issued, {} taken by the exits, {} on the line, {} lost, {} stalled, {} removed by "
                      "hand; {} a minute over the session.\n\n",
                      last.issued, last.taken, last.on_line, last.lost, last.stalled, last.removed,
                      per_min(rate(s, 0, s.end)));
    if (!plot_png.empty())
        md += fmt::format("![Objects taken per minute, lost and stalled; faults shaded]({})\n\n", plot_png);
    md += "## Faults\n\n";
    if (s.faults.empty()) md += "No slot was forced in the session.\n\n";
    for (size_t k = 0; k < s.faults.size(); ++k) {
        const SessionFault& f = s.faults[k];
        md += fmt::format("### {}. `{}` {}\n\n| | |\n|---|---|\n", k + 1, f.path, f.how);
        for (const Row& r : fault_rows(s, f)) md += fmt::format("| {} | {} |\n", r.key, cell(r.value));
        md += "\n";
        if (f.actions.empty()) {
            md += "Nobody acted while it held.\n\n";
            continue;
        }
        md += "While it held:\n\n| plant time | wall clock | who | event |\n|---|---|---|---|\n";
        for (size_t i : f.actions) {
            const SessionEvent& ev = s.events[i];
            md += fmt::format("| {} s | {} | {} | `{}` |\n", engine::time_text(ev.time, s.dt), dash(ev.wall), cell(who(ev)),
                              cell(ev.line));
        }
        md += "\n";
    }
    if (const std::vector<Row> drills = drill_rows(s); !drills.empty()) {
        md += "## Drills\n\n| drill, as scheduled | what became of it |\n|---|---|\n";
        for (const Row& r : drills) md += fmt::format("| {} | {} |\n", cell(r.key), cell(r.value));
        md += "\n";
    }
    md += "## What each person did\n\n";
    for (const std::string& p : people(s)) {
        md += fmt::format("### {}\n\n| plant time | wall clock | event |\n|---|---|---|\n", p);
        for (const SessionEvent& ev : s.events)
            if (!ev.planned && who(ev) == p)
                md += fmt::format("| {} s | {} | `{}` |\n", engine::time_text(ev.time, s.dt), dash(ev.wall), cell(ev.line));
        md += "\n";
    }
    if (people(s).empty()) md += "Nobody sent an event.\n\n";
    return md;
}

std::string report_html(const Session& s, const std::string& plot_svg) {
    std::string h = fmt::format(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Session report: {0}</title>\n"
        "<style>body{{font-family:'DejaVu Sans',sans-serif;max-width:60em;margin:2em auto;color:#222}}"
        "table{{border-collapse:collapse;margin:.5em 0 1em}}td,th{{border:1px solid #bbb;padding:.2em .5em;"
        "text-align:left;vertical-align:top}}th{{background:#eee}}code{{font-size:.95em}}svg{{max-width:100%;height:auto}}"
        "h3{{page-break-after:avoid}}@media print{{body{{margin:0}}section{{page-break-inside:avoid}}}}</style>\n"
        "</head><body>\n<h1>Session report: {0}</h1>\n",
        esc(s.plant));
    const SessionSample& last = s.samples.empty() ? SessionSample{} : s.samples.back();
    h += fmt::format("<p>Plant time 0 to {} s; {} events, {} faults. Replayed headless from the session's events file: "
                     "<code>{}</code></p>\n",
                     engine::time_text(s.end, s.dt), s.events.size(), s.faults.size(), esc(replay_command(s)));
    h += fmt::format("<p>At the end: {} issued, {} taken by the exits, {} on the line, {} lost, {} stalled, {} removed by "
                     "hand; {} a minute over the session.</p>\n",
                     last.issued, last.taken, last.on_line, last.lost, last.stalled, last.removed,
                     esc(per_min(rate(s, 0, s.end))));
    if (!plot_svg.empty()) {
        const size_t svg = plot_svg.find("<svg");  // without the XML prologue
        h += "<figure>" + (svg == std::string::npos ? plot_svg : plot_svg.substr(svg)) +
             "<figcaption>Objects taken per minute, lost and stalled; faults shaded.</figcaption></figure>\n";
    }
    h += "<h2>Faults</h2>\n";
    if (s.faults.empty()) h += "<p>No slot was forced in the session.</p>\n";
    for (size_t k = 0; k < s.faults.size(); ++k) {
        const SessionFault& f = s.faults[k];
        h += fmt::format("<section><h3>{}. <code>{}</code> {}</h3>\n<table>\n", k + 1, esc(f.path), esc(f.how));
        for (const Row& r : fault_rows(s, f)) h += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", esc(r.key), esc(r.value));
        h += "</table>\n";
        if (f.actions.empty()) {
            h += "<p>Nobody acted while it held.</p></section>\n";
            continue;
        }
        h += "<p>While it held:</p>\n<table><tr><th>plant time</th><th>wall clock</th><th>who</th><th>event</th></tr>\n";
        for (size_t i : f.actions) {
            const SessionEvent& ev = s.events[i];
            h += fmt::format("<tr><td>{} s</td><td>{}</td><td>{}</td><td><code>{}</code></td></tr>\n",
                             engine::time_text(ev.time, s.dt), esc(dash(ev.wall)), esc(who(ev)), esc(ev.line));
        }
        h += "</table></section>\n";
    }
    if (const std::vector<Row> drills = drill_rows(s); !drills.empty()) {
        h += "<h2>Drills</h2>\n<table><tr><th>drill, as scheduled</th><th>what became of it</th></tr>\n";
        for (const Row& r : drills) h += fmt::format("<tr><td>{}</td><td>{}</td></tr>\n", esc(r.key), esc(r.value));
        h += "</table>\n";
    }
    h += "<h2>What each person did</h2>\n";
    for (const std::string& p : people(s)) {
        h += fmt::format("<section><h3>{}</h3>\n<table><tr><th>plant time</th><th>wall clock</th><th>event</th></tr>\n",
                         esc(p));
        for (const SessionEvent& ev : s.events)
            if (!ev.planned && who(ev) == p)
                h += fmt::format("<tr><td>{} s</td><td>{}</td><td><code>{}</code></td></tr>\n",
                                 engine::time_text(ev.time, s.dt), esc(dash(ev.wall)), esc(ev.line));
        h += "</table></section>\n";
    }
    if (people(s).empty()) h += "<p>Nobody sent an event.</p>\n";
    return h + "</body></html>\n";
}

std::string report_plot_data(const Session& s) {
    // Per 10 s of plant time: objects taken per minute over that window, lost so far, stalled now.
    std::string d = "# time_s taken_per_min lost stalled\n";
    const double w = 10;
    for (double t = w; t <= s.end + 1e-9; t += w) {
        const double r = rate(s, t - w, t);
        const SessionSample& x = at(s, t);
        d += fmt::format("{:.3f} {:.3f} {} {}\n", t, r < 0 ? 0 : r, x.lost, x.stalled);
    }
    return d;
}

std::string report_plot_script(const Session& s, const std::string& data, const std::string& stem) {
    std::string body = "set xlabel 'plant time (s)'\nset ylabel 'objects taken per minute'\nset y2label 'objects'\n"
                       "set ytics nomirror\nset y2tics\nset yrange [0:*]\nset y2range [0:1<*]\nset key top left\n"
                       "set grid xtics ytics lc rgb '#dddddd'\n";
    body += fmt::format("set xrange [0:{:.3f}]\n", std::max(s.end, 1.0));
    for (size_t k = 0; k < s.faults.size(); ++k) {
        const SessionFault& f = s.faults[k];
        const double end = f.released < 0 ? s.end : f.released;
        body += fmt::format("set object {} rect from {:.3f}, graph 0 to {:.3f}, graph 1 fc rgb '#f4c7c3' fs solid 0.5 "
                            "noborder behind\nset label {} '{}' at {:.3f}, graph 0.97 left font ',9'\n",
                            k + 1, f.set, std::max(end, f.set + 0.5), k + 1, k + 1, f.set);
    }
    body += fmt::format("plot '{0}' using 1:2 with steps lw 2 lc rgb '#1f77b4' title 'taken per minute', "
                        "'{0}' using 1:3 axes x1y2 with lines lw 2 lc rgb '#d62728' title 'lost', "
                        "'{0}' using 1:4 axes x1y2 with lines lw 2 dt 2 lc rgb '#ff7f0e' title 'stalled'\n",
                        data);
    return fmt::format("set terminal pngcairo size 1000,420 font 'DejaVu Sans,10'\nset output '{0}.png'\n{1}"
                       "set terminal svg size 1000,420 font 'DejaVu Sans,10' background '#ffffff'\nset output '{0}.svg'\n"
                       "replot\nunset output\n",
                       stem, body);
}

bool write_report(const Session& s, const std::string& events_text, const std::string& dir, std::string& error) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) {
        error = fmt::format("{}: cannot create the report's folder: {}", dir, ec.message());
        return false;
    }
    auto put = [&](const std::string& name, const std::string& text) {
        std::ofstream f(fs::path(dir) / name, std::ios::binary);
        f << text;
        if (!f.flush()) error = fmt::format("{}: cannot write", (fs::path(dir) / name).string());
        return bool(f);
    };
    if (!put("session.events", events_text) || !put("throughput.dat", report_plot_data(s)) ||
        !put("throughput.gp", report_plot_script(s, "throughput.dat", "throughput")))
        return false;
    // gnuplot (scripts/setup.sh installs it), in the report's folder.
    bool plotted = false;
    {
        const std::string gp = "gnuplot", script = "throughput.gp";
        std::vector<char*> argv = {const_cast<char*>(gp.c_str()), const_cast<char*>(script.c_str()), nullptr};
        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init(&fa);
        posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
        // Its warnings too ("empty y2 range" when nothing was lost): they would land in the
        // middle of `plant serve`'s log; a plot that fails is said in the report.
        posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_addchdir_np(&fa, dir.c_str());
        pid_t pid = 0;
        if (posix_spawnp(&pid, gp.c_str(), &fa, nullptr, argv.data(), environ) == 0) {
            int status = 0;
            while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
            }
            plotted = WIFEXITED(status) && WEXITSTATUS(status) == 0;
        }
        posix_spawn_file_actions_destroy(&fa);
    }
    std::string svg;
    if (plotted) {
        std::ifstream f(fs::path(dir) / "throughput.svg", std::ios::binary);
        svg.assign(std::istreambuf_iterator<char>(f), {});
    }
    std::string md = report_markdown(s, plotted ? "throughput.png" : "");
    if (!plotted) md += "(No plot: gnuplot did not run; `bash scripts/setup.sh` installs it.)\n";
    return put("report.md", md) && put("report.html", report_html(s, svg));
}

std::string report_page(const Session& s, const std::string& events_text, std::string& error) {
    namespace fs = std::filesystem;
    std::string dir = (fs::temp_directory_path() / "plant-report-XXXXXX").string();
    if (!mkdtemp(dir.data())) {
        error = fmt::format("cannot make a temporary folder for the report: {}", std::strerror(errno));
        return {};
    }
    std::string page;
    if (write_report(s, events_text, dir, error)) {
        std::ifstream f(fs::path(dir) / "report.html", std::ios::binary);
        page.assign(std::istreambuf_iterator<char>(f), {});
        if (page.empty()) error = "the report page could not be read back";
    }
    std::error_code ec;
    fs::remove_all(dir, ec);
    return page;
}

int report_main(const graph::Graph& g, const std::string& plant, const std::string& events_path,
                const std::string& dir, double until, std::ostream& out, std::ostream& err) {
    Session s;
    std::string error;
    if (!replay_session(g, plant, events_path, until, s, error)) {
        err << error << "\n";
        return 1;
    }
    std::ifstream in(events_path, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!write_report(s, text, dir, error)) {
        err << error << "\n";
        return 1;
    }
    out << fmt::format("report: {0}/report.md, {0}/report.html ({1} faults, {2} events, {3} s of plant time)\n", dir,
                       s.faults.size(), s.events.size(), engine::time_text(s.end, s.dt));
    return 0;
}

}  // namespace plant::view
