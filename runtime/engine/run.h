// The `plant run` command on a compiled graph. `args` are the flags after the plant
// file; the summary goes to `out`, progress and errors to `err`.
//
//   --for 10s            simulated time (s, ms, min; default 10s)
//   --rate 150Hz         physics rate (default: the graph's settings.rate)
//   --trace FILE         CSV trace (trace.h); --trace-bodies, --trace-places,
//                        --trace-slots choose the default column groups;
//                        --trace-rate 50Hz samples less often than every step
//   --event "5s DO.comp.slot [value]"   a timed external input (repeatable)
//   --events FILE        one such event per line
//   --realtime           do not run faster than real time
//   --broadphase dbvt|sap
//   --threads N          threads for the physics of a plant in several regions
//                        (default: one per core; results do not depend on it)
//   --quiet              no progress line
//
// Returns 0, or 2 for a bad flag or flag value (with a message on `err`).
#pragma once

#include "engine/engine.h"
#include "engine/run_args.h"
#include "graph/graph.h"

#include <iosfwd>
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
    std::vector<int32_t> void_records_;
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
    virtual std::vector<int32_t> forceable() const { return {}; }
};

int run_main(const graph::Graph& g, const std::vector<std::string>& args, std::ostream& out,
             std::ostream& err, RunObserver* observer = nullptr, RunLink* link = nullptr);

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
