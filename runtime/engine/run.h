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
#include <string>
#include <vector>

namespace plant::engine {

// Watches a run step by step (the recorder of `plant run --record`). Called before the
// first step, for each event as it is applied (before the step it feeds), after each step,
// and at the end (false with `error` set: the run fails).
class RunObserver {
public:
    virtual ~RunObserver() = default;
    virtual void started(const Engine& e) = 0;
    virtual void event(const Engine& e, const Event& ev) = 0;
    virtual void stepped(const Engine& e) = 0;
    virtual bool finished(const Engine& e, std::string& error) = 0;
};

int run_main(const graph::Graph& g, const std::vector<std::string>& args, std::ostream& out,
             std::ostream& err, RunObserver* observer = nullptr);

// Objects with dynamic bodies: issued by sources, taken by exits, on the line, lost (left
// the world), stalled over 30 s (the first few names of the last two).
struct MaterialCounts {
    int64_t issued = 0, taken = 0, on_line = 0, lost = 0, stalled = 0;
    std::string lost_names, stalled_names;
};
MaterialCounts material_counts(const Engine& e);

}  // namespace plant::engine
