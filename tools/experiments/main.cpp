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
#include "analysis.h"

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

namespace fs = std::filesystem;
using namespace plant::experiments;

namespace {

struct Run {
    std::string graph_path, trace_path;
    plant::graph::Graph g;
    Table trace;
    Bottle bottle;
    std::string label, tag;  // legend text ("k = 4 kg/s"), column suffix ("k4")
};

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
    auto k = [](const Run& r) { return r.g.fields[size_t(r.bottle.field)].gain; };
    auto m = [](const Run& r) { return r.bottle.mass(); };
    auto v = [](const Run& r) { return r.bottle.belt_speed; };
    auto f = [](const Run& r) { return r.g.fields[size_t(r.bottle.field)].max_force; };
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

// ---- traction ----

std::vector<double> bottle_lean(const Run& r) {
    std::vector<double> l(r.trace.rows());
    for (size_t i = 0; i < l.size(); ++i) l[i] = lean_along(quat_at(r, "main.q", i), r.bottle.belt_dir);
    return l;
}

// The same sweep run at finer steps (scripts/experiments.sh adds 600, 2400 and 9600 Hz):
// how the gap to the law's exact solution closes as the step shrinks. Writes
// traction_rates.csv (per rate a gnuplot data block: time, then per run the deviation
// from the law with the measured lean, % of belt speed), traction_rates.gp and returns
// the summary's section.
std::string traction_rates(const fs::path& out, std::vector<std::vector<Run>>& groups, double xmax) {
    std::sort(groups.begin(), groups.end(),
              [](const std::vector<Run>& a, const std::vector<Run>& b) { return rate_of(a[0]) < rate_of(b[0]); });
    std::string csv, md;
    md += "\n## The gap, step by step\n\n"
          "The same runs at finer physics steps (`plant run --rate`). Nothing but the law acts along the belt, and "
          "a body at height z_i above the centre of mass moves along it at V + z_i·dλ/dt, λ the bottle's lean "
          "(its axis along the belt, the sine of the lean angle). So the centre of mass obeys "
          "M·dV/dt = Σk·(v_belt − V) − Σk_i·z_i·dλ/dt: the law's exact solution **with the measured lean** "
          "(λ linear between samples; docs/experiments.md). The deviation from it is the runtime's step error; "
          "the deviation from the upright solution adds the bottle's rocking.\n\n"
          "| run | physics rate (Hz) | step / (M/Σk) | largest deviation from exact upright (% of belt speed, at ms) | "
          "largest deviation from the law with the measured lean (% of belt speed, at ms) | largest tilt (°) |\n"
          "|---|---|---|---|---|---|\n";
    std::vector<std::string> rows(groups.empty() ? 0 : groups[0].size());
    for (size_t gi = 0; gi < groups.size(); ++gi) {
        std::vector<Run>& runs = groups[gi];
        const std::vector<double>& t = *runs[0].trace.col("time");
        std::vector<std::vector<double>> dev;
        if (gi > 0) csv += "\n\n";
        csv += "time";
        for (const Run& r : runs) csv += ",dev_" + r.tag;
        csv += "\n";
        for (size_t k = 0; k < runs.size(); ++k) {
            const Run& r = runs[k];
            const Bottle& b = r.bottle;
            const std::vector<double> v = bottle_speed(r), lean = bottle_lean(r);
            const std::vector<double> law = leaning_speed(t, lean, v[0], b);
            const Traction x = analyse_traction(t, v, b, step_of(r), lean);
            double tilt = 0;
            for (size_t i = 0; i < t.size(); ++i) tilt = std::max(tilt, tilt_deg(quat_at(r, "main.q", i)));
            const double pct = 100 / std::abs(b.belt_speed);
            std::vector<double> d(t.size());
            for (size_t i = 0; i < t.size(); ++i) d[i] = (v[i] - law[i]) * pct;
            dev.push_back(std::move(d));
            rows[k] += fmt::format("| {} | {} | {:.3f} | {:+.2f} at {:.1f} | {:+.2f} at {:.1f} | {:.2f} |\n", r.label,
                              num(rate_of(r)), step_of(r) * b.gain_sum / b.mass(), x.max_dev * pct,
                              1000 * x.max_dev_time, x.max_dev_lean * pct, 1000 * x.max_dev_lean_time, tilt);
        }
        for (size_t i = 0; i < t.size(); ++i) {
            if (t[i] > xmax + 1e-12) break;
            csv += num(t[i]);
            for (const std::vector<double>& d : dev) csv += fmt::format(",{}", d[i]);
            csv += "\n";
        }
    }
    for (const std::string& row : rows) md += row;
    write_file(out / "traction_rates.csv", csv);

    // One colour per run (as in traction.png), one dash type per rate, finest solid.
    std::string plot = fmt::format(
        "set title 'Traction: simulated minus the law with the measured lean, per physics rate'\n"
        "set xlabel 'time [s]'\nset ylabel 'deviation [% of belt speed]'\n"
        "set xrange [0:{}]\nset grid\nset key right bottom box opaque\nplot ",
        num(xmax));
    std::vector<std::string> parts;
    for (size_t gi = 0; gi < groups.size(); ++gi) {
        const int dash = int(std::min<size_t>(groups.size() - 1 - gi, 3)) + 1;
        for (size_t k = 0; k < groups[gi].size(); ++k)
            parts.push_back(fmt::format("'traction_rates.csv' index {} skip 1 using 1:{} with lines dt {} lw 1.5 lc rgb '{}' title '{}, {} Hz'",
                                        gi, 2 + k, dash, colour(k), groups[gi][k].label, num(rate_of(groups[gi][0]))));
    }
    plot += fmt::format("{}", fmt::join(parts, ", \\\n     "));
    write_file(out / "traction_rates.gp", terminals("traction_rates", plot));
    md += "\nThe deviation from the law with the measured lean falls in proportion to the step: the runtime "
          "integrates the law to first order, as Bullet integrates everything else. The deviation from the upright "
          "solution does not vanish: it is the rocking of the two-body bottle (std.bottle), whose bottom body "
          "the band pulls 3 cm below the centre of mass. Files: traction_rates.csv, traction_rates.png, "
          "traction_rates.svg.\n";
    return md;
}

int traction(const fs::path& out, std::vector<Run>& all) {
    // The sweep is the runs at the first run's rate; runs at other rates are the same
    // sweep at finer steps.
    std::vector<std::vector<Run>> groups;
    for (Run& r : all) {
        auto same = [&](const std::vector<Run>& g) { return rate_of(g[0]) == rate_of(r); };
        auto it = std::find_if(groups.begin(), groups.end(), same);
        if (it == groups.end()) groups.emplace_back().push_back(std::move(r));
        else it->push_back(std::move(r));
    }
    for (std::vector<Run>& g : groups) {
        bottle_runs(g, "k");
        if (g.size() != groups[0].size())
            fail(fmt::format("{} runs at {} Hz, {} at {} Hz: each rate needs the same sweep", g.size(),
                             num(rate_of(g[0])), groups[0].size(), num(rate_of(groups[0][0]))));
    }
    std::vector<Run>& runs = groups[0];
    const std::vector<double>& t = *runs[0].trace.col("time");
    // Per run: simulated speed, the exact upright solution, the runtime's step, tilt,
    // lean and the law's solution for that lean.
    std::vector<std::vector<double>> speed, exact, stepped, tilt, lean, leaning;
    std::vector<Traction> res;
    for (const Run& r : runs) {
        const Bottle& b = r.bottle;
        const double dt = step_of(r);
        speed.push_back(bottle_speed(r));
        lean.push_back(bottle_lean(r));
        const double v0 = speed.back()[0];
        leaning.push_back(leaning_speed(t, lean.back(), v0, b));
        std::vector<double> ex(t.size()), st(t.size()), tl(t.size());
        for (size_t i = 0; i < t.size(); ++i) {
            ex[i] = upright_speed(t[i], v0, b.belt_speed, b.gain_sum, b.mass());
            st[i] = runtime_upright_speed(t[i], v0, b.belt_speed, b, dt);
            tl[i] = tilt_deg(quat_at(r, "main.q", i));
        }
        exact.push_back(ex);
        stepped.push_back(st);
        tilt.push_back(tl);
        res.push_back(analyse_traction(t, speed.back(), b, dt, lean.back()));
    }
    // The series, sampled as run, and both solutions on a fine grid for the plot.
    std::string csv = "time";
    for (const Run& r : runs) csv += fmt::format(",v_{0},exact_{0},runtime_{0},tilt_{0},lean_{0},leaning_{0}", r.tag);
    csv += "\n";
    for (size_t i = 0; i < t.size(); ++i) {
        csv += num(t[i]);
        for (size_t k = 0; k < runs.size(); ++k)
            csv += fmt::format(",{},{},{},{},{},{}", speed[k][i], exact[k][i], stepped[k][i], tilt[k][i], lean[k][i],
                               leaning[k][i]);
        csv += "\n";
    }
    write_file(out / "traction.csv", csv);
    std::string fine = "time";
    for (const Run& r : runs) fine += fmt::format(",exact_{0},runtime_{0}", r.tag);
    fine += "\n";
    for (int i = 0;; ++i) {
        const double tf = i * 0.25e-3;
        if (tf > t.back() + 1e-12) break;
        fine += num(tf);
        for (size_t k = 0; k < runs.size(); ++k) {
            const Bottle& b = runs[k].bottle;
            fine += fmt::format(",{},{}", upright_speed(tf, speed[k][0], b.belt_speed, b.gain_sum, b.mass()),
                                runtime_upright_speed(tf, speed[k][0], b.belt_speed, b, step_of(runs[k])));
        }
        fine += "\n";
    }
    write_file(out / "traction_analytic.csv", fine);

    // The plot: simulated points joined; the runtime's step dashed, the exact law dotted,
    // one colour per run.
    double slowest = 0, vmax = 0;
    for (size_t k = 0; k < runs.size(); ++k) {
        slowest = std::max(slowest, res[k].t95_runtime);
        vmax = std::max(vmax, runs[k].bottle.belt_speed);
    }
    const double xmax = std::min(t.back(), std::max(0.05, 3 * slowest));
    std::string plot = fmt::format(
        "set title 'Traction: a bottle let go on a belt at {} m/s (physics at {} Hz)'\n"
        "set xlabel 'time [s]'\nset ylabel 'bottle speed along the belt [m/s]'\n"
        "set xrange [0:{}]\nset yrange [0:{}]\nset grid\nset key right bottom box opaque\n"
        "plot ",
        num(runs[0].bottle.belt_speed), num(rate_of(runs[0])), num(xmax), num(vmax * 1.1));
    for (size_t k = 0; k < runs.size(); ++k) {
        plot += fmt::format(
            "'traction.csv' skip 1 using 1:{} with linespoints pt 7 ps 0.7 lw 1.5 lc rgb '{}' title '{} (simulated)', \\\n"
            "     'traction_analytic.csv' skip 1 using 1:{} with lines dt 2 lw 2 lc rgb '{}' notitle, \\\n"
            "     'traction_analytic.csv' skip 1 using 1:{} with lines dt 3 lw 1.5 lc rgb '{}' notitle, \\\n     ",
            2 + 6 * k, colour(k), runs[k].label, 3 + 2 * k, colour(k), 2 + 2 * k, colour(k));
    }
    plot += "NaN with lines dt 2 lw 2 lc rgb '#000000' title 'analytic: the law as the runtime steps it (upright bottle)', \\\n"
            "     NaN with lines dt 3 lw 1.5 lc rgb '#000000' title 'analytic: the law exact in time (upright bottle)'";
    write_file(out / "traction.gp", terminals("traction", plot));

    std::string md = "# Traction\n\n";
    md += "A bottle is let go on a running belt; its speed along the belt (of its centre of mass, both bodies) "
          "over time, next to two analytic solutions of the conveyor law for an upright bottle whose bodies are "
          "both pulled (Σk = 2k, M its mass):\n\n"
          "- **exact**: v(t) = v_belt·(1 − exp(−Σk·t/M)), the law solved exactly in time;\n"
          "- **runtime step**: v(n·dt) = v_belt·(1 − (1 − f)^n), the law as the runtime integrates the bottle "
          "(one rigid group, docs/runtime.md), f the fraction of the speed error one step removes when the band "
          "keeps the bottle upright (f = 1 − exp(−Σk·dt/M) for a body without lever arm).\n\n";
    md += plant_line(runs[0]) + "\n\n";
    md += "| run | bottle mass (g) | belt speed (m/s) | Σk (kg/s) | M/Σk (ms) | f per step | time to 95 % simulated (ms) | "
          "runtime step (ms) | exact (ms) | largest deviation from runtime step (% of belt speed, at ms) | "
          "largest deviation from exact (% of belt speed, at ms) | overshoot (% of belt speed) | largest tilt (°) |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (size_t k = 0; k < runs.size(); ++k) {
        const Bottle& b = runs[k].bottle;
        const Traction& x = res[k];
        const double pct = 100 / std::abs(b.belt_speed);
        md += fmt::format("| {} | {} | {} | {} | {} | {:.4f} | {} | {} | {} | {:+.2f} at {:.1f} | {:+.2f} at {:.1f} | {} | {} |\n",
                          runs[k].label, num(b.mass() * 1000), num(b.belt_speed), num(b.gain_sum),
                          fixed(1000 * b.mass() / b.gain_sum, 2), runtime_step_fraction(b, step_of(runs[k])),
                          fixed(1000 * x.t95, 1), fixed(1000 * x.t95_runtime, 1), fixed(1000 * x.t95_analytic, 1),
                          x.max_dev_runtime * pct, 1000 * x.max_dev_runtime_time, x.max_dev * pct,
                          1000 * x.max_dev_time, fixed(std::max(0.0, x.overshoot) * pct, 2),
                          fixed(*std::max_element(tilt[k].begin(), tilt[k].end()), 2));
    }
    md += "\nTimes to 95 % of belt speed: simulated, interpolated between samples (one per step); the analytic ones in "
          "closed form. Deviations are simulated minus analytic at the samples, negative where the simulated bottle "
          "lags. Where the bottle leans back measurably (largest tilt), the band does not stop its rotation at once "
          "and the runtime-step solution no longer applies exactly. Files: traction.csv (per run TAG: v_TAG "
          "simulated, exact_TAG, runtime_TAG, tilt_TAG in degrees, lean_TAG the lean λ, leaning_TAG the law with "
          "that lean), traction_analytic.csv (both upright solutions every 0.25 ms), traction.png, traction.svg.\n";
    md += traction_rates(out, groups, xmax);
    write_file(out / "summary.md", md);
    return 0;
}

// ---- tipping ----

// The belts' slip limit a run's bottle starts under (N per body; 0: none).
double slip_limit(const Run& r) { return r.g.fields[size_t(r.bottle.field)].max_force; }

std::string swing_text(const Swing& s, const Swing& first) {
    if (!s.found) return "none";
    return fmt::format("{:.2f}° at {:.0f} ms, {}", s.peak, 1000 * s.time,
                       first.found && &s != &first ? (s.side == first.side ? "same side" : "other side")
                                                   : (s.side < 0 ? "top backwards" : "top forwards"));
}

int tipping(const fs::path& out, std::vector<Run>& runs) {
    const std::vector<double>& t = bottle_runs(runs, "mass");
    std::vector<Tipping> res;
    std::vector<std::vector<double>> tilt, pitch, speed;
    constexpr double kThreshold = 1.0;  // degrees: a swing must exceed the contact jitter
    for (const Run& r : runs) {
        std::vector<double> tl(t.size()), pt(t.size());
        for (size_t i = 0; i < t.size(); ++i) {
            const Quat q = quat_at(r, "main.q", i);
            tl[i] = tilt_deg(q);
            pt[i] = pitch_deg(q, r.bottle.belt_dir);
        }
        tilt.push_back(tl);
        pitch.push_back(pt);
        speed.push_back(bottle_speed(r));
        res.push_back(analyse_tipping(t, pt, tl, speed.back(), kThreshold));
    }
    std::string csv = "time";
    for (const Run& r : runs) csv += fmt::format(",tilt_{0},pitch_{0},v_{0}", r.tag);
    csv += "\n";
    for (size_t i = 0; i < t.size(); ++i) {
        csv += num(t[i]);
        for (size_t k = 0; k < runs.size(); ++k) csv += fmt::format(",{},{},{}", tilt[k][i], pitch[k][i], speed[k][i]);
        csv += "\n";
    }
    write_file(out / "tipping.csv", csv);

    // Two panels: the first 0.3 s where the bottle tips, and the whole run.
    double ymax = 1;
    for (const Tipping& x : res) ymax = std::max(ymax, x.peak_tilt);
    // One colour per mass, one dash pattern per gain.
    std::vector<double> masses, gains;
    for (const Run& r : runs) {
        masses.push_back(r.bottle.mass());
        gains.push_back(r.g.fields[size_t(r.bottle.field)].gain);
    }
    auto rank = [](std::vector<double> all, double x) {
        std::sort(all.begin(), all.end());
        all.erase(std::unique(all.begin(), all.end()), all.end());
        return size_t(std::lower_bound(all.begin(), all.end(), x) - all.begin());
    };
    // A panel shows the runs on belts with slip limit `limit` (all runs when `limit` < 0).
    auto panel = [&](const std::string& title, double x0, double x1, double limit) {
        std::string p = fmt::format("set title '{}'\nset xrange [{}:{}]\nplot ", title, num(x0), num(x1));
        bool first = true;
        for (size_t k = 0; k < runs.size(); ++k) {
            if (limit >= 0 && slip_limit(runs[k]) != limit) continue;
            p += fmt::format("{}'tipping.csv' skip 1 using 1:{} with lines lw 2 dt {} lc rgb '{}' title '{}'",
                             first ? "" : ", \\\n     ", 2 + 3 * k, 1 + rank(gains, gains[k]),
                             colour(rank(masses, masses[k])), runs[k].label);
            first = false;
        }
        return p + "\n";
    };
    const double zoom = std::min(t.back(), 0.3);
    // Runs with and without a slip limit side by side, else the first moments and the whole run.
    std::vector<double> limits;
    for (const Run& r : runs)
        if (std::find(limits.begin(), limits.end(), slip_limit(r)) == limits.end()) limits.push_back(slip_limit(r));
    std::string panels;
    if (limits.size() > 1)
        for (double f : limits) panels += panel(fmt::format("{}, first {} s", limit_label(f), num(zoom)), 0, zoom, f);
    else
        panels = panel(fmt::format("first {} s", num(zoom)), 0, zoom, -1) + panel("whole run", 0, t.back(), -1);
    std::string plot = fmt::format(
        "set multiplot layout 1,{} title 'Tipping: a bottle put on a belt at {} m/s (physics at {} Hz)'\n"
        "set xlabel 'time [s]'\nset ylabel 'angle between bottle axis and vertical [deg]'\n"
        "set yrange [0:{}]\nset grid\nset key right top box opaque\n{}unset multiplot",
        std::max<size_t>(2, limits.size()), num(runs[0].bottle.belt_speed), num(rate_of(runs[0])),
        num(std::ceil(ymax * 1.15 * 2) / 2), panels);
    write_file(out / "tipping.gp", terminals("tipping", plot));

    std::string md = "# Tipping\n\n";
    md += "A bottle is put on a running belt; the angle between its axis and the vertical over time. The belt pulls "
          "its small bottom body as hard as its main body, which tips the bottle back (its top lags).\n\n";
    md += plant_line(runs[0]) + "\n\n";
    md += fmt::format(
        "A swing is an excursion of the bottle's lean along the belt beyond {}° (the contact jitter of a bottle "
        "riding a belt stays below that); the second swing is the largest one after the first has ended.\n\n",
        num(kThreshold));
    auto gain = [](const Run& r) { return r.g.fields[size_t(r.bottle.field)].gain; };
    std::vector<double> t95(runs.size());
    for (size_t k = 0; k < runs.size(); ++k) t95[k] = time_to_fraction(t, speed[k], runs[k].bottle.belt_speed, 0.95);
    md += "| run | bottle mass (g) | k (kg/s) | slip limit per body | belt speed (m/s) | time to 95 % of belt speed (ms) | "
          "peak tilt (°) | at (ms) | first swing | second swing | largest tilt after the first swing (°) | "
          "tilt at the end (°) | speed at the end (m/s) |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (size_t k = 0; k < runs.size(); ++k) {
        const Run& r = runs[k];
        const Tipping& x = res[k];
        md += fmt::format("| {} | {} | {} | {} | {} | {} | {:.2f} | {:.0f} | {} | {} | {:.2f} | {:.2f} | {:.4f} |\n",
                          r.label, num(r.bottle.mass() * 1000), num(gain(r)), limit_text(slip_limit(r)),
                          num(r.bottle.belt_speed), fixed(1000 * t95[k], 1), x.peak_tilt, 1000 * x.peak_time,
                          swing_text(x.first, x.first), swing_text(x.second, x.first), x.later_max, x.final_tilt,
                          x.final_speed);
    }
    // The trade-off: one row per belt (gain and slip limit), one column per mass.
    std::vector<std::pair<double, double>> belts;
    std::vector<double> masses_sorted;
    for (const Run& r : runs) {
        if (std::find(belts.begin(), belts.end(), std::pair{gain(r), slip_limit(r)}) == belts.end())
            belts.emplace_back(gain(r), slip_limit(r));
        if (std::find(masses_sorted.begin(), masses_sorted.end(), r.bottle.mass()) == masses_sorted.end())
            masses_sorted.push_back(r.bottle.mass());
    }
    std::sort(masses_sorted.begin(), masses_sorted.end());
    md += "\n## Gain × mass\n\nPer belt and bottle: time to 95 % of belt speed / peak tilt / second swing. "
          "\"lighter tips more\" when the peak tilt strictly decreases from the lightest to the heaviest bottle.\n\n"
          "| k (kg/s) | slip limit per body |";
    for (double m : masses_sorted) md += fmt::format(" {:g} g |", m * 1000);
    md += " lighter tips more |\n|---|---|";
    for (size_t i = 0; i <= masses_sorted.size(); ++i) md += "---|";
    md += "\n";
    for (const auto& [kb, fb] : belts) {
        md += fmt::format("| {} | {} |", num(kb), limit_text(fb));
        bool decreasing = true;
        double previous = INFINITY;
        for (double m : masses_sorted) {
            std::string cell = " — |";
            for (size_t k = 0; k < runs.size(); ++k) {
                const Run& r = runs[k];
                if (gain(r) != kb || slip_limit(r) != fb || r.bottle.mass() != m) continue;
                cell = fmt::format(" {} ms / {:.2f}° / {} |", fixed(1000 * t95[k], 1), res[k].peak_tilt,
                                   res[k].second.found ? fmt::format("{:.2f}°", res[k].second.peak) : "none");
                decreasing = decreasing && res[k].peak_tilt < previous;
                previous = res[k].peak_tilt;
            }
            md += cell;
        }
        md += decreasing ? " yes |\n" : " no |\n";
    }
    if (std::none_of(res.begin(), res.end(), [](const Tipping& x) { return x.second.found; }))
        md += "\nNo run swings a second time: the law damps a rocking bottle before it can (the rocking probe, "
              "`scripts/experiments.sh --only rocking`, and docs/experiments.md, \"The second swing: what the law "
              "allows\").\n";
    md += "\nFiles: tipping.csv (per run: tilt_TAG and the signed lean pitch_TAG in degrees, > 0 forwards; v_TAG "
          "the speed along the belt in m/s), tipping.png, tipping.svg.\n";
    write_file(out / "summary.md", md);
    return 0;
}

// ---- spacing ----


// One spacing run: both bottles' paths, the Manhattan distance and the gap along the track.
struct SpacingRun {
    Bottle a, b;
    std::vector<double> ax, ay, bx, by, manhattan, gap;
    Stats d, g;
    int laps_a = 0, laps_b = 0;
    size_t off_track = 0;
    double worst_tilt = 0, gap_end = 0;
    // The gap where both bottles cross the middle of a straight belt, and again 3 cm before
    // its end: the belt's speed times how much later b crosses than a. Then per transfer
    // (from one belt's end to the next belt's middle) the change, and the bottles' lanes as
    // they reach the transfer: u, the offset across the incoming belt towards the side the
    // track turns to (for a right turn, the right), a's minus b's.
    struct Passage {
        std::string belt;
        double time = 0;           // a at the belt's middle, s
        double gap_mid = 0, gap_end = 0;  // m
        double lateral_a = 0, lateral_b = 0;  // across the belt 3 cm before its end, > 0 left, m
        Vec3 dir{};
    };
    std::vector<Passage> passages;  // in the order a rode them
    struct Transfer {
        std::string from, to;
        int turn = 0;  // +1 left, -1 right, 0 a U-turn (two corners) or straight on
        std::vector<double> change, lane;  // gap change and u_a − u_b, m
    };
    std::vector<Transfer> transfers;
    double belt_change = 0;  // largest |gap change| from a belt's middle to its end, m
};

SpacingRun analyse_spacing_run(Run& r) {
    SpacingRun x;
    std::string err;
    if (!find_bottle(r.g, "a", x.a, err) || !find_bottle(r.g, "b", x.b, err)) fail(r.graph_path + ": " + err);
    r.bottle = x.a;
    const std::vector<double>& t = *r.trace.col("time");
    const size_t n = t.size();
    x.ax.resize(n), x.ay.resize(n), x.bx.resize(n), x.by.resize(n), x.manhattan.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const Vec3 pa = vec_at(r, "a.p", i), pb = vec_at(r, "b.p", i);
        x.ax[i] = pa[0], x.ay[i] = pa[1], x.bx[i] = pb[0], x.by[i] = pb[1];
        x.manhattan[i] = std::abs(pa[0] - pb[0]) + std::abs(pa[1] - pb[1]);
        if (!in_some_field(r.g, pa) || !in_some_field(r.g, pb)) ++x.off_track;
        x.worst_tilt = std::max({x.worst_tilt, tilt_deg(quat_at(r, "a.q", i)), tilt_deg(quat_at(r, "b.q", i))});
    }
    // b must reach a's point within 5 times the starting distance, and pass within 10 cm of it
    // (the width of a belt with its rails).
    x.gap = track_gap(x.ax, x.ay, x.bx, x.by, 0.1, 5 * x.manhattan[0]);
    std::vector<double> known;
    for (double v : x.gap)
        if (!std::isnan(v)) known.push_back(v), x.gap_end = v;
    x.d = stats(x.manhattan);
    x.g = stats(known);
    x.laps_a = laps(x.ax, x.ay, x.a.belt_dir, 0.1), x.laps_b = laps(x.bx, x.by, x.b.belt_dir, 0.1);

    for (const Straight& s : straights(r.g)) {
        const Vec3 end{s.centre[0] + s.dir[0] * (s.length / 2 - 0.03), s.centre[1] + s.dir[1] * (s.length / 2 - 0.03), 0};
        const double w = s.width / 2;
        const auto ma = crossings(t, x.ax, x.ay, s.centre, s.dir, w), mb = crossings(t, x.bx, x.by, s.centre, s.dir, w);
        const auto ea = crossings(t, x.ax, x.ay, end, s.dir, w), eb = crossings(t, x.bx, x.by, end, s.dir, w);
        const size_t k_end = std::min({ma.size(), mb.size(), ea.size(), eb.size()});
        for (size_t k = 0; k < k_end; ++k)
            x.passages.push_back({s.name, ma[k].time, s.speed * (mb[k].time - ma[k].time),
                                  s.speed * (eb[k].time - ea[k].time), ea[k].lateral, eb[k].lateral, s.dir});
    }
    std::sort(x.passages.begin(), x.passages.end(), [](const auto& p, const auto& q) { return p.time < q.time; });
    for (size_t k = 0; k < x.passages.size(); ++k) {
        const SpacingRun::Passage& p = x.passages[k];
        x.belt_change = std::max(x.belt_change, std::abs(p.gap_end - p.gap_mid));
        if (k + 1 == x.passages.size()) break;
        const SpacingRun::Passage& q = x.passages[k + 1];
        const double z = p.dir[0] * q.dir[1] - p.dir[1] * q.dir[0];
        const int turn = z > 0.5 ? 1 : z < -0.5 ? -1 : 0;
        auto it = std::find_if(x.transfers.begin(), x.transfers.end(),
                               [&](const SpacingRun::Transfer& tr) { return tr.from == p.belt && tr.to == q.belt; });
        if (it == x.transfers.end()) it = x.transfers.insert(x.transfers.end(), {p.belt, q.belt, turn, {}, {}});
        it->change.push_back(q.gap_mid - p.gap_end);
        it->lane.push_back(turn * (p.lateral_a - p.lateral_b));
    }
    return x;
}

int spacing(const fs::path& out, std::vector<Run>& runs) {
    std::vector<SpacingRun> res;
    for (Run& r : runs) res.push_back(analyse_spacing_run(r));
    const std::vector<double>& t = *runs[0].trace.col("time");
    for (const Run& r : runs)
        if (*r.trace.col("time") != t)
            fail(r.trace_path + ": its times differ from " + runs[0].trace_path + "'s (use the same --for and rate)");
    // Labels: the plant, and the slip limit where the runs differ in it.
    const bool show_limit = std::any_of(runs.begin(), runs.end(), [&](const Run& r) { return slip_limit(r) != slip_limit(runs[0]); });
    for (Run& r : runs) {
        r.label = r.g.str(r.g.plant);
        r.tag = r.label;
        if (show_limit) {
            r.label += ", " + limit_label(slip_limit(r));
            r.tag += fmt::format("_f{:g}", slip_limit(r));
        }
    }

    std::string csv = "time";
    for (const Run& r : runs) csv += fmt::format(",a_x_{0},a_y_{0},b_x_{0},b_y_{0},manhattan_{0},gap_{0}", r.tag);
    csv += "\n";
    for (size_t i = 0; i < t.size(); ++i) {
        csv += num(t[i]);
        for (const SpacingRun& x : res)
            csv += fmt::format(",{},{},{},{},{},{}", x.ax[i], x.ay[i], x.bx[i], x.by[i], x.manhattan[i],
                               std::isnan(x.gap[i]) ? std::string("NaN") : fmt::format("{}", x.gap[i]));
        csv += "\n";
    }
    write_file(out / "spacing.csv", csv);

    std::string manhattan_plot, gap_plot, path_plot;
    for (size_t k = 0; k < runs.size(); ++k) {
        const std::string sep = k ? ", \\\n     " : "";
        const int c = 2 + 6 * int(k);
        manhattan_plot += fmt::format("{}'spacing.csv' skip 1 using 1:(${}*100) with lines lw 1.2 lc rgb '{}' title '{}'",
                                      sep, c + 4, colour(k), runs[k].label);
        gap_plot += fmt::format("{}'spacing.csv' skip 1 using 1:(${}*100) with lines lw 1.5 lc rgb '{}' title '{}'", sep,
                                c + 5, colour(k), runs[k].label);
        path_plot += fmt::format("{}'spacing.csv' skip 1 using {}:{} with lines lw 1 lc rgb '{}' title '{} (a)'", sep, c,
                                 c + 1, colour(k), runs[k].label);
    }
    const std::string plot = fmt::format(
        "set multiplot title 'Spacing: two bottles on a closed loop at {} m/s (physics at {} Hz)'\n"
        "set grid\nset key below horizontal\nset xrange [0:{}]\nset xlabel 'time [s]'\n"
        "set origin 0,0.5\nset size 0.62,0.48\nset title 'Manhattan distance |Δx| + |Δy|'\nset ylabel 'distance [cm]'\n"
        "plot {}\n"
        "set origin 0,0\nset size 0.62,0.48\nset title 'gap along the track (b to where a was)'\nset ylabel 'gap [cm]'\n"
        "plot {}\n"
        "set origin 0.62,0\nset size 0.38,0.95\nset title 'The loops: paths of bottle a'\nset xlabel 'x [m]'\n"
        "set ylabel 'y [m]'\nset size ratio -1\nset autoscale\nplot {}\n"
        "unset multiplot",
        num(res[0].a.belt_speed), num(rate_of(runs[0])), num(t.back()), manhattan_plot, gap_plot, path_plot);
    write_file(out / "spacing.gp", terminals("spacing", plot));

    std::string md = "# Spacing\n\n";
    md += "Two bottles ride a closed loop of 5 straight belts, 1 left and 5 right turns; the Manhattan distance "
          "|Δx| + |Δy| between their centres of mass over time, and the gap along the track: how far the bottle "
          "behind (b) travels along its own path until it passes where the one in front (a) was.\n\n";
    md += plant_line(runs[0]) + "\n\n| quantity |";
    for (const Run& r : runs) md += " " + r.label + " |";
    md += "\n|---|";
    for (size_t k = 0; k < runs.size(); ++k) md += "---|";
    md += "\n";
    auto row = [&](const std::string& what, auto cell) {
        md += fmt::format("| {} |", what);
        for (size_t k = 0; k < runs.size(); ++k) md += fmt::format(" {} |", cell(runs[k], res[k]));
        md += "\n";
    };
    auto cm = [](double v) { return fmt::format("{:.2f}", v * 100); };
    row("run", [&](const Run&, const SpacingRun& x) { return fmt::format("{:g} s, {} samples", t.back(), x.d.n); });
    row("belt speed (m/s)", [](const Run&, const SpacingRun& x) { return num(x.a.belt_speed); });
    row("belts' slip limit per body", [](const Run& r, const SpacingRun&) { return limit_text(slip_limit(r)); });
    row("distance at the start (cm)", [&](const Run&, const SpacingRun& x) { return cm(x.manhattan[0]); });
    row("Manhattan: minimum (cm)", [&](const Run&, const SpacingRun& x) { return cm(x.d.min); });
    row("Manhattan: maximum (cm)", [&](const Run&, const SpacingRun& x) { return cm(x.d.max); });
    row("Manhattan: mean (cm)", [&](const Run&, const SpacingRun& x) { return cm(x.d.mean); });
    row("Manhattan: variance (cm²)", [](const Run&, const SpacingRun& x) { return fmt::format("{:.2f}", x.d.variance * 1e4); });
    row("along the track: minimum (cm)", [&](const Run&, const SpacingRun& x) { return cm(x.g.min); });
    row("along the track: maximum (cm)", [&](const Run&, const SpacingRun& x) { return cm(x.g.max); });
    row("along the track: mean (cm)", [&](const Run&, const SpacingRun& x) { return cm(x.g.mean); });
    row("along the track: variance (cm²)", [](const Run&, const SpacingRun& x) { return fmt::format("{:.2f}", x.g.variance * 1e4); });
    row("along the track: last (cm)", [&](const Run&, const SpacingRun& x) { return cm(x.gap_end); });
    row("laps completed (a, b)", [](const Run&, const SpacingRun& x) { return fmt::format("{}, {}", x.laps_a, x.laps_b); });
    row("samples with a bottle off the belts", [](const Run&, const SpacingRun& x) { return fmt::format("{}", x.off_track); });
    row("largest tilt of either bottle (°)", [](const Run&, const SpacingRun& x) { return fmt::format("{:.2f}", x.worst_tilt); });
    md += "\nStatistics over every sample (one per step; the gap along the track over the samples where b has "
          "reached a's point by the end), the variance over the samples (population). A bottle is on the belts "
          "while its centre of mass is inside a belt's force field. A lap is counted when a bottle passes its "
          "start position again.\n";

    md += "\n## Where the gap changes\n\nThe gap where both bottles cross the middle of a straight belt, and 3 cm "
          "before its end: the belt speed times how much later b crosses than a. Along a belt it does not change "
          "(largest change from the middle to the end, below). Per transfer (from the end of one belt to the "
          "middle of the next): the change of the gap, and u_a − u_b, how much further than b bottle a rode "
          "towards the side the track turns to (right for a right turn), across the incoming belt 3 cm before "
          "its end. A bottle nearer that side has less way to go through a right angle, by just that offset: "
          "the gap would change by u_a − u_b.\n";
    for (size_t k = 0; k < runs.size(); ++k) {
        const SpacingRun& x = res[k];
        md += fmt::format("\n{}: largest change along a belt {:.2f} cm.\n\n| from | to | turn | passages | gap change: "
                          "mean (cm) | min (cm) | max (cm) | u_a − u_b: min (cm) | max (cm) | correlation | "
                          "largest |change − (u_a − u_b)| (cm) |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
                          runs[k].label, x.belt_change * 100);
        for (const SpacingRun::Transfer& tr : x.transfers) {
            const Stats c = stats(tr.change), u = stats(tr.lane);
            double cov = 0, residual = 0;
            for (size_t i = 0; i < tr.change.size(); ++i) {
                cov += (tr.change[i] - c.mean) * (tr.lane[i] - u.mean) / double(c.n);
                residual = std::max(residual, std::abs(tr.change[i] - tr.lane[i]));
            }
            const bool turns = tr.turn != 0;
            const std::string corr = turns && c.n > 2 && c.variance > 0 && u.variance > 0
                                         ? fmt::format("{:+.2f}", cov / std::sqrt(c.variance * u.variance))
                                         : "—";
            md += fmt::format("| {} | {} | {} | {} | {:+.2f} | {:+.2f} | {:+.2f} | {} | {} | {} | {} |\n", tr.from, tr.to,
                              tr.turn > 0 ? "left" : tr.turn < 0 ? "right" : "U-turn or none", c.n, c.mean * 100,
                              c.min * 100, c.max * 100, turns ? fmt::format("{:+.2f}", u.min * 100) : "—",
                              turns ? fmt::format("{:+.2f}", u.max * 100) : "—", corr,
                              turns ? fmt::format("{:.2f}", residual * 100) : "—");
        }
    }
    md += "\nFiles: spacing.csv (per run TAG: both bottles' x and y, manhattan_TAG and gap_TAG in m), spacing.png, "
          "spacing.svg.\n";
    write_file(out / "summary.md", md);
    return 0;
}

// ---- rocking ----

// A bottle let go leaning back on a belt at rest (rocking.plant): its lean along the band
// (+x), the band it stands on (the field's gain and slip limit; gain 0 on a bare band), the
// tilt it was let go at and its rebound.
struct RockRun {
    double k = 0, limit = 0, mass = 0, tilt = 0;
    std::vector<double> pitch;
    Rebound rebound;
    std::string tag;
    std::array<double, 3> band() const { return {k, limit, mass}; }  // what a row of the summary is
};

std::string band_text(double k, double limit) {
    return k == 0 ? std::string("bare band") : fmt::format("k = {:g} kg/s, {}", k, limit_label(limit));
}

int rocking(const fs::path& out, std::vector<Run>& runs) {
    const std::vector<double>& t = same_times(runs);
    std::vector<RockRun> rr;
    for (const Run& r : runs) {
        const int32_t main = body_named(r.g, "bottle.main"), bottom = body_named(r.g, "bottle.bottom");
        if (main < 0 || bottom < 0) fail(r.graph_path + ": the plant has no bottle (bodies bottle.main and bottle.bottom)");
        RockRun x;
        x.mass = r.g.bodies[size_t(main)].mass + r.g.bodies[size_t(bottom)].mass;
        if (const int32_t f = field_at(r.g, r.g.bodies[size_t(bottom)].pose.p); f >= 0) {
            x.k = r.g.fields[size_t(f)].gain;
            x.limit = r.g.fields[size_t(f)].max_force;
        }
        for (size_t i = 0; i < t.size(); ++i) x.pitch.push_back(pitch_deg(quat_at(r, "main.q", i), {1, 0, 0}));
        x.tilt = std::round(-x.pitch.front() * 100) / 100;
        x.rebound = analyse_rebound(t, x.pitch);
        x.tag = fmt::format("k{:g}_f{:g}_m{:g}_t{:g}", x.k, x.limit, x.mass * 1000, x.tilt);
        rr.push_back(std::move(x));
    }
    std::string csv = "time";
    for (const RockRun& x : rr) csv += ",pitch_" + x.tag;
    csv += "\n";
    for (size_t i = 0; i < t.size(); ++i) {
        csv += num(t[i]);
        for (const RockRun& x : rr) csv += fmt::format(",{}", x.pitch[i]);
        csv += "\n";
    }
    write_file(out / "rocking.csv", csv);

    // The bands (gain, limit, mass) in the order of the runs, and the tilts, ascending.
    std::vector<std::array<double, 3>> bands;
    std::vector<double> tilts;
    for (const RockRun& x : rr) {
        if (std::find(bands.begin(), bands.end(), x.band()) == bands.end()) bands.push_back(x.band());
        if (std::find(tilts.begin(), tilts.end(), x.tilt) == tilts.end()) tilts.push_back(x.tilt);
    }
    std::sort(tilts.begin(), tilts.end());
    const bool masses = std::any_of(rr.begin(), rr.end(), [&](const RockRun& x) { return x.mass != rr[0].mass; });
    auto band_name = [&](const std::array<double, 3>& b) {
        return band_text(b[0], b[1]) + (masses ? fmt::format(", {:g} g", b[2] * 1000) : "");
    };

    // One panel per band, one colour per tilt: the first 0.4 s.
    const double zoom = std::min(t.back(), 0.4);
    std::string panels;
    for (const auto& b : bands) {
        panels += fmt::format("set title '{}'\nplot ", band_name(b));
        bool first = true;
        for (size_t k = 0; k < rr.size(); ++k) {
            const RockRun& x = rr[k];
            if (x.band() != b) continue;
            const size_t c = size_t(std::find(tilts.begin(), tilts.end(), x.tilt) - tilts.begin());
            panels += fmt::format("{}'rocking.csv' skip 1 using 1:{} with lines lw 2 lc rgb '{}' title 'let go at {:g}°'",
                                  first ? "" : ", \\\n     ", 2 + k, colour(c), x.tilt);
            first = false;
        }
        panels += ", 0 with lines lc rgb '#888888' dt 2 notitle\n";
    }
    const size_t cols = bands.size() <= 4 ? std::min<size_t>(bands.size(), 2) : 3, rows = (bands.size() + cols - 1) / cols;
    const std::string plot = fmt::format(
        "set multiplot layout {},{} title 'Rocking: a bottle let go leaning back on a belt at rest (physics at {} Hz)'\n"
        "set xlabel 'time [s]'\nset ylabel 'lean [deg], > 0: top forwards'\n"
        "set xrange [0:{}]\nset yrange [{}:4]\nset grid\nset key right bottom box opaque\n{}unset multiplot",
        rows, cols, num(rate_of(runs[0])), num(zoom), num(-std::ceil(tilts.back() + 1)), panels);
    write_file(out / "rocking.gp", terminals("rocking", plot));

    std::string md = "# Rocking\n\n";
    md += "A bottle is let go leaning back, on its base's rear edge, on a belt at rest; it falls back onto its base. "
          "Its rebound is its largest forward lean once it is back on its base (lean above −1°): a second swing "
          "when it exceeds 1°. On a bare band only Bullet's contact acts; a belt's field pulls both of the bottle's "
          "bodies towards the band's speed, and so damps the rocking (docs/experiments.md, Tipping).\n\n";
    md += plant_line(runs[0]) + "\n\n";
    md += fmt::format("Rebound (°) per band and tilt{}; **bold**: a second swing.\n\n| band |",
                      masses ? "" : fmt::format(", {:g} g bottle", rr[0].mass * 1000));
    for (double tl : tilts) md += fmt::format(" let go at {:g}° |", tl);
    md += " second swings | back on its base after (ms) |\n|---|";
    for (size_t i = 0; i < tilts.size() + 2; ++i) md += "---|";
    md += "\n";
    auto run_at = [&](const std::array<double, 3>& b, double tilt) -> const RockRun* {
        const auto it = std::find_if(rr.begin(), rr.end(), [&](const RockRun& x) { return x.band() == b && x.tilt == tilt; });
        return it == rr.end() ? nullptr : &*it;
    };
    for (const auto& b : bands) {
        md += "| " + band_name(b) + " |";
        int swings = 0, n = 0;
        std::vector<std::string> backs;
        for (double tl : tilts) {
            const RockRun* x = run_at(b, tl);
            if (!x) {
                md += " — |";
                continue;
            }
            const double v = x->rebound.rebound;
            const bool swing = v > 1;
            md += std::isnan(v) ? " never back |" : swing ? fmt::format(" **{:.2f}** |", v) : fmt::format(" {:.2f} |", v);
            swings += swing;
            ++n;
            backs.push_back(std::isnan(x->rebound.back_time) ? "—" : fmt::format("{:.0f}", 1000 * x->rebound.back_time));
        }
        md += fmt::format(" {} of {} | {} |\n", swings, n, fmt::join(backs, ", "));
    }
    md += "\nFiles: rocking.csv (per run: pitch_TAG, the lean along the band in degrees, > 0 forwards; TAG names gain, "
          "limit, mass and tilt), rocking.png, rocking.svg.\n";
    write_file(out / "summary.md", md);
    return 0;
}

}  // namespace

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
