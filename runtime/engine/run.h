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

#include "graph/graph.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace plant::engine {

int run_main(const graph::Graph& g, const std::vector<std::string>& args, std::ostream& out,
             std::ostream& err);

}  // namespace plant::engine
