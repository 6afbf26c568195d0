// plant-analyse tipping: a bottle put on a running belt; how far it leans (docs/experiments.md).
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

std::string swing_text(const Swing& s, const Swing& first) {
    if (!s.found) return "none";
    return fmt::format("{:.2f}° at {:.0f} ms, {}", s.peak, 1000 * s.time,
                       first.found && &s != &first ? (s.side == first.side ? "same side" : "other side")
                                                   : (s.side < 0 ? "top backwards" : "top forwards"));
}

}  // namespace

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
        gains.push_back(r.g.fields[graph::FieldId(r.bottle.field)].gain);
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
    auto gain = [](const Run& r) { return r.g.fields[graph::FieldId(r.bottle.field)].gain; };
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

}  // namespace plant::analyse
