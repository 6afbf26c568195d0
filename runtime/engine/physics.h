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
    int world_of(int32_t b) const { return world_of_[b]; }
    int threads() const;
    Workers& workers() { return *workers_; }
    // Bodies of two worlds whose bounding boxes met (their contact was not simulated).
    int64_t missed_contacts() const { return missed_; }

    // Bullet's body, to read. A welded host's Bullet body carries its passenger too: its
    // centre of mass, velocity and inertia are the pair's; com(), velocity(),
    // angular_velocity() and inertia_world() give each body's own.
    const btRigidBody& rb(int32_t b) const { return *bodies_[b]; }
    // Bullet's body, to write its state by hand: ends its weld first (until the next step).
    btRigidBody& write(int32_t b);
    btVector3 com(int32_t b) const { return carries_[b] ? host_com(b) : bodies_[b]->getCenterOfMassPosition(); }
    btVector3 velocity(int32_t b) const { return carries_[b] ? host_velocity(b) : bodies_[b]->getLinearVelocity(); }
    const btVector3& angular_velocity(int32_t b) const { return bodies_[b]->getAngularVelocity(); }
    btMatrix3x3 inertia_world(int32_t b) const;  // the body's own tensor, in the world
    // A force at the body's centre of mass and a torque (its carrier's, while welded).
    void apply(int32_t b, const btVector3& force, const btVector3& torque);
    bool welded(int32_t b) const { return weld_of_[b] >= 0 && welds_[weld_of_[b]].on; }
    bool in_world(int32_t b) const { return in_world_[b]; }
    bool declared_dynamic(int32_t b) const { return g_.bodies[b].mode == graph::BodyMode::Dynamic; }
    // Simulated by the dynamics right now: declared dynamic, in the world, dynamics on.
    bool dynamic_now(int32_t b) const { return in_world_[b] && dyn_on_[b] && mass_[b] > 0; }
    bool dynamics_on(int32_t b) const { return dyn_on_[b]; }
    bool collision_on(int32_t b) const { return coll_on_[b]; }
    double mass(int32_t b) const { return mass_[b]; }

    // Membership: a body out of the world (a pooled object, one taken by an exit) is
    // not simulated and touches nothing; constraints are in the world exactly when all
    // their bodies are.
    void insert(int32_t b);
    void take_out(int32_t b);
    void set_dynamics(int32_t b, bool on);  // off: kinematic, moved by us
    void set_collision(int32_t b, bool on);  // off: in no broadphase pair
    void set_joint(int32_t j, bool on);
    bool joint_on(int32_t j) const { return joint_on_[j]; }
    // Changes whenever membership, a dynamics mode or a joint changes (caches compare it).
    uint64_t version() const { return version_; }

    // The body frame (graph::Body::pose), not Bullet's centre-of-mass frame.
    graph::Pose pose(int32_t b) const;
    btTransform frame(int32_t b) const;
    // Steady transport (transport.cpp): a lone dynamic body or a weld's host (with its
    // passenger) that the conveyor law alone moves leaves the solver: flagged static, in no
    // pair, its broadphase box parked, its state written by coast_to() each step. land()
    // returns it; anything that writes its state or mode (unweld) lands it first.
    void coast(int32_t b);
    void land(int32_t b);
    // Coasting: b itself, or the host that carries b.
    bool coasting(int32_t b) const {
        if (coast_[b]) return true;
        const int32_t w = weld_of_.empty() ? -1 : weld_of_[b];
        return w >= 0 && welds_[w].on && coast_[welds_[w].host];
    }
    // Sets a coasting carrier's centre-of-mass frame and velocities; its passenger follows.
    void coast_to(int32_t b, const btTransform& com_frame, const btVector3& v, const btVector3& w);
    // The passenger host b carries now, or -1.
    int32_t passenger(int32_t b) const {
        const int32_t w = weld_of_.empty() ? -1 : weld_of_[b];
        return w >= 0 && welds_[w].on && welds_[w].host == b ? welds_[w].pass : -1;
    }
    // Joined by no joint at all.
    bool lone(int32_t b) const { return body_joints_.num.empty() || body_joints_.num[b] == 0; }
    // Counts the times a static body was placed (caches of static geometry compare it).
    uint64_t statics_placed() const { return statics_placed_; }

    // Teleport (also resets the previous pose, so a kinematic body gains no speed).
    void place(int32_t b, const btTransform& frame);
    // Kinematic move: Bullet derives the body's velocity from it in the next step.
    void move(int32_t b, const btTransform& frame);

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
    struct Weld {
        int32_t host = -1, pass = -1, joint = -1;
        graph::Pose rel;         // the passenger's body frame in the host's
        BodyShape own, both;     // the host alone, and the pair about its centre of mass
        btTransform off;         // the passenger's Bullet frame in the carrier's
        bool on = false;
    };
    void find_welds();
    void weld_on(Weld& w);
    void weld_off(Weld& w);
    void follow(const Weld& w);
    void follow_world(int w);  // the welds whose carriers are in world w
    void unweld(int32_t b);
    void reshape(int32_t b, const BodyShape& s);
    btVector3 host_com(int32_t b) const;
    btVector3 host_velocity(int32_t b) const;
    void refilter(int32_t b);
    void park(int32_t b);  // parked: no pairs, its AABB far away
    void add_to_world(int32_t b, bool filtered);
    void set_mode_flags(int32_t b);
    void sync_joints(int32_t b);
    // Bullet's constraints: made from the graph; a weld's exists only while it is in a world.
    void make_joint(int32_t j);
    void add_joint(int32_t j);     // into its world (made first if need be)
    void remove_joint(int32_t j);  // out of its world (a weld's constraint is dropped)
    void add_joints_at_start(const std::vector<char>& pool);
    World& world_at(int32_t b) { return worlds_[world_of_[b]]; }
    void make_world(World& w, Broadphase bp, size_t bodies);
    // regions.cpp
    void find_regions(bool split);  // split: regions allowed (not with sweep-and-prune)
    int home(int32_t b) const;  // the region whose box b's bounding box meets, or the void
    void aabb(int32_t b, btScalar grow, btVector3& lo, btVector3& hi) const;  // now, grown
    // A welded passenger: in the world, but not in Bullet's (its carrier stands for it).
    bool carried(int32_t b) const { return !carried_.empty() && carried_[b]; }
    void assign_worlds();
    void move_group(int32_t group, int to);
    void merge_worlds();
    void placed_static(int32_t b);

    const graph::Graph& g_;
    btVector3 gravity_;
    ShapeCache shapes_;
    std::unique_ptr<BoxHullContacts> contacts_;  // outlives the dispatchers, which call it
    std::vector<std::unique_ptr<btRigidBody>> bodies_;
    std::vector<std::unique_ptr<btTypedConstraint>> joints_;  // a weld's: null while it holds
    std::vector<btTransform> local_, local_inv_;  // Bullet frame relative to the body frame
    std::vector<btVector3> inertia_;
    std::vector<double> mass_;
    std::vector<uint8_t> in_world_, dyn_on_, coll_on_, joint_in_, joint_on_;
    std::vector<uint8_t> coast_;  // per body: off the solver in steady transport (transport.cpp)
    uint64_t statics_placed_ = 0;
    std::vector<int> group_, mask_;  // broadphase filter while in the world
    Csr body_joints_;
    std::vector<Weld> welds_;
    std::vector<int32_t> weld_of_;  // per body: its weld (host or passenger), or -1
    std::vector<uint8_t> carries_;  // per body: 1 while it carries a passenger
    std::vector<uint8_t> carried_;  // per body: 1 while it is a carried passenger (no look into welds_)
    std::vector<int32_t> weld_joint_;  // per joint: the weld it makes, or -1
    bool welds_dirty_ = true;
    uint64_t version_ = 0;

    // Bullet's constraint solvers, one per thread (worker_slot()): a world steps with the solver
    // of the thread that steps it. A solver keeps only its arrays from one call to the next
    // (each call sets up every entry it reads), so which one a world gets changes no result,
    // and the arrays sized for the largest world's contacts exist once per thread, not per world.
    std::vector<std::unique_ptr<btSequentialImpulseConstraintSolver>> solvers_;
    // Regions (regions.cpp): bodies joined by joints form a group and share a world.
    std::vector<World> worlds_;       // declared after the bodies: destroyed before them
    std::vector<int32_t> world_of_;   // per body
    std::vector<int32_t> group_of_;   // per body
    Csr group_bodies_;                // per group: its bodies
    std::vector<uint8_t> anchored_;   // per group: holds a static body (never leaves its region)
    std::vector<int32_t> free_groups_;  // groups of movers that are not anchored
    std::vector<int> free_to_;          // per free group: the world it goes to (assign_worlds)
    std::vector<int32_t> movers_;     // bodies that are not static
    std::vector<int32_t> to_step_;    // scratch: the worlds to step
    struct Near {  // a mover's bounding box and world, for void groups to meet
        btVector3 lo, hi;
        int world;
    };
    std::vector<int32_t> void_groups_, void_home_, moved_joints_;  // scratch of assign_worlds
    std::vector<uint8_t> void_mark_;  // per group: in void_groups_
    std::vector<Near> near_;
    int void_ = -1;                   // the void's world, or -1 with one region
    int64_t missed_ = 0;
    std::unique_ptr<Workers> workers_;
};

}  // namespace plant::engine
