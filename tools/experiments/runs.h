#pragma once
// What the experiments of plant-analyse share: a run (its graph and trace), reading and
// labelling runs, the columns of a trace, writing files and gnuplot scripts. One file per
// experiment (traction.cpp, tipping.cpp, spacing.cpp, rocking.cpp); main.cpp dispatches.
#include "analysis.h"

#include "graph/graph.h"

#include <filesystem>
#include <string>
#include <vector>

namespace plant::analyse {

namespace fs = std::filesystem;
using namespace plant::experiments;

struct Run {
    std::string graph_path, trace_path;
    plant::graph::Graph g;
    Table trace;
    Bottle bottle;
    std::string label, tag;  // legend text ("k = 4 kg/s"), column suffix ("k4")
};

[[noreturn]] void fail(const std::string& msg);
const std::vector<double>& need(const Run& r, const std::string& name);
Vec3 vec_at(const Run& r, const std::string& name, size_t i);
Quat quat_at(const Run& r, const std::string& name, size_t i);
// The physics rate of a run, from its trace (sampled every step: `plant run` without
// --trace-rate), so that a run with `--rate` is analysed at the rate it ran. A trace prints
// its times to a thousandth of a step (docs/runtime.md), so the mean step over the whole run
// gives the rate to far better than the 0.01 Hz it is rounded to.
double rate_of(const Run& r);
double step_of(const Run& r);
double along(const Vec3& v, const Vec3& d);
// The bottle's centre-of-mass speed along its belt, per sample.
std::vector<double> bottle_speed(const Run& r);
std::string num(double x);
// A slip limit per body (N); 0 is none. The experiment plants' 1 kN is never reached: the
// original, unlimited law.
std::string limit_text(double f);
// The same as a legend entry.
std::string limit_label(double f);
std::string fixed(double x, int digits);
Run load(const std::string& graph_path, const std::string& trace_path);
// Legend labels from what differs between the runs (the swept parameter always).
void label_runs(std::vector<Run>& runs, const std::string& primary);
void write_file(const fs::path& p, const std::string& text);
// The sample times the runs share (it fails when they differ).
const std::vector<double>& same_times(const std::vector<Run>& runs);
// The runs of a one-bottle experiment: each run's bottle found, the runs labelled by
// `primary`, their sample times checked to be the same. Returns those times.
const std::vector<double>& bottle_runs(std::vector<Run>& runs, const std::string& primary);
std::string plant_line(const Run& r);
std::string colour(size_t i);
std::string terminals(const std::string& name, const std::string& plot);
// The belts' slip limit a run's bottle starts under (N per body; 0: none).
double slip_limit(const Run& r);

// The experiments: each writes OUTDIR/NAME.csv, NAME.gp and summary.md; returns the exit code.
int traction(const fs::path& out, std::vector<Run>& runs);
int tipping(const fs::path& out, std::vector<Run>& runs);
int spacing(const fs::path& out, std::vector<Run>& runs);
int rocking(const fs::path& out, std::vector<Run>& runs);

}  // namespace plant::analyse
