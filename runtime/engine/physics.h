// The one owner of the Bullet world and of every Bullet object: created in order
// (configuration, dispatcher, broadphase, solver, world, shapes, bodies, constraints)
// and destroyed in reverse. Bodies carry their graph id in setUserIndex, constraints
// in setUserConstraintId. The phases change membership and modes only through here.
#pragma once

#include "engine/engine.h"
#include "engine/shapes.h"
#include "engine/tables.h"

#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <memory>
#include <vector>

class btDefaultCollisionConfiguration;
class btCollisionDispatcher;
class btBroadphaseInterface;
class btSequentialImpulseConstraintSolver;
class btDiscreteDynamicsWorld;
class btTypedConstraint;

namespace plant::engine {

class BoxHullContacts;

class Physics {
public:
    Physics(const graph::Graph& g, const Tables& t, Broadphase bp);
    ~Physics();
    Physics(const Physics&) = delete;
    Physics& operator=(const Physics&) = delete;

    void step(double dt);
    btDiscreteDynamicsWorld& world() { return *world_; }

    btRigidBody& rb(int32_t b) const { return *bodies_[b]; }
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
    // Teleport (also resets the previous pose, so a kinematic body gains no speed).
    void place(int32_t b, const btTransform& frame);
    // Kinematic move: Bullet derives the body's velocity from it in the next step.
    void move(int32_t b, const btTransform& frame);

private:
    void refilter(int32_t b);
    void add_to_world(int32_t b, bool filtered);
    void set_mode_flags(int32_t b);
    void sync_joints(int32_t b);

    const graph::Graph& g_;
    std::unique_ptr<btDefaultCollisionConfiguration> config_;
    std::unique_ptr<BoxHullContacts> contacts_;  // outlives the dispatcher, which calls it
    std::unique_ptr<btCollisionDispatcher> dispatcher_;
    std::unique_ptr<btBroadphaseInterface> broadphase_;
    std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
    std::unique_ptr<btDiscreteDynamicsWorld> world_;
    ShapeCache shapes_;
    std::vector<std::unique_ptr<btRigidBody>> bodies_;
    std::vector<std::unique_ptr<btTypedConstraint>> joints_;
    std::vector<btTransform> local_, local_inv_;  // Bullet frame relative to the body frame
    std::vector<btVector3> inertia_;
    std::vector<double> mass_;
    std::vector<uint8_t> in_world_, dyn_on_, coll_on_, joint_in_, joint_on_;
    std::vector<int> group_, mask_;  // broadphase filter while in the world
    Csr body_joints_;
    uint64_t version_ = 0;
};

}  // namespace plant::engine
