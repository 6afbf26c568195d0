// The analysis behind the three measurements of the original work (plants/experiments,
// scripts/experiments.sh): what a compiled experiment plant holds (the bottle, the belt
// it starts on), the conveyor law's exact solution for an upright bottle, and the
// numbers the summaries report (time to 95 % of belt speed, tilt and swings, distance
// statistics). Pure functions over the graph and over sampled series, shared by the
// `plant-analyse` tool and the unit tests.
#pragma once

#include "graph/graph.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace plant::experiments {

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>;  // x y z w, as in the graph and the traces

// ---- what the compiled plant holds ----

// A std.bottle instance: its main body and its small bottom body, read from the graph.
struct Bottle {
    int32_t main = -1, bottom = -1;  // Body ids
    double m_main = 0, m_bottom = 0; // kg
    // Σ over the bottle's bodies of the gains of the fields their centres of mass start
    // in (kg/s): the law pulls each such body with k·(v_target − v), whatever its mass.
    double gain_sum = 0;
    int32_t field = -1;              // the field the main body starts in (else the bottom body's)
    double belt_speed = 0;           // its target speed, m/s
    Vec3 belt_dir{1, 0, 0};          // its direction in the world
    // Each body's pull and lever, upright at the start: k_* the gain of the fields its
    // centre of mass starts in (kg/s), z_* its height above the bottle's centre of mass
    // (m). The law's torque about that centre, for a speed error e of both bodies, is
    // e·(k_main·z_main + k_bottom·z_bottom): the bottom body pulls below the centre.
    double k_main = 0, k_bottom = 0;
    double z_main = 0, z_bottom = 0;
    // The bottle's moment of inertia about the horizontal axis across its belt through its
    // centre of mass (kg·m²): the axis it tips about.
    double inertia = 0;
    // Gravity along the belt direction (m/s²): not 0 where the band slopes.
    double gravity_along = 0;
    double mass() const { return m_main + m_bottom; }
    double lever_sum() const { return z_main + z_bottom; }
};

// Finds the bottle whose bodies are `<name>.main` and `<name>.bottom` (e.g. "bottle").
// False with `error` set when it is not there.
bool find_bottle(const graph::Graph& g, std::string_view name, Bottle& out, std::string& error);

// Is `p` inside the box of a force field (fields fixed in the world, at their start pose)?
bool in_some_field(const graph::Graph& g, const Vec3& p);
// The first enabled field whose box holds `p` at the start, or -1 (a bare band).
int32_t field_at(const graph::Graph& g, const Vec3& p);
// The body whose component path is `path` (e.g. "bottle.main"), or -1.
int32_t body_named(const graph::Graph& g, const std::string& path);

// Do all bodies have friction 0 and restitution 0 (the original setup)?
bool frictionless(const graph::Graph& g);

// ---- the conveyor law ----

// Speed along the belt of an upright bottle on a belt whose field pulls its bodies with
// gains summing to `gain_sum`: the exact solution of M·dv/dt = gain_sum·(v_target − v),
//   v(t) = v_target + (v0 − v_target)·exp(−gain_sum·t / M).
double upright_speed(double t, double v0, double v_target, double gain_sum, double mass);

// The time at which `v` first reaches `fraction` of `target` (linear interpolation between
// samples); NaN when it never does.
double time_to_fraction(const std::vector<double>& t, const std::vector<double>& v, double target, double fraction);

// The same for upright_speed from rest: −M/gain_sum · ln(1 − fraction).
double upright_time_to_fraction(double fraction, double gain_sum, double mass);

// The law as the runtime steps it for an upright bottle (docs/runtime.md, "Rigid
// groups"; runtime/engine/conveyor.cpp): the bottle is one rigid group, and one step
// solves (D/s + dt·A)·(Δv, Δω) = dt·A·(e, 0) in its speed along the belt and its
// rotation about the tipping axis, with D = diag(M, I), A = Σ k_i·(1, z_i)ᵀ(1, z_i) and
// the stretch s = (exp(a) − 1)/a, a = Σk_i·dt/M. The contact with the band then stops the
// rotation, so each step removes the same fraction of the speed error e:
//   runtime_step_fraction = Δv / e.
// For a body without lever (z_i = 0) it is 1 − exp(−a), the exact solution; the levers
// of the bottom body make it smaller: part of each step's pull goes into a rotation the
// band takes away again.
double runtime_step_fraction(const Bottle& b, double dt);
// The speed after t (a whole number of steps dt, interpolated between them as an
// exponential): v_target + (v0 − v_target)·(1 − fraction)^(t/dt).
double runtime_upright_speed(double t, double v0, double v_target, const Bottle& b, double dt);

// How far a body's z axis (the bottle's axis) leans along `dir`, a unit vector: the axis
// dotted with `dir`, the sine of pitch_deg. < 0 while the top lags behind.
double lean_along(const Quat& q, const Vec3& dir);

// The law's exact solution for a bottle that leans. Nothing but the law and gravity acts
// along the belt (frictionless contacts push across the band), and body i, at height z_i
// above the centre of mass on the bottle's axis, moves along the belt at V + z_i·dλ/dt,
// λ the lean (lean_along). So the centre of mass's speed V obeys
//   M·dV/dt = Σk_i·(v_target − V) − (Σ k_i·z_i)·dλ/dt + M·g_along,
// linear in V, with the lean as its input. Solved exactly in time with λ linear between
// the samples: over a step of length h with e = exp(−Σk·h/M) and
// V* = v_target + (M·g_along − Σk_i z_i·Δλ/h)/Σk,
//   V(t + h) = V* + (V(t) − V*)·e.
// With λ constant it is upright_speed. Returns V at the samples t, from V(t[0]) = v0.
std::vector<double> leaning_speed(const std::vector<double>& t, const std::vector<double>& lean, double v0,
                                  const Bottle& b);

struct Traction {
    double t95 = 0;            // simulated time to 95 % of belt speed, s
    double t95_analytic = 0;   // the same for the exact upright solution (upright_speed)
    double t95_runtime = 0;    // the same for runtime_upright_speed
    double max_dev = 0;        // largest |simulated − exact upright solution|, m/s, signed
    double max_dev_time = 0;   // when
    double max_dev_runtime = 0;       // largest |simulated − runtime_upright_speed|, m/s, signed
    double max_dev_runtime_time = 0;  // when
    double max_dev_lean = 0;          // largest |simulated − leaning_speed|, m/s, signed (0 without a lean)
    double max_dev_lean_time = 0;     // when
    double overshoot = 0;      // max(v) − belt speed, m/s (≤ 0: none)
    double max_drop = 0;       // largest fall below the speed reached before, m/s
    double final_speed = 0;    // last sample
};
// `lean`: the bottle's lean per sample (lean_along), for max_dev_lean; empty: not known.
Traction analyse_traction(const std::vector<double>& t, const std::vector<double>& v, const Bottle& b, double dt,
                          const std::vector<double>& lean = {});

// ---- tilt ----

// The angle between a body's z axis (the bottle's axis) and the vertical, in degrees.
double tilt_deg(const Quat& q);
// The same, signed in the vertical plane along `dir`: > 0 when the top leans towards
// `dir` (forward on a belt running along `dir`), < 0 when it lags behind.
double pitch_deg(const Quat& q, const Vec3& dir);

struct Swing {
    bool found = false;
    double peak = 0;  // |pitch| at the peak, degrees
    double time = 0;  // s
    int side = 0;     // sign of the pitch at the peak: -1 backwards, +1 forwards
};
struct Tipping {
    double peak_tilt = 0, peak_time = 0;  // largest tilt over the run
    Swing first;    // the first excursion of |pitch| beyond the threshold
    Swing second;   // the largest excursion after the first one ended
    double later_max = 0;  // largest tilt after the first swing ended (contact jitter if no second swing)
    double final_tilt = 0, final_speed = 0;
};
// A swing is a run of samples with |pitch| > threshold_deg on one side of the vertical.
Tipping analyse_tipping(const std::vector<double>& t, const std::vector<double>& pitch,
                        const std::vector<double>& tilt, const std::vector<double>& speed,
                        double threshold_deg = 1.0);

// ---- rocking ----

// A bottle let go leaning back (plants/experiments/rocking.plant): when it is back on its
// base (the first sample whose lean `pitch` is above -1°) and its rebound, the largest
// forward lean from then on, in degrees (beyond 1°: a second swing). NaN when it never
// comes back.
struct Rebound {
    double back_time = NAN;
    double rebound = NAN;
};
Rebound analyse_rebound(const std::vector<double>& t, const std::vector<double>& pitch);

// ---- spacing ----

struct Stats {
    double min = 0, max = 0, mean = 0, variance = 0;  // population variance
    size_t n = 0;
};
Stats stats(const std::vector<double>& x);

// Laps completed: how often the path crosses, moving towards +`dir`, the line through
// its first point perpendicular to `dir` (within `half_width` of that point).
int laps(const std::vector<double>& x, const std::vector<double>& y, const Vec3& dir, double half_width);

// The gap along the track between a bottle in front (a) and one behind (b), per sample i:
// how far b travels along its own path (in the horizontal plane) from sample i until it
// crosses the line through a's position at i perpendicular to a's heading there (a's
// displacement over its last centimetre of path), within `reach` of that position. NaN
// where b does not get there within `max_gap` of path (at the end of the series). On one
// straight belt it is the distance between the two; around a corner it follows b's path.
std::vector<double> track_gap(const std::vector<double>& ax, const std::vector<double>& ay,
                              const std::vector<double>& bx, const std::vector<double>& by, double reach,
                              double max_gap);

// A straight belt of the track: a world-fixed field whose pull runs along the longer side
// of its box, at least twice its width (not a corner's square band, not an arc's piece).
struct Straight {
    std::string name;  // its top-level component, e.g. "b1"
    Vec3 centre{}, dir{};
    double length = 0, width = 0, speed = 0;
};
std::vector<Straight> straights(const graph::Graph& g);

// The moments a path crosses, moving along `dir`, the line through `point` across `dir`
// (within `half_width` of `point`), with the path's offset along that line there (> 0 to
// the left of `dir`), interpolated between the samples.
struct Crossing {
    double time = 0, lateral = 0;
};
std::vector<Crossing> crossings(const std::vector<double>& t, const std::vector<double>& x, const std::vector<double>& y,
                                const Vec3& point, const Vec3& dir, double half_width);

// ---- traces ----

// A CSV trace as `plant run --trace` writes it: a header line, then numbers.
struct Table {
    std::vector<std::string> names;
    std::vector<std::vector<double>> cols;
    size_t rows() const { return cols.empty() ? 0 : cols[0].size(); }
    // The column named `name`, or null.
    const std::vector<double>* col(std::string_view name) const;
};
bool read_csv(std::istream& in, Table& out, std::string& error);
bool read_csv_file(const std::string& path, Table& out, std::string& error);

}  // namespace plant::experiments
