// Everything that changes while a plant runs, apart from Bullet's own objects: flat
// arrays indexed by graph ids (IdVector<XId, T>: indexed by that id type), sized once from
// the graph's counts. A step only
// writes into them (the lists are reserved to their bound, so push_back never grows).
#pragma once

#include "engine/engine.h"
#include "engine/pose.h"
#include "engine/tables.h"
#include "engine/workers.h"

#include <LinearMath/btMatrix3x3.h>
#include <LinearMath/btVector3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace plant::engine {

struct TriggerState {
    btTransform pose = btTransform::getIdentity();  // the box centre in the world
    // Objects inside now: from `adr` in its slice's list of this step (State::inside), and
    // how many were inside the step before.
    int32_t slice = 0, adr = 0, num = 0, before = 0;
    int64_t enters = 0;
    // This step's list against the previous one, found on a physics thread before the lists
    // move (kinds/trigger/run.cpp): objects that came in (the first of them) and that left.
    int32_t entered = 0, left = 0;
    graph::DoId first_in;
    graph::Adr<graph::Slot> slots;  // its component's first slot (set at the start)
};

struct LaneRec {
    int32_t pos;  // the op's position in the program
    graph::SlotId slot;
};
struct LaneRun {
    std::vector<LaneRec> out, in;
    int64_t access_null = 0, access_type = 0;
};

// A kind on the kind table keeps its state in a type of its own (kinds/NAME/run.cpp), made
// once outside the step (KindBehaviour::make_state) and reached with kind_data<T>().
struct KindData {
    virtual ~KindData() = default;
};

struct GraphicsState {
    Pose base;            // tracked pose (body, parent, or its own / set_pose)
    Pose offset;          // animation offset, identity when none ever played
    Pose pose, prev;      // base * offset, now and one step ago
    int32_t anim = -1;    // playing animation
    int32_t finished = -1;  // the animation that finished this step (kinds/graphics/run.cpp)
    double t = 0;         // its time
    // The attached body's Bullet transform `base` was computed from; `base_fresh` false when
    // something else set `base` (set_pose, an object issued), so the body's is taken again.
    btTransform body_tr;
    bool base_fresh = false;
    // Pose and prev not kept up while its body moves: nothing reads them (its pose output is
    // not watched; no child, no gripper follows it; no animation plays: kinds/graphics/run.cpp).
    // body_tr then holds the body's frame when last visited in the world, from which
    // Engine::graphics_pose computes the pose as a visit would have.
    bool stale = false;
    // A stale graphics' base: its body's frame kept, times its place on the body (on_body).
    Pose base_from_frame(const Pose& local) const { return pmul(from_bt(body_tr), local); }
};

// Where graphics i sits on its body (its pose in the body's frame, as both stood at the start).
inline Pose on_body(const graph::Graph& g, graph::GraphicsId i) {
    const graph::Graphics& x = g.graphics[i];
    return pmul(pinv(g.bodies[x.body].pose), x.pose);
}

struct SourceState {
    int32_t head = 0, free = 0;  // ring of free pooled DOs: pool_ring[adr + (head + i) % num]
    int32_t ring_adr = 0;
    int64_t issued = 0;
    double next_issue = 0;       // for sources with a rate
};

// A trainee's hand on a dynamic body (hands.cpp): the point it holds, in the body frame,
// and where it pulls that point to, in the world.
struct Hand {
    graph::BodyId body;
    btVector3 anchor{0, 0, 0};
    btVector3 target{0, 0, 0};
};

// A singular flow whose condition never held (or whose last run found no object).
inline constexpr int64_t kNeverHeld = INT64_MIN / 2;

struct State {
    template <class IdT, class T>
    using IdVector = graph::IdVector<IdT, T>;
    template <class T>
    using PerSlot = IdVector<graph::SlotId, T>;
    template <class T>
    using PerBody = IdVector<graph::BodyId, T>;
    template <class T>
    using PerField = IdVector<graph::FieldId, T>;
    template <class T>
    using PerPlace = IdVector<graph::PlaceId, T>;

    double time = 0;
    int64_t step = 0;

    // Slots: values (a copy of graph.values), activity, and the lists of active slots
    // (so clearing costs what was activated, not the number of slots).
    std::vector<double> values;
    PerSlot<uint8_t> act;
    // The outputs active in a step's logic phase, kept for observers (Engine::active) when
    // phase 4 clears them: the list, and as flags in seen[step % 2] (the other array drops the
    // step before's list meanwhile: petri.cpp).
    std::array<PerSlot<uint8_t>, 2> seen;
    std::vector<graph::SlotId> out_list, seen_list, in_list;
    std::vector<uint64_t> logic_due;  // the logic phase's ops due, a bit per op (schedule.h)
    std::vector<graph::SlotId> pending;  // activated at the start of the next logic phase
    IdVector<graph::FlowId, int64_t> once_held;  // the last step a singular flow's condition held (it runs on a step whose previous did not)
    PerSlot<uint8_t> watched;       // refreshed although no flow reads it
    uint64_t watches = 0;           // bumped each time `watched` is refreshed (Runtime::refresh_observers):
                                    // what a kind keeps of it is read again (kinds/graphics/run.cpp)
    PerBody<uint8_t> body_outputs;  // bit i = output i (from bodyslot::pose) used
    std::vector<graph::BodyId> observed_bodies;
    std::vector<graph::CompId> comp_list;  // phase 5: components with an active input
    IdVector<graph::CompId, uint8_t> comp_mark;

    // Bodies.
    PerBody<Vec3> cmd_lin, cmd_ang;      // velocity of a kinematic body, moved by us
    std::vector<graph::BodyId> commanded;  // bodies ever given such a velocity, once each
    PerBody<uint8_t> is_commanded;
    PerBody<graph::GripperId> held_by;   // gripper holding the body, -1
    PerBody<btTransform> grip_rel;       // body frame relative to the gripper's
    PerBody<uint8_t> gone;               // left the world or NaN: warned once, taken out
    IdVector<graph::DoId, double> lost_at;  // when it left the world, -1
    IdVector<graph::DoId, Loss> loss;       // where and when (Engine::loss)
    std::vector<graph::DoId> lost;       // the DOs lost, in that order (reserved: every DO)
    // Per body: the last acting field its centre of mass was in (-1: none since it was
    // issued), the step count then and the centre of mass (fields.cpp), for Loss.
    PerBody<graph::FieldId> ride_field;
    PerBody<int64_t> ride_step;
    PerBody<btVector3> ride_at;
    // Per body, for Engine::stalled_for: since when it has been slower than a tenth of the
    // running field it is in, and the last step in which it was (-1: never).
    PerBody<double> stall_since, field_run;  // field_run: scratch, the fastest field's speed
    PerBody<int64_t> slow_step;

    // Fields: scratch for the conveyor law, and rigid groups (fixed joints).
    PerField<double> field_speed;
    PerField<uint8_t> field_on;
    // Each field's pose, gain matrix and reach in x and y, for the Bullet frame its
    // carrier had (most carriers never move: a band).
    struct FieldFrame {
        btTransform pose;  // the field's box: its frame and its half extents (what lookups read)
        btVector3 half;
        bool valid = false;
        btTransform carrier;
        btMatrix3x3 K;
    };
    PerField<FieldFrame> field_frame;
    // Per field, beside its frame (and written with it): its bounding box in x and y, the
    // frame's origin and the box's half sizes. Every lookup tests it first, and passes over
    // most fields on it: 16 bytes each, where a frame takes 196.
    struct FieldXY {
        btScalar cx = 0, cy = 0, rx = 0, ry = 0;
        // How far p is outside the box in x or y (negative: within it in both).
        btScalar beyond(const btVector3& p) const { return std::max(std::abs(p.x() - cx) - rx, std::abs(p.y() - cy) - ry); }
    };
    PerField<FieldXY> field_xy;
    // Per field, this step: acting (on, gain > 0), target velocity.
    PerField<uint8_t> field_act;
    PerField<btVector3> field_target;
    // ... and a turning field's angular speed about its pivot's vertical, rad/s (its speed over
    // its radius; 0 for one that does not turn): its target for a body is turning_target (below),
    // and field_target is 0.
    PerField<btScalar> field_spin;
    // The physics phase looks at every field's frame, and whether it acts, only after a static
    // body was placed (nothing else moves one: a velocity is refused): a field without a
    // carrier or on a static body stays where it is. In other steps it looks at the fields
    // carried by a body that is not static (`field_carried`) and at those whose inputs were
    // written since it last looked (`field_touched`, each once: kinds/field/run.cpp).
    std::vector<graph::FieldId> field_carried, field_touched;
    PerField<uint8_t> field_is_touched;
    uint64_t field_statics = UINT64_MAX;  // Physics::statics_placed when it last looked at every field
    // The fields by the cells (cells.h) of (x, y) of their bounding boxes (fields.cpp): cell keys
    // sorted, each with its fields in id order; fields covering very many cells are in `field_big`.
    std::vector<uint64_t> field_cells;
    std::vector<int32_t> field_cell_adr, field_cell_list, field_big;
    std::vector<std::pair<uint64_t, int32_t>> field_filed;  // scratch of the build
    bool field_cells_valid = false;
    uint64_t field_builds = 0;  // how many times they were filed (Steady::Near)
    // Dynamic bodies in the world by physics world (CSR), and the touched ones in the same slots.
    std::vector<int32_t> world_adr, world_num, worlds_busy;
    std::vector<int32_t> world_next;  // scratch: list_field_bodies' next place in each world's list
    std::vector<graph::BodyId> world_list, touched;
    // list_field_bodies' slices (fields.cpp): per slice and world, its bodies' count, then
    // where the slice's first body of that world goes in world_list (sized with the physics:
    // Runtime's constructor); per body, whether the law acts on it this step.
    std::vector<int32_t> slice_world;
    graph::IdVector<graph::BodyId, uint8_t> law_on;
    PerBody<btVector3> force;          // the law at the body's velocity, summed over fields
    PerBody<btMatrix3x3> gain;         // its gain matrices k·R·diag|d|·R^T, summed
    PerBody<double> body_k;
    // Rigid groups, each by its root body: per body its group, per root the group's
    // mass and list (group_list[group_adr .. + group_num]) (fields.cpp).
    PerBody<graph::BodyId> group_of;
    PerBody<double> group_mass;
    PerBody<int32_t> group_adr, group_num;
    PerBody<uint8_t> group_mark;
    std::vector<graph::BodyId> group_list;
    // Slip limit: per body the largest max_force of the fields it is in (+inf: one is
    // unlimited; 0: in none yet), and in a rigid group which members' law saturated and the
    // constant force each then gets (conveyor.cpp).
    PerBody<double> body_cap;
    PerBody<uint8_t> law_sat;
    PerBody<btVector3> sat_force;
    uint64_t groups_version = ~uint64_t(0);  // Physics::version the groups were built for

    // Petri nets.
    PerPlace<int64_t> tokens;  // up to graph::kMaxTokens
    // What phase 4 reads and writes of each place it touches, in one record a place: the sums
    // of the weights its fired transitions consume and produce, whether a put gave it a token
    // this step, and (set at the start, never changed) its output slots and its net's position
    // in Tables::nets.
    struct PlaceStep {
        int64_t consume = 0, produce = 0;
        graph::SlotId entered, tokens_slot;  // -1: none
        int32_t net = 0;
        uint8_t put = 0;
    };
    PerPlace<PlaceStep> place_step;
    std::vector<uint8_t> net_live;
    // The nets in slices on the physics threads (petri.cpp): per slice, the outputs its nets
    // made active, in order (fired transitions, then places, net by net).
    std::vector<std::vector<graph::SlotId>> petri_made;
    // Per slice of the job that clears the outputs (petri.cpp): the active inputs a component
    // acts on, in order, as many as fit (`full` when more came).
    struct PetriActs {
        std::array<graph::SlotId, 64> slots;
        uint32_t num = 0;
        bool full = false;
    };
    std::array<PetriActs, kMaxSlices> petri_acts;

    // The logic phase in lanes (logic.cpp, schedule.h), with more than one thread: what each
    // lane's ops activated, with the op's position in the program, and the warnings they
    // counted; the due bits by position in Schedule::lane_ops (all clear between the phases:
    // a lane's run clears every bit of its words).
    std::vector<LaneRun> lane_runs;
    std::vector<uint64_t> lane_due;
    std::vector<uint64_t> lane_made;  // a bit per position in the program: its op activated a slot (the join)
    std::vector<size_t> join_at;  // the join's slices: where their records begin in each lane's lists (logic.cpp)

    IdVector<graph::TriggerId, TriggerState> triggers;
    // Per trigger: whether an object is inside it this step (TriggerState::num > 0), packed for
    // the loops that look at many triggers and act on the few with something inside (exits).
    IdVector<graph::TriggerId, uint8_t> trigger_occupied;
    // The triggers' objects (DOs), found on the physics threads (kinds/trigger/run.cpp): per
    // slice of the triggers, their lists one after the other, each sorted; two sets, this
    // step's and the step before's (which the new lists are compared with), in turn.
    std::array<std::vector<std::vector<graph::DoId>>, 2> trigger_lists;
    int trigger_side = 0;  // which set is this step's
    // Per slice: the outputs its triggers' events made active, in order (kinds/trigger/run.cpp).
    std::vector<std::vector<graph::SlotId>> trigger_made;
    std::span<const graph::DoId> inside(const TriggerState& ts) const {
        const graph::DoId* first = trigger_lists[trigger_side][ts.slice].data() + ts.adr;
        return {first, first + ts.num};
    }
    // Per slice of prepare_fields' job (fields.cpp): a field's frame changed, a kinematic part
    // left its room.
    std::vector<uint8_t> slice_moved, slice_left;
    IdVector<graph::GripperId, graph::DoId> gripper_held;  // DO held, -1
    IdVector<graph::GraphicsId, GraphicsState> graphics;
    // 1 when a source issuing its object set a graphics' base since the graphics' last step
    // (kinds/graphics/run.cpp: a root on no body is passed over while nothing moves it).
    IdVector<graph::GraphicsId, uint8_t> graphics_placed;
    IdVector<graph::GraphicsId, int32_t> variant;  // selected variant, -1
    IdVector<graph::SourceId, SourceState> sources;
    std::vector<graph::DoId> pool_ring;
    IdVector<graph::ExitId, int64_t> exit_count;

    // Forced slots (forces.cpp), sized by the first Engine::force: per slot its mode and
    // whether the force began or ended since the last logic phase; per value the forced
    // value and the natural one (what the component or the flows wrote underneath).
    PerSlot<uint8_t> force_mode, force_edge;
    std::vector<double> force_value, force_natural;
    std::vector<graph::SlotId> forced_in, forced_out;  // forced or just released, once each

    std::vector<double> plugin_state;  // Tables::plugin_run's state_adr into it
    // The kinds on the kind table: their state, by CompKind (nullptr: none).
    std::array<std::unique_ptr<KindData>, size_t(graph::CompKind::Plugin) + 1> kinds;

    // Hands (hands.cpp): reserved at the start, changed between steps only (events).
    std::vector<Hand> hands;
    PerBody<uint8_t> in_hand;  // its object is in a hand (no conveyor law on it)
    int64_t removed = 0;  // objects taken out of the plant by hand (`remove` events)

    Warnings warn;
};

void init_state(State& s, const graph::Graph& g, const Tables& t);

// The state of a kind on the kind table, as the type its run.cpp made.
template <class T>
T& kind_data(State& s, graph::CompKind kind) {
    return static_cast<T&>(*s.kinds[size_t(kind)]);
}

// A turning field's target for a body whose centre of mass is at `local` in the field's frame,
// moving at `vl` (in that frame): the band's rotation, spin × (q − pivot), at q = local +
// vl·half_dt. The law takes it half a step on (half_dt = dt/2), where the body is in the middle
// of its step: the chord a step moves it along is the circle's tangent there, so a body riding
// the field keeps to its circle. (Taken where the body starts the step, the target lags a
// step's turn, and a body drifts outwards by π·v·dt/2 a quarter turn: 5 mm at 50 cm/s and
// 150 Hz.)
inline btVector3 turning_target(btScalar spin, const btVector3& pivot, const btVector3& local, const btVector3& vl,
                                btScalar half_dt) {
    const btVector3 rel = local + vl * half_dt - pivot;
    return btVector3(-spin * rel.y(), spin * rel.x(), 0);
}

// How many slices phase 4 steps the nets in (petri.cpp); each slice's list is sized at the start.
size_t petri_slices(size_t nets);

}  // namespace plant::engine
