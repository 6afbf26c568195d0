#include "engine/run.h"

#include "engine/engine.h"
#include "engine/interrupt.h"
#include "engine/run_args.h"
#include "engine/trace.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <memory>
#include <ostream>
#include <thread>

namespace plant::engine {

using namespace plant::graph;

namespace {

struct RunOptions {
    double duration = 10, rate = 0, trace_rate = 0;
    std::string trace;
    TraceSelect select;
    bool realtime = false, quiet = false;
    Broadphase broadphase = Broadphase::Dbvt;
    int threads = 0;
    bool steady = true;
    std::vector<Event> events;
};

bool parse_args(const Graph& g, const std::vector<std::string>& args, RunOptions& o, std::string& error) {
    SlotIndex slots;
    auto value = [&](size_t& i, std::string& v) {
        if (i + 1 >= args.size()) {
            error = fmt::format("{} needs a value", args[i]);
            return false;
        }
        v = args[++i];
        return true;
    };
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        std::string v;
        if (a == "--for") {
            if (!value(i, v) || !parse_duration(v, o.duration, error)) return false;
        } else if (a == "--rate") {
            if (!value(i, v) || !parse_frequency(v, o.rate, error)) return false;
            if (o.rate < graph::kMinRate || o.rate > graph::kMaxRate) {
                error = fmt::format("--rate {}: the physics rate must lie between 1 Hz and 1 MHz", v);
                return false;
            }
        } else if (a == "--trace-rate") {
            if (!value(i, v) || !parse_frequency(v, o.trace_rate, error)) return false;
            if (o.trace_rate > graph::kMaxRate) {
                error = fmt::format("--trace-rate {}: at most 1 MHz", v);
                return false;
            }
        } else if (a == "--trace") {
            if (!value(i, o.trace)) return false;
        } else if (a == "--trace-bodies") {
            o.select.bodies = true;
        } else if (a == "--trace-places") {
            o.select.places = true;
        } else if (a == "--trace-slots") {
            o.select.slots = true;
        } else if (a == "--realtime") {
            o.realtime = true;
        } else if (a == "--quiet") {
            o.quiet = true;
        } else if (a == "--broadphase") {
            if (!value(i, v)) return false;
            if (v == "dbvt") o.broadphase = Broadphase::Dbvt;
            else if (v == "sap") o.broadphase = Broadphase::Sap;
            else {
                error = fmt::format("--broadphase: '{}' is neither dbvt nor sap", v);
                return false;
            }
        } else if (a == "--threads") {
            if (!value(i, v)) return false;
            char* end = nullptr;
            const long n = std::strtol(v.c_str(), &end, 10);
            if (v.empty() || *end || n < 1 || n > 256) {
                error = fmt::format("--threads: '{}' is not a number of threads from 1 to 256", v);
                return false;
            }
            o.threads = int(n);
        } else if (a == "--steady-transport") {
            if (!value(i, v)) return false;
            if (v != "on" && v != "off") {
                error = fmt::format("--steady-transport: '{}' is neither on nor off", v);
                return false;
            }
            o.steady = v == "on";
        } else if (a == "--event" || a == "--events") {
            if (!value(i, v)) return false;
            if (slots.empty()) slots = slot_index(g);
            if (a == "--events") {
                if (!load_events(g, slots, v, o.events, error)) return false;
            } else {
                Event ev;
                if (!parse_event(g, slots, v, ev, error)) return false;
                o.events.push_back(std::move(ev));
            }
        } else {
            error = fmt::format("unknown flag '{}'", a);
            return false;
        }
    }
    // The plant file's own timed inputs first: at equal times the command line's come after
    // them (a later force of the same slot wins), in their command-line order.
    std::vector<Event> planned = plant_events(g);
    o.events.insert(o.events.begin(), std::make_move_iterator(planned.begin()), std::make_move_iterator(planned.end()));
    std::stable_sort(o.events.begin(), o.events.end(),
                     [](const Event& x, const Event& y) { return x.time < y.time; });
    return true;
}

// Counts of the plant's void records (events per column, several records of one
// column summed) and the final values of its number records, in declaration order.
// The `records` section: records grouped by column (several records of one column summed);
// void columns count events (from the run's RecordTally), numbers show their final value.
class Tally {
public:
    explicit Tally(const Graph& g) {
        for (size_t r = 0; r < g.records.size(); ++r) {
            const Record& rec = g.records[r];
            const SlotType t = g.slots[rec.slot].type;
            if (t != SlotType::Void && t != SlotType::Bool && t != SlotType::Int && t != SlotType::Real) continue;
            const std::string col(g.str(rec.column));
            auto it = std::find_if(cols_.begin(), cols_.end(), [&](const Column& c) { return c.name == col; });
            if (it == cols_.end()) it = cols_.insert(cols_.end(), Column{col, t == SlotType::Void, {}, {}});
            it->slots.push_back(rec.slot);
            it->records.push_back(r);
        }
    }
    void print(const Engine& e, const RecordTally& counts, std::ostream& out) const {
        if (cols_.empty()) return;
        size_t width = 0;
        for (const Column& c : cols_) width = std::max(width, c.name.size());
        fmt::print(out, "records:\n");
        for (const Column& c : cols_) {
            if (c.events) {
                int64_t count = 0;
                for (size_t r : c.records) count += counts.count(r);
                const double minutes = e.time() / 60;
                fmt::print(out, "  {:<{}}  {} events ({:.1f} per minute)\n", c.name, width, count,
                           minutes > 0 ? double(count) / minutes : 0.0);
                continue;
            }
            double sum = 0;
            for (int32_t x : c.slots) sum += e.value(SlotId(x))[0];
            fmt::print(out, "  {:<{}}  {:g}{}\n", c.name, width, sum, c.slots.size() > 1 ? " (sum)" : "");
        }
    }

private:
    struct Column {
        std::string name;
        bool events;
        std::vector<int32_t> slots;
        std::vector<size_t> records;
    };
    std::vector<Column> cols_;
};

// The forces of a run (events that force or release a slot), for the summary and the
// trace's `forced` column: each force with the step time it took effect and its end.
class ForceLog {
public:
    // `events`' forces and `more` slots (a link's) may force.
    ForceLog(const std::vector<Event>& events, const std::vector<int32_t>& more) {
        auto add = [&](int32_t s) {
            if (std::find(slots_.begin(), slots_.end(), s) == slots_.end()) slots_.push_back(s);
        };
        for (const Event& ev : events)
            if (ev.force)
                for (int32_t s : ev.slots) add(s);
        for (int32_t s : more) add(s);
    }
    const std::vector<int32_t>& slots() const { return slots_; }
    void applied(const graph::Graph& g, const Event& ev, double at) {
        if (!ev.force) return;
        for (Entry& x : log_)
            if (x.path == ev.path && x.until < 0) x.until = at;
        if (ev.mode != ForceMode::None) log_.push_back({ev.path, force_text(g, ev), at, -1});
    }
    void print(const Engine& e, std::ostream& out) const {
        if (log_.empty()) return;
        size_t width = 0;
        for (const Entry& x : log_) width = std::max(width, x.path.size());
        fmt::print(out, "forced:           {}\n", log_.size());
        for (const Entry& x : log_)
            fmt::print(out, "  {:<{}}  {:<14}  from {} s to {}\n", x.path, width, x.how, time_text(x.from, e.dt()),
                       x.until < 0 ? fmt::format("the end ({} s)", time_text(e.time(), e.dt()))
                                   : fmt::format("{} s", time_text(x.until, e.dt())));
    }

private:
    // "stuck VALUE", "open", "invert": the force as its events-file line says it.
    static std::string force_text(const graph::Graph& g, const Event& ev) {
        const std::string line = format_event(g, ev);
        const size_t at = line.find(" " + ev.path + " ");
        return at == std::string::npos ? line : line.substr(at + ev.path.size() + 2);
    }
    struct Entry {
        std::string path, how;
        double from, until;
    };
    std::vector<int32_t> slots_;
    std::vector<Entry> log_;
};

}  // namespace

RecordTally::RecordTally(const Graph& g) : g_(g), count_(g.records.size(), 0) {
    for (size_t r = 0; r < g.records.size(); ++r)
        if (g.slots[size_t(g.records[r].slot)].type == SlotType::Void) void_records_.push_back(int32_t(r));
}

void RecordTally::step(const Engine& e) {
    for (int32_t r : void_records_) count_[size_t(r)] += e.active(g_.records[size_t(r)].slot) ? 1 : 0;
}

void RecordTally::finish(const Engine& e) {
    for (int32_t r : void_records_) count_[size_t(r)] += e.emitted(g_.records[size_t(r)].slot) ? 1 : 0;
}

void RecordTally::reset() { std::fill(count_.begin(), count_.end(), 0); }

std::vector<double> RecordTally::values(const Engine& e) const {
    std::vector<double> v(g_.records.size(), 0);
    for (size_t r = 0; r < g_.records.size(); ++r) {
        const int32_t sl = g_.records[r].slot;
        const SlotType t = g_.slots[size_t(sl)].type;
        if (t == SlotType::Void) v[r] = double(count_[r]);
        else if (t == SlotType::Bool || t == SlotType::Int || t == SlotType::Real) v[r] = e.value(SlotId(sl))[0];
    }
    return v;
}

MaterialCounts material_counts(const Engine& e) {
    const Graph& g = e.graph();
    MaterialCounts m;
    std::vector<uint8_t> counted(g.dos.size(), 0);
    auto name = [&](std::string& list, int64_t n, int32_t d) {
        if (n <= 5) list += (n > 1 ? ", " : "") + std::string(g.str(g.dos[size_t(d)].path));
        else if (n == 6) list += ", ...";
    };
    for (size_t b = 0; b < g.bodies.size(); ++b) {
        if (g.bodies[b].mode != BodyMode::Dynamic) continue;
        const int32_t d = g.comps[g.bodies[b].comp].owner;
        if (counted[d]) continue;
        if (e.lost_at(DoId(d)) >= 0) {
            counted[d] = 1;
            name(m.lost_names, ++m.lost, d);
        } else if (e.body_in_world(BodyId(int32_t(b)))) {
            counted[d] = 1;
            ++m.on_line;
            if (e.stalled_for(BodyId(int32_t(b))) > 30) name(m.stalled_names, ++m.stalled, d);
        }
    }
    for (size_t s = 0; s < g.sources.size(); ++s) m.issued += e.issued(SourceId(int32_t(s)));
    for (size_t x = 0; x < g.exits.size(); ++x) m.taken += e.taken(ExitId(int32_t(x)));
    m.removed = e.removed();
    return m;
}

std::string loss_text(const Engine& e, DoId d) {
    const Graph& g = e.graph();
    const Loss& l = e.loss(d);
    auto mm = [](double v) { return std::round(v * 1000) / 1000 + 0.0; };  // no "-0.000"
    const std::string at = fmt::format("at {} s at ({:.3f} {:.3f} {:.3f}) m", time_text(double(l.field_step) * e.dt(), e.dt()),
                                       mm(l.place[0]), mm(l.place[1]), mm(l.place[2]));
    return l.field.valid() ? "off " + g.comp_path(g.fields[size_t(l.field)].comp) + " " + at : "on no conveyor " + at;
}

namespace {

// The lost objects, one a line in the order lost, up to this many.
constexpr size_t kLossLines = 20;

// Objects with dynamic bodies: issued, taken, lost, on the line, stalled.
void material(const Engine& e, std::ostream& out) {
    const Graph& g = e.graph();
    const MaterialCounts m = material_counts(e);
    if (g.sources.empty() && g.exits.empty() && m.lost == 0 && m.on_line == 0) return;
    fmt::print(out, "objects:\n");
    if (!g.sources.empty()) fmt::print(out, "  issued by sources:     {}\n", m.issued);
    if (!g.exits.empty()) fmt::print(out, "  taken by exits:        {}\n", m.taken);
    fmt::print(out, "  on the line:           {}\n", m.on_line);
    if (m.removed) fmt::print(out, "  removed by hand:       {}\n", m.removed);
    fmt::print(out, "  lost (left the world): {}{}\n", m.lost, m.lost ? " (" + m.lost_names + ")" : "");
    const std::span<const DoId> lost = e.lost();
    for (size_t i = 0; i < lost.size() && i < kLossLines; ++i)
        fmt::print(out, "    {}: {}; left the world at {} s\n", g.str(g.dos[size_t(lost[i])].path), loss_text(e, lost[i]),
                   time_text(double(e.loss(lost[i]).step) * e.dt(), e.dt()));
    if (lost.size() > kLossLines) fmt::print(out, "    ... and {} more\n", lost.size() - kLossLines);
    fmt::print(out, "  stalled over 30 s:     {}{}\n", m.stalled, m.stalled ? " (" + m.stalled_names + ")" : "");
}

void summary(const Engine& e, const Tally& tally, const RecordTally& counts, double wall, std::ostream& out) {
    const Graph& g = e.graph();
    const Warnings& w = e.warnings();
    std::vector<std::string> silent;
    for (size_t t = 0; t < g.triggers.size(); ++t)
        if (e.trigger_enters(TriggerId(int32_t(t))) == 0) silent.push_back(g.comp_path(g.triggers[t].comp));
    fmt::print(out, "simulated time:   {} s\n", time_text(e.time(), e.dt()));
    fmt::print(out, "steps:            {} at {:g} Hz\n", e.steps(), 1.0 / e.dt());
    if (e.regions() > 1)
        fmt::print(out, "physics regions:  {} (a Bullet world each), on {} thread{}\n", e.regions(), e.threads(),
                   e.threads() == 1 ? "" : "s");
    fmt::print(out, "wall time:        {:.3f} s\n", wall);
    fmt::print(out, "real-time factor: {:.1f}\n", wall > 0 ? e.time() / wall : 0.0);
    material(e, out);
    tally.print(e, counts, out);
    fmt::print(out, "warnings:         {}\n", w.total() + int64_t(silent.size()));
    auto line = [&](const char* what, int64_t n) {
        if (n) fmt::print(out, "  {}: {}\n", what, n);
    };
    line("objects that left the world", w.left_world);
    line("objects with a NaN state", w.nan_state);
    line("dynamic flows without an object", w.access_null);
    line("dynamic flows with an object of another type", w.access_type);
    line("issues from an empty pool", w.pool_empty);
    line("contacts between physics regions not simulated", w.missed_contacts);
    line("places, velocities or belt speeds out of range, not applied", w.out_of_range);
    line("hands refused (a body not free to take, an object a gripper holds)", w.hand_refused);
    if (!silent.empty()) {
        std::string names;
        for (size_t i = 0; i < silent.size() && i < 5; ++i) names += (i ? ", " : "") + silent[i];
        if (silent.size() > 5) names += ", ...";
        fmt::print(out, "  triggers that never fired: {} ({})\n", silent.size(), names);
    }
}

}  // namespace

int run_main(const Graph& g, const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
             RunObserver* observer, RunLink* link) {
    RunOptions o;
    std::string error;
    if (!parse_args(g, args, o, error)) {
        fmt::print(err, "plant run: error: {}\n", error);
        return 2;
    }
    std::ofstream trace_file;
    if (!o.trace.empty()) {
        trace_file.open(o.trace, std::ios::binary);
        if (!trace_file) {
            fmt::print(err, "plant run: error: --trace: cannot write '{}'\n", o.trace);
            return 2;
        }
    }

    Options eo;
    eo.rate = o.rate;
    eo.broadphase = o.broadphase;
    eo.threads = o.threads;
    eo.steady_transport = o.steady;
    Engine e(g, eo);
    Tally tally(g);
    RecordTally counts(g);

    ForceLog forces(o.events, link ? link->forceable() : std::vector<int32_t>{});
    std::unique_ptr<TraceWriter> trace;
    if (trace_file.is_open()) {
        std::vector<TraceColumn> columns = trace_columns(g, o.select);
        if (can_lose(g)) columns.push_back(lost_column());
        if (!forces.slots().empty()) columns.push_back(forced_column(forces.slots()));
        trace = std::make_unique<TraceWriter>(e, std::move(columns), trace_file);
        trace->header();
        trace->row();
    }
    const double step_count = std::ceil(o.duration / e.dt() - 1e-9);
    if (!(step_count < 1e18)) {
        fmt::print(err, "plant run: error: --for {:g}s: more than 1e18 steps at {:g} Hz\n", o.duration, 1.0 / e.dt());
        return 2;
    }
    const int64_t steps = int64_t(step_count);
    for (const Event& ev : o.events)
        if (!ev.planned && ev.time > double(steps) * e.dt() + time_slack(e.dt()))  // the plant's own: a shorter run is fine
            fmt::print(err, "plant run: warning: the event '{}' is after the end of the run ({} s): it is never applied\n",
                       format_event(g, ev, e.dt()), time_text(double(steps) * e.dt(), e.dt()));
    if (observer) observer->started(e);
    // A trace row every `every` steps; a rate far below one row per run gives the first and last rows.
    const double every_steps = o.trace_rate > 0 ? std::round(1.0 / (o.trace_rate * e.dt())) : 1;
    const int64_t every = every_steps < 1 ? 1 : every_steps > 1e18 ? int64_t(1e18) : int64_t(every_steps);

    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto wall = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    double next_progress = 2.0;  // only runs longer than ~2 s of wall time report progress
    bool progressed = false;
    size_t next_event = 0;
    InterruptGuard interrupt;
    int stopped_by = 0;
    std::string link_error;
    for (int64_t i = 0; i < steps; ++i) {
        stopped_by = InterruptGuard::requested();
        const bool link_failed = !stopped_by && link && !link->wait(link_error);
        if (link_failed && link_error.empty()) stopped_by = InterruptGuard::requested();  // while waiting
        if (stopped_by || link_failed) {  // the step that ran last ends the run
            if (i > 0) counts.finish(e);
            if (trace && i > 0) trace->finish();
            if (trace && e.steps() % every != 0) trace->row();
            break;
        }
        const double t_next = double(e.steps() + 1) * e.dt();
        for (; next_event < o.events.size() && due(e, o.events[next_event]); ++next_event) {
            apply_event(e, o.events[next_event]);
            forces.applied(g, o.events[next_event], t_next);
            if (observer) observer->event(e, o.events[next_event]);
        }
        if (link) {
            link->before_step(e);
            for (const Event* ev : link->applied()) {
                forces.applied(g, *ev, t_next);
                if (observer) observer->event(e, *ev);
            }
        }
        e.step();
        if (link) link->after_step(e);
        counts.step(e);
        if (trace) trace->step();
        if (i + 1 == steps) {  // what the last step produced after its logic phase counts too
            counts.finish(e);
            if (trace) trace->finish();
        }
        if (observer) observer->stepped(e, counts);
        if (trace && (e.steps() % every == 0 || i + 1 == steps)) trace->row();
        if ((i & 63) != 63 && !o.realtime) continue;
        const double w = wall();
        if (o.realtime && e.time() > w) std::this_thread::sleep_for(std::chrono::duration<double>(e.time() - w));
        if (!o.quiet && w >= next_progress) {
            fmt::print(err, "\rplant: {:.1f} s of {:g} s simulated, {:.1f}x real time   ", e.time(), o.duration,
                       e.time() / w);
            err.flush();
            next_progress = w + 1.0;
            progressed = true;
        }
    }
    if (progressed) fmt::print(err, "\n");
    if (trace) {
        trace->flush();
        if (!trace_file.flush()) {  // a full disk or /dev/full: the trace asked for is not there
            fmt::print(err, "plant run: error: --trace: writing '{}' failed\n", o.trace);
            return 1;
        }
    }
    if (observer && !observer->finished(e, counts, error)) {
        fmt::print(err, "plant run: error: {}\n", error);
        return 1;
    }
    if (stopped_by)
        fmt::print(out, "interrupted:      by {} after {} s of {:g} s\n", InterruptGuard::name(stopped_by), time_text(e.time(), e.dt()),
                   o.duration);
    summary(e, tally, counts, wall(), out);
    forces.print(e, out);
    if (!link_error.empty()) {
        fmt::print(err, "plant run: error: {}\n", link_error);
        return 1;
    }
    return stopped_by ? InterruptGuard::exit_code(stopped_by) : 0;
}

}  // namespace plant::engine
