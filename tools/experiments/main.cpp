// plant-analyse: turns the runs of an experiment plant (plants/experiments) into the
// series CSV, a gnuplot script for the plot and a Markdown summary.
//
//   plant-analyse traction OUTDIR GRAPH TRACE [GRAPH TRACE ...]
//   plant-analyse tipping  OUTDIR GRAPH TRACE [GRAPH TRACE ...]
//   plant-analyse spacing  OUTDIR GRAPH TRACE [GRAPH TRACE ...]   (one run per loop and limit, side by side)
//   plant-analyse rocking  OUTDIR GRAPH TRACE [GRAPH TRACE ...]   (a bottle let go leaning back: rebound per band and tilt)
//
// GRAPH is the compiled plant of one run (`plant build ... -o run.graph`, with the run's
// --set values) and TRACE its `plant run --trace` CSV. Masses, gains and belt speeds are
// read from the graph, never assumed. Writes OUTDIR/NAME.csv, OUTDIR/NAME.gp (run it
// with gnuplot in OUTDIR: NAME.png and NAME.svg) and OUTDIR/summary.md; traction also
// writes OUTDIR/traction_analytic.csv, the law's solution on a fine time grid.
#include "runs.h"

#include <iostream>
#include <string>
#include <system_error>
#include <vector>

using namespace plant::analyse;

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() < 4 || args.size() % 2 != 0) {
        std::cerr << "usage: plant-analyse traction|tipping|spacing|rocking OUTDIR GRAPH TRACE [GRAPH TRACE ...]\n";
        return 2;
    }
    const std::string what = args[0];
    const fs::path out = args[1];
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) fail("cannot create " + out.string());
    std::vector<Run> runs;
    for (size_t i = 2; i + 1 < args.size(); i += 2) runs.push_back(load(args[i], args[i + 1]));
    if (what == "traction") return traction(out, runs);
    if (what == "tipping") return tipping(out, runs);
    if (what == "spacing") return spacing(out, runs);
    if (what == "rocking") return rocking(out, runs);
    std::cerr << "plant-analyse: error: unknown experiment '" << what << "' (traction, tipping, spacing, rocking)\n";
    return 2;
}
