// The runtime: executes a compiled plant graph (graph/graph.h) on Bullet physics.
//
//   plant::engine::Engine e(graph);
//   for (int i = 0; i < 1500; ++i) e.step();   // 10 s at 150 Hz
//
// The graph is the constant model; the engine owns the mutable state, sized once from
// the graph's counts, and the Bullet world. step() runs the five phases described in
// docs/runtime.md and does no heap allocation. Same graph, same options, same inputs:
// bit-identical results.
#pragma once

#include "graph/graph.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>

namespace plant::engine {

// Bullet's broadphase: the AABB tree suits sparse plants, sweep-and-prune dense ones
// (bench/README.md); choose by measurement.
enum class Broadphase : uint8_t { Dbvt, Sap };

struct Options {
    double dt = 0;    // fixed physics step in s; 0: 1 / rate
    double rate = 0;  // steps per second when dt is 0; 0: graph.settings.rate
    Broadphase broadphase = Broadphase::Dbvt;
    // Threads that step the physics of a plant in several regions (0: one per core). The
    // results do not depend on it.
    int threads = 0;
    // Bottles in steady transport leave Bullet's solver and move by the conveyor law's exact
    // solution (docs/runtime.md, "Steady transport"); with the plant's
    // settings.steady_transport, both must be on.
    bool steady_transport = true;
    // The logic phase runs every node each step instead of only those due (docs/runtime.md,
    // "Performance notes"): the same results, slower; for the test that shows they are.
    bool logic_every_node = false;
    // A plant of 2,000 bodies or more has its memory backed by huge pages as it runs, on a
    // thread of its own (engine/pages.h, docs/runtime.md "Performance notes"): no result changes.
    bool huge_pages = true;
};

// Runtime warnings: counted, never fatal (the summary of a run prints them).
struct Warnings {
    int64_t left_world = 0;    // objects a body of which fell below z = -10 m or went beyond 1 km
    int64_t nan_state = 0;     // objects a body of which got a NaN position or velocity
    int64_t access_null = 0;   // a dynamic flow ran while its reference held no object
    int64_t access_type = 0;   // ... held an object of another type (or out of its range)
    int64_t pool_empty = 0;    // a source was asked to issue with an empty pool
    int64_t missed_contacts = 0;  // bodies of two physics regions met (see docs/runtime.md)
    int64_t out_of_range = 0;  // the plant's logic set a place, velocity or belt speed out of
                               // graph/range.h's range (or not finite): not applied
    int64_t hand_refused = 0;  // a grab of a body that is not free to take (parked, gripped,
                               // not dynamic), or a remove of an object a gripper holds
    int64_t total() const {
        return left_world + nan_state + access_null + access_type + pool_empty + missed_contacts + out_of_range +
               hand_refused;
    }
};

struct Runtime;  // the internals (engine/runtime.h)
struct StepProfile;  // engine/workers.h

// Where and when an object was lost (left the world: a body fell below z = -10 m, went beyond
// 1 km or got a NaN state). Its place on the line is where it last rode a conveyor: the last
// step one of its bodies had its centre of mass in an acting force field, that field, and
// that body's centre of mass then (a bottle pushed over a rail: the rail; one that fell off a
// belt's end: the end). An object that never rode one has field -1, and its place and time
// are those of leaving the world.
struct Loss {
    int64_t step = -1;                // the step it left the world in (ends at step · dt); -1: not lost
    graph::Vec3 out{0, 0, 0};         // the centre of mass of the body that left, then
    graph::FieldId field{};           // the last conveyor field it rode, or none
    int64_t field_step = -1;          // the step count when it was last in that field
    graph::Vec3 place{0, 0, 0};       // the centre of mass then
};

// Fault forcing (docs/runtime.md, "Forced slots"): a slot held at a value (stuck), cut
// (open: never active, reads as off), or inverted (bool), until released (None). The
// components' own state goes on underneath; readers of the slot (flows, connectors,
// traces, the viewer) see the forced signal.
enum class ForceMode : uint8_t { None, Stuck, Open, Invert };

class Engine {
public:
    explicit Engine(const graph::Graph& g, Options opt = {});
    ~Engine();
    Engine(const Engine&) = delete;
    Engine& operator=(const Engine&) = delete;

    void step();

    double time() const;    // simulated seconds at the end of the last step
    int64_t steps() const;
    double dt() const;
    // Steps per second: time() is steps() / rate() up to rounding; a trace prints the latter.
    double rate() const;
    const graph::Graph& graph() const;

    // An external input (a timed event): the value (slot_width doubles, none for
    // void) is written now, the slot becomes active in the logic phase of the next step.
    void input(graph::SlotId slot, std::span<const double> value = {});
    // Forces a slot (or releases it with ForceMode::None) from the next step on; `value`
    // is the stuck value (slot_width doubles; void: {1} on, {0} off). Like input(), called
    // between steps only: the one way in is engine::apply_event.
    void force(graph::SlotId slot, ForceMode mode, std::span<const double> value = {});
    ForceMode forced(graph::SlotId slot) const;

    // A trainee's hand (docs/runtime.md, "Hands"): holds a dynamic body at the world point
    // `at` and pulls that point towards a target (first `at`, then each hand_move's) with
    // a bounded force, holding the body upright, until hand_drop. remove_object takes an
    // object out of the plant, back to its source's pool, counted by removed() (not lost).
    // Between steps only, like input(): the one way in is engine::apply_event.
    void hand_grab(graph::BodyId body, const graph::Vec3& at);
    void hand_move(graph::BodyId body, const graph::Vec3& to);
    void hand_drop(graph::BodyId body);
    void remove_object(graph::DoId object);
    bool held(graph::BodyId body) const;  // by a hand
    int64_t removed() const;

    // Strings for string slots: the graph's names, then any interned here.
    int32_t intern(std::string_view s);
    std::string_view str(int32_t name) const;

    // Refresh a slot's value every step even though no flow reads it (traces, tests).
    void watch(graph::SlotId slot);
    std::span<const double> value(graph::SlotId slot) const;
    // Outputs: active in the logic phase of the last step. Inputs: activated by it.
    bool active(graph::SlotId slot) const;
    // An output produced after the last logic phase (in phases 4 and 5: a place entered,
    // an object issued), which the next step's logic phase will see active.
    bool emitted(graph::SlotId slot) const;

    graph::Pose body_pose(graph::BodyId body) const;  // the body frame, in the world
    graph::Vec3 body_com(graph::BodyId body) const;   // centre of mass, in the world
    graph::Vec3 body_velocity(graph::BodyId body) const;
    graph::Vec3 body_angular_velocity(graph::BodyId body) const;
    bool body_in_world(graph::BodyId body) const;
    bool body_collision(graph::BodyId body) const;        // collision on now
    int32_t graphics_variant(graph::GraphicsId graphics) const;  // among its own variants, -1: its model
    bool trigger_occupied(graph::TriggerId trigger) const;   // an object inside now
    bool field_on(graph::FieldId field) const;
    double field_speed(graph::FieldId field) const;        // target speed now, m/s
    int64_t tokens(graph::PlaceId place) const;  // at most graph::kMaxTokens
    graph::Pose graphics_pose(graph::GraphicsId graphics) const;
    int64_t trigger_enters(graph::TriggerId trigger) const;  // objects that entered so far
    int64_t issued(graph::SourceId source) const;           // objects a source issued so far
    int64_t taken(graph::ExitId exit) const;              // objects an exit took so far
    double lost_at(graph::DoId object) const;           // when the object left the world; -1: never
    const Loss& loss(graph::DoId object) const;         // where and when (step -1: not lost)
    std::span<const graph::DoId> lost() const;          // the objects lost so far, in the order lost
    // Seconds since a dynamic body was last moving: at least a tenth of the speed of the
    // running conveyor field it is in, or in no running field at all (0 then).
    double stalled_for(graph::BodyId body) const;
    const Warnings& warnings() const;
    int regions() const;  // physics regions: Bullet worlds of static bodies (physics.h)
    int threads() const;  // threads that step them
    // Where the steps' wall time goes (workers.h); set profile().on to start timing.
    StepProfile& profile();

    Runtime& internals() { return *rt_; }

private:
    std::unique_ptr<Runtime> rt_;
};

// Bullet's memory comes from size-class free lists that recycle what Bullet frees
// (bullet_alloc.cpp): after the first steps, Bullet's per-step requests (broadphase tree
// nodes, clipping arrays) are served from them. This counts the times they grew from the
// system heap so far (by a quarter of a class's blocks each time), for benchmarks; 0 in
// sanitizer builds, which use the heap directly.
uint64_t bullet_heap_requests();

}  // namespace plant::engine
