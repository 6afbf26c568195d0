// `plant run`'s own flags (the run's length, rate, trace, events, summary): read into an
// engine::RunOptions with the messages the run has always given for bad values. `plant
// run` adds the plant's and the parts' flags (app/run.cpp); the tests and the golden runner
// run a graph with these alone (run_main).
#pragma once

#include "app/cli.h"
#include "engine/run.h"
#include "graph/graph.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace plant::app {

struct RunFlags {
    std::string duration, rate, trace_rate, trace, broadphase, threads, steady, summary = "text";
    bool trace_bodies = false, trace_places = false, trace_slots = false, realtime = false, quiet = false;
    std::vector<std::string> event, events;
    CLI::Option* event_option = nullptr;
    CLI::Option* events_option = nullptr;
};
void add_run_flags(Cli& cli, RunFlags& f);
// The flags' values for a run of `g` (events parsed against its slots, in command-line
// order, after the plant's own); false with `error`.
bool run_options(const graph::Graph& g, const Cli& cli, const RunFlags& f, engine::RunOptions& o, std::string& error);

// Runs and prints the summary on `out` as text or JSON (`summary`); the exit code.
int run_and_report(const graph::Graph& g, const engine::RunOptions& o, const std::string& summary, std::ostream& out,
                   std::ostream& err, engine::RunObserver* observer, engine::RunLink* link);

// A run of `g` with the flags in `args` (--for 10s ...): errors as "plant run: error: ..."
// on `err` (exit code 2), the summary on `out`.
int run_main(const graph::Graph& g, const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
             engine::RunObserver* observer = nullptr, engine::RunLink* link = nullptr);

}  // namespace plant::app
