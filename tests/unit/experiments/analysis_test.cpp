// tools/experiments: the analysis functions on inputs whose answers are known by hand.
#include "analysis.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <sstream>

using namespace plant::experiments;

namespace {

Quat about_y(double deg) {  // a rotation about +y: tips the z axis towards +x
    const double h = deg * std::numbers::pi / 360;
    return {0, std::sin(h), 0, std::cos(h)};
}

}  // namespace

TEST_CASE("experiments: the upright solution and its time to a fraction of the target") {
    CHECK(upright_speed(0, 0, 0.5, 2, 0.04) == 0);
    CHECK(upright_speed(0.02, 0, 0.5, 2, 0.04) == doctest::Approx(0.5 * (1 - std::exp(-1.0))));
    CHECK(upright_speed(1e3, 0.2, 0.5, 2, 0.04) == doctest::Approx(0.5));
    CHECK(upright_time_to_fraction(0.95, 2, 0.04) == doctest::Approx(0.02 * std::log(20.0)));
    // Sampled: linear interpolation between the samples around the level.
    const std::vector<double> t{0, 1, 2, 3}, v{0, 0.4, 0.6, 1.0};
    CHECK(time_to_fraction(t, v, 1.0, 0.5) == doctest::Approx(1.5));
    CHECK(time_to_fraction(t, v, 1.0, 1.0) == doctest::Approx(3));
    CHECK(std::isnan(time_to_fraction(t, v, 2.0, 0.95)));
    CHECK(time_to_fraction(t, {0, -0.4, -0.6, -1.0}, -1.0, 0.5) == doctest::Approx(1.5));  // a belt running backwards
}

TEST_CASE("experiments: the runtime's step is exact for a bottle without lever arms, slower with them") {
    Bottle b;
    b.m_main = 0.036;
    b.m_bottom = 0.004;
    b.k_main = b.k_bottom = 4;
    b.inertia = 2.8e-5;
    const double dt = 1 / 150.0, a = 8 * dt / 0.04;
    CHECK(runtime_step_fraction(b, dt) == doctest::Approx(1 - std::exp(-a)).epsilon(1e-12));
    CHECK(runtime_upright_speed(3 * dt, 0, 0.5, b, dt) == doctest::Approx(upright_speed(3 * dt, 0, 0.5, 8, 0.04)));
    b.z_main = 0.0037;
    b.z_bottom = -0.0333;  // the bottom body pulls below the centre of mass
    const double f = runtime_step_fraction(b, dt);
    CHECK(f < 1 - std::exp(-a));
    CHECK(f > 0.5);
    b.k_main = b.k_bottom = 0;
    CHECK(runtime_step_fraction(b, dt) == 0);
}

TEST_CASE("experiments: the law's exact solution for a leaning bottle") {
    Bottle b;
    b.m_main = 0.036;
    b.m_bottom = 0.004;
    b.k_main = b.k_bottom = 1;
    b.gain_sum = 2;
    b.z_main = 0.0037;
    b.z_bottom = -0.0333;
    b.belt_speed = 0.5;
    const double M = b.mass(), K = 2, S = b.z_main + b.z_bottom;
    // A bottle that does not lean follows the upright solution.
    std::vector<double> t, still;
    for (int i = 0; i <= 60; ++i) t.push_back(i / 150.0), still.push_back(0.01);
    const std::vector<double> v = leaning_speed(t, still, 0, b);
    for (size_t i = 0; i < t.size(); ++i) CHECK(v[i] == doctest::Approx(upright_speed(t[i], 0, 0.5, K, M)));
    // A smooth lean, sampled every 2 ms: against M·dV/dt = K·(v_belt − V) − S·dλ/dt
    // integrated by classical Runge-Kutta every microsecond with the exact dλ/dt.
    const double A = 0.03, w = 40;
    auto lean = [&](double x) { return -A * std::sin(w * x); };
    auto rate = [&](double x, double V) { return (K * (0.5 - V) - S * (-A * w * std::cos(w * x))) / M; };
    std::vector<double> ts, ls;
    for (int i = 0; i <= 100; ++i) ts.push_back(i * 0.002), ls.push_back(lean(i * 0.002));
    const std::vector<double> law = leaning_speed(ts, ls, 0, b);
    double V = 0, x = 0, worst = 0;
    const double h = 1e-6;
    for (size_t i = 1; i < ts.size(); ++i) {
        while (x < ts[i] - h / 2) {
            const double k1 = rate(x, V), k2 = rate(x + h / 2, V + h / 2 * k1), k3 = rate(x + h / 2, V + h / 2 * k2),
                         k4 = rate(x + h, V + h * k3);
            V += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
            x += h;
        }
        worst = std::max(worst, std::abs(law[i] - V));
    }
    CHECK(worst < 1e-3 * 0.5);                            // within 0.1 % of the belt speed
    CHECK(std::abs(law[50] - upright_speed(ts[50], 0, 0.5, K, M)) > 0.01);  // and the lean matters
    // On a slope gravity shifts the speed the law settles at by M·g_along/Σk.
    b.gravity_along = -0.1;
    std::vector<double> tl, flat;
    for (int i = 0; i <= 300; ++i) tl.push_back(i / 150.0), flat.push_back(0);
    CHECK(leaning_speed(tl, flat, 0, b).back() == doctest::Approx(0.5 - M * 0.1 / K));
    // analyse_traction reports the largest gap to it.
    b.gravity_along = 0;
    std::vector<double> sim = leaning_speed(ts, ls, 0, b);
    sim[30] -= 0.004;
    const Traction tr = analyse_traction(ts, sim, b, 0.002, ls);
    CHECK(tr.max_dev_lean == doctest::Approx(-0.004));
    CHECK(tr.max_dev_lean_time == doctest::Approx(ts[30]));
    CHECK(analyse_traction(ts, sim, b, 0.002).max_dev_lean == 0);  // no lean given
}

TEST_CASE("experiments: traction numbers from a sampled curve") {
    Bottle b;
    b.m_main = 0.04;
    b.k_main = 2;
    b.belt_speed = 0.5;
    b.gain_sum = 2;
    const double dt = 0.01;
    std::vector<double> t, v;
    for (int i = 0; i <= 100; ++i) {
        t.push_back(i * dt);
        v.push_back(upright_speed(i * dt, 0, 0.5, 2, 0.04));
    }
    v[50] += 0.01;  // a bump above the target, then a drop back
    const Traction x = analyse_traction(t, v, b, dt);
    CHECK(x.t95 == doctest::Approx(upright_time_to_fraction(0.95, 2, 0.04)).epsilon(0.02));
    CHECK(x.max_dev == doctest::Approx(0.01));
    CHECK(x.max_dev_time == doctest::Approx(0.5));
    CHECK(x.overshoot == doctest::Approx(0.01).epsilon(0.01));
    CHECK(x.max_drop == doctest::Approx(0.01).epsilon(0.01));
    CHECK(x.final_speed == doctest::Approx(0.5));
}

TEST_CASE("experiments: tilt and signed lean of a body's z axis") {
    CHECK(tilt_deg({0, 0, 0, 1}) == doctest::Approx(0));
    CHECK(tilt_deg(about_y(30)) == doctest::Approx(30));
    CHECK(tilt_deg(about_y(-30)) == doctest::Approx(30));
    CHECK(pitch_deg(about_y(30), {1, 0, 0}) == doctest::Approx(30));    // top towards +x: forwards
    CHECK(pitch_deg(about_y(30), {-1, 0, 0}) == doctest::Approx(-30));  // on a belt running along -x
    CHECK(pitch_deg(about_y(30), {0, 1, 0}) == doctest::Approx(0));     // a lean across the belt
    CHECK(lean_along(about_y(30), {1, 0, 0}) == doctest::Approx(0.5));   // the sine of the pitch
    CHECK(lean_along(about_y(-30), {1, 0, 0}) == doctest::Approx(-0.5));
    const double h = 10 * std::numbers::pi / 360;
    CHECK(tilt_deg({std::sin(h), 0, 0, std::cos(h)}) == doctest::Approx(10));  // about x
}

TEST_CASE("experiments: swings are excursions beyond the threshold, one side at a time") {
    std::vector<double> t, pitch, tilt, speed;
    auto add = [&](double p) {
        t.push_back(double(t.size()) * 0.01);
        pitch.push_back(p);
        tilt.push_back(std::abs(p));
        speed.push_back(1);
    };
    for (double p : {0.0, -0.5, -2.0, -5.0, -3.0, -0.2, 0.3, 1.5, 2.5, 0.4, -0.3, -1.2, 0.1}) add(p);
    const Tipping x = analyse_tipping(t, pitch, tilt, speed, 1.0);
    CHECK(x.peak_tilt == 5.0);
    CHECK(x.peak_time == doctest::Approx(0.03));
    CHECK(x.first.found);
    CHECK(x.first.side == -1);
    CHECK(x.first.peak == 5.0);
    CHECK(x.second.found);
    CHECK(x.second.side == 1);  // the largest later swing, on the other side
    CHECK(x.second.peak == 2.5);
    CHECK(x.later_max == 2.5);
    CHECK(x.final_tilt == doctest::Approx(0.1));

    std::vector<double> quiet(t.size(), 0.4);
    const Tipping q = analyse_tipping(t, quiet, quiet, speed, 1.0);
    CHECK_FALSE(q.first.found);
    CHECK_FALSE(q.second.found);
    CHECK(q.peak_tilt == 0.4);
}

TEST_CASE("experiments: statistics and laps") {
    const Stats s = stats({1, 2, 3, 4});
    CHECK(s.min == 1);
    CHECK(s.max == 4);
    CHECK(s.mean == 2.5);
    CHECK(s.variance == doctest::Approx(1.25));
    CHECK(s.n == 4);

    // Three and a half turns on a circle, starting at its bottom heading +x.
    std::vector<double> x, y;
    for (int i = 0; i <= 700; ++i) {
        const double a = i * 3.5 * 2 * std::numbers::pi / 700;
        x.push_back(std::sin(a));
        y.push_back(1 - std::cos(a));
    }
    CHECK(laps(x, y, {1, 0, 0}, 0.1) == 3);
    CHECK(laps(x, y, {-1, 0, 0}, 0.1) == 0);  // never passes the gate the other way
}

TEST_CASE("experiments: the gap along the track, on a straight line and around a right angle") {
    // b follows a's path 0.2 m behind, both at 0.01 m per sample: along +x to (1, 0), then −y.
    auto path = [](double s, double& x, double& y) {
        if (s <= 1) x = s, y = 0;
        else x = 1, y = -(s - 1);
    };
    std::vector<double> ax, ay, bx, by;
    for (int i = 0; i <= 300; ++i) {
        double x, y;
        path(0.2 + 0.01 * i, x, y);
        ax.push_back(x), ay.push_back(y);
        path(0.01 * i, x, y);
        bx.push_back(x), by.push_back(y);
    }
    const std::vector<double> gap = track_gap(ax, ay, bx, by, 0.1, 1.0);
    REQUIRE(gap.size() == ax.size());
    // Along the track the gap is 0.2 m everywhere, though the Manhattan distance around the
    // corner is too and the straight one is less; at the end b has not got there yet.
    for (size_t i = 0; i + 21 < gap.size(); ++i) {  // the last 20 samples: b reaches a's point at the end or not at all
        CAPTURE(i);
        CHECK(gap[i] == doctest::Approx(0.2).epsilon(1e-9));
    }
    CHECK(std::isnan(gap.back()));
    // b at half speed on the outgoing leg from sample 110: the gap grows.
    std::vector<double> slow_bx = bx, slow_by = by;
    for (size_t i = 0; i < slow_bx.size(); ++i) {
        double x, y;
        path(i <= 110 ? 0.01 * double(i) : 1.1 + 0.005 * double(i - 110), x, y);
        slow_bx[i] = x, slow_by[i] = y;
    }
    const std::vector<double> slow = track_gap(ax, ay, slow_bx, slow_by, 0.1, 1.0);
    CHECK(slow[90] == doctest::Approx(0.2));   // b reaches a's point at sample 110, before it slows
    CHECK(slow[120] == doctest::Approx(0.25)); // a at 1.4 m of path, b at 1.15 m
    // A path that never passes a's point within reach has no gap.
    std::vector<double> far_by(by.size(), 0.5);
    const std::vector<double> none = track_gap(ax, ay, bx, far_by, 0.1, 1.0);
    CHECK(std::isnan(none[0]));
}

TEST_CASE("experiments: reading a trace") {
    std::istringstream good("time,a.x,a.y\n0,1,2\n0.5,3,4e-3\n");
    plant::experiments::Table t;
    std::string err;
    REQUIRE(read_csv(good, t, err));
    CHECK(t.rows() == 2);
    REQUIRE(t.col("a.y"));
    CHECK((*t.col("a.y"))[1] == doctest::Approx(0.004));
    CHECK(t.col("b") == nullptr);

    std::istringstream short_row("time,a\n0,1\n1\n");
    CHECK_FALSE(read_csv(short_row, t, err));
    CHECK(err.find("line 3") != std::string::npos);
    std::istringstream text("time,a\n0,x\n");
    CHECK_FALSE(read_csv(text, t, err));
    std::istringstream empty("");
    CHECK_FALSE(read_csv(empty, t, err));
}

TEST_CASE("experiments: a rebound is the largest forward lean once the bottle is back on its base") {
    const std::vector<double> t{0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07};
    // Let go at -10°, back above -1° at 0.03 s, then forwards by 1.5° and back.
    const Rebound r = analyse_rebound(t, {-10, -8, -3, -0.5, 0.8, 1.5, -0.6, -2});
    CHECK(r.back_time == doctest::Approx(0.03));
    CHECK(r.rebound == doctest::Approx(1.5));
    // Coming back without leaning forwards: the rebound is the largest lean after, below 0.
    const Rebound flat = analyse_rebound(t, {-10, -6, -2, -0.9, -0.3, -0.1, -0.05, -0.1});
    CHECK(flat.back_time == doctest::Approx(0.03));
    CHECK(flat.rebound == doctest::Approx(-0.05));
    // Never back on its base (fell over, or held back): NaN.
    const Rebound never = analyse_rebound(t, {-10, -12, -20, -40, -60, -80, -90, -90});
    CHECK(std::isnan(never.back_time));
    CHECK(std::isnan(never.rebound));
}
