// A headless run of a compiled graph: `plant run`'s loop (its command line is app/run.cpp).
// The run applies its events through apply_event (events.h), steps the engine, writes the
// trace and hands a summary of what happened to its caller, which prints it as text or JSON.
#pragma once

#include "engine/engine.h"
#include "engine/events.h"
#include "engine/trace.h"
#include "graph/graph.h"

#include <functional>
#include <iosfwd>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace plant::engine {

// Events of the plant's void records so far (one count per record), taken after each step:
// the summary's `records` section, the viewer's status and recordings read the same counts.
class RecordTally {
public:
    explicit RecordTally(const graph::Graph& g);
    void step(const Engine& e);
    // At the end of a run: the events produced in its last step after its logic phase (an
    // issue in phase 5), which no further step will count.
    void finish(const Engine& e);
    void reset();
    int64_t count(size_t record) const { return count_[record]; }
    // One number per record: events so far (void) or the value now (bool, int, real; else 0).
    std::vector<double> values(const Engine& e) const;

private:
    const graph::Graph& g_;
    std::vector<graph::Id<graph::Record>> void_records_;
    std::vector<int64_t> count_;
};

// Watches a run step by step (the recorder of `plant run --record`). Called before the
// first step, for each event as it is applied (before the step it feeds), after each step
// (with the run's record counts), and at the end (false with `error` set: the run fails).
class RunObserver {
public:
    virtual ~RunObserver() = default;
    virtual void started(const Engine& e) = 0;
    virtual void event(const Engine& e, const Event& ev) = 0;
    virtual void stepped(const Engine& e, const RecordTally& tally) = 0;
    virtual bool finished(const Engine& e, const RecordTally& tally, std::string& error) = 0;
};

// An external link that exchanges with the run only at step boundaries (the PLC link's
// Modbus server, plc/server.h). Before each step: wait() (lock-step: until a client grants
// the step; false with `error` ends the run, false without one: a SIGINT / SIGTERM came
// while waiting) and before_step() (what its clients wrote,
// through apply_event, after the step's timed events); after each step: after_step().
// applied() lists the events the last before_step() applied: the run logs their forces in
// its summary and hands them to its observer (a recording), as it does --event's.
class RunLink {
public:
    virtual ~RunLink() = default;
    virtual bool wait(std::string& error) = 0;
    virtual void before_step(Engine& e) = 0;
    virtual std::span<const Event* const> applied() const = 0;
    virtual void after_step(const Engine& e) = 0;
    // The slots its clients can force (the PLC link's fault block): the trace's `forced`
    // column watches them from the start.
    virtual std::vector<graph::SlotId> forceable() const { return {}; }
};

// What a run does, as `plant run`'s flags say it (app/run_flags.h reads them).
struct RunOptions {
    double duration = 10;   // simulated seconds
    double rate = 0;        // physics rate, Hz (0: the graph's settings.rate)
    double trace_rate = 0;  // trace rows per second (0: every step)
    std::string trace;      // the CSV trace's path ("": none)
    TraceSelect select;
    bool realtime = false, quiet = false;
    Broadphase broadphase = Broadphase::Dbvt;
    int threads = 0;
    bool steady = true;  // steady transport (Options::steady_transport)
    std::vector<Event> events;  // sorted by time: the plant's own first at equal times
};

// Everything a run's summary says, for people (app/summary.cpp prints it as text) and for
// programs (`plant run --summary=json`, docs/runtime.md "The summary as JSON").
struct RunSummary {
    std::string interrupted_by;  // "SIGINT"... ("": the run went to its end)
    double duration = 0;         // the simulated time asked for, s
    double time = 0, dt = 0;     // simulated time reached, step length (s)
    int64_t steps = 0;
    int regions = 1, threads = 1;
    double wall = 0;  // s
    struct Lost {
        std::string object, where;  // loss_text
        double left_at = 0;         // s, when it left the world
    };
    struct Objects {
        bool shown = false;  // the plant has sources or exits, or objects with dynamic bodies
        std::optional<int64_t> issued, taken;  // only with sources, exits
        int64_t on_line = 0, removed = 0, lost = 0, stalled = 0;
        std::string lost_names, stalled_names;  // the first few (MaterialCounts)
        std::vector<Lost> lost_objects;         // every lost object, in the order lost
        std::vector<std::string> stalled_objects;
    } objects;
    struct Record {
        std::string column;
        bool events = false;  // void records: an event count; else the final value
        int64_t count = 0;
        double per_minute = 0, value = 0;
        bool sum = false;  // several records of one column
    };
    std::vector<Record> records;
    struct Warning {
        const char* key;   // "left_world" (JSON)
        const char* text;  // "objects that left the world"
        int64_t count;
    };
    int64_t warnings = 0;            // the total, silent triggers included
    std::vector<Warning> warning_counts;   // every kind, 0 included
    std::vector<std::string> silent_triggers;  // triggers that never fired
    struct Force {
        std::string path, how;
        double from = 0, until = -1;  // s; -1: to the end
    };
    std::vector<Force> forces;
};

// Runs `g` as `o` says. Before the run ends badly or well, `report` gets the summary (not
// when the run could not start). Returns 0, 2 for options the graph cannot run (a trace
// that cannot be written, too many steps), 1 when the trace, the observer or the link
// failed, or InterruptGuard's code after SIGINT / SIGTERM. Errors go to `err`, as
// "plant run: error: ...", and the progress line.
int run(const graph::Graph& g, const RunOptions& o, std::ostream& err, RunObserver* observer, RunLink* link,
        const std::function<void(const RunSummary&)>& report);

// Objects with dynamic bodies: issued by sources, taken by exits, on the line, lost (left
// the world), stalled over 30 s (the first few names of the last two), removed by hand
// (`remove` events: back in their pool, not lost).
struct MaterialCounts {
    int64_t issued = 0, taken = 0, on_line = 0, lost = 0, stalled = 0, removed = 0;
    std::string lost_names, stalled_names;
};
MaterialCounts material_counts(const Engine& e);

// Where a lost object left the line (Engine::loss), for people, without commas (a trace's
// cell): "off feed.drive at 76.413 s at (-1.251 -0.114 0.050) m", the last conveyor field it
// rode, the time it was last in it and its centre of mass then; or "on no conveyor at 12.007 s
// at (0.100 0.000 -10.002) m", where it left the world.
std::string loss_text(const Engine& e, graph::DoId object);

}  // namespace plant::engine
