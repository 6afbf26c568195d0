#include "engine/run.h"

#include "engine/engine.h"
#include "engine/interrupt.h"
#include "engine/events.h"
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

// Counts of the plant's void records (events per column, several records of one
// column summed) and the final values of its number records, in declaration order.
// The `records` section: records grouped by column (several records of one column summed);
// void columns count events (from the run's RecordTally), numbers show their final value.
class Tally {
public:
    explicit Tally(const Graph& g) {
        for (Id<Record> r : ids_of(g.records)) {
            const Record& rec = g.records[r];
            const SlotType t = g.slots[rec.slot].type;
            if (t != SlotType::Void && t != SlotType::Bool && t != SlotType::Int && t != SlotType::Real) continue;
            const std::string col(g.str(rec.column));
            auto it = std::find_if(cols_.begin(), cols_.end(), [&](const Column& c) { return c.name == col; });
            if (it == cols_.end()) it = cols_.insert(cols_.end(), Column{col, t == SlotType::Void, {}, {}});
            it->slots.push_back(rec.slot);
            it->records.push_back(index(r));
        }
    }
    void fill(const Engine& e, const RecordTally& counts, std::vector<RunSummary::Record>& out) const {
        for (const Column& c : cols_) {
            RunSummary::Record r{c.name, c.events, 0, 0, 0, c.slots.size() > 1};
            if (c.events) {
                for (size_t x : c.records) r.count += counts.count(x);
                const double minutes = e.time() / 60;
                r.per_minute = minutes > 0 ? double(r.count) / minutes : 0.0;
            } else {
                for (SlotId x : c.slots) r.value += e.value(x)[0];
            }
            out.push_back(std::move(r));
        }
    }

private:
    struct Column {
        std::string name;
        bool events;
        std::vector<SlotId> slots;
        std::vector<size_t> records;
    };
    std::vector<Column> cols_;
};

// The forces of a run (events that force or release a slot), for the summary and the
// trace's `forced` column: each force with the step time it took effect and its end.
class ForceLog {
public:
    // `events`' forces and `more` slots (a link's) may force.
    ForceLog(const std::vector<Event>& events, const std::vector<SlotId>& more) {
        auto add = [&](SlotId s) {
            if (std::find(slots_.begin(), slots_.end(), s) == slots_.end()) slots_.push_back(s);
        };
        for (const Event& ev : events)
            if (ev.force)
                for (SlotId s : ev.slots) add(s);
        for (SlotId s : more) add(s);
    }
    const std::vector<SlotId>& slots() const { return slots_; }
    void applied(const graph::Graph& g, const Event& ev, double at) {
        if (!ev.force) return;
        for (Entry& x : log_)
            if (x.path == ev.path && x.until < 0) x.until = at;
        if (ev.mode != ForceMode::None) log_.push_back({ev.path, force_text(g, ev), at, -1});
    }
    void fill(std::vector<RunSummary::Force>& out) const {
        for (const Entry& x : log_) out.push_back({x.path, x.how, x.from, x.until});
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
    std::vector<SlotId> slots_;
    std::vector<Entry> log_;
};

}  // namespace

RecordTally::RecordTally(const Graph& g) : g_(g), count_(g.records.size(), 0) {
    for (Id<Record> r : ids_of(g.records))
        if (g.slots[g.records[r].slot].type == SlotType::Void) void_records_.push_back(r);
}

void RecordTally::step(const Engine& e) {
    for (Id<Record> r : void_records_) count_[index(r)] += e.active(g_.records[r].slot) ? 1 : 0;
}

void RecordTally::finish(const Engine& e) {
    for (Id<Record> r : void_records_) count_[index(r)] += e.emitted(g_.records[r].slot) ? 1 : 0;
}

void RecordTally::reset() { std::fill(count_.begin(), count_.end(), 0); }

std::vector<double> RecordTally::values(const Engine& e) const {
    std::vector<double> v(g_.records.size(), 0);
    for (Id<Record> r : ids_of(g_.records)) {
        const SlotId sl = g_.records[r].slot;
        const SlotType t = g_.slots[sl].type;
        if (t == SlotType::Void) v[index(r)] = double(count_[index(r)]);
        else if (t == SlotType::Bool || t == SlotType::Int || t == SlotType::Real) v[index(r)] = e.value(sl)[0];
    }
    return v;
}

MaterialCounts material_counts(const Engine& e) {
    const Graph& g = e.graph();
    MaterialCounts m;
    IdVector<DoId, uint8_t> counted(g.dos.count(), 0);
    auto name = [&](std::string& list, int64_t n, DoId d) {
        if (n <= 5) list += (n > 1 ? ", " : "") + std::string(g.str(g.dos[d].path));
        else if (n == 6) list += ", ...";
    };
    for (BodyId b : ids_of(g.bodies)) {
        if (g.bodies[b].mode != BodyMode::Dynamic) continue;
        const DoId d = g.comps[g.bodies[b].comp].owner;
        if (counted[d]) continue;
        if (e.lost_at(d) >= 0) {
            counted[d] = 1;
            name(m.lost_names, ++m.lost, d);
        } else if (e.body_in_world(b)) {
            counted[d] = 1;
            ++m.on_line;
            if (e.stalled_for(b) > 30) name(m.stalled_names, ++m.stalled, d);
        }
    }
    for (SourceId s : ids_of(g.sources)) m.issued += e.issued(s);
    for (ExitId x : ids_of(g.exits)) m.taken += e.taken(x);
    m.removed = e.removed();
    return m;
}

std::string loss_text(const Engine& e, DoId d) {
    const Graph& g = e.graph();
    const Loss& l = e.loss(d);
    auto mm = [](double v) { return std::round(v * 1000) / 1000 + 0.0; };  // no "-0.000"
    const std::string at = fmt::format("at {} s at ({:.3f} {:.3f} {:.3f}) m", time_text(double(l.field_step) * e.dt(), e.dt()),
                                       mm(l.place[0]), mm(l.place[1]), mm(l.place[2]));
    return l.field.valid() ? "off " + g.comp_path(g.fields[l.field].comp) + " " + at : "on no conveyor " + at;
}

namespace {

// What the summary says of a run that has ended (or was stopped) with `e` as it is.
RunSummary summarise(const Engine& e, const Tally& tally, const RecordTally& counts, const ForceLog& forces,
                     double duration, double wall, int stopped_by) {
    const Graph& g = e.graph();
    RunSummary s;
    if (stopped_by) s.interrupted_by = InterruptGuard::name(stopped_by);
    s.duration = duration;
    s.time = e.time();
    s.dt = e.dt();
    s.steps = e.steps();
    s.regions = e.regions();
    s.threads = e.threads();
    s.wall = wall;
    const MaterialCounts m = material_counts(e);
    RunSummary::Objects& o = s.objects;
    o.shown = !(g.sources.empty() && g.exits.empty() && m.lost == 0 && m.on_line == 0);
    if (!g.sources.empty()) o.issued = m.issued;
    if (!g.exits.empty()) o.taken = m.taken;
    o.on_line = m.on_line;
    o.removed = m.removed;
    o.lost = m.lost;
    o.stalled = m.stalled;
    o.lost_names = m.lost_names;
    o.stalled_names = m.stalled_names;
    for (const DoId d : e.lost())
        o.lost_objects.push_back({std::string(g.str(g.dos[d].path)), loss_text(e, d), double(e.loss(d).step) * e.dt()});
    IdVector<DoId, uint8_t> seen(g.dos.count(), 0);
    for (BodyId b : ids_of(g.bodies)) {
        const DoId d = g.comps[g.bodies[b].comp].owner;
        if (g.bodies[b].mode != BodyMode::Dynamic || seen[d] || e.lost_at(d) >= 0) continue;
        if (!e.body_in_world(b)) continue;
        seen[d] = 1;
        if (e.stalled_for(b) > 30) o.stalled_objects.emplace_back(g.str(g.dos[d].path));
    }
    tally.fill(e, counts, s.records);
    const Warnings& w = e.warnings();
    s.warning_counts = {
        {"left_world", "objects that left the world", w.left_world},
        {"nan_state", "objects with a NaN state", w.nan_state},
        {"access_null", "dynamic flows without an object", w.access_null},
        {"access_type", "dynamic flows with an object of another type", w.access_type},
        {"pool_empty", "issues from an empty pool", w.pool_empty},
        {"missed_contacts", "contacts between physics regions not simulated", w.missed_contacts},
        {"out_of_range", "places, velocities or belt speeds out of range, not applied", w.out_of_range},
        {"hand_refused", "hands refused (a body not free to take, an object a gripper holds)", w.hand_refused},
    };
    for (TriggerId t : ids_of(g.triggers))
        if (e.trigger_enters(t) == 0) s.silent_triggers.push_back(g.comp_path(g.triggers[t].comp));
    s.warnings = w.total() + int64_t(s.silent_triggers.size());
    forces.fill(s.forces);
    return s;
}

}  // namespace

int run(const Graph& g, const RunOptions& o, std::ostream& err, RunObserver* observer, RunLink* link,
        const std::function<void(const RunSummary&)>& report) {
    std::string error;
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

    ForceLog forces(o.events, link ? link->forceable() : std::vector<SlotId>{});
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
    report(summarise(e, tally, counts, forces, o.duration, wall(), stopped_by));
    if (!link_error.empty()) {
        fmt::print(err, "plant run: error: {}\n", link_error);
        return 1;
    }
    return stopped_by ? InterruptGuard::exit_code(stopped_by) : 0;
}

}  // namespace plant::engine
