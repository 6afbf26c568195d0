// Steady transport (docs/runtime.md, "Steady transport") on against off: bottles that ride a
// belt alone leave Bullet's solver and come back before anything touches them, and nothing a
// user observes changes beyond the last digits: the same counters, the same bottles taken by
// the same exits in the same steps, within 1 mm of the same places; the three measurements'
// traces byte for byte.
#include "../compiler/compile_helper.h"
#include "../stdlib/lookup.h"
#include "app/run_flags.h"
#include "engine/engine.h"
#include "engine/run.h"
#include "engine/runtime.h"
#include "graph/kinds.h"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace plant;
using namespace plant::test;
using plant::engine::Engine;

namespace {

// What a run shows, step by step.
struct Seen {
    struct Taken {
        int64_t step;
        int32_t exit, object;
        std::string id;
    };
    struct Left {  // a body that left the world, where it was the step before
        int64_t step;
        int32_t body;
        graph::Vec3 at;
    };
    std::vector<Taken> taken;
    std::vector<Left> left;
    std::vector<int64_t> issued, exits, enters, tokens;
    std::vector<graph::DoId> lost;
    engine::Warnings warn;
    std::vector<std::vector<graph::Vec3>> track;  // per step, the listed bodies' centres of mass
    int64_t left_solver = 0, rejoined = 0, guided = 0, coasted = 0, rested = 0;
    std::array<int64_t, engine::kOnSolverReasons> why{};  // unit-steps on the solver, by why
    // Steps in which the units' own reasons (Steady::why_of) did not add up to what the
    // step added to why(), and the unit-steps they put on the solver.
    int64_t why_apart = 0, why_units = 0;
    int64_t on_solver(engine::OnSolver w) const { return why[size_t(w)]; }
};

void finish(Engine& e, Seen& s) {
    const graph::Graph& g = e.graph();
    for (size_t i = 0; i < g.sources.size(); ++i) s.issued.push_back(e.issued(graph::SourceId(int32_t(i))));
    for (size_t i = 0; i < g.exits.size(); ++i) s.exits.push_back(e.taken(graph::ExitId(int32_t(i))));
    for (size_t i = 0; i < g.triggers.size(); ++i) s.enters.push_back(e.trigger_enters(graph::TriggerId(int32_t(i))));
    for (size_t i = 0; i < g.places.size(); ++i) s.tokens.push_back(e.tokens(graph::PlaceId(int32_t(i))));
    s.lost.assign(e.lost().begin(), e.lost().end());
    s.warn = e.warnings();
    s.left_solver = e.internals().steady.left;
    s.rejoined = e.internals().steady.rejoined;
    s.guided = e.internals().steady.guided;
    s.coasted = e.internals().steady.coasted;
    s.rested = e.internals().steady.rested;
    s.why = e.internals().steady.why();
}

// Runs g for `steps` with steady transport on or off; `inputs` are (step, slot) pairs.
// `lists`: whether each unit keeps its list of what is filed near it (Steady::Near); then
// `listed` counts the units holding a list of the filings as they stand at the end, and how
// often the static pieces and the fields were filed.
struct Listed {
    int64_t units = 0;
    uint64_t pieces = 0, fields = 0;
};
Seen run(const graph::Graph& g, bool steady, int64_t steps, const std::vector<int32_t>& tracked = {},
         const std::vector<std::pair<int64_t, int32_t>>& inputs = {}, bool lists = true, Listed* listed = nullptr) {
    engine::Options o;
    o.steady_transport = steady;
    Engine e(g, o);
    e.internals().steady.near_on = lists;
    Seen s;
    for (const graph::Exit& x : g.exits) {
        e.watch(graph::SlotId(g.comps[x.comp].slot_adr + graph::exitslot::object));
        e.watch(graph::SlotId(g.comps[x.comp].slot_adr + graph::exitslot::id));
    }
    std::vector<graph::Vec3> last(g.bodies.size());
    std::vector<uint8_t> in(g.bodies.size());
    for (size_t b = 0; b < g.bodies.size(); ++b) {
        in[b] = e.body_in_world(graph::BodyId(int32_t(b)));
        last[b] = e.body_com(graph::BodyId(int32_t(b)));
    }
    std::array<int64_t, engine::kOnSolverReasons> why_before = e.internals().steady.why();
    for (int64_t i = 0; i < steps; ++i) {
        for (const auto& [at, slot] : inputs)
            if (at == i) e.input(graph::SlotId(slot));
        e.step();
        {
            const engine::Steady& S = e.internals().steady;
            std::array<int64_t, engine::kOnSolverReasons> units{};
            for (size_t b = 0; b < S.why_of.size(); ++b)
                if (const engine::OnSolver w = S.why_of[graph::BodyId(int32_t(b))]; w != engine::OnSolver::kCount)
                    ++units[size_t(w)], ++s.why_units;
            const std::array<int64_t, engine::kOnSolverReasons> why_now = S.why();
            for (size_t k = 0; k < units.size(); ++k)
                if (why_now[k] - why_before[k] != units[k]) {
                    ++s.why_apart;
                    break;
                }
            why_before = why_now;
        }
        for (size_t x = 0; x < g.exits.size(); ++x) {
            const graph::Adr<graph::Slot> s0 = g.comps[g.exits[graph::ExitId(x)].comp].slot_adr;
            if (!e.active(graph::SlotId(s0 + graph::exitslot::taken))) continue;
            s.taken.push_back({e.steps(), int32_t(x), int32_t(e.value(graph::SlotId(s0 + graph::exitslot::object))[0]),
                               std::string(e.str(int32_t(e.value(graph::SlotId(s0 + graph::exitslot::id))[0])))});
        }
        for (size_t b = 0; b < g.bodies.size(); ++b) {
            if (g.bodies[graph::BodyId(b)].mode != graph::BodyMode::Dynamic) continue;
            const bool now = e.body_in_world(graph::BodyId(int32_t(b)));
            if (in[b] && !now) s.left.push_back({e.steps(), int32_t(b), last[b]});
            in[b] = now;
            if (now) last[b] = e.body_com(graph::BodyId(int32_t(b)));
        }
        if (!tracked.empty()) {
            s.track.emplace_back();
            for (int32_t b : tracked)  // NaN once out of the world (a parked body stays where it was taken)
                s.track.back().push_back(e.body_in_world(graph::BodyId(b)) ? e.body_com(graph::BodyId(b))
                                                                          : graph::Vec3{NAN, NAN, NAN});
        }
    }
    finish(e, s);
    // Each unit's own reason adds up, step by step, to what why() counts.
    CHECK(s.why_apart == 0);
    int64_t why_total = 0;
    for (int64_t n : s.why) why_total += n;
    CHECK(s.why_units == why_total);
    if (listed) {
        const engine::Steady& S = e.internals().steady;
        listed->pieces = S.grid_builds, listed->fields = e.internals().st.field_builds;
        for (const engine::Steady::Near& n : S.near)
            listed->units += n.epoch == S.grid_builds + e.internals().st.field_builds && n.hazards != engine::Steady::kFull;
    }
    return s;
}

double distance(const graph::Vec3& a, const graph::Vec3& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// How far two runs are apart where bodies left the world and along the tracked bodies.
struct Apart {
    int64_t steps = 0;   // the largest difference in the step a body left the world in
    double at = 0;       // m, the largest distance between where it was then
    double track = 0;    // m, the largest distance between tracked bodies in one step
};

// Two runs agree on everything counted (sources, exits, every trigger's entries, every place's
// tokens, the objects lost, the warnings) and on which object each exit took, in what order,
// with what code. Returns how far apart they are in time and space.
Apart compare(const Seen& a, const Seen& b) {
    CHECK(a.issued == b.issued);
    CHECK(a.exits == b.exits);
    CHECK(a.enters == b.enters);
    CHECK(a.tokens == b.tokens);
    CHECK(a.lost == b.lost);
    CHECK(a.warn.total() == b.warn.total());
    Apart d;
    REQUIRE(a.taken.size() == b.taken.size());
    for (size_t i = 0; i < a.taken.size(); ++i) {
        CAPTURE(i);
        CHECK(a.taken[i].exit == b.taken[i].exit);
        CHECK(a.taken[i].object == b.taken[i].object);
        CHECK(a.taken[i].id == b.taken[i].id);
        d.steps = std::max(d.steps, std::abs(a.taken[i].step - b.taken[i].step));
    }
    REQUIRE(a.left.size() == b.left.size());
    for (size_t i = 0; i < a.left.size(); ++i) {
        CAPTURE(i);
        CHECK(a.left[i].body == b.left[i].body);
        d.steps = std::max(d.steps, std::abs(a.left[i].step - b.left[i].step));
        d.at = std::max(d.at, distance(a.left[i].at, b.left[i].at));
    }
    REQUIRE(a.track.size() == b.track.size());
    for (size_t i = 0; i < a.track.size(); ++i)
        for (size_t k = 0; k < a.track[i].size(); ++k)
            if (!std::isnan(a.track[i][k][0]) && !std::isnan(b.track[i][k][0]))  // while both are in the world
                d.track = std::max(d.track, distance(a.track[i][k], b.track[i][k]));
    MESSAGE(a.taken.size() << " taken, " << a.left.size() << " bodies left the world; apart by at most " << d.steps
                           << " steps, " << d.at * 1000 << " mm where they left, " << d.track * 1000
                           << " mm along the tracked bodies; " << a.left_solver << " times off the solver, "
                           << a.rejoined << " back");
    return d;
}

// On and off the same: within `tol` all along, and where and when bodies left the world,
// up to `steps` steps (a trigger takes a bottle by its bounding box, and a hull's box turns with
// it: a bottle that turned about its axis a little otherwise than on the solver meets an exit's
// trigger a step earlier or later, a step's way from where it would have).
void same(const Seen& on, const Seen& off, double tol = 1e-3, int64_t steps = 0, double step_way = 0) {
    const Apart d = compare(on, off);
    CHECK(d.steps <= steps);
    CHECK(d.at < tol + double(d.steps) * step_way);
    CHECK(d.track < tol);
    CHECK(off.left_solver == 0);
}

// On against off differs no more than a 1 µm nudge does with steady transport off (where
// bottles meet, a run is chaotic), with room for a trigger's step and 1 cm. Returns the nudge's
// spread.
Apart within_nudge(const Seen& on, const Seen& off, const Seen& off_nudged) {
    const Apart chaos = compare(off_nudged, off), d = compare(on, off);
    CHECK(d.steps <= chaos.steps + 2);
    CHECK(d.at <= chaos.at + 0.01);
    CHECK(d.track <= chaos.track + 0.01);
    return chaos;
}

// The same against the largest spread of several nudges (of a few µm each): where a run
// branches (a queue buckling to the left or to the right of a pin), one nudge may happen to
// take the same branch and another the other one.
Apart within_nudges(const Seen& on, const Seen& off, const std::vector<Seen>& off_nudged) {
    Apart chaos;
    for (const Seen& n : off_nudged) {
        const Apart c = compare(n, off);
        chaos.steps = std::max(chaos.steps, c.steps);
        chaos.at = std::max(chaos.at, c.at);
        chaos.track = std::max(chaos.track, c.track);
    }
    const Apart d = compare(on, off);
    CHECK(d.steps <= chaos.steps + 2);
    CHECK(d.at <= chaos.at + 0.01);
    CHECK(d.track <= chaos.track + 0.01);
    return chaos;
}

// Two runs the same to the bit: every tracked body's place in every step (NaN, out of the
// world, alike), when and where bodies left the world and what the exits took, and each
// step's verdicts (how often units left the solver and came back, and why they were on it).
void identical(const Seen& a, const Seen& b) {
    const Apart d = compare(a, b);
    CHECK(d.steps == 0);
    CHECK(d.at == 0);
    REQUIRE(a.track.size() == b.track.size());
    int64_t differ = 0;
    for (size_t i = 0; i < a.track.size(); ++i)
        for (size_t k = 0; k < a.track[i].size(); ++k)
            for (int j = 0; j < 3; ++j) {
                const double x = a.track[i][k][size_t(j)], y = b.track[i][k][size_t(j)];
                differ += !(x == y || (std::isnan(x) && std::isnan(y)));
            }
    CHECK(differ == 0);
    CHECK(a.left_solver == b.left_solver);
    CHECK(a.rejoined == b.rejoined);
    CHECK(a.coasted == b.coasted);
    CHECK(a.rested == b.rested);
    CHECK(a.guided == b.guided);
    CHECK(a.why == b.why);
}

// Three bottles on a belt turned by `angle` (degrees) before a straight one with an exit: they
// come onto the straight one drifting across it towards its rail. `nudge`: how much further on
// each starts.
std::string rail_plant(const std::string& angle, const char* nudge) {
    const std::string a = "(" + angle + " deg)";
    return R"(
import std.belts, std.bottle
plant Rail {
    feed: Belt(length = 1 m) at (-1 m * cos)" + a + ", 1 m * sin" + a + ", 0 m) rotate z by -" + angle + R"( deg
    run: Belt(length = 3 m)
    for i in 0 .. 3 {
        b[i]: Bottle at ((-1 m + 10 cm + i * 30 cm + )" + nudge + ") * cos" + a + ", -(-1 m + 10 cm + i * 30 cm) * sin" + a + R"(,
                         -2 mm + (10 cm + i * 30 cm) / 1 m * 2 mm) rotate z by -)" + angle + R"( deg
    }
    trigger out_volume at (2.9 m, 0 m, 4 cm) { extent = (4 cm, 10 cm, 10 cm) }
    exit done { trigger = out_volume }
}
)";
}

// plants/bottling.plant, and how many of its steps `seconds` take.
graph::Graph bottling(int seconds, int64_t& steps) {
    Compilation c;
    compile_repo_file("plants/bottling.plant", c);
    REQUIRE(c.ok());
    steps = int64_t(seconds * c.graph.settings.rate + 0.5);
    return c.graph;
}


}  // namespace

// A line whose bottles queue at separators is chaotic: with steady transport off, belts running
// 0.2 ppm faster (belt_speed = 50.00001 cm/s) take the same bottles in the same order, but up to
// 18 steps earlier or later and 37 mm apart where they leave the world (measured over 600 s).
// Steady transport changes the last digits as such a nudge does: the counters and the
// commissioning order are the same, and the times and places stay within what the nudge
// gives, with room (measured on against off: 19 steps, 39 mm).
TEST_CASE("steady transport: the bottling plant over 600 s counts, routes and commissions the same bottles on and off") {
    int64_t steps = 0;
    const graph::Graph g = bottling(PLANT_SANITIZED ? 120 : 600, steps);
    const Seen on = run(g, true, steps), off = run(g, false, steps);
    CHECK(on.left_solver > 0);
    CHECK(on.taken.size() > 0);
    CHECK(off.left_solver == 0);
    const Apart d = compare(on, off);
    CHECK(d.steps <= 30);
    CHECK(d.at < 0.1);
}

TEST_CASE("steady transport: a bottle dropped onto a moving belt rides off the solver and leaves by the exit as on the solver") {
    const graph::Graph g = compiled_text(R"(
import std.belts, std.bottle
plant Drop {
    belt: Belt(length = 3 m)
    b: Bottle at (20 cm, 0 m, 2 cm)
    trigger out_volume at (2.9 m, 0 m, 4 cm) { extent = (4 cm, 10 cm, 10 cm) }
    exit done { trigger = out_volume }
}
)",
                                    "drop.plant");
    const std::vector<int32_t> mains = bodies_ending(g, ".main");
    const Seen on = run(g, true, 150 * 7, mains), off = run(g, false, 150 * 7, mains);
    CHECK(on.left_solver == 1);
    CHECK(on.rejoined == 0);  // the exit's trigger sees it off the solver, and the exit takes it
    CHECK(on.taken.size() == 1);
    same(on, off, 1e-3, 1, 0.5 / 150);  // at most a step apart at the exit: 3.3 mm at 0.5 m/s
}

// A Curve's turning field (docs/runtime.md, "Steady transport"): a bottle that rides it settles
// onto its circle and leaves the solver in the curve, and the exit after the next belt takes it
// as on the solver. `across`: where the bottle stands across the first belt (y), and so which
// circle it rides.
void rides_curve(const char* across, const char* name) {
    const graph::Graph g = compiled_text(std::string(R"(
import std.belts, std.bottle
plant Turn {
    b1: Belt(length = 1 m)
    c1: Curve(radius = 30 cm, left = true) at (1 m, 0 m, 0 m)
    b2: Belt(length = 1 m) at (1.3 m, 30 cm, 0 m) rotate z by 90 deg
    b: Bottle at (20 cm, )") + across + R"(, 2 cm)
    trigger out_volume at (1.3 m, 1.25 m, 4 cm) { extent = (10 cm, 4 cm, 10 cm) }
    exit done { trigger = out_volume }
}
)",
                                         name);
    const std::vector<int32_t> mains = bodies_ending(g, ".main");
    REQUIRE(mains.size() == 1);
    const Seen on = run(g, true, 150 * 7, mains), off = run(g, false, 150 * 7, mains);
    CHECK(on.taken.size() == 1);
    CHECK(on.lost.empty());
    same(on, off, 2e-3, 1, 0.5 / 150);  // at most a step apart at the exit
    // The steps it spends in the curve's quarter, and how many of them off the solver.
    engine::Options o;
    o.steady_transport = true;
    Engine e(g, o);
    const graph::BodyId bottle(mains[0]);
    int in_curve = 0, off_in_curve = 0;
    for (int i = 0; i < 150 * 7; ++i) {
        e.step();
        const graph::Vec3 c = e.body_com(bottle);
        if (!e.body_in_world(bottle) || c[0] < 1.0 || c[1] > 0.3) continue;
        ++in_curve;
        off_in_curve += e.internals().phys.coasting(bottle) ? 1 : 0;
    }
    MESSAGE(off_in_curve << " of " << in_curve << " steps in the curve off the solver");
    CHECK(in_curve > 100);                // a quarter of a 30 cm circle at 50 cm/s: 141 steps
    CHECK(off_in_curve > in_curve / 2);
}

TEST_CASE("steady transport: a bottle rides a Curve off the solver, and reaches the exit as on the solver") {
    rides_curve("0 m", "steady_curve.plant");
}

// 13 mm towards the outer rail, the bottle rides a circle whose edge passes 4 to 6 mm inside
// the rail's pieces (straight, 10° apart, their faces 4 cm from the centre line). Two steps at
// 50 cm/s are 6.7 mm: the test that it keeps clear of a piece follows its centre's path along
// the piece, not a disc as wide as the path all round it, which would reach the rail.
TEST_CASE("steady transport: a bottle rides a Curve off the solver 5 mm from its outer rail") {
    rides_curve("-13 mm", "steady_curve_outer.plant");
}

// A belt turned by 3° before a straight one: bottles come onto the straight one drifting across
// it at 2.6 cm/s, meet its rail and then slide along it. Off the solver the rail is a
// frictionless, inelastic contact (it ends their motion towards it), as Bullet's contacts are on
// the solver. A bottle meeting a rail is chaotic as a queue is (a hull turning against a rail):
// on against off differs no more than a bottle placed 1 µm further on does with steady
// transport off.
TEST_CASE("steady transport: bottles drifting onto a rail slide along it off the solver as on it") {
    const graph::Graph g = compiled_text(rail_plant("3", "0 mm"), "steady_rail.plant"),
                       nudged = compiled_text(rail_plant("3", "0.001 mm"), "steady_rail_nudged.plant");
    const std::vector<int32_t> mains = bodies_ending(g, ".main");
    const Seen on = run(g, true, 150 * 10, mains), off = run(g, false, 150 * 10, mains),
               off_nudged = run(nudged, false, 150 * 10, mains);
    CHECK(on.guided > 0);  // unit-steps off the solver along the rail
    CHECK(on.taken.size() == 3);
    MESSAGE(on.guided << " unit-steps off the solver along the rail");
    within_nudge(on, off, off_nudged);
}

// A belt turned by 0.7° before a straight one: bottles come onto the straight one drifting
// across it at 6 mm/s, faster than they may slide along a rail (2 mm/s) but no faster than they
// may come up to one off the solver (1 cm/s): they reach their rail off the solver, which stops
// them there, and slide along it.
TEST_CASE("steady transport: bottles coming slowly up to a rail reach it off the solver as on it") {
    const graph::Graph g = compiled_text(rail_plant("0.7", "0 mm"), "steady_approach.plant"),
                       nudged = compiled_text(rail_plant("0.7", "0.001 mm"), "steady_approach_nudged.plant");
    const std::vector<int32_t> mains = bodies_ending(g, ".main");
    REQUIRE(mains.size() == 3);
    // Steps in which a bottle coasts towards the rail (its face at y = -4 cm: it drifts to -y)
    // faster than 2 mm/s with its box within 2 mm of the face.
    int64_t approaching = 0;
    {
        engine::Options o;
        o.steady_transport = true;
        Engine e(g, o);
        for (int i = 0; i < 150 * 10; ++i) {
            e.step();
            for (int32_t m : mains) {
                const graph::BodyId u(m);
                approaching += e.internals().phys.coasting(u) && e.internals().phys.rb(u).getLinearVelocity().y() < -0.002 &&
                               e.internals().index.lo(u).y() < -0.04 + 0.002;
            }
        }
    }
    MESSAGE(approaching << " unit-steps off the solver coming up to the rail");
    CHECK(approaching > 10);
    const Seen on = run(g, true, 150 * 10, mains), off = run(g, false, 150 * 10, mains),
               off_nudged = run(nudged, false, 150 * 10, mains);
    CHECK(on.guided > 0);
    CHECK(on.taken.size() == 3);
    within_nudge(on, off, off_nudged);
}

// A bottle standing on a frictionless table, where no field acts: nothing acts on it, so it
// keeps its state off the solver (at rest, as a bottle waits at a storage for the arm). A second
// bottle slides off a belt onto the table and strikes it off centre (1 cm aside, so that which
// way each goes does not hang on micrometres): the first comes back to the solver before the
// second can touch it, and both move as on the solver. (The second is recorded, so it rides
// the belt on the solver: the runs differ only by the first's rest.)
TEST_CASE("steady transport: a bottle at rest where no field acts leaves the solver and lands before another reaches it") {
    auto text = [](const char* nudge) {
        return std::string(R"(
import std.arm, std.belts, std.bottle
plant Rest {
    feed: Belt(length = 1 m, rails = false) at (-1 m, 0 m, 0 m)
    table: Table(size = 1 m) at (50 cm, 0 m, 0 m)
    still: Bottle at (30 cm, 0 m, 0 m)
    moving: Bottle at (-80 cm + )") + nudge + R"(, 1 cm, -1.6 mm)
    record moving.main.position  // read: it stays on the solver, on the belt too
}
)";
    };
    const graph::Graph g = compiled_text(text("0 mm"), "steady_rest.plant"),
                       nudged = compiled_text(text("0.001 mm"), "steady_rest_nudged.plant");
    const std::vector<int32_t> still = bodies_ending(g, "still.main"), moving = bodies_ending(g, "moving.main");
    REQUIRE(still.size() == 1);
    REQUIRE(moving.size() == 1);
    const graph::BodyId a(still[0]), b(moving[0]);
    int resting = 0, pushed = 0;
    {
        engine::Options o;
        o.steady_transport = true;
        Engine e(g, o);
        for (int i = 0; i < 150 * 3; ++i) {
            e.step();
            const bool off = e.internals().phys.coasting(a);
            resting += off;
            const double gap = e.body_com(a)[0] - e.body_com(b)[0];
            CAPTURE(i);
            CAPTURE(gap);
            if (gap < 0.06) CHECK_FALSE(off);  // a bottle's width (4.4 cm) and two steps' way apart: on the solver
            pushed += e.body_com(a)[0] > 0.31;
        }
    }
    CHECK(resting > 150);  // off the solver for more than a second before the other came
    CHECK(pushed > 0);     // and then pushed on
    const std::vector<int32_t> both{still[0], moving[0]};
    const Seen on = run(g, true, 150 * 3, both), off = run(g, false, 150 * 3, both),
               off_nudged = run(nudged, false, 150 * 3, both);
    CHECK(on.left_solver >= 1);
    CHECK(on.rejoined >= 1);
    // Why each unit is on the solver, every step: the recorded one because it is read; each
    // unit is counted in each step, on the solver or off it.
    CHECK(on.on_solver(engine::OnSolver::kRead) == 150 * 3);
    int64_t counted = on.coasted;
    for (int64_t n : on.why) counted += n;
    CHECK(counted == 2 * 150 * 3);
    CHECK(on.on_solver(engine::OnSolver::kNeighbour) > 0);  // the still one, as the other came near
    const Apart chaos = compare(off_nudged, off), d = compare(on, off);
    CHECK(d.track <= chaos.track + 0.001);
}

// A bottle standing alone on a frictionless table, in a plant with no field at all, 20 s: on
// the solver Bullet's contacts jiggle it at up to 3 mm/s horizontally and 5 mm/s vertically
// about a place it keeps within hundredths of a millimetre; off the solver it is held at rest
// there.
TEST_CASE("steady transport: a bottle resting where no field acts stays where it stands") {
    const graph::Graph g = compiled_text(R"(
import std.arm, std.bottle
plant Stand {
    table: Table(size = 1 m) at (50 cm, 0 m, 0 m)
    still: Bottle at (30 cm, 0 m, 0 m)
}
)",
                                    "steady_stand.plant");
    const std::vector<int32_t> mains = bodies_ending(g, "still.main");
    REQUIRE(mains.size() == 1);
    const Seen on = run(g, true, 150 * 20, mains), off = run(g, false, 150 * 20, mains);
    CHECK(on.coasted > 150 * 18);  // off the solver nearly all the time
    same(on, off, 1e-4);           // within 0.1 mm of where Bullet keeps it
}

// A static hull beside it (a separator's funnel is two): a wedge whose corner points at the
// bottle from 45°, 3.1 cm from its centre, 9 mm from its side. The wedge's bounding box meets
// the bottle's grown box; its outline seen from above does not come near the bottle, so the
// bottle leaves the solver as on a bare table (until 2026-12-01 a hull was in the way wherever
// its box was: the bottle then rested, held still by what is near it).
TEST_CASE("steady transport: a bottle beside a static hull's corner leaves the solver") {
    const graph::Graph g = compiled_text(R"(
import std.arm, std.bottle
plant Wedge {
    table: Table(size = 1 m) at (50 cm, 0 m, 0 m)
    still: Bottle at (30 cm, 0 m, 0 m)
    physics wedge: static {
        shape hull((32.2 cm, 2.2 cm, 0 m), (35.7 cm, 2.2 cm, 0 m), (32.2 cm, 5.7 cm, 0 m),
                   (32.2 cm, 2.2 cm, 4 cm), (35.7 cm, 2.2 cm, 4 cm), (32.2 cm, 5.7 cm, 4 cm))
        friction = 0
        restitution = 0
    }
}
)",
                                    "steady_wedge.plant");
    const std::vector<int32_t> mains = bodies_ending(g, "still.main");
    REQUIRE(mains.size() == 1);
    const Seen on = run(g, true, 150 * 20, mains), off = run(g, false, 150 * 20, mains);
    CHECK(on.coasted > 150 * 18);
    CHECK(on.rested == 0);  // steady at rest, as on a bare table: not held still by the wedge
    same(on, off, 1e-4);
}

TEST_CASE("steady transport: bottles on a belt stopped and started again move as on the solver") {
    const graph::Graph g = compiled_text(R"(
import std.belts, std.bottle
plant Stop {
    belt: Belt(length = 6 m)
    for i in 0 .. 5 { b[i]: Bottle at (20 cm + i * 20 cm, 0 m, -2 mm + (20 cm + i * 20 cm) / 6 m * 2 mm) }
    timer halt: oneshot { period = 3 s; autostart = true }
    timer restart: oneshot { period = 4.5 s; autostart = true }
    flow halt.tick -> belt.stop
    flow restart.tick -> belt.go
}
)",
                                    "steady_stop.plant");
    const std::vector<int32_t> mains = bodies_ending(g, ".main");
    const Seen on = run(g, true, 150 * 7, mains), off = run(g, false, 150 * 7, mains);
    CHECK(on.left_solver >= 10);  // each bottle before the stop and after the start
    CHECK(on.rejoined >= 5);      // at the stop
    same(on, off);
}

// A queue is chaotic (bottles pressed against each other and a gate): a bottle placed 1 µm
// further on gives, with steady transport off, other exit times by some steps. On against off
// differs no more than that.
TEST_CASE("steady transport: a queue forms before a held separator and passes one by one as on the solver") {
    auto text = [](const char* nudge) {
        return std::string(R"(
import std.belts, std.bottle, std.separator
plant Queue {
    belt: Belt(length = 6 m)
    sep: Separator at (4 m, 0 m, 0 m)
    trigger out_volume at (5.8 m, 0 m, 4 cm) { extent = (4 cm, 10 cm, 10 cm) }
    exit done { trigger = out_volume }
    for i in 0 .. 6 { b[i]: Bottle at (20 cm + i * 30 cm + )") + nudge +
               R"(, 0 m, -2 mm + (20 cm + i * 30 cm) / 6 m * 2 mm) }
}
)";
    };
    const graph::Graph g = compiled_text(text("0 mm"), "steady_queue.plant");
    const int32_t hold = slot_named(g, "sep.holding.start"), free = slot_named(g, "sep.holding.stop");
    REQUIRE(hold >= 0);
    REQUIRE(free >= 0);
    const std::vector<int32_t> mains = bodies_ending(g, ".main");
    const std::vector<std::pair<int64_t, int32_t>> inputs = {{0, hold}, {150 * 10, free}};
    const Seen on = run(g, true, 150 * 25, mains, inputs), off = run(g, false, 150 * 25, mains, inputs);
    std::vector<Seen> off_nudged;
    for (const char* nudge : {"0.001 mm", "0.002 mm", "0.003 mm", "0.005 mm", "0.007 mm"})
        off_nudged.push_back(run(compiled_text(text(nudge), "steady_queue_nudged.plant"), false, 150 * 25, mains, inputs));
    CHECK(on.left_solver >= 6);
    CHECK(on.taken.size() == 6);
    // The queue rests off the solver while it waits (held still at the pin, and behind each
    // other), and is on the solver while it closes up.
    CHECK(on.rested > 6 * 150);
    CHECK(on.on_solver(engine::OnSolver::kHeldBack) > 150);
    CHECK(within_nudges(on, off, off_nudged).steps > 0);  // the queue is chaotic indeed
}

// Five bottles in single file pressed against a closed gate: they rest off the solver, each
// held still by the gate or by the bottle before it. The gate opens (its pin's collision off):
// the bottles within reach of the pin land, and with them, in the same step, the resting ones
// behind, so that the queue moves off at once as on the solver (a bottle landing only when it
// sees the one before it move would start a step later than it, and the queue would string
// out).
TEST_CASE("steady transport: a queue resting at a gate moves off at once when the gate opens") {
    const graph::Graph g = compiled_text(R"(
import std.belts, std.bottle, std.separator
plant Gated {
    belt: Belt(length = 4 m, width = 5 cm)  // one lane: the bottles queue in single file
    gate: Gate(width = 5 cm) at (2 m, 0 m, 0 m)
    for i in 0 .. 5 { b[i]: Bottle at (20 cm + i * 25 cm, 0 m, -2 mm + (20 cm + i * 25 cm) / 4 m * 2 mm) }
}
)",
                                    "steady_gate.plant");
    const int32_t open = slot_named(g, "gate.pin.collision_off");  // what the gate's open does to it
    REQUIRE(open >= 0);
    const std::vector<int32_t> mains = bodies_ending(g, ".main");
    REQUIRE(mains.size() == 5);
    constexpr int64_t kOpen = 150 * 6;
    // Per bottle, the first step after the gate opened in which it is 1 mm on from where it waited.
    auto starts = [&](bool steady, int64_t& rested) {
        engine::Options o;
        o.steady_transport = steady;
        Engine e(g, o);
        std::vector<double> held(mains.size());
        std::vector<int64_t> first(mains.size(), -1);
        for (int64_t i = 0; i < kOpen + 150; ++i) {
            if (i == kOpen) {
                for (size_t k = 0; k < mains.size(); ++k) held[k] = e.body_com(graph::BodyId(mains[k]))[0];
                e.input(graph::SlotId(open));
            }
            e.step();
            if (i < kOpen) continue;
            for (size_t k = 0; k < mains.size(); ++k)
                if (first[k] < 0 && e.body_com(graph::BodyId(mains[k]))[0] > held[k] + 0.001) first[k] = i;
        }
        rested = e.internals().steady.rested;
        return first;
    };
    int64_t rested_on = 0, rested_off = 0;
    const std::vector<int64_t> on = starts(true, rested_on), off = starts(false, rested_off);
    CHECK(rested_on > 5 * 150);  // the five at rest for more than a second each, together
    CHECK(rested_off == 0);
    for (size_t k = 0; k < mains.size(); ++k) {
        CAPTURE(k);
        CHECK(off[k] >= kOpen);
        CHECK(std::abs(on[k] - off[k]) <= 1);
    }
}

TEST_CASE("steady transport: the measurements' traces are the same bytes on and off") {
    struct Case {
        const char* plant;
        const char* duration;
    };
    for (const Case& k : {Case{"traction", "1s"}, Case{"tipping", "3s"}, Case{"spacing", "50s"}, Case{"rocking", "1s"}}) {
        CAPTURE(k.plant);
        Compilation c;
        compile_repo_file(std::string("plants/experiments/") + k.plant + ".plant", c);
        REQUIRE(c.ok());
        std::string traces[2];
        for (int on = 0; on < 2; ++on) {
            const std::string path = (scratch_dir() / (std::string("steady_") + k.plant + (on ? "_on" : "_off") + ".csv")).string();
            std::ostringstream out, err;
            REQUIRE(app::run_main(c.graph, {"--for", k.duration, "--quiet", "--trace", path,
                                               "--steady-transport", on ? "on" : "off"},
                                     out, err) == 0);
            std::ifstream in(path, std::ios::binary);
            traces[on] = std::string(std::istreambuf_iterator<char>(in), {});
        }
        CHECK(traces[0].size() > 1000);
        CHECK(traces[0] == traces[1]);
    }
}

TEST_CASE("steady transport: --steady-transport takes on or off") {
    Compilation c;
    compile_repo_file("plants/experiments/traction.plant", c);
    REQUIRE(c.ok());
    std::ostringstream out, err;
    CHECK(app::run_main(c.graph, {"--for", "0.1s", "--quiet", "--steady-transport", "maybe"}, out, err) == 2);
    CHECK(err.str().find("--steady-transport: 'maybe' is neither on nor off") != std::string::npos);
}

namespace {

// The plant's one bottle (its main body), and options with steady transport on.
graph::BodyId the_bottle(const graph::Graph& g) {
    const std::vector<int32_t> mains = bodies_ending(g, ".main");
    REQUIRE(mains.size() == 1);
    return graph::BodyId(mains[0]);
}
engine::Options steady_on() {
    engine::Options o;
    o.steady_transport = true;
    return o;
}

// Two belts end to end: a std.belts band rises 2 mm along its length, so the next one starts
// 2 mm lower and a bottle steps down onto it. While its centre is over its own band, the next
// one lies below it and touches nothing (docs/runtime.md, "Steady transport": a piece clear
// below is passed over): it stays off the solver until its path comes within 1 mm of its
// field's end, and the exit takes it as on the solver. Raised by 2 mm, the next band is level
// with the end of the first: the bottle stands on both, and is on the solver there.
std::string joint_plant(const char* rise) {
    return std::string(R"(
import std.belts, std.bottle
plant Joint {
    b1: Belt(length = 1 m)
    b2: Belt(length = 1 m) at (1 m, 0 m, )") + rise + R"()
    b: Bottle at (20 cm, 0 m, 2 cm)
    trigger out_volume at (1.9 m, 0 m, 4 cm) { extent = (4 cm, 10 cm, 10 cm) }
    exit done { trigger = out_volume }
}
)";
}

// The steps in which the bottle's centre is between `from` and `to` along x (where the step's
// check finds it), and how many of them it spent off the solver.
std::pair<int, int> off_between(const graph::Graph& g, double from, double to) {
    const graph::BodyId bottle = the_bottle(g);
    Engine e(g, steady_on());
    int in = 0, off = 0;
    for (int i = 0; i < 150 * 3; ++i) {
        const double x = e.body_com(bottle)[0];
        e.step();
        if (x < from || x > to) continue;
        ++in;
        off += e.internals().phys.coasting(bottle);
    }
    return {in, off};
}

}  // namespace

TEST_CASE("steady transport: a bottle stays off the solver over the next band below it, up to its own band's end") {
    // Its bounding box (4.2 cm wide), grown by two steps and 2 mm, meets the next band from
    // x = 96.9 cm on; its path comes within 1 mm of the field's face at x = 1 m from 99.2 cm on.
    const graph::Graph g = compiled_text(joint_plant("0 m"), "steady_joint.plant");
    const auto [in, off] = off_between(g, 0.972, 0.990);
    MESSAGE(off << " of " << in << " steps over the joint off the solver");
    CHECK(in >= 4);
    CHECK(off == in);
    const std::vector<int32_t> mains = bodies_ending(g, ".main");
    const Seen on = run(g, true, 150 * 5, mains), off_run = run(g, false, 150 * 5, mains);
    CHECK(on.taken.size() == 1);
    same(on, off_run, 1e-3, 1, 0.5 / 150);  // at most a step apart at the exit
}

TEST_CASE("steady transport: a bottle on two bands level with each other is on the solver") {
    const graph::Graph g = compiled_text(joint_plant("2 mm"), "steady_joint_level.plant");
    const auto [in, off] = off_between(g, 0.972, 0.990);
    CHECK(in >= 4);
    CHECK(off == 0);
    const std::vector<int32_t> mains = bodies_ending(g, ".main");
    const Seen on = run(g, true, 150 * 5, mains);
    CHECK(on.on_solver(engine::OnSolver::kSupport) > 0);
    CHECK(on.taken.size() == 1);
}

// A field starting just across a cell's edge (cells of 25 cm: docs/runtime.md, "Steady
// transport") from a bottle coasting on a belt: the bottle's path comes within 1 mm of that
// field's face while its centre is still in the cell before, so the field must be filed under
// that cell too (fields are filed grown by 5 cm) or the bottle would ride into a second field
// off the solver. Nothing else is near that face: no band, no rail, no body.
TEST_CASE("steady transport: a bottle lands before a field that starts in the next cell") {
    const graph::Graph g = compiled_text(R"(
import std.belts, std.bottle
plant Edge {
    belt: Belt(length = 1.5 m)
    bt: Bottle at (20 cm, 0 m, 2 cm)
    // x from 1.0005 m to 1.4 m: the cell from 1 m to 1.25 m and on, none before.
    field push at (1.0005 m + 19.975 cm, 0 m, 6 cm) {
        extent = (39.95 cm, 8 cm, 12 cm)
        direction = (1, 0, 0)
        speed = 50 cm/s
        gain = 16 kg/s
        max_force = 0.1 N
    }
}
)",
                                    "steady_cell_edge.plant");
    const graph::BodyId bottle = the_bottle(g);
    Engine e(g, steady_on());
    const double face = 1.0005, reach = 0.001 + 2 * 0.5 / 150;  // 1 mm and two steps at 50 cm/s
    int coasted = 0, near_face = 0;
    for (int i = 0; i < 150 * 3; ++i) {
        const double x = e.body_com(bottle)[0];  // where the step's check finds it
        e.step();
        const bool off = e.internals().phys.coasting(bottle);
        coasted += off;
        if (x > face - reach + 1e-4 && x < 1.35) {  // its path within 1 mm of the face, or past it
            ++near_face;
            CAPTURE(i);
            CAPTURE(x);
            CHECK_FALSE(off);
        }
    }
    CHECK(coasted > 100);    // it rode off the solver before the field
    CHECK(near_face > 20);   // and was seen near and past the face
}

// Each unit keeps a list of the fields and the static pieces filed under the cells near it,
// made again when it moves out of them or the filings change (a field on a moving body, a
// part out of its room), and walks that instead of the cells. The lists find what the cells
// find: with them and without, a run is the same to the bit, verdict by verdict.
TEST_CASE("steady transport: each unit's list of what lies near it finds what the cells find") {
    SUBCASE("the bottling plant, its separators' pins and its switches' blades moving") {
        int64_t steps = 0;
        const graph::Graph g = bottling(PLANT_SANITIZED ? 20 : 60, steps);
        const std::vector<int32_t> mains = bodies_ending(g, ".main");
        Listed listed;
        const Seen with = run(g, true, steps, mains, {}, true, &listed), without = run(g, true, steps, mains, {}, false);
        CHECK(listed.units > 0);  // the lists were kept
        CHECK(with.coasted > 0);  // and units rode off the solver
        identical(with, without);
    }
    SUBCASE("a field carried over bottles standing on a table: the fields are filed again in every step") {
        const graph::Graph g = compiled_text(R"(
import std.arm, std.belts, std.bottle
plant Swept {
    belt: Belt(length = 3 m, rails = false)
    table: Table(size = 1 m) at (1.5 m, 60 cm, 0 m)
    physics pallet at (20 cm, 0 m, 1 cm) { mass = 500 g; shape box(6 cm, 5 cm, 1 cm) }
    field sweep on pallet at (20 cm, 30 cm, 6 cm) { extent = (6 cm, 60 cm, 12 cm); speed = 0 m/s; gain = 1 kg/s }
    for i in 0 .. 3 { b[i]: Bottle at (1.2 m + i * 25 cm, 30 cm, 0 m) }
}
)",
                                        "steady_swept.plant");
        const std::vector<int32_t> mains = bodies_ending(g, ".main");
        Listed listed;
        const Seen with = run(g, true, 150 * 6, mains, {}, true, &listed), without = run(g, true, 150 * 6, mains, {}, false);
        CHECK(listed.units > 0);
        CHECK(listed.fields > 150 * 5);  // the carried field moved in every step
        CHECK(with.coasted > 150 * 3);   // the bottles stood off the solver
        // and the field's faces passed over them (the pallet's centre is on one in every step)
        CHECK(with.on_solver(engine::OnSolver::kFieldEdge) > 150 * 6);
        identical(with, without);
    }
}
