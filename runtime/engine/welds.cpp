// Welded pairs carried by one Bullet body (see physics.h, Physics::Weld).
//
// A bottle is a main body and a small bottom body joined by a fixed joint (std.bottle).
// Given to Bullet as two bodies and a constraint, the pair costs a second body to
// integrate, six solver rows every iteration and an island that holds both; about 15 %
// of the bottling plant's step. The constraint only keeps the two rigidly together, so
// while the weld holds (joint enabled, both in the world and dynamic, the bottom body
// taking no collisions) the main body's Bullet body takes the pair's mass, centre of mass
// and inertia, and the bottom body leaves Bullet's world: after each step its state is
// the carrier's rigid motion at its place. The conveyor law still pulls each body at its
// own centre of mass with its own velocity (apply() passes a passenger's force on to its
// carrier at that point), so the bottle tips as before.
//
// Anything that changes a body's membership or mode, or writes its state by hand, ends
// the weld first; update_welds() forms it again before the next step's forces.
#include "engine/physics.h"

#include "engine/contact.h"
#include "engine/pose.h"

#include <BulletDynamics/ConstraintSolver/btTypedConstraint.h>
#include <BulletCollision/BroadphaseCollision/btBroadphaseInterface.h>
#include <BulletCollision/BroadphaseCollision/btOverlappingPairCache.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>

#include <unordered_map>
#include <vector>

namespace plant::engine {

using namespace plant::graph;

namespace {

bool same(const BodyShape& a, const BodyShape& b) {
    return a.shape == b.shape && a.local == b.local && a.inertia == b.inertia && a.mass == b.mass;
}

}  // namespace

bool Physics::WeldShape::operator==(const WeldShape& o) const {
    return rel == o.rel && same(own, o.own) && same(both, o.both) && off == o.off;
}

void Physics::find_welds() {
    weld_of_.assign(g_.bodies.size(), -1);
    carries_.assign(g_.bodies.size(), BodyId{});
    carried_.assign(g_.bodies.size(), BodyId{});
    weld_joint_.assign(g_.joints.size(), -1);
    // Welds alike to the bit share their WeldShape's row, looked for among the rows made for
    // the same pair's shape (a pool's bottles share theirs: shapes.h).
    std::unordered_map<const void*, std::vector<int32_t>> rows_of;
    for (JointId j : ids_of(g_.joints)) {
        const Joint& jt = g_.joints[j];
        if (jt.kind != JointKind::Fixed || !jt.body_b.valid() || jt.body_a == jt.body_b) continue;
        const BodyId a = jt.body_a, b = jt.body_b;
        if (!declared_dynamic(a) || !declared_dynamic(b) || mass_[a] <= 0 || mass_[b] <= 0) continue;
        const bool a_solid = g_.bodies[a].collision, b_solid = g_.bodies[b].collision;
        if (a_solid == b_solid) continue;  // the passenger is the one without collisions
        Weld w;
        w.host = a_solid ? a : b;
        w.pass = a_solid ? b : a;
        w.joint = j;
        if (body_joints_.num[w.pass] != 1 || weld_of_[w.host] >= 0 || weld_of_[w.pass] >= 0) continue;
        WeldShape ws;
        // The joint holds frame_a on a where frame_b is on b.
        ws.rel = a_solid ? pmul(jt.frame_a, pinv(jt.frame_b)) : pmul(jt.frame_b, pinv(jt.frame_a));
        ws.own = BodyShape{bodies_[w.host]->getCollisionShape(), local_[w.host], inertia_[w.host], mass_[w.host]};
        ws.both = shapes_.build_welded(g_, g_.bodies[w.host], g_.bodies[w.pass], ws.rel);
        ws.off = ws.both.local.inverse() * to_bt(ws.rel) * local_[w.pass];
        std::vector<int32_t>& rows = rows_of[ws.both.shape];
        w.shape = -1;
        for (const int32_t k : rows)
            if (weld_shapes_[size_t(k)] == ws) {
                w.shape = k;
                break;
            }
        if (w.shape < 0) {
            contacts_->prepare(*ws.both.shape);  // not at its first contact, inside a step
            w.shape = count_of(weld_shapes_);
            rows.push_back(w.shape);
            weld_shapes_.push_back(ws);
        }
        weld_of_[w.host] = weld_of_[w.pass] = weld_joint_[j] = count_of(welds_);
        welds_.push_back(w);
    }
}

void Physics::update_welds() {
    if (!welds_dirty_) return;
    welds_dirty_ = false;
    for (Weld& w : welds_) {
        const bool want = joint_on_[w.joint] && in_world_[w.host] && in_world_[w.pass] && dyn_on_[w.host] &&
                          dyn_on_[w.pass] && !coll_on_[w.pass];
        if (want && !w.on) weld_on(w);
        else if (!want && w.on) weld_off(w);
    }
}

void Physics::unweld(BodyId b) {
    if (!coast_.empty() && coasting(b)) land(unit_of(b));  // its state is written
    if (weld_of_.empty() || weld_of_[b] < 0) return;  // (none yet while the constructor runs)
    Weld& w = welds_[weld_of_[b]];
    if (w.on) weld_off(w);
    welds_dirty_ = true;
}

// Gives body b's Bullet body another shape and mass, keeping its body frame and the
// velocity of every point of it.
void Physics::reshape(BodyId b, const BodyShape& s) {
    wrote(b);
    btRigidBody& r = *bodies_[b];
    const btTransform body = frame(b);
    const btVector3 v = r.getLinearVelocity(), w = r.getAngularVelocity(), c = r.getCenterOfMassPosition();
    local_[b] = s.local;
    local_inv_[b] = s.local.inverse();
    r.setCollisionShape(s.shape);
    r.setMassProps(btScalar(s.mass), s.inertia);
    r.setGravity(gravity_);                       // Bullet keeps gravity as a force: m·g
    r.setCenterOfMassTransform(body * s.local);   // and the interpolation frame, the inertia
    r.setLinearVelocity(v + w.cross(r.getCenterOfMassPosition() - c));
    r.setAngularVelocity(w);
    // Collision algorithms were made for the old shape: the pairs get new ones next step.
    World& in = world_at(b);
    in.broadphase->getOverlappingPairCache()->cleanProxyFromPairs(r.getBroadphaseHandle(), in.dispatcher.get());
    in.world->updateSingleAabb(&r);
}

void Physics::weld_on(Weld& w) {
    if (joint_in_[w.joint]) remove_joint(w.joint);  // and its Bullet constraint is dropped
    world_at(w.pass).world->removeRigidBody(bodies_[w.pass].get());
    reshape(w.host, shape_of(w).both);
    w.on = true;
    carries_[w.host] = w.pass;
    carried_[w.pass] = w.host;
    follow(w);
}

void Physics::weld_off(Weld& w) {
    follow(w);  // the passenger where its carrier left it
    w.on = false;
    carries_[w.host] = BodyId{};
    carried_[w.pass] = BodyId{};
    reshape(w.host, shape_of(w).own);
    set_mode_flags(w.pass);
    add_to_world(w.pass, true);
    if (in_world_[w.host] && in_world_[w.pass]) add_joint(w.joint);  // made again from the graph
}

void Physics::follow(const Weld& w) {
    const btRigidBody& h = *bodies_[w.host];
    btRigidBody& p = *bodies_[w.pass];
    wrote(w.pass);
    const btTransform t = h.getWorldTransform() * shape_of(w).off;
    p.setWorldTransform(t);
    p.setInterpolationWorldTransform(t);
    p.setLinearVelocity(h.getLinearVelocity() + h.getAngularVelocity().cross(t.getOrigin() - h.getCenterOfMassPosition()));
    p.setAngularVelocity(h.getAngularVelocity());
}

// A carrier is a body Bullet simulates (dynamic, in the world): it is among its world's
// non-static bodies. Each passenger is written by its own carrier's world only.
void Physics::follow_world(int w) {
    if (welds_.empty()) return;
    // Static bodies carry nothing: only the others are visited (a line has about 200 static
    // bodies, each a cache miss to read).
    const btCollisionObjectArray& all = worlds_[w].world->getCollisionObjectArray();
    for (const int i : live_objects(w)) {
        const BodyId b(all[i]->getUserIndex());  // its graph id (physics.cpp)
        if (all[i]->isStaticObject() || !carries_[b].valid()) continue;
        follow(welds_[weld_of_[b]]);
    }
}

btRigidBody& Physics::write(BodyId b) {
    unweld(b);
    wrote(b);
    return *bodies_[b];
}

btVector3 Physics::host_velocity(BodyId b) const {
    const btRigidBody& r = *bodies_[b];
    return r.getLinearVelocity() + r.getAngularVelocity().cross(host_com(b) - r.getCenterOfMassPosition());
}


void Physics::apply(BodyId b, const btVector3& force, const btVector3& torque) {
    btRigidBody& carrier = *bodies_[welded(b) ? welds_[weld_of_[b]].host : b];
    carrier.applyForce(force, com(b) - carrier.getCenterOfMassPosition());
    carrier.applyTorque(torque);
}

}  // namespace plant::engine
