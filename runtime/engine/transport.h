// Steady transport (docs/runtime.md, "Steady transport"): a bottle that rides a belt upright,
// at the band's speed, with nothing but the band and the rails it slides along within reach,
// is moved by the conveyor law's exact solution instead of Bullet's solver, and returns to the
// solver, with its state, the step before anything else could touch it.
#pragma once

#include "engine/workers.h"
#include "graph/ids.h"

#include <LinearMath/btTransform.h>

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace plant::engine {

struct Runtime;

// Why a unit is on Bullet's solver in a step: the first test of steadiness it fails
// (docs/runtime.md, "Steady transport"), counted over a run in Steady::why.
enum class OnSolver : uint8_t {
    kHeld,        // not simulated (dynamics or collision off), gone, held by a gripper or a hand
    kRead,        // something reads its outputs (a record, a flow, a watch)
    kTurning,     // rocks or spins
    kTilted,      // more than 2 degrees from upright
    kFieldEdge,   // at a field's face, or in two acting fields
    kFieldSlope,  // its field is not level, or drives along its z axis
    kFieldTurns,  // its field turns (a turntable's, a curve's band): its target is not one velocity
    kHeldBack,    // along a driven axis, slower than half its field's target (in a queue, at a pin)
    kSpeed,       // otherwise off its field's target along a driven axis (speeding up, slowing down)
    kDrift,       // drifting across its field faster than 5 cm/s
    kMoving,      // in no field, moving faster than 5 mm/s along an axis
    kPart,        // a kinematic part moving within reach
    kSupport,     // on two supports (or two pieces of one), or on one with friction
    kRailFast,    // coming up to a rail faster than 1 cm/s
    kChannel,     // between two rails
    kInTheWay,    // a static piece in the way (not a rail it slides along)
    kNoSupport,   // no support, or one whose top is not level
    kEdge,        // in no field, at its support's edge
    kNeighbour,   // another body within reach
    kChanged,     // off the solver, and its field's target, its field or its support changed
    kSettling,    // steady for fewer than 5 steps in a row
    kStill,       // still (it may rest) for less than 0.1 s
    kCreeping,    // still, but more than 0.5 mm from where it was 0.1 s before (a queue closing up)
    kCount
};
inline constexpr size_t kOnSolverReasons = size_t(OnSolver::kCount);
// The reasons' names, for tables.
const char* on_solver_name(OnSolver w);

struct Steady {
    bool on = false;  // Options::steady_transport and the plant's settings.steady_transport
    template <class T>
    using PerBody = graph::IdVector<graph::BodyId, T>;
    // Per body (a lone body or a weld's host: a unit).
    PerBody<int16_t> settled;            // consecutive steps the unit was steady
    PerBody<int16_t> still;              // consecutive steps it was still (it may rest)
    PerBody<btVector3> rest_from;        // its centre of mass when it was first still
    PerBody<graph::FieldId> field;       // coasting: the field it rides (resting: rests in)
    PerBody<graph::BodyId> support;      // coasting: the static body it stands on
    PerBody<int16_t> piece;              // coasting: which piece of it, in a compound (else -1)
    PerBody<btVector3> target;           // coasting, resting: the field's target velocity, in the world
                                         // (a turning field's angular velocity: target_of)
    PerBody<btVector3> normal;           // coasting: the support's top face's normal
    PerBody<btScalar> height;            // coasting: its centre of mass above the top face's plane
    PerBody<btScalar> yaw;               // coasting: its angular velocity about the vertical
    PerBody<btVector3> relax;            // coasting: exp(-a) per field axis (1: free axis)
    PerBody<uint8_t> action;             // per unit, this step's decision (check_steady)
    // Per unit, why it is on the solver after this step's check (the first test it failed, or
    // kNeighbour: kept there by a resting neighbour); kCount where it is not (off the solver,
    // out of the world, a passenger): why() unit by unit (plant_bench_bottling --profile
    // counts them by the object whose field the unit rides).
    PerBody<OnSolver> why_of;
    // check_steady's slices: from each slice's first index on, its units that land or leave
    // and those off the solver, and how many of each (and of those along a rail, and resting) it found.
    std::vector<graph::BodyId> events, found;
    std::array<size_t, kMaxSlices> slice_events{}, slice_found{};
    // The units coasting (or resting) after this step's check, in id order: the found ones of
    // its found_slices slices of `found` (none before the first check or with steady transport
    // off). Read where they are, on the threads that move them (advance_steady), not copied
    // into one list on the calling thread.
    size_t found_slices = 0;
    std::span<const graph::BodyId> coasting_in(size_t slice) const {
        return {found.data() + slice_of(found.size(), found_slices, slice).first, slice_found[slice]};
    }
    size_t coasting_count() const {
        size_t n = 0;
        for (size_t i = 0; i < found_slices; ++i) n += slice_found[i];
        return n;
    }
    template <class F>
    void each_coasting(F&& f) const {
        for (size_t i = 0; i < found_slices; ++i)
            for (const graph::BodyId u : coasting_in(i)) f(u);
    }
    std::array<int64_t, kMaxSlices> slice_guided{}, slice_rested{};
    // ... and those units grouped by their world: world w's at [world_adr[w], world_adr[w + 1])
    // of by_world; busy: the worlds with any.
    std::vector<graph::BodyId> by_world;
    std::vector<int32_t> world_adr, world_fill;
    std::vector<int> busy;
    PerBody<btVector3> top;              // coasting: a point of the support's top face
    // coasting: the rail it slides along, if any: the face's axis (0 x, 1 y), the side the rail
    // is on (+1, -1; 0: none) and how far along that axis the unit's shape may reach
    PerBody<int8_t> guide_axis, guide_side;
    PerBody<btScalar> guide_face;
    int64_t left = 0, rejoined = 0;      // times a unit left the solver and came back
    int64_t guided = 0;                  // unit-steps off the solver sliding along a rail
    int64_t coasted = 0;                 // unit-steps off the solver (after each step's check)
    int64_t rested = 0;                  // ... of them resting (held still: Physics::rest)
    // check_steady: units landing with a resting neighbour, or staying on the solver with one
    // (in the order found), and the search's stack.
    std::vector<graph::BodyId> joined, stack;
    // Unit-steps on the solver (after each step's check), by why (OnSolver): each slice of
    // check_steady's job adds to its own row, all run long, and the check after it counts the
    // units a resting neighbour keeps there; why() sums them when asked.
    std::array<std::array<int64_t, kOnSolverReasons>, kMaxSlices> slice_why{};
    int64_t neighbours = 0;
    std::array<int64_t, kOnSolverReasons> why() const {
        std::array<int64_t, kOnSolverReasons> sum{};
        for (const auto& row : slice_why)
            for (size_t k = 0; k < kOnSolverReasons; ++k) sum[k] += row[k];
        sum[size_t(OnSolver::kNeighbour)] += neighbours;
        return sum;
    }

    // Static geometry near which nothing coasts: static bodies (a support and the rails it
    // slides along aside) and kinematic bodies within a box around where they were (a gate or
    // a blade moving inside it); filed in the cells of cells.h over (x, y). Triggers only read
    // poses: they see a coasting unit as any body.
    struct Hazard {
        btVector3 lo, hi;
        graph::BodyId body;        // the static or kinematic body
        bool fixed = false;        // a static body (else a kinematic part)
        bool box = false;          // a box with its faces on the world's axes (a static piece's
                                   // [lo, hi] is it; a kinematic part's is its room)
        int16_t piece = -1;        // its piece of a static compound
        btScalar friction = 0, restitution = 0;  // the body's (read here: its Bullet body is
                                                 // far in memory, and they do not change)
        // A static box turned about the vertical only (a curve's rail piece): its centre, the
        // cosine and sine of its turn and its half sizes in x and y, for a test more precise
        // than its bounding box.
        bool obb = false;
        btScalar ocx = 0, ocy = 0, oc = 1, os = 0, ohx = 0, ohy = 0;
        // A static piece's outline seen from above, for a turned box (obb: its corners) and a
        // convex hull (a separator's funnel: the convex hull of its points' x and y), counter-
        // clockwise: poly_xy[2·poly, 2·(poly + corners)), and the margin the shape adds around
        // it. poly < 0: none.
        int32_t poly = -1;
        int16_t corners = 0;
        btScalar poly_margin = 0;
    };
    std::vector<Hazard> hazards;
    std::vector<btScalar> poly_xy;  // the outlines (Hazard::poly)
    std::vector<uint8_t> level_top;  // beside hazards: a static piece whose top face is level
    std::vector<btVector4> top_plane;  // beside them: that face's plane (normal, and its offset along it)
    std::vector<uint64_t> cells;
    std::vector<int32_t> cell_adr, cell_list, big;
    std::vector<std::array<btScalar, 4>> cell_box;  // beside cell_list: each entry's hazard's box in (x, y)
    std::vector<std::pair<uint64_t, int32_t>> filed;
    // Per unit: what is filed near it, so that a unit whose lookups stay within the same cells
    // does not look those cells up again (most steps): each field (State::field_cells) and each
    // hazard filed under cells [x0, x1] × [y0, y1], once, as both filings stood at `epoch`
    // (grid_builds + State::field_builds). Walking these finds what walking the cells finds,
    // and some more that lies too far to count (transport.cpp, near_of). Two cache lines.
    static constexpr int kNearIds = 25;
    struct alignas(64) Near {
        int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
        uint64_t epoch = ~uint64_t(0);
        uint8_t fields = 0, hazards = 0;  // id[0, fields): fields, then the hazards; kFull: more than fit
        std::array<int32_t, kNearIds> id;
    };
    static_assert(sizeof(Near) == 128);
    static constexpr uint8_t kFull = 0xff;
    PerBody<Near> near;
    bool near_on = true;  // off: every walk looks up the cells (the tests compare the two)
    std::vector<graph::BodyId> kinematic;      // declared kinematic bodies (and dynamic ones off)
    PerBody<btVector3> home_lo, home_hi;       // per body: the box its hazard was filed with
    PerBody<btTransform> home_tr;              // ... and its transform then
    bool grid_valid = false;
    uint64_t grid_statics = 0;                 // Physics::statics_placed when built
    uint64_t grid_builds = 0;                  // how many times it was built
    // Per kinematic part: grid_builds and Physics::writes when it was last found in its room;
    // while both stand it still is, and kinematic_left does not read it.
    PerBody<uint64_t> in_room_grid;
    PerBody<uint32_t> in_room_writes;
};

void start_steady(Runtime& r, bool on);
// In the physics phase, after the fields' frames and before the law: units that must return to
// the solver land, units steady long enough leave it.
// `left`: whether a kinematic part left its room this step (kinematic_left, found beside the
// fields' frames on the physics threads).
void check_steady(Runtime& r, bool left);
// Whether one of kinematic parts [begin, end) of Steady::kinematic left the room it was filed
// with (then the static geometry is filed again). Writes only those parts' in_room_ entries:
// slices of them on any threads.
bool kinematic_left(Runtime& r, size_t begin, size_t end);
// After Bullet's step: the coasting units move by the law's exact solution.
void advance_steady(Runtime& r);

}  // namespace plant::engine
