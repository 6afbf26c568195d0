// The one owner of the Bullet worlds and of every Bullet object: created in order
// (shapes, bodies, constraints, then per world configuration, dispatcher, broadphase, solver,
// world) and destroyed in reverse. Bodies carry their graph id in setUserIndex, constraints
// in setUserConstraintId. The phases change membership and modes only through here.
//
// A plant whose static bodies fall apart into regions far enough from each other (the lines
// of a plant side by side) gets a Bullet world per region, stepped on several threads, and
// one for what moves outside every region; bodies move between them as they go. See
// regions.cpp.
#pragma once

#include "engine/engine.h"
#include "engine/shapes.h"
#include "engine/tables.h"

#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <memory>
#include <span>
#include <vector>

class btCollisionConfiguration;
class btCollisionDispatcher;
class btBroadphaseInterface;
class btSequentialImpulseConstraintSolver;
class btDiscreteDynamicsWorld;
class btTypedConstraint;

namespace plant::engine {

class BoxHullContacts;
class Workers;

// Bullet's allocator (bullet_alloc.cpp): installed before main by physics.cpp, so that every
// program with a runtime has it (a file of a static library that nothing calls would be
// left out of the program). False in sanitizer builds, where Bullet uses the heap.
bool install_bullet_pool();
bool bullet_pool();  // whether this build has it (physics.cpp installs it before main)

// A body declared kinematic, as Bullet's saveKinematicState last left it after working out
// its velocity from a transform that had not moved, and its broadphase box as its world last
// worked it out (physics.cpp, IslandWorld). `writes` and `box_writes`: Physics::writes(b)
// then; while it is the same, nothing has written the body since.
struct KinematicRest {
    btTransform at;
    btVector3 lin, ang;
    btScalar dt = 0;
    bool valid = false;
    bool box_valid = false, active = false;
    uint32_t writes = 0, box_writes = 0;
    btBroadphaseProxy* proxy = nullptr;
};

class Physics {
public:
    // threads: how many threads may step the worlds (0: one per core).
    Physics(const graph::Graph& g, const Tables& t, Broadphase bp, int threads = 1);
    ~Physics();
    Physics(const Physics&) = delete;
    Physics& operator=(const Physics&) = delete;

    // Forms and ends welds as membership and modes say: call before the step's forces
    // are applied (phase_physics does).
    void update_welds();
    // Steps every world once by dt. With the bodies in the worlds they step in (regions.cpp),
    // `ready` runs on the calling thread; then each world's job (on the physics threads) runs
    // `before(world)` and Bullet's step of that world, and its welded passengers follow their
    // carriers. One fork and one join per step.
    struct StepHooks {
        void (*ready)(void* ctx) = nullptr;
        void (*before)(void* ctx, int world) = nullptr;
        void* ctx = nullptr;
    };
    void step(double dt, const StepHooks& hooks);
    void step(double dt);
    // Bullet's worlds: one per region, then (with more than one region) the void's.
    int worlds() const { return int(worlds_.size()); }
    btDiscreteDynamicsWorld& world(int w = 0) { return *worlds_[w].world; }
    int world_of(graph::BodyId b) const { return world_of_[b]; }
    int threads() const;
    Workers& workers() { return *workers_; }
    // Bodies of two worlds whose bounding boxes met (their contact was not simulated).
    int64_t missed_contacts() const { return missed_; }

    // Bullet's body, to read. A welded host's Bullet body carries its passenger too: its
    // centre of mass, velocity and inertia are the pair's; com(), velocity(),
    // angular_velocity() and inertia_world() give each body's own.
    const btRigidBody& rb(graph::BodyId b) const { return *bodies_[b]; }
    // What bounds a convex shape's reach, measured when it was made; null for another shape.
    const ShapeReach* reach(const btCollisionShape& s) const { return shapes_.reach(s); }
    // Asks the processor for b's pose and velocity ahead of a pass over bodies that reads them
    // (a hint: it changes no result). A pass over many bodies in an order that is not their
    // order in memory (by place: the body index) misses on each one.
    void prefetch(graph::BodyId b) const {
        const char* t = reinterpret_cast<const char*>(&bodies_[b]->getWorldTransform());
        __builtin_prefetch(t);
        __builtin_prefetch(t + sizeof(btTransform) - 1);
        __builtin_prefetch(reinterpret_cast<const char*>(&bodies_[b]->getLinearVelocity()));
    }
    // The same for b's place and velocities, where b is in a world (check_bodies' look).
    void ask_body(graph::BodyId b) const {
        if (in_world_[b]) prefetch(b);
    }
    // The same for b's place alone, where b is in a world (assign_worlds' pass over the groups).
    void ask_origin(graph::BodyId b) const {
        if (in_world_[b]) __builtin_prefetch(&bodies_[b]->getWorldTransform().getOrigin());
    }
    // Bullet's body, to write its state by hand: ends its weld first (until the next step).
    btRigidBody& write(graph::BodyId b);
    btVector3 com(graph::BodyId b) const { return carries_[b].valid() ? host_com(b) : bodies_[b]->getCenterOfMassPosition(); }
    btVector3 velocity(graph::BodyId b) const { return carries_[b].valid() ? host_velocity(b) : bodies_[b]->getLinearVelocity(); }
    const btVector3& angular_velocity(graph::BodyId b) const { return bodies_[b]->getAngularVelocity(); }
    btMatrix3x3 inertia_world(graph::BodyId b) const {  // the body's own tensor, in the world
        const btMatrix3x3 R = (frame(b) * (carries_[b].valid() ? own_local(b) : local_[b])).getBasis();
        return R.scaled(inertia_[b]) * R.transpose();
    }
    // A force at the body's centre of mass and a torque (its carrier's, while welded).
    void apply(graph::BodyId b, const btVector3& force, const btVector3& torque);
    bool welded(graph::BodyId b) const { return carries_[b].valid() || carried_[b].valid(); }
    // The welds found at the start, and the rows of what their pairs are (welds alike share one).
    size_t weld_count() const { return welds_.size(); }
    size_t weld_shape_count() const { return weld_shapes_.size(); }
    bool in_world(graph::BodyId b) const { return in_world_[b]; }
    // How many times b's Bullet state (pose, velocity, flags, activation, broadphase box) has
    // been written other than by Bullet's step: every writer of Physics counts (wrote()), and
    // so does a world calling Bullet's saveKinematicState on a kinematic body (its velocity).
    // Bullet's step writes a kinematic body nothing else that differs (its solver writes back
    // the velocity it read, unchanged: no impulse moves a body of infinite mass). While the
    // count stands, a kinematic body is as it was: its world and steady transport pass over
    // it without reading it (physics.cpp, transport.cpp).
    uint32_t writes(graph::BodyId b) const { return writes_[b]; }
    bool declared_dynamic(graph::BodyId b) const { return mode_[b] == graph::BodyMode::Dynamic; }
    bool declared_static(graph::BodyId b) const { return mode_[b] == graph::BodyMode::Static; }
    // Simulated by the dynamics right now: declared dynamic, in the world, dynamics on.
    bool dynamic_now(graph::BodyId b) const { return in_world_[b] && dyn_on_[b] && mass_[b] > 0; }
    bool dynamics_on(graph::BodyId b) const { return dyn_on_[b]; }
    bool collision_on(graph::BodyId b) const { return coll_on_[b]; }
    double mass(graph::BodyId b) const { return mass_[b]; }

    // Membership: a body out of the world (a pooled object, one taken by an exit) is
    // not simulated and touches nothing; constraints are in the world exactly when all
    // their bodies are.
    void insert(graph::BodyId b);
    void take_out(graph::BodyId b);
    void set_dynamics(graph::BodyId b, bool on);  // off: kinematic, moved by us
    void set_collision(graph::BodyId b, bool on);  // off: in no broadphase pair
    void set_joint(graph::JointId j, bool on);
    bool joint_on(graph::JointId j) const { return joint_on_[j]; }
    // Changes whenever membership, a dynamics mode or a joint changes (caches compare it).
    uint64_t version() const { return version_; }
    // How many times step() has run: between two steps a body's state changes only through
    // the writers that count (writes), and its membership only with version().
    uint64_t steps() const { return steps_; }

    // The body frame (graph::Body::pose), not Bullet's centre-of-mass frame.
    graph::Pose pose(graph::BodyId b) const;
    btTransform frame(graph::BodyId b) const { return bodies_[b]->getWorldTransform() * local_inv_[b]; }
    // Steady transport (transport.cpp): a lone dynamic body or a weld's host (with its
    // passenger) that the conveyor law alone moves leaves the solver: flagged static, in no
    // pair, its broadphase box parked, its state written by coast_to() each step. land()
    // returns it; anything that writes its state or mode (unweld) lands it first.
    void coast(graph::BodyId b);
    // A unit held at rest (in a queue, against a pin, on a stopped band, beside others at
    // rest) leaves the solver another way: flagged static and of infinite mass, its velocity
    // zero, its broadphase box where it stands, so that what meets it stops as at a wall.
    // land() returns it too, with its mass.
    void rest(graph::BodyId b);
    void land(graph::BodyId b);
    // The unit b belongs to: b, or the host that carries b.
    graph::BodyId unit_of(graph::BodyId b) const {
        return carried_.empty() || !carried_[b].valid() ? b : carried_[b];
    }
    // Coasting (or resting), and resting: b's unit (only a unit leaves the solver).
    bool coasting(graph::BodyId b) const { return coast_[unit_of(b)] != 0; }
    bool resting(graph::BodyId b) const { return coast_[unit_of(b)] == kResting; }
    // Sets a coasting carrier's centre-of-mass frame and velocities; its passenger follows.
    void coast_to(graph::BodyId b, const btTransform& com_frame, const btVector3& v, const btVector3& w);
    // The passenger host b carries now, or -1.
    graph::BodyId passenger(graph::BodyId b) const { return carries_.empty() ? graph::BodyId{} : carries_[b]; }
    // Joined by no joint at all.
    bool lone(graph::BodyId b) const { return body_joints_.num.empty() || body_joints_.num[b] == 0; }
    // Counts the times a static body was placed (caches of static geometry compare it).
    uint64_t statics_placed() const { return statics_placed_; }

    // Teleport (also resets the previous pose, so a kinematic body gains no speed).
    void place(graph::BodyId b, const btTransform& frame);
    // Kinematic move: Bullet derives the body's velocity from it in the next step.
    void move(graph::BodyId b, const btTransform& frame);

private:
    // One Bullet world: a region's static bodies and the movers (bodies that are not static)
    // near them, or the void's movers (regions.cpp).
    struct World {
        World();
        ~World();
        World(World&&) noexcept;
        World& operator=(World&&) noexcept;
        std::unique_ptr<btCollisionConfiguration> config;
        std::unique_ptr<btCollisionDispatcher> dispatcher;
        std::unique_ptr<btBroadphaseInterface> broadphase;
        std::unique_ptr<btDiscreteDynamicsWorld> world;
        btVector3 lo{0, 0, 0}, hi{-1, -1, -1};  // the region's box (the void's is empty)
        bool active = false;                   // has a mover in the world: step it
        int32_t movers = 0;                    // bodies that are not static in it (largest first)
    };
    // A welded pair: a dynamic body that takes no collisions (a bottle's foot) joined by
    // an enabled fixed joint to a dynamic host is left out of Bullet's world, and the
    // host's Bullet body carries both (the fixed constraint leaves Bullet's world too). After
    // each step the passenger's state is copied from its carrier. See welds.cpp.
    // What a weld's pair is, apart from which bodies: welds alike to the bit (a pool's bottles)
    // share one row, so a pooled bottle keeps 20 bytes of its weld, not 336.
    struct WeldShape {
        graph::Pose rel;         // the passenger's body frame in the host's
        BodyShape own, both;     // the host alone, and the pair about its centre of mass
        btTransform off;         // the passenger's Bullet frame in the carrier's
        bool operator==(const WeldShape& o) const;  // to the bit, and the same shapes
    };
    struct Weld {
        graph::BodyId host, pass;
        graph::JointId joint;
        int32_t shape;  // its row in weld_shapes_
        bool on = false;
    };
    const WeldShape& shape_of(const Weld& w) const { return weld_shapes_[size_t(w.shape)]; }
    void find_welds();
    void weld_on(Weld& w);
    void weld_off(Weld& w);
    void follow(const Weld& w);
    void follow_world(int w);  // the welds whose carriers are in world w
    // The indices in world w's objects of those that are not static bodies, as its last step
    // found them (physics.cpp, IslandWorld): valid until a body joins or leaves that world.
    std::span<const int> live_objects(int w) const;
    void unweld(graph::BodyId b);
    void reshape(graph::BodyId b, const BodyShape& s);
    // A host's own Bullet frame relative to its body frame (its weld's own.local), where
    // host_com and inertia_world find the host's own within the pair.
    const btTransform& own_local(graph::BodyId b) const { return shape_of(welds_[size_t(weld_of_[b])]).own.local; }
    btVector3 host_com(graph::BodyId b) const { return frame(b) * own_local(b).getOrigin(); }
    btVector3 host_velocity(graph::BodyId b) const;
    void refilter(graph::BodyId b);
    void park(graph::BodyId b);  // parked: no pairs, its AABB far away
    void add_to_world(graph::BodyId b, bool filtered);
    void set_mode_flags(graph::BodyId b);
    void sync_joints(graph::BodyId b);
    // Bullet's constraints: made from the graph; a weld's exists only while it is in a world.
    void make_joint(graph::JointId j);
    void add_joint(graph::JointId j);     // into its world (made first if need be)
    void remove_joint(graph::JointId j);  // out of its world (a weld's constraint is dropped)
    void add_joints_at_start(const graph::IdVector<graph::BodyId, char>& pool);
    void reserve_joint_refs(const graph::IdVector<graph::BodyId, char>& pool);
    World& world_at(graph::BodyId b) { return worlds_[world_of_[b]]; }
    void make_world(World& w, Broadphase bp, size_t bodies);
    // regions.cpp
    void find_regions(bool split);  // split: regions allowed (not with sweep-and-prune)
    int home(graph::BodyId b) const;  // the region whose box b's bounding box meets, or the void
    void aabb(graph::BodyId b, btScalar grow, btVector3& lo, btVector3& hi) const;  // now, grown
    // A welded passenger: in the world, but not in Bullet's (its carrier stands for it).
    bool carried(graph::BodyId b) const { return !carried_.empty() && carried_[b].valid(); }
    void assign_worlds();
    void move_group(int32_t group, int to);
    void merge_worlds();
    void placed_static(graph::BodyId b);

    const graph::Graph& g_;
    btVector3 gravity_;
    ShapeCache shapes_;
    std::unique_ptr<BoxHullContacts> contacts_;  // outlives the dispatchers, which call it
    template <class T>
    using PerBody = graph::IdVector<graph::BodyId, T>;
    template <class T>
    using PerJoint = graph::IdVector<graph::JointId, T>;
    PerBody<std::unique_ptr<btRigidBody>> bodies_;
    PerJoint<std::unique_ptr<btTypedConstraint>> joints_;  // a weld's: null while it holds
    PerBody<btTransform> local_, local_inv_;  // Bullet frame relative to the body frame
    PerBody<btVector3> inertia_;
    PerBody<double> mass_;
    PerBody<uint8_t> in_world_, dyn_on_, coll_on_;
    PerBody<graph::BodyMode> mode_;  // Body::mode, in an array of its own: a Body row is large
    PerJoint<uint8_t> joint_in_, joint_on_;
    PerBody<uint8_t> coast_;  // per body: off the solver in steady transport (transport.cpp): kCoasting, kResting
    static constexpr uint8_t kCoasting = 1, kResting = 2;
    PerBody<uint32_t> writes_;  // per body: writes(); each body's counted by its own world only while it steps
    void wrote(graph::BodyId b) { ++writes_[b]; }
    std::vector<KinematicRest> kin_rest_;  // per body declared kinematic (its user index 2)
    uint64_t statics_placed_ = 0;
    PerBody<int> group_, mask_;  // broadphase filter while in the world
    Csr<graph::BodyId, graph::JointId> body_joints_;
    std::vector<Weld> welds_;
    std::vector<WeldShape> weld_shapes_;
    PerBody<int32_t> weld_of_;  // per body: its weld (host or passenger), or -1
    // Per body, while its weld is on (else none): the passenger it carries, and the carrier
    // that carries it (the accessors above ask these whether a body is welded).
    PerBody<graph::BodyId> carries_, carried_;
    PerJoint<int32_t> weld_joint_;  // per joint: the weld it makes, or -1
    bool welds_dirty_ = true;
    uint64_t version_ = 0;
    uint64_t steps_ = 0;

    // Bullet's constraint solvers, one per thread (worker_slot()): a world steps with the solver
    // of the thread that steps it. A solver keeps only its arrays from one call to the next
    // (each call sets up every entry it reads), so which one a world gets changes no result,
    // and the arrays sized for the largest world's contacts exist once per thread, not per world.
    std::vector<std::unique_ptr<btSequentialImpulseConstraintSolver>> solvers_;
    // Regions (regions.cpp): bodies joined by joints form a group and share a world.
    std::vector<World> worlds_;       // declared after the bodies: destroyed before them
    PerBody<int32_t> world_of_;   // per body
    PerBody<int32_t> group_of_;   // per body
    Csr<int32_t, graph::BodyId> group_bodies_;  // per group: its bodies
    std::vector<uint8_t> anchored_;   // per group: holds a static body (never leaves its region)
    std::vector<int32_t> free_groups_;  // groups of movers that are not anchored
    std::vector<int32_t> free_at_;      // per group: its position in free_groups_, or -1
    // A bit per position in free_groups_: clear while none of the group's bodies has been in
    // the world since assign_worlds found it parked in the void's world (it would stay there:
    // the decision passes over it; insert sets it).
    std::vector<uint64_t> free_live_;
    // assign_worlds' free groups that move (or join the void), as (position in free_groups_,
    // world or mark): each slice of the decision writes its own from its first group's
    // position on, and how many (free_moves_); a group that stays writes nothing.
    std::vector<std::pair<int32_t, int>> free_to_;
    std::vector<int32_t> free_moves_;  // per slice (kMaxSlices)
    std::vector<graph::BodyId> movers_;  // bodies that are not static
    std::vector<graph::BodyId> anchored_movers_;  // those in anchored groups
    // Per slice of movers_ and world (slice-major): its bodies that are not static and not
    // coasting (assign_worlds).
    std::vector<int32_t> slice_movers_;
    std::vector<int32_t> to_step_;    // scratch: the worlds to step
    std::vector<int32_t> by_movers_;  // every world, by its movers (most first), then id: as last ordered
    struct Near {  // a mover's bounding box and world, for void groups to meet
        btVector3 lo, hi;
        int world;
    };
    std::vector<int32_t> void_groups_, void_home_;  // scratch of assign_worlds
    std::vector<graph::JointId> moved_joints_;
    std::vector<uint8_t> void_mark_;  // per group: in void_groups_
    std::vector<Near> near_;
    int void_ = -1;                   // the void's world, or -1 with one region
    int64_t missed_ = 0;
    std::unique_ptr<Workers> workers_;
};

}  // namespace plant::engine
