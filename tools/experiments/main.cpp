// plant-analyse: turns the runs of an experiment plant (plants/experiments) into the
// series CSV, a gnuplot script for the plot and a Markdown summary.
//
//   plant-analyse traction OUTDIR GRAPH TRACE [GRAPH TRACE ...]
//   plant-analyse tipping  OUTDIR GRAPH TRACE [GRAPH TRACE ...]
//   plant-analyse spacing  OUTDIR GRAPH TRACE
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
// The physics step of a run, from its trace (sampled every step: `plant run` without
// --trace-rate), so that a run with `--rate` is analysed at the rate it ran.
double step_of(const Run& r) {
    const std::vector<double>& t = *r.trace.col("time");
    return t[1] - t[0];
}
double rate_of(const Run& r) { return std::round(1 / step_of(r) * 1e6) / 1e6; }

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
    const bool show_k = primary == "k" || differs(k), show_m = primary == "mass" || differs(m), show_v = differs(v);
    std::map<std::string, int> seen;
    for (Run& r : runs) {
        std::vector<std::string> parts, tags;
        if (show_m) parts.push_back(fmt::format("{:g} g", m(r) * 1000)), tags.push_back(fmt::format("m{:g}", m(r) * 1000));
        if (show_k) parts.push_back(fmt::format("k = {:g} kg/s", k(r))), tags.push_back(fmt::format("k{:g}", k(r)));
        if (show_v) parts.push_back(fmt::format("{:g} m/s", v(r))), tags.push_back(fmt::format("v{:g}", v(r)));
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

// The runs of a one-bottle experiment: each run's bottle found, the runs labelled by
// `primary`, their sample times checked to be the same. Returns those times.
const std::vector<double>& bottle_runs(std::vector<Run>& runs, const std::string& primary) {
    for (Run& r : runs) {
        std::string err;
        if (!find_bottle(r.g, "bottle", r.bottle, err)) fail(r.graph_path + ": " + err);
    }
    label_runs(runs, primary);
    for (const Run& r : runs)
        if (*r.trace.col("time") != *runs[0].trace.col("time"))
            fail(r.trace_path + ": its times differ from " + runs[0].trace_path + "'s (use the same --for and rate)");
    return *runs[0].trace.col("time");
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
    auto panel = [&](const std::string& title, double x0, double x1) {
        std::string p = fmt::format("set title '{}'\nset xrange [{}:{}]\nplot ", title, num(x0), num(x1));
        for (size_t k = 0; k < runs.size(); ++k)
            p += fmt::format("{}'tipping.csv' skip 1 using 1:{} with lines lw 2 dt {} lc rgb '{}' title '{}'",
                             k ? ", \\\n     " : "", 2 + 3 * k, 1 + rank(gains, gains[k]),
                             colour(rank(masses, masses[k])), runs[k].label);
        return p + "\n";
    };
    const double zoom = std::min(t.back(), 0.3);
    std::string plot = fmt::format(
        "set multiplot layout 1,2 title 'Tipping: a bottle put on a belt at {} m/s (physics at {} Hz)'\n"
        "set xlabel 'time [s]'\nset ylabel 'angle between bottle axis and vertical [deg]'\n"
        "set yrange [0:{}]\nset grid\nset key right top box opaque\n{}{}unset multiplot",
        num(runs[0].bottle.belt_speed), num(rate_of(runs[0])), num(std::ceil(ymax * 1.15 * 2) / 2),
        panel(fmt::format("first {} s", num(zoom)), 0, zoom), panel("whole run", 0, t.back()));
    write_file(out / "tipping.gp", terminals("tipping", plot));

    std::string md = "# Tipping\n\n";
    md += "A bottle is put on a running belt; the angle between its axis and the vertical over time. The belt pulls "
          "its small bottom body as hard as its main body, which tips the bottle back (its top lags).\n\n";
    md += plant_line(runs[0]) + "\n\n";
    md += fmt::format(
        "A swing is an excursion of the bottle's lean along the belt beyond {}° (the contact jitter of a bottle "
        "riding a belt stays below that); the second swing is the largest one after the first has ended.\n\n",
        num(kThreshold));
    md += "| run | bottle mass (g) | k (kg/s) | belt speed (m/s) | peak tilt (°) | at (ms) | first swing | second swing | "
          "largest tilt after the first swing (°) | tilt at the end (°) | speed at the end (m/s) |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (size_t k = 0; k < runs.size(); ++k) {
        const Run& r = runs[k];
        const Tipping& x = res[k];
        md += fmt::format("| {} | {} | {} | {} | {:.2f} | {:.0f} | {} | {} | {:.2f} | {:.2f} | {:.4f} |\n", r.label,
                          num(r.bottle.mass() * 1000), num(r.g.fields[size_t(r.bottle.field)].gain),
                          num(r.bottle.belt_speed), x.peak_tilt, 1000 * x.peak_time, swing_text(x.first, x.first),
                          swing_text(x.second, x.first), x.later_max, x.final_tilt, x.final_speed);
    }
    md += "\nFiles: tipping.csv (per run: tilt_TAG and the signed lean pitch_TAG in degrees, > 0 forwards; v_TAG "
          "the speed along the belt in m/s), tipping.png, tipping.svg.\n";
    write_file(out / "summary.md", md);
    return 0;
}

// ---- spacing ----

int spacing(const fs::path& out, std::vector<Run>& runs) {
    if (runs.size() != 1) fail("spacing takes one run");
    Run& r = runs[0];
    Bottle a, b;
    std::string err;
    if (!find_bottle(r.g, "a", a, err) || !find_bottle(r.g, "b", b, err)) fail(r.graph_path + ": " + err);
    const std::vector<double>& t = *r.trace.col("time");
    std::vector<double> ax(t.size()), ay(t.size()), bx(t.size()), by(t.size()), d(t.size());
    size_t off_track = 0;
    double worst_tilt = 0;
    for (size_t i = 0; i < t.size(); ++i) {
        const Vec3 pa = vec_at(r, "a.p", i), pb = vec_at(r, "b.p", i);
        ax[i] = pa[0], ay[i] = pa[1], bx[i] = pb[0], by[i] = pb[1];
        d[i] = std::abs(pa[0] - pb[0]) + std::abs(pa[1] - pb[1]);
        if (!in_some_field(r.g, pa) || !in_some_field(r.g, pb)) ++off_track;
        worst_tilt = std::max({worst_tilt, tilt_deg(quat_at(r, "a.q", i)), tilt_deg(quat_at(r, "b.q", i))});
    }
    const Stats s = stats(d);
    const int laps_a = laps(ax, ay, a.belt_dir, 0.1), laps_b = laps(bx, by, b.belt_dir, 0.1);

    std::string csv = "time,a_x,a_y,b_x,b_y,manhattan\n";
    for (size_t i = 0; i < t.size(); ++i)
        csv += fmt::format("{},{},{},{},{},{}\n", num(t[i]), ax[i], ay[i], bx[i], by[i], d[i]);
    write_file(out / "spacing.csv", csv);

    const std::string plot = fmt::format(
        "set multiplot title 'Spacing: two bottles on a closed loop at {} m/s (physics at {} Hz)'\n"
        "set origin 0,0\nset size 0.62,0.95\n"
        "set title 'Manhattan distance between the bottles'\nset xlabel 'time [s]'\n"
        "set ylabel 'distance |Δx| + |Δy| [cm]'\nset grid\nset key below horizontal\nset xrange [0:{}]\n"
        "plot 'spacing.csv' skip 1 using 1:($6*100) with lines lw 1.5 lc rgb '{}' title 'distance', \\\n"
        "     {} with lines dt 2 lw 1.5 lc rgb '#555555' title 'mean {:.1f} cm', \\\n"
        "     {} with lines lw 1 lc rgb '#d62728' title 'min {:.1f} cm', \\\n"
        "     {} with lines lw 1 lc rgb '#2ca02c' title 'max {:.1f} cm'\n"
        "set origin 0.62,0\nset size 0.38,0.95\n"
        "set title 'The loop: paths of the two bottles'\nset xlabel 'x [m]'\nset ylabel 'y [m]'\n"
        "set size ratio -1\nset autoscale\nset key below horizontal\n"
        "plot 'spacing.csv' skip 1 using 2:3 with lines lw 1.5 lc rgb '{}' title 'bottle a (in front)', \\\n"
        "     'spacing.csv' skip 1 using 4:5 with lines lw 1 dt 2 lc rgb '{}' title 'bottle b'\n"
        "unset multiplot",
        num(a.belt_speed), num(rate_of(r)), num(t.back()), colour(0), num(s.mean * 100), s.mean * 100,
        num(s.min * 100), s.min * 100, num(s.max * 100), s.max * 100, colour(0), colour(1));
    write_file(out / "spacing.gp", terminals("spacing", plot));

    std::string md = "# Spacing\n\n";
    md += "Two bottles ride a closed loop of 5 straight belts and 6 curves (1 left, 5 right); the Manhattan distance "
          "|Δx| + |Δy| between their centres of mass over time.\n\n";
    md += plant_line(r) + "\n\n";
    md += fmt::format(
        "| quantity | value |\n|---|---|\n"
        "| run | {:g} s, {} samples |\n"
        "| belt speed | {} m/s |\n"
        "| distance at the start | {:.2f} cm |\n"
        "| minimum | {:.2f} cm |\n| maximum | {:.2f} cm |\n| mean | {:.2f} cm |\n"
        "| variance | {:.2f} cm² |\n| standard deviation | {:.2f} cm |\n"
        "| laps completed (a, b) | {}, {} |\n"
        "| samples with a bottle off the belts | {} |\n"
        "| largest tilt of either bottle | {:.2f}° |\n",
        t.back(), s.n, num(a.belt_speed), d[0] * 100, s.min * 100, s.max * 100, s.mean * 100, s.variance * 1e4,
        std::sqrt(s.variance) * 100, laps_a, laps_b, off_track, worst_tilt);
    md += "\nStatistics over every sample (one per step), the variance over the samples (population). A bottle is "
          "on the belts while its centre of mass is inside a belt's force field. A lap is counted when a bottle "
          "passes its start position again. Files: spacing.csv, spacing.png, spacing.svg.\n";
    write_file(out / "summary.md", md);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() < 4 || args.size() % 2 != 0) {
        std::cerr << "usage: plant-analyse traction|tipping|spacing OUTDIR GRAPH TRACE [GRAPH TRACE ...]\n";
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
    std::cerr << "plant-analyse: error: unknown experiment '" << what << "' (traction, tipping, spacing)\n";
    return 2;
}
