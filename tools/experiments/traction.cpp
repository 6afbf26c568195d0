// plant-analyse traction: a bottle let go on a running belt, against the law solved exactly
// and as the runtime integrates it (docs/experiments.md).
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

namespace {

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

}  // namespace

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

}  // namespace plant::analyse
