// What the experiments of plant-analyse share (runs.h).
#include "runs.h"

#include "graph/text.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace plant::analyse {

[[noreturn]] void fail(const std::string& msg) {
    std::cerr << "plant-analyse: error: " << msg << "\n";
    std::exit(1);
}

const std::vector<double>& need(const Run& r, const std::string& name) {
    const std::vector<double>* c = r.trace.col(name);
    if (!c) fail(fmt::format("{}: no column '{}' (does the plant record it?)", r.trace_path, name));
    return *c;
}

Vec3 vec_at(const Run& r, const std::string& name, size_t i) {
    return {need(r, name + ".x")[i], need(r, name + ".y")[i], need(r, name + ".z")[i]};
}
Quat quat_at(const Run& r, const std::string& name, size_t i) {
    return {need(r, name + ".qx")[i], need(r, name + ".qy")[i], need(r, name + ".qz")[i], need(r, name + ".qw")[i]};
}
// The physics rate of a run, from its trace (sampled every step: `plant run` without
// --trace-rate), so that a run with `--rate` is analysed at the rate it ran. A trace prints
// its times to a thousandth of a step (docs/runtime.md), so the mean step over the whole run
// gives the rate to far better than the 0.01 Hz it is rounded to.
double rate_of(const Run& r) {
    const std::vector<double>& t = *r.trace.col("time");
    const double step = (t.back() - t.front()) / double(t.size() - 1);
    return std::round(1 / step * 100) / 100;
}
double step_of(const Run& r) { return 1 / rate_of(r); }

double along(const Vec3& v, const Vec3& d) { return v[0] * d[0] + v[1] * d[1] + v[2] * d[2]; }

// The bottle's centre-of-mass speed along its belt, per sample.
std::vector<double> bottle_speed(const Run& r) {
    const Bottle& b = r.bottle;
    std::vector<double> v(r.trace.rows());
    for (size_t i = 0; i < v.size(); ++i)
        v[i] = (b.m_main * along(vec_at(r, "main.v", i), b.belt_dir) +
                b.m_bottom * along(vec_at(r, "bottom.v", i), b.belt_dir)) / b.mass();
    return v;
}

std::string num(double x) { return fmt::format("{:g}", x); }
// A slip limit per body (N); 0 is none. The experiment plants' 1 kN is never reached: the
// original, unlimited law.
std::string limit_text(double f) {
    if (f == 0) return "none";
    return f >= 100 ? fmt::format("unlimited ({:g} N)", f) : fmt::format("{:g} N", f);
}
// The same as a legend entry.
std::string limit_label(double f) { return f == 0 || f >= 100 ? "unlimited law" : fmt::format("slip limit {:g} N", f); }
std::string fixed(double x, int digits) {
    if (std::isnan(x)) return "—";
    return fmt::format("{:.{}f}", x, digits);
}

Run load(const std::string& graph_path, const std::string& trace_path) {
    Run r;
    r.graph_path = graph_path;
    r.trace_path = trace_path;
    std::string err;
    if (!plant::graph::load_text_file(graph_path, r.g, err)) fail(err);
    if (!read_csv_file(trace_path, r.trace, err)) fail(err);
    if (!r.trace.col("time") || r.trace.rows() < 2) fail(trace_path + ": no time series");
    return r;
}

// Legend labels from what differs between the runs (the swept parameter always).
void label_runs(std::vector<Run>& runs, const std::string& primary) {
    auto differs = [&](auto get) {
        return std::any_of(runs.begin(), runs.end(), [&](const Run& r) { return get(r) != get(runs[0]); });
    };
    auto k = [](const Run& r) { return r.g.fields[graph::FieldId(r.bottle.field)].gain; };
    auto m = [](const Run& r) { return r.bottle.mass(); };
    auto v = [](const Run& r) { return r.bottle.belt_speed; };
    auto f = [](const Run& r) { return r.g.fields[graph::FieldId(r.bottle.field)].max_force; };
    const bool show_f = differs(f);
    const bool show_k = primary == "k" || differs(k), show_m = primary == "mass" || differs(m), show_v = differs(v);
    std::map<std::string, int> seen;
    for (Run& r : runs) {
        std::vector<std::string> parts, tags;
        if (show_m) parts.push_back(fmt::format("{:g} g", m(r) * 1000)), tags.push_back(fmt::format("m{:g}", m(r) * 1000));
        if (show_k) parts.push_back(fmt::format("k = {:g} kg/s", k(r))), tags.push_back(fmt::format("k{:g}", k(r)));
        if (show_v) parts.push_back(fmt::format("{:g} m/s", v(r))), tags.push_back(fmt::format("v{:g}", v(r)));
        if (show_f) parts.push_back(limit_label(f(r))), tags.push_back(fmt::format("f{:g}", f(r)));
        r.label = fmt::format("{}", fmt::join(parts, ", "));
        r.tag = fmt::format("{}", fmt::join(tags, "_"));
        if (int n = seen[r.tag]++; n > 0) {
            r.tag = fmt::format("{}_{}", r.tag, n + 1);
            r.label = fmt::format("{} ({})", r.label, n + 1);
        }
    }
}

void write_file(const fs::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
    if (!f) fail("cannot write " + p.string());
}

// The sample times the runs share (it fails when they differ).
const std::vector<double>& same_times(const std::vector<Run>& runs) {
    for (const Run& r : runs)
        if (*r.trace.col("time") != *runs[0].trace.col("time"))
            fail(r.trace_path + ": its times differ from " + runs[0].trace_path + "'s (use the same --for and rate)");
    return *runs[0].trace.col("time");
}

// The runs of a one-bottle experiment: each run's bottle found, the runs labelled by
// `primary`, their sample times checked to be the same. Returns those times.
const std::vector<double>& bottle_runs(std::vector<Run>& runs, const std::string& primary) {
    for (Run& r : runs) {
        std::string err;
        if (!find_bottle(r.g, "bottle", r.bottle, err)) fail(r.graph_path + ": " + err);
    }
    label_runs(runs, primary);
    return same_times(runs);
}

std::string plant_line(const Run& r) {
    return fmt::format("Plant `{}`, physics at {} Hz; friction and restitution {} on every body.",
                       r.g.str(r.g.plant), num(rate_of(r)),
                       frictionless(r.g) ? "0" : "**not** 0");
}

// gnuplot: one colour per run, the same in both terminals.
constexpr const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};
std::string colour(size_t i) { return kColours[i % std::size(kColours)]; }

std::string terminals(const std::string& name, const std::string& plot) {
    return fmt::format(
        "set datafile separator comma\n"
        "set terminal pngcairo size 1100,700 font 'DejaVu Sans,11'\nset output '{0}.png'\n{1}\n"
        "set terminal svg size 1100,700 font 'DejaVu Sans,11' background '#ffffff'\nset output '{0}.svg'\n{1}\n"
        "unset output\n",
        name, plot);
}

// The belts' slip limit a run's bottle starts under (N per body; 0: none).
double slip_limit(const Run& r) { return r.g.fields[graph::FieldId(r.bottle.field)].max_force; }

}  // namespace plant::analyse
