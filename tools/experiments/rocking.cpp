// plant-analyse rocking: a bottle let go leaning back on a belt at rest (docs/experiments.md).
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

}  // namespace

int rocking(const fs::path& out, std::vector<Run>& runs) {
    const std::vector<double>& t = same_times(runs);
    std::vector<RockRun> rr;
    for (const Run& r : runs) {
        const int32_t main = body_named(r.g, "bottle.main"), bottom = body_named(r.g, "bottle.bottom");
        if (main < 0 || bottom < 0) fail(r.graph_path + ": the plant has no bottle (bodies bottle.main and bottle.bottom)");
        RockRun x;
        x.mass = r.g.bodies[graph::BodyId(main)].mass + r.g.bodies[graph::BodyId(bottom)].mass;
        if (const int32_t f = field_at(r.g, r.g.bodies[graph::BodyId(bottom)].pose.p); f >= 0) {
            x.k = r.g.fields[graph::FieldId(f)].gain;
            x.limit = r.g.fields[graph::FieldId(f)].max_force;
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

}  // namespace plant::analyse
