// The three experiment plants (plants/experiments), compiled with --set values and run
// on Bullet in-process: what physics requires of traction, tipping and spacing. The
// numbers come from running the physics; the thresholds are stated with their reasons.
#include "paths.h"
#include "../compiler/compile_helper.h"
#include "analysis.h"
#include "engine/engine.h"

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

using namespace plant::experiments;
using plant::engine::Engine;
using plant::graph::BodyId;

namespace {

std::string experiment(const std::string& name) { return std::string(PLANT_SOURCE_DIR) + "/plants/experiments/" + name; }

std::unique_ptr<plant::Compilation> compile(const std::string& name, const std::vector<std::string>& sets) {
    auto c = std::make_unique<plant::Compilation>();
    plant::CompileOptions opts;
    opts.stdlib_dir = PLANT_STDLIB_DIR;
    opts.overrides = sets;
    plant::compile_file(experiment(name), opts, *c);
    return c;
}

// One bottle on one belt: its centre-of-mass speed along the belt, each body's speed
// along the belt, tilt and lean per step.
struct BottleRun {
    Bottle bottle;
    double dt = 0;
    std::vector<double> t, v, v_main, v_bottom, tilt, pitch, lean;
};

// Physics at `rate` Hz (the plants' `rate` parameter, 150 Hz by default).
BottleRun run_bottle(const std::string& plant, std::vector<std::string> sets, double seconds, double rate = 150) {
    BottleRun r;
    if (rate != 150) sets.push_back("rate=" + std::to_string(rate) + " Hz");
    auto c = compile(plant, sets);
    REQUIRE(c->ok());
    std::string err;
    REQUIRE(find_bottle(c->graph, "bottle", r.bottle, err));
    REQUIRE(frictionless(c->graph));
    CHECK(c->graph.settings.rate == doctest::Approx(rate));
    Engine e(c->graph);
    r.dt = 1 / c->graph.settings.rate;
    const Bottle& b = r.bottle;
    auto sample = [&] {
        const auto vm = e.body_velocity(BodyId(b.main)), vb = e.body_velocity(BodyId(b.bottom));
        auto along = [&](const plant::graph::Vec3& v) {
            return v[0] * b.belt_dir[0] + v[1] * b.belt_dir[1] + v[2] * b.belt_dir[2];
        };
        const auto q = e.body_pose(BodyId(b.main)).q;
        r.t.push_back(e.time());
        r.v.push_back((b.m_main * along(vm) + b.m_bottom * along(vb)) / b.mass());
        r.v_main.push_back(along(vm));
        r.v_bottom.push_back(along(vb));
        r.tilt.push_back(tilt_deg(q));
        r.pitch.push_back(pitch_deg(q, b.belt_dir));
        r.lean.push_back(lean_along(q, b.belt_dir));
    };
    sample();
    const int steps = int(std::lround(seconds / r.dt));
    for (int i = 0; i < steps; ++i) {
        e.step();
        sample();
    }
    CHECK(e.warnings().total() == 0);
    return r;
}

std::string k_set(double k) { return "k=" + std::to_string(k) + " kg/s"; }
std::string mass_set(double grams) { return "mass=" + std::to_string(grams) + " g"; }

// Two bottles `a` (in front) and `b` on a loop (spacing.plant, spacing_corners.plant): their
// centres of mass per step, how many steps one of them was off the belts, the largest tilt.
struct LoopRun {
    Bottle a, b;
    plant::graph::Graph g;
    std::vector<double> t, ax, ay, bx, by, manhattan;
    size_t off = 0;
    double worst_tilt = 0;
};

LoopRun run_loop(const std::string& plant, double seconds) {
    LoopRun r;
    auto c = compile(plant, {});
    REQUIRE(c->ok());
    REQUIRE(frictionless(c->graph));
    std::string err;
    REQUIRE(find_bottle(c->graph, "a", r.a, err));
    REQUIRE(find_bottle(c->graph, "b", r.b, err));
    Engine e(c->graph);
    const int steps = int(std::lround(seconds * c->graph.settings.rate));
    for (int i = 0; i <= steps; ++i) {
        if (i > 0) e.step();
        const auto pa = e.body_com(BodyId(r.a.main)), pb = e.body_com(BodyId(r.b.main));
        r.t.push_back(e.time());
        r.ax.push_back(pa[0]), r.ay.push_back(pa[1]), r.bx.push_back(pb[0]), r.by.push_back(pb[1]);
        r.manhattan.push_back(std::abs(pa[0] - pb[0]) + std::abs(pa[1] - pb[1]));
        if (!in_some_field(c->graph, pa) || !in_some_field(c->graph, pb)) ++r.off;
        r.worst_tilt = std::max(
            {r.worst_tilt, tilt_deg(e.body_pose(BodyId(r.a.main)).q), tilt_deg(e.body_pose(BodyId(r.b.main)).q)});
    }
    CHECK(e.warnings().total() == 0);
    r.g = c->graph;
    return r;
}

}  // namespace

TEST_CASE("traction: the bottle approaches the belt speed monotonically, and a larger k gets there sooner") {
    double previous_t95 = INFINITY;
    for (double k : {1.0, 4.0, 16.0}) {
        CAPTURE(k);
        const BottleRun r = run_bottle("traction.plant", {k_set(k)}, 0.6);
        const double vb = r.bottle.belt_speed;
        REQUIRE(vb == doctest::Approx(0.5));
        CHECK(r.bottle.gain_sum == doctest::Approx(2 * k));  // both bodies are pulled from the start
        const Traction x = analyse_traction(r.t, r.v, r.bottle, r.dt);
        // A small tolerance: a bottle standing on a belt jitters by about 0.2 % from step to
        // step (contacts), and rocks while it accelerates: with std.bottle's straight-sided
        // hull the largest dip measured is 1.25 % of the belt speed (k = 4 kg/s).
        CHECK(x.overshoot <= 0.01 * vb);
        CHECK(x.max_drop <= 0.015 * vb);
        CHECK(std::abs(x.final_speed - vb) <= 0.01 * vb);
        CHECK(x.t95 < previous_t95);
        // The bottle cannot reach the belt speed sooner than the law solved exactly for an
        // upright bottle: leaning and the runtime's step only delay it.
        CHECK(x.t95 >= x.t95_analytic);
        previous_t95 = x.t95;
    }
}

TEST_CASE("traction: simulated and analytic speeds agree within 1 % of the belt speed") {
    for (double k : {1.0, 4.0, 16.0}) {
        CAPTURE(k);
        const BottleRun r = run_bottle("traction.plant", {k_set(k)}, 0.6);
        const Bottle& b = r.bottle;
        const double tol = 0.01 * b.belt_speed;
        // The law as the runtime steps a bottle the band keeps upright: it holds at every
        // step in which the bottle stood (tilt at most 0.5 deg before and after), within
        // 1.5 % (1.17 % measured for k = 1 kg/s while the bottle rocks on its base).
        const double tol_stepped = 0.015 * b.belt_speed;
        size_t checked = 0;
        for (size_t i = 1; i < r.t.size(); ++i) {
            if (r.tilt[i] > 0.5 || r.tilt[i - 1] > 0.5) continue;
            CAPTURE(r.t[i]);
            CHECK(std::abs(r.v[i] - runtime_upright_speed(r.t[i], r.v[0], b.belt_speed, b, r.dt)) <= tol_stepped);
            ++checked;
        }
        CHECK(checked >= r.t.size() * 9 / 10);
        // With k = 16 kg/s the bottle reaches belt speed within one step and stays upright:
        // the law's exact solution holds at every step.
        if (k == 16)
            for (size_t i = 0; i < r.t.size(); ++i)
                CHECK(std::abs(r.v[i] - upright_speed(r.t[i], r.v[0], b.belt_speed, b.gain_sum, b.mass())) <= tol);
    }
}

TEST_CASE("traction: with a step that resolves the pull, the speed follows the law's exact solution for the bottle's lean within 1 %") {
    // For k = 1 and 4 kg/s the 40 g bottle rocks (its bottom body is pulled 3 cm below the
    // centre of mass), so no step brings it within 1 % of the upright solution. The law's
    // exact solution with the measured lean as input (leaning_speed) is what the runtime
    // must converge to: the gap to it is the step's error, first order in the step.
    for (double k : {1.0, 4.0, 16.0}) {
        CAPTURE(k);
        double gap[2] = {0, 0}, upright_gap = 0;
        const double rates[2] = {1200, 4800};
        for (int i = 0; i < 2; ++i) {
            const BottleRun r = run_bottle("traction.plant", {k_set(k)}, 0.3, rates[i]);
            const Traction x = analyse_traction(r.t, r.v, r.bottle, r.dt, r.lean);
            gap[i] = std::abs(x.max_dev_lean) / r.bottle.belt_speed;
            upright_gap = std::abs(x.max_dev) / r.bottle.belt_speed;
        }
        CAPTURE(gap[0]);
        CAPTURE(gap[1]);
        CAPTURE(upright_gap);
        CHECK(gap[1] <= 0.01);
        CHECK(gap[1] <= 0.4 * gap[0]);  // a 4 times finer step: a gap about 4 times smaller
        CHECK(gap[1] < upright_gap);    // the lean explains most of the gap to the upright solution
    }
}

TEST_CASE("tipping: every bottle ends upright and moving at belt speed") {
    for (double k : {16.0, 0.5})
        for (double m : {20.0, 40.0, 80.0}) {
            CAPTURE(k);
            CAPTURE(m);
            const BottleRun r = run_bottle("tipping.plant", {k_set(k), mass_set(m)}, 3);
            REQUIRE(r.bottle.belt_speed == doctest::Approx(1.0));
            CHECK(r.bottle.mass() == doctest::Approx(m / 1000));
            CHECK(*std::max_element(r.tilt.begin(), r.tilt.end()) < 30);  // never falls over
            CHECK(r.tilt.back() < 1);
            CHECK(std::abs(r.v.back() - 1.0) < 0.01);
        }
}

TEST_CASE("tipping: on a belt whose pull outlasts the bottle's rocking, the peak angle decreases as the mass increases") {
    // The sweep of the issue: 20, 40 and 80 g at 1 m/s. The pull's speed error decays with
    // M/(2k); with k = 0.5 kg/s that is 20 to 80 ms, longer than the bottle takes to lean
    // back, so gravity's restoring torque, which grows with M while the pull does not, sets
    // the peak: the heavier the bottle, the less it tips (docs/experiments.md, Tipping).
    std::vector<double> peaks;
    for (double m : {20.0, 40.0, 80.0}) {
        const BottleRun r = run_bottle("tipping.plant", {k_set(0.5), mass_set(m)}, 1);
        peaks.push_back(*std::max_element(r.tilt.begin(), r.tilt.end()));
    }
    CAPTURE(peaks[0]);
    CAPTURE(peaks[1]);
    CAPTURE(peaks[2]);
    CHECK(peaks[0] > 1);  // the lightest bottle swings visibly
    CHECK(peaks[0] > peaks[1]);
    CHECK(peaks[1] > peaks[2]);
}

TEST_CASE("tipping: the motion depends on k and the mass only through k/M") {
    // Scaling the gain and the mass together scales every force (the law's, gravity's, the
    // contacts') with the mass: the accelerations, and so the motion, are the same.
    const BottleRun a = run_bottle("tipping.plant", {k_set(1), mass_set(40)}, 0.5);
    const BottleRun b = run_bottle("tipping.plant", {k_set(2), mass_set(80)}, 0.5);
    REQUIRE(a.tilt.size() == b.tilt.size());
    double worst = 0;
    for (size_t i = 0; i < a.tilt.size(); ++i) worst = std::max(worst, std::abs(a.pitch[i] - b.pitch[i]));
    CHECK(worst < 0.05);
    CHECK(*std::max_element(a.tilt.begin(), a.tilt.end()) > 1);  // there is a swing to compare
}

TEST_CASE("tipping: a bottle rocks back only while the pull's torque beats gravity's, less the heavier it is") {
    // The law pulls both bodies with k·e; about the bottle's centre of mass that is a torque
    // k·e·|Σz| (the bottom body's lever below it, the main body's above). Standing on its base
    // of radius r the bottle holds a torque up to M·g·r before its front edge lifts. At the
    // start e is the belt speed v, so with M > k·v·|Σz| / (g·r) it cannot rock at all.
    auto probe = compile("tipping.plant", {k_set(1)});
    REQUIRE(probe->ok());
    Bottle b;
    std::string err;
    REQUIRE(find_bottle(probe->graph, "bottle", b, err));
    const auto& hull = probe->graph.shapes[probe->graph.bodies[plant::graph::BodyId(b.main)].shape_adr.first()];
    double radius = 0, lowest = INFINITY;
    for (int32_t i = 0; i < hull.point_num; ++i) lowest = std::min(lowest, probe->graph.points[plant::graph::Id<plant::graph::Point>(hull.point_adr + i)].p[2]);
    for (int32_t i = 0; i < hull.point_num; ++i) {
        const auto& p = probe->graph.points[plant::graph::Id<plant::graph::Point>(hull.point_adr + i)].p;
        if (p[2] < lowest + 1e-9) radius = std::max(radius, std::hypot(p[0], p[1]));
    }
    REQUIRE(radius > 0);
    const double m_crit = 1.0 * b.belt_speed * std::abs(b.lever_sum()) / (9.81 * radius);
    MESSAGE("k = 1 kg/s at 1 m/s: no rocking above " << m_crit * 1000 << " g");
    std::vector<double> peaks;
    for (double share : {0.25, 0.5, 1.25}) {
        const BottleRun r = run_bottle("tipping.plant", {k_set(1), mass_set(share * m_crit * 1000)}, 1);
        const Tipping x = analyse_tipping(r.t, r.pitch, r.tilt, r.v);
        peaks.push_back(x.peak_tilt);
        CAPTURE(share);
        CHECK(x.first.found == (share < 1));  // a swing beyond 1 deg exactly below the threshold
        if (x.first.found) CHECK(x.first.side == -1);  // the top lags: the bottle leans back
    }
    CHECK(peaks[0] > peaks[1]);
    CHECK(peaks[1] > peaks[2]);
}

TEST_CASE("spacing: two bottles ride the loop for 50 s, stay on the belts, and keep a bounded distance") {
    const LoopRun r = run_loop("spacing.plant", 50);
    CHECK(r.off == 0);           // both centres of mass are over a belt at every step
    CHECK(r.worst_tilt < 10);    // and the bottles stand
    // Repeatedly around the loop: one lap is about 8.2 m, 16.5 s at 50 cm/s.
    CHECK(laps(r.ax, r.ay, r.a.belt_dir, 0.1) >= 2);
    CHECK(laps(r.bx, r.by, r.b.belt_dir, 0.1) >= 2);
    const std::vector<double>& d = r.manhattan;
    const Stats s = stats(d);
    MESSAGE("Manhattan distance: min " << s.min << " m, max " << s.max << " m, mean " << s.mean << " m, variance "
                                       << s.variance << " m^2");
    CHECK(d.front() == doctest::Approx(0.2));
    // Bounded: the bottles never touch (4 cm apart centre to centre, and the Manhattan
    // distance is at least the straight one) and never drift to twice their start distance.
    CHECK(s.min > 0.04);
    CHECK(s.max < 2 * d.front());
}

TEST_CASE("spacing on right angles: both bottles ride every lap on the belts for 50 s, the gap changing at the transfers only") {
    // The original's kind of loop (spacing_corners.plant, the original, unlimited law): 5
    // belts joined by std.transfers Corners. 50 s of physics cost about 0.15 s here.
    const LoopRun r = run_loop("spacing_corners.plant", 50);
    CHECK(r.off == 0);  // both centres of mass are over a belt or a corner's band at every step
    CHECK(r.worst_tilt < 15);  // and the bottles stand (2.5° measured; 8.7° in the U-turn before)
    // One lap is about 5.7 m, 11.3 s at 50 cm/s: 4 complete laps in 50 s, none lost.
    CHECK(laps(r.ax, r.ay, r.a.belt_dir, 0.1) == 4);
    CHECK(laps(r.bx, r.by, r.b.belt_dir, 0.1) == 4);
    const std::vector<double> gap = track_gap(r.ax, r.ay, r.bx, r.by, 0.1, 1.0);
    // b reaches a's last point gap / speed before the end (under 1 s: the gap stays under 50 cm,
    // below); the samples after it have no gap, and nearly all before it have one.
    std::vector<double> known;
    for (double g : gap)
        if (!std::isnan(g)) known.push_back(g);
    CHECK(known.size() + 150 >= gap.size());
    const Stats s = stats(known);
    MESSAGE("gap along the track: min " << s.min << " m, max " << s.max << " m, mean " << s.mean << " m");
    CHECK(gap.front() == doctest::Approx(0.2).epsilon(0.01));
    // Along a belt the gap does not change: both bottles ride it at its speed. It changes at the
    // transfers only, by up to the band's free width, in a random walk (docs/experiments.md,
    // "Where the gap changes"): so a run's range is its own (measured 17.2 to 42.5 cm, and
    // 18.5 to 28.3 cm before the solver took contacts in the plant's order). The bottles never
    // close up to touching (4 cm) and the walk stays within 10 to 50 cm.
    double belt_change = 0;
    int passages = 0;
    for (const Straight& b : straights(r.g)) {
        const Vec3 end{b.centre[0] + b.dir[0] * (b.length / 2 - 0.03), b.centre[1] + b.dir[1] * (b.length / 2 - 0.03), 0};
        const double w = b.width / 2;
        const auto ma = crossings(r.t, r.ax, r.ay, b.centre, b.dir, w), mb = crossings(r.t, r.bx, r.by, b.centre, b.dir, w);
        const auto ea = crossings(r.t, r.ax, r.ay, end, b.dir, w), eb = crossings(r.t, r.bx, r.by, end, b.dir, w);
        for (size_t k = 0; k < std::min({ma.size(), mb.size(), ea.size(), eb.size()}); ++k, ++passages)
            belt_change = std::max(belt_change, std::abs(b.speed * ((eb[k].time - ea[k].time) - (mb[k].time - ma[k].time))));
    }
    CHECK(passages >= 5 * 3);  // 5 belts, at least 3 passages each
    CHECK(belt_change < 0.001);
    CHECK(s.min >= 0.10);
    CHECK(s.max <= 0.50);
}

TEST_CASE("tipping with std.belts' slip limit: at k = 16 kg/s the lighter the bottle, the more it tips") {
    // With max_force = 0.3 N per body (std.belts' default when measured; 0.1 N since issue 34) the pull is saturated while the
    // bottle is slower than the belt by more than 0.3 N / k: a force independent of the speed
    // error and of the mass, whose torque 0.3 N·|Σz| only bottles under 45 g cannot hold on
    // their base (M·g·r). Measured at 150 Hz: 10.6°, 8.9°, 0.5° (docs/experiments.md, Tipping).
    std::vector<double> peaks;
    for (double m : {20.0, 40.0, 80.0}) {
        CAPTURE(m);
        const BottleRun r = run_bottle("tipping.plant", {k_set(16), mass_set(m), "max_force=0.3 N"}, 1.5);
        const Tipping x = analyse_tipping(r.t, r.pitch, r.tilt, r.v);
        peaks.push_back(x.peak_tilt);
        CHECK(x.peak_tilt < 30);                     // rocks, does not fall
        CHECK(r.tilt.back() < 1);                    // ends upright
        CHECK(std::abs(r.v.back() - 1.0) < 0.01);    // at belt speed
        if (x.first.found) CHECK(x.first.side == -1);  // leaning back, top lagging
    }
    CAPTURE(peaks[0]);
    CAPTURE(peaks[1]);
    CAPTURE(peaks[2]);
    CHECK(peaks[0] > 5);  // the 20 g bottle rocks visibly
    CHECK(peaks[0] > peaks[1]);
    CHECK(peaks[1] > peaks[2]);
}

TEST_CASE("tipping: pulled at its bottom body only, a bottle falls over: the pull on the main body holds it up") {
    // tipping_bottom_pull.plant: the field reaches 1 cm above the band, so the law pulls only
    // the bottom body. On frictionless contacts the base is dragged forward under the main body,
    // which nothing pulls: every bottle falls on its back, at any k and mass (docs/experiments.md,
    // "Why light bottles tip least at high k").
    for (double k : {1.0, 16.0})
        for (double m : {20.0, 80.0}) {
            CAPTURE(k);
            CAPTURE(m);
            const BottleRun r = run_bottle("tipping_bottom_pull.plant", {k_set(k), mass_set(m)}, 1.5);
            CHECK(r.bottle.k_main == 0);
            CHECK(r.bottle.k_bottom == doctest::Approx(k));
            CHECK(r.tilt.back() > 80);
        }
    // With the field as high as std.belts' (12 cm) it is tipping.plant, step for step.
    const BottleRun probe = run_bottle("tipping_bottom_pull.plant", {k_set(16), mass_set(20), "reach=12 cm"}, 0.5);
    const BottleRun plant = run_bottle("tipping.plant", {k_set(16), mass_set(20)}, 0.5);
    REQUIRE(probe.pitch.size() == plant.pitch.size());
    double worst = 0;
    for (size_t i = 0; i < probe.pitch.size(); ++i) worst = std::max(worst, std::abs(probe.pitch[i] - plant.pitch[i]));
    CHECK(worst < 0.01);
}

TEST_CASE("rocking: let go leaning back, a bottle swings forwards a second time on a bare band, not on std.belts' belt") {
    // rocking.plant: a 20 g bottle let go at -tilt on its base's rear edge, on a belt standing
    // still. The rebound is the largest forward lean once the bottle is back on its base
    // (lean above -1°). Bullet's contact gives a bare band a second swing at most tilts
    // (measured 1.1°, 0.3°, 2.3°, 1.5°, 3.1° at 8, 10, 12, 15, 20°, the same for every mass);
    // std.belts' field (16 kg/s, 0.3 N per body, speed 0) takes it out at every tilt (at most
    // -0.02°), and so does a limit of 0.05 N, under what lifts a 20 g bottle at 1 m/s (0.13 N):
    // the law damps the rocking (docs/experiments.md, "The second swing: what the law allows").
    auto rebounds = [](const std::vector<std::string>& sets) {
        std::vector<double> out;
        for (double tilt : {8.0, 10.0, 12.0, 15.0, 20.0}) {
            std::vector<std::string> s = sets;
            s.push_back("tilt=" + std::to_string(tilt) + " deg");
            auto c = compile("rocking.plant", s);
            REQUIRE(c->ok());
            REQUIRE(frictionless(c->graph));
            const int32_t main = body_named(c->graph, "bottle.main");
            REQUIRE(main >= 0);
            Engine e(c->graph);
            std::vector<double> t{e.time()}, pitch{pitch_deg(e.body_pose(BodyId(main)).q, {1, 0, 0})};
            for (int i = 0; i < 150; ++i) {  // 1 s
                e.step();
                t.push_back(e.time());
                pitch.push_back(pitch_deg(e.body_pose(BodyId(main)).q, {1, 0, 0}));
            }
            CHECK(e.warnings().total() == 0);
            CHECK(pitch.front() == doctest::Approx(-tilt).epsilon(0.001));
            CHECK(std::abs(pitch.back()) < 1);  // ends upright
            const Rebound rb = analyse_rebound(t, pitch);
            REQUIRE_FALSE(std::isnan(rb.back_time));  // came back onto its base
            out.push_back(rb.rebound);
        }
        return out;
    };
    const std::vector<double> bare = rebounds({"k=0 kg/s"});
    const std::vector<double> belt = rebounds({});
    const std::vector<double> light = rebounds({"max_force=0.05 N"});
    const auto swings = std::count_if(bare.begin(), bare.end(), [](double x) { return x > 1; });
    INFO(fmt::format("rebounds (deg) at 8, 10, 12, 15, 20 deg: bare {:.2f}; std.belts {:.2f}; 0.05 N {:.2f}",
                     fmt::join(bare, ", "), fmt::join(belt, ", "), fmt::join(light, ", ")));
    CHECK(swings >= 3);
    CHECK(*std::max_element(bare.begin(), bare.end()) > 2);
    CHECK(*std::max_element(belt.begin(), belt.end()) < 0.3);
    CHECK(*std::max_element(light.begin(), light.end()) < 1);
    // On the bare band the motion is the same for every mass (every force scales with it).
    const std::vector<double> heavy = rebounds({"k=0 kg/s", "mass=80 g"});
    for (size_t i = 0; i < bare.size(); ++i) CHECK(heavy[i] == doctest::Approx(bare[i]).epsilon(1e-6));
}
