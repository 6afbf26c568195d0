// Membership and modes of bodies and constraints: the only way the phases change
// what Bullet simulates. See physics.h.
#include "engine/physics.h"

#include "engine/pose.h"

#include <BulletDynamics/ConstraintSolver/btTypedConstraint.h>
#include <BulletCollision/BroadphaseCollision/btBroadphaseInterface.h>
#include <BulletCollision/BroadphaseCollision/btOverlappingPairCache.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>

namespace plant::engine {

using namespace plant::graph;

namespace {
// Statics and kinematics never need pairs among themselves (no response possible).
constexpr int kAll = btBroadphaseProxy::AllFilter;
constexpr int kStatic = btBroadphaseProxy::StaticFilter;
constexpr int kKinematic = btBroadphaseProxy::KinematicFilter;
}  // namespace

void Physics::add_to_world(BodyId b, bool filtered) {
    switch (mode_[b]) {
    case BodyMode::Dynamic: group_[b] = btBroadphaseProxy::DefaultFilter, mask_[b] = kAll; break;
    case BodyMode::Static: group_[b] = kStatic, mask_[b] = kAll ^ kStatic; break;
    case BodyMode::Kinematic: group_[b] = kKinematic, mask_[b] = kAll ^ kStatic ^ kKinematic; break;
    }
    const bool pairs = filtered && coll_on_[b] && coast_[b] != kCoasting;  // a resting body keeps its pairs
    world_at(b).world->addRigidBody(bodies_[b].get(), pairs ? group_[b] : 0, pairs ? mask_[b] : 0);
    if (coast_[b] == kCoasting) park(b);  // moved to another region's world while coasting
}

// Bullet's static/kinematic flags as the body's mode and dynamics switch say. A parked
// body is flagged static: Bullet integrates every non-static body of its world each step
// (predictIntegratedTransform, without looking at its activation), parked or not.
void Physics::set_mode_flags(BodyId b) {
    wrote(b);
    btRigidBody& r = *bodies_[b];
    int f = r.getCollisionFlags() & ~(btCollisionObject::CF_STATIC_OBJECT | btCollisionObject::CF_KINEMATIC_OBJECT);
    const BodyMode mode = mode_[b];
    if (!in_world_[b] || mode == BodyMode::Static || coast_[b]) f |= btCollisionObject::CF_STATIC_OBJECT;
    else if (mode == BodyMode::Kinematic || !dyn_on_[b]) f |= btCollisionObject::CF_KINEMATIC_OBJECT;
    r.setCollisionFlags(f);
}

void Physics::sync_joints(BodyId b) {
    if (body_joints_.num.empty()) return;
    for (JointId j : body_joints_[b]) {
        const Joint& jt = g_.joints[j];
        bool want = in_world_[jt.body_a] && (!jt.body_b.valid() || in_world_[jt.body_b]);
        if (want == bool(joint_in_[j])) continue;
        if (want) add_joint(j);
        else remove_joint(j);
    }
}

// A body out of the world stays in Bullet's world, parked: not simulated, in no
// broadphase pair. Removing and re-adding would allocate a broadphase proxy each time
// an object is issued or taken; parking costs nothing per step.
void Physics::insert(BodyId b) {
    if (in_world_[b]) return;
    unweld(b);
    btRigidBody& r = *bodies_[b];
    r.forceActivationState(mode_[b] == BodyMode::Static ? ISLAND_SLEEPING : DISABLE_DEACTIVATION);
    in_world_[b] = 1;
    if (!free_at_.empty())  // its group is looked at by assign_worlds again
        if (const int32_t k = free_at_[group_of_[b]]; k >= 0) free_live_[size_t(k) / 64] |= uint64_t(1) << (k % 64);
    set_mode_flags(b);
    refilter(b);
    ++version_;
    sync_joints(b);
}

void Physics::take_out(BodyId b) {
    if (!in_world_[b]) return;
    unweld(b);
    in_world_[b] = 0;
    ++version_;
    sync_joints(b);
    btRigidBody& r = *bodies_[b];
    r.setLinearVelocity(btVector3(0, 0, 0));
    r.setAngularVelocity(btVector3(0, 0, 0));
    r.clearForces();
    r.forceActivationState(DISABLE_SIMULATION);
    set_mode_flags(b);
    park(b);
}

void Physics::park(BodyId b) {
    wrote(b);
    btBroadphaseProxy* proxy = bodies_[b]->getBroadphaseHandle();
    proxy->m_collisionFilterGroup = 0;
    proxy->m_collisionFilterMask = 0;
    World& w = world_at(b);
    w.broadphase->getOverlappingPairCache()->cleanProxyFromPairs(proxy, w.dispatcher.get());
    // Its AABB goes out of the way too, each parked body to a point of its own: a body
    // issued where its parked twin sits (a source's pool) collided with it although the
    // twin's proxy has no group and no mask (seen with btDbvtBroadphase). The points are
    // scattered over a square, b·7919 mod 65521 metres across and b div 65521 along: along a
    // line, Bullet's tree (which puts a leaf beside its nearest, and ours is never rebalanced:
    // physics.cpp, LeanDbvt) grew into a chain as deep as the bodies parked there, each
    // parking walked it, and the walk's stack grew as deep (a 200-line bottling plant spent a
    // quarter of its start there, its pools waiting in the void's world). The tree's shape
    // changes no result (docs/runtime.md, "The solver's order").
    constexpr int64_t kSide = 65521;  // a prime: b·7919 mod kSide differs for every b below it
    const btVector3 park(btScalar(5000 + int64_t{b.v} * 7919 % kSide), btScalar(5000 + b.v / kSide), 5000);
    w.broadphase->setAabb(proxy, park, park, w.dispatcher.get());
}

// Dynamic and kinematic bodies share Bullet's list of non-static bodies and our
// broadphase group: switching needs flags and mass only, no re-adding.
void Physics::set_dynamics(BodyId b, bool on) {
    if (!declared_dynamic(b) || bool(dyn_on_[b]) == on) return;
    unweld(b);
    btRigidBody& r = *bodies_[b];
    if (on) {
        r.setMassProps(btScalar(mass_[b]), inertia_[b]);
        r.updateInertiaTensor();
        r.setGravity(gravity_);
    } else {
        r.setMassProps(0, btVector3(0, 0, 0));  // sets CF_STATIC_OBJECT: set_mode_flags decides
        r.setInterpolationWorldTransform(r.getWorldTransform());
    }
    r.setLinearVelocity(btVector3(0, 0, 0));
    r.setAngularVelocity(btVector3(0, 0, 0));
    r.clearForces();
    dyn_on_[b] = on;
    set_mode_flags(b);
    ++version_;
}

// A body that takes no collisions is in no broadphase pair at all (group and mask 0),
// like a parked one: no narrowphase work for it. Triggers do not need its pairs; they
// read AABBs from our own index (kinds/trigger/run.cpp).
void Physics::set_collision(BodyId b, bool on) {
    if (bool(coll_on_[b]) == on) return;
    unweld(b);
    coll_on_[b] = on;
    if (in_world_[b]) refilter(b);
}

// Gives an in-world body's proxy the filter its mode and collision switch ask for and
// makes the broadphase look for its pairs again.
void Physics::refilter(BodyId b) {
    wrote(b);
    btRigidBody& r = *bodies_[b];
    World& w = world_at(b);
    btBroadphaseProxy* proxy = r.getBroadphaseHandle();
    proxy->m_collisionFilterGroup = coll_on_[b] ? group_[b] : 0;
    proxy->m_collisionFilterMask = coll_on_[b] ? mask_[b] : 0;
    if (!coll_on_[b]) {  // cleanProxyFromPairs would keep the pairs (and their contacts next step)
        w.broadphase->getOverlappingPairCache()->removeOverlappingPairsContainingProxy(proxy, w.dispatcher.get());
        return;
    }
    // Through a far box and back, so the broadphase looks for new pairs even if the
    // body comes back where it was (issued where it was parked, collision switched on).
    const btVector3 far(999, 999, 999);
    w.broadphase->setAabb(proxy, far, far, w.dispatcher.get());
    w.world->updateSingleAabb(&r);
}

void Physics::set_joint(JointId j, bool on) {
    if (weld_joint_[j] >= 0) unweld(welds_[weld_joint_[j]].host);
    if (joints_[j]) joints_[j]->setEnabled(on);  // a weld's joint is made with joint_on_
    joint_on_[j] = on;
    ++version_;
}

Pose Physics::pose(BodyId b) const { return from_bt(frame(b)); }

void Physics::place(BodyId b, const btTransform& f) {
    unweld(b);
    wrote(b);
    btRigidBody& r = *bodies_[b];
    btTransform t = f * local_[b];
    r.setWorldTransform(t);
    r.setInterpolationWorldTransform(t);
    if (in_world_[b]) world_at(b).world->updateSingleAabb(&r);
    if (mode_[b] == BodyMode::Static) ++statics_placed_;
    if (void_ >= 0 && mode_[b] == BodyMode::Static) placed_static(b);
}

void Physics::move(BodyId b, const btTransform& f) {
    wrote(b);
    bodies_[b]->setWorldTransform(f * local_[b]);
}

}  // namespace plant::engine
