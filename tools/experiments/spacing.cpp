// plant-analyse spacing: two bottles on a closed loop (docs/experiments.md).
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

}  // namespace

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

}  // namespace plant::analyse
