#include "engine/physics.h"

#include "engine/contact.h"
#include "engine/pose.h"
#include "engine/workers.h"

#include <BulletCollision/BroadphaseCollision/btAxisSweep3.h>
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletDynamics/ConstraintSolver/btFixedConstraint.h>
#include <BulletDynamics/ConstraintSolver/btHingeConstraint.h>
#include <BulletDynamics/ConstraintSolver/btPoint2PointConstraint.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletDynamics/ConstraintSolver/btSliderConstraint.h>
#include <BulletCollision/CollisionDispatch/btSimulationIslandManager.h>
#include <BulletCollision/CollisionDispatch/btUnionFind.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <cstring>
#include <cstdint>
#include <cstdlib>
#include <thread>

namespace plant::engine {

using namespace plant::graph;

namespace {

// Installed before main, so that every Bullet object of the process comes from it.
[[maybe_unused]] const bool g_bullet_pool = install_bullet_pool();

// ---- The dynamics world: Bullet's, with a constraint lookup per island that does not
// scan every constraint. Bullet's island callback looks for an island's joints by a
// linear scan of all joints (and counts to the end), once per island: with a bottle per
// island and a weld per bottle that is quadratic in the bottles (5 % of a step at 1,000
// bottles). Here each island's run of joints is found by binary search in the same
// sorted array; the groups handed to the solver are Bullet's.
// What the solver is handed is in an order of the plant's own: an island's joints by their
// graph ids, its contact manifolds by their bodies' (in_order). Bullet hands them in the order
// its pair cache holds the pairs, which follows the broadphase's trees (their shape, how
// bodies came and went), and the sequential-impulse solver's sums depend on that order; in
// this one they do not. So the broadphase is free to keep its trees as it likes (LeanDbvt), and
// a plant of one world gives the same bytes with either broadphase (determinism_test).
int island_of(const btTypedConstraint* c) {
    const int a = c->getRigidBodyA().getIslandTag();
    return a >= 0 ? a : c->getRigidBodyB().getIslandTag();
}

class IslandSolver : public btSimulationIslandManager::IslandCallback {
public:
    void setup(btContactSolverInfo* info, btConstraintSolver* solver, btDispatcher* dispatcher,
               btTypedConstraint** sorted, int num) {
        info_ = info, solver_ = solver, dispatcher_ = dispatcher, sorted_ = sorted, num_ = num;
    }
    void processIsland(btCollisionObject** bodies, int num_bodies, btPersistentManifold** manifolds,
                       int num_manifolds, int island) override {
        if (island < 0) {  // islands not split: everything at once
            solver_->solveGroup(bodies, num_bodies, in_order(manifolds, num_manifolds), num_manifolds, sorted_, num_,
                                *info_, nullptr, dispatcher_);
            return;
        }
        btTypedConstraint** first = std::lower_bound(
            sorted_, sorted_ + num_, island, [](const btTypedConstraint* c, int id) { return island_of(c) < id; });
        btTypedConstraint** last = first;
        while (last != sorted_ + num_ && island_of(*last) == island) ++last;
        const int num_joints = int(last - first);
        if (info_->m_minimumSolverBatchSize <= 1) {
            solver_->solveGroup(bodies, num_bodies, in_order(manifolds, num_manifolds), num_manifolds,
                                num_joints ? first : nullptr, num_joints, *info_, nullptr, dispatcher_);
            return;
        }
        for (int i = 0; i < num_bodies; ++i) bodies_.push_back(bodies[i]);
        const int from = manifolds_.size();
        for (int i = 0; i < num_manifolds; ++i) manifolds_.push_back(manifolds[i]);
        if (num_manifolds > 1) sort_by_key(&manifolds_[from], num_manifolds);
        for (btTypedConstraint** c = first; c != last; ++c) joints_.push_back(*c);
        if (joints_.size() + manifolds_.size() > info_->m_minimumSolverBatchSize) flush();
    }
    // The island's manifolds in an order of their own (by_key), whatever order the pair cache
    // holds them in: a copy, sorted (its room kept from step to step); a batch sorts each
    // island's run where it copies it. Islands are solved apart or in batches: either way a
    // contact's sums read only its own island's bodies.
    btPersistentManifold** in_order(btPersistentManifold** manifolds, int n) {
        if (n <= 1) return manifolds;
        order_.resize(n);
        for (int i = 0; i < n; ++i) order_[i] = manifolds[i];
        sort_by_key(&order_[0], n);
        return &order_[0];
    }
    static void sort_by_key(btPersistentManifold** first, int n) { std::sort(first, first + n, by_key); }
    // A manifold's two bodies (their graph ids, in the manifold's order: its pair's) and the
    // parts (a compound's children) its first contact point joins; a manifold without points
    // adds nothing to the solver and sorts among its pair's anywhere.
    static bool by_key(const btPersistentManifold* x, const btPersistentManifold* y) {
        auto key = [](const btPersistentManifold* m) {
            const int n = m->getNumContacts();
            const btManifoldPoint* p = n ? &m->getContactPoint(0) : nullptr;
            return std::array<int, 6>{m->getBody0()->getUserIndex(), m->getBody1()->getUserIndex(),
                                      p ? p->m_partId0 : -2, p ? p->m_index0 : -2,
                                      p ? p->m_partId1 : -2, p ? p->m_index1 : -2};
        };
        return key(x) < key(y);
    }
    void flush() {
        solver_->solveGroup(bodies_.size() ? &bodies_[0] : nullptr, bodies_.size(),
                            manifolds_.size() ? &manifolds_[0] : nullptr, manifolds_.size(),
                            joints_.size() ? &joints_[0] : nullptr, joints_.size(), *info_, nullptr, dispatcher_);
        bodies_.resize(0);
        manifolds_.resize(0);
        joints_.resize(0);
    }

private:
    btContactSolverInfo* info_ = nullptr;
    btConstraintSolver* solver_ = nullptr;
    btDispatcher* dispatcher_ = nullptr;
    btTypedConstraint** sorted_ = nullptr;
    int num_ = 0;
    btAlignedObjectArray<btCollisionObject*> bodies_;
    btAlignedObjectArray<btPersistentManifold*> manifolds_;
    btAlignedObjectArray<btTypedConstraint*> joints_;
    btAlignedObjectArray<btPersistentManifold*> order_;
};

// Proxy p out of its stage's list and to the head of stage `to`'s (STAGECOUNT: the fixed
// tree's), as Bullet's broadphase moves a proxy between its stage lists.
void restage(btDbvtBroadphase& bp, btDbvtProxy* p, int to) {
    btDbvtProxy*& from = bp.m_stageRoots[p->stage];
    if (p->links[0]) p->links[0]->links[1] = p->links[1];
    else from = p->links[1];
    if (p->links[1]) p->links[1]->links[0] = p->links[0];
    p->stage = to;
    btDbvtProxy*& head = bp.m_stageRoots[to];
    p->links[0] = nullptr;
    p->links[1] = head;
    if (head) head->links[0] = p;
    head = p;
}

// What btDbvtBroadphase::setAabb (Bullet 3.24) does when handed the box a proxy holds, the
// proxy in the dynamic tree and its leaf's volume holding that box (it did since the call that
// gave the proxy this box: a leaf's volume changes only when its own proxy's box does): it
// counts the call and moves the proxy to the head of the current stage's list (so it is not
// taken to the fixed tree), the trees untouched and no pair sought. Done here without the
// look at the leaf (a cache miss for each still kinematic part, each step), with the same
// writes in the same order. A debug build checks the leaf.
void keep_box(btDbvtBroadphase& bp, btDbvtProxy* p) {
    assert(p->stage != btDbvtBroadphase::STAGECOUNT);
    assert(p->leaf->volume.Contain(btDbvtVolume::FromMM(p->m_aabbMin, p->m_aabbMax)));
    ++bp.m_updates_call;
    restage(bp, p, bp.m_stageCurrent);
}

// Bullet's broadphase of two AABB trees (btDbvtBroadphase, 3.24) without its incremental
// optimisation: each step Bullet takes a leaf of each tree out and puts it back where it
// fits best (optimizeIncremental; the fixed tree's pass again after any body settles into it),
// a walk down the tree and back up, mostly cache misses: 12 % of the step at 5,000 bottles
// (417 worlds). The trees' shape decides only the order in which pairs are found, and the
// solver no longer sees that order (IslandSolver::in_order), so a step's results are the same
// bytes with the passes or without them. The rest is what Bullet's step of the broadphase does:
// the bodies whose boxes stayed put for two steps move to the fixed tree; pairs whose boxes
// parted are dropped, a tenth of the pairs looked at per step (and at least as many as were
// found); Bullet's counters kept as it keeps them.
class LeanDbvt : public btDbvtBroadphase {
public:
    void calculateOverlappingPairs(btDispatcher* dispatcher) override {
        m_stageCurrent = (m_stageCurrent + 1) % STAGECOUNT;
        if (m_stageRoots[m_stageCurrent]) m_needcleanup = true;
        for (btDbvtProxy* p = m_stageRoots[m_stageCurrent]; p;) {
            btDbvtProxy* next = p->links[1];
            restage(*this, p, STAGECOUNT);
            m_sets[0].remove(p->leaf);
            ATTRIBUTE_ALIGNED16(btDbvtVolume) box = btDbvtVolume::FromMM(p->m_aabbMin, p->m_aabbMax);
            p->leaf = m_sets[1].insert(box, p);
            p = next;
        }
        if (m_needcleanup) {
            btBroadphasePairArray& pairs = m_paircache->getOverlappingPairArray();
            if (pairs.size() > 0) {
                int ni = std::min(pairs.size(), std::max(m_newpairs, (pairs.size() * m_cupdates) / 100));
                for (int i = 0; i < ni; ++i) {
                    btBroadphasePair& pr = pairs[(m_cid + i) % pairs.size()];
                    btDbvtProxy* pa = static_cast<btDbvtProxy*>(pr.m_pProxy0);
                    btDbvtProxy* pb = static_cast<btDbvtProxy*>(pr.m_pProxy1);
                    if (!Intersect(pa->leaf->volume, pb->leaf->volume)) {
                        m_paircache->removeOverlappingPair(pa, pb, dispatcher);
                        --ni;
                        --i;
                    }
                }
                m_cid = pairs.size() > 0 ? (m_cid + ni) % pairs.size() : 0;
            }
        }
        ++m_pid;
        m_newpairs = 1;
        m_needcleanup = false;
        m_updates_ratio = m_updates_call > 0 ? m_updates_done / btScalar(m_updates_call) : 0;
        m_updates_done /= 2;
        m_updates_call /= 2;
        performDeferredRemoval(dispatcher);
    }
};

class IslandWorld : public btDiscreteDynamicsWorld {
public:
    IslandWorld(const Graph& g, std::vector<KinematicRest>& rest, IdVector<BodyId, uint32_t>& writes, btDispatcher* d,
                btBroadphaseInterface* bp, btConstraintSolver* cs, btCollisionConfiguration* cc)
        : btDiscreteDynamicsWorld(d, bp, cs, cc), g_(g), rest_(rest), writes_(writes),
          dbvt_(dynamic_cast<btDbvtBroadphase*>(bp)) {}

    // The world's list of objects changes only through these (Bullet's addRigidBody calls
    // addCollisionObject; its removeCollisionObject calls removeRigidBody for a rigid body):
    // list_live finds the live objects again after any of them.
    void addCollisionObject(btCollisionObject* o, int group = btBroadphaseProxy::StaticFilter,
                            int mask = btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter) override {
        btDiscreteDynamicsWorld::addCollisionObject(o, group, mask);
        changed_ = true;
    }
    void removeCollisionObject(btCollisionObject* o) override {
        btDiscreteDynamicsWorld::removeCollisionObject(o);
        changed_ = true;
    }
    void removeRigidBody(btRigidBody* body) override {
        btDiscreteDynamicsWorld::removeRigidBody(body);
        changed_ = true;
    }

    // Bullet's visits every collision object of the world and reads whether it is active: a
    // cache miss each, and a line of the bottling plant has about 200 static bodies, which are
    // never active (sleeping from the start, flagged static: nothing wakes them; membership.cpp).
    // Here only the other objects are visited (list_live), in Bullet's order: the same boxes,
    // updated in the same order. A body declared kinematic that nothing wrote since its box was
    // last worked out (Physics::writes; a line has 18, pins and switch blades, mostly still)
    // has the same box and the same activation: its broadphase gets the box it holds, without
    // a look at the body (its pose, its shape).
    void updateAabbs() override {
        if (m_forceUpdateAllAabbs) return btDiscreteDynamicsWorld::updateAabbs();
        list_live();
        constexpr int kAhead = 4;  // a kinematic part's proxy (keep_box relinks it) asked for ahead: a hint
        for (int k = 0; k < live_.size(); ++k) {
            if (dbvt_ && k + kAhead < live_.size() && live_kin_[k + kAhead].rest >= 0)
                if (const btBroadphaseProxy* ahead = rest_[size_t(live_kin_[k + kAhead].rest)].proxy)
                    __builtin_prefetch(&static_cast<const btDbvtProxy*>(ahead)->links);
            btCollisionObject* o = m_collisionObjects[live_[k]];
            const Kin kn = live_kin_[k];
            if (kn.rest < 0) {
                if (o->isActive()) updateSingleAabb(o);
                continue;
            }
            KinematicRest& rest = rest_[size_t(kn.rest)];
            if (rest.box_valid && rest.box_writes == writes_[kn.body]) {
                assert(o->isActive() == rest.active && (!rest.active || same_box(*o)));
                if (rest.active && dbvt_) {
                    keep_box(*dbvt_, static_cast<btDbvtProxy*>(rest.proxy));
                } else if (rest.active) {
                    const btVector3 lo = rest.proxy->m_aabbMin, hi = rest.proxy->m_aabbMax;
                    m_broadphasePairCache->setAabb(rest.proxy, lo, hi, m_dispatcher1);
                }
                continue;
            }
            rest.active = o->isActive();
            if (rest.active) updateSingleAabb(o);
            rest.proxy = o->getBroadphaseHandle();
            rest.box_writes = writes_[kn.body];
            // Bullet keeps the old box of a body whose new one is too large (a centre of mass
            // far off its body): then its box is worked out again each step.
            rest.box_valid = !rest.active || same_box(*o);
        }
#ifndef NDEBUG
        for (int i = 0; i < m_collisionObjects.size(); ++i) {
            const btCollisionObject& o = *m_collisionObjects[i];
            assert(!fixed(o) || (!o.isActive() && o.isStaticObject()));
        }
#endif
    }

    // Bullet's islands (btDiscreteDynamicsWorld::calculateSimulationIslands with its island
    // manager's two passes, as built: STATIC_SIMULATION_ISLAND_OPTIMIZATION) write an island
    // tag, a companion id and a hit fraction into every object of the world each step, the
    // static bodies' included (a cache miss each, and most of the step's missed writes). A
    // static body always ends with tag -1, companion -2, fraction 1, and nothing reads them
    // in between (static bodies merge no islands): they are written once, when the list of
    // the other objects is found, and the passes visit those others, in Bullet's order, with
    // Bullet's union-find indices (counted over the objects that are not static or kinematic).
    void calculateSimulationIslands() override {
        list_live();
        btSimulationIslandManager& im = *getSimulationIslandManager();
        int index = 0;
        for (int k = 0; k < live_.size(); ++k) {
            btCollisionObject* o = m_collisionObjects[live_[k]];
            if (!o->isStaticOrKinematicObject()) o->setIslandTag(index++);
            o->setCompanionId(-1);
            o->setHitFraction(btScalar(1));
        }
        im.initUnionFind(index);
        im.findUnions(getDispatcher(), this);
        btUnionFind& unions = im.getUnionFind();
        auto unite = [&unions](const btCollisionObject* a, const btCollisionObject* b) {
            if (a && b && !a->isStaticOrKinematicObject() && !b->isStaticOrKinematicObject())
                unions.unite(a->getIslandTag(), b->getIslandTag());
        };
        for (int i = 0; i < m_predictiveManifolds.size(); ++i)
            unite(m_predictiveManifolds[i]->getBody0(), m_predictiveManifolds[i]->getBody1());
        for (int i = 0; i < m_constraints.size(); ++i)
            if (m_constraints[i]->isEnabled()) unite(&m_constraints[i]->getRigidBodyA(), &m_constraints[i]->getRigidBodyB());
        index = 0;
        for (int k = 0; k < live_.size(); ++k) {
            btCollisionObject* o = m_collisionObjects[live_[k]];
            if (!o->isStaticOrKinematicObject()) {
                o->setIslandTag(unions.find(index));
                unions.getElement(index).m_sz = live_[k];  // its index in the world's objects
                o->setCompanionId(-1);
                ++index;
            } else {
                o->setIslandTag(-1);
                o->setCompanionId(-2);
            }
        }
    }
    void solveConstraints(btContactSolverInfo& info) override {
        m_sortedConstraints.resize(m_constraints.size());
        for (int i = 0; i < m_constraints.size(); ++i) m_sortedConstraints[i] = m_constraints[i];
        // By island, and within one by the joint's graph id.
        if (m_sortedConstraints.size() > 1)
            std::sort(&m_sortedConstraints[0], &m_sortedConstraints[0] + m_sortedConstraints.size(),
                      [](const btTypedConstraint* a, const btTypedConstraint* b) {
                          const int ia = island_of(a), ib = island_of(b);
                          return ia != ib ? ia < ib : a->getUserConstraintId() < b->getUserConstraintId();
                      });
        islands_.setup(&info, m_constraintSolver, getDispatcher(),
                       m_sortedConstraints.size() ? &m_sortedConstraints[0] : nullptr, m_sortedConstraints.size());
        m_constraintSolver->prepareSolve(getNumCollisionObjects(), getDispatcher()->getNumManifolds());
        m_islandManager->buildAndProcessIslands(getDispatcher(), this, &islands_);
        islands_.flush();
        m_constraintSolver->allSolved(info, m_debugDrawer);
    }

    // Bullet's visits every collision object of the world, parked and static ones included;
    // kinematic bodies are all in the list of non-static ones (parked bodies are flagged static).
    // Bullet works a kinematic body's velocity out of its transform's change (an inverse, a
    // quaternion, an arc cosine), and most kinematic parts (pins, blades, an arm at rest) stand
    // still: from a transform that did not move it writes what it wrote the step before. So a
    // body declared kinematic keeps, in its KinematicRest (user index 2), what that step left
    // (the transform, the velocities it wrote, the step); while all of it is still there bit
    // for bit, the same call would write the same bits, and it is not made.
    // A rest found again unchanged, or just left, holds while nothing writes the body
    // (Physics::writes): then the body is not even read.
    void saveKinematicState(btScalar dt) override {
        list_live();
        for (int i = 0; i < m_nonStaticRigidBodies.size(); ++i) {
            const Kin kn = nonstatic_kin_[i];
            if (kn.rest >= 0) {
                const KinematicRest& rest = rest_[size_t(kn.rest)];
                if (rest.valid && rest.writes == writes_[kn.body] && same_bits(dt, rest.dt)) {
                    assert(m_nonStaticRigidBodies[i]->getActivationState() == ISLAND_SLEEPING ||
                           !m_nonStaticRigidBodies[i]->isKinematicObject() || unchanged(*m_nonStaticRigidBodies[i], rest, dt));
                    continue;
                }
            }
            btRigidBody* body = m_nonStaticRigidBodies[i];
            if (body->getActivationState() == ISLAND_SLEEPING || !body->isKinematicObject()) continue;
            if (kn.rest < 0) {
                body->saveKinematicState(dt);
                continue;
            }
            KinematicRest& rest = rest_[size_t(kn.rest)];
            if (rest.valid && unchanged(*body, rest, dt)) {
                rest.writes = writes_[kn.body];
                continue;
            }
            const bool still = same_bits(body->getWorldTransform(), body->getInterpolationWorldTransform());
            body->saveKinematicState(dt);
            ++writes_[kn.body];  // its velocity
            rest.valid = still;
            if (!still) continue;
            rest.at = body->getWorldTransform();
            rest.lin = body->getLinearVelocity(), rest.ang = body->getAngularVelocity();
            rest.dt = dt;
            rest.writes = writes_[kn.body];
        }
    }

    // The indices of the objects that are not static bodies, as this step's list_live left
    // them (the world's objects do not change while it steps).
    std::span<const int> live() const {
        assert(seen_.size() == m_collisionObjects.size());
        const int* first = live_.size() ? &live_[0] : nullptr;
        return {first, first + live_.size()};
    }

private:
    // A body declared kinematic: its graph id and its KinematicRest (user index 2); rest -1
    // for any other body.
    struct Kin {
        int32_t rest = -1;
        BodyId body;
    };
    static Kin kin_of(const btCollisionObject& o) { return {o.getUserIndex2(), BodyId(o.getUserIndex())}; }

    // The indices of the world's objects that are not static bodies, found again whenever the
    // world's list of objects changed (a body added or removed: `changed_`; a debug build
    // compares the lists as pointers each time); a static body found then gets the island
    // fields Bullet would give it. Beside them, and beside Bullet's list of non-static bodies
    // (which changes only with the objects), which are declared kinematic (Kin); each of these
    // counts as written (Physics::writes).
    void list_live() {
        const int n = m_collisionObjects.size();
        assert(changed_ || (n == seen_.size() && (n == 0 || std::memcmp(&seen_[0], &m_collisionObjects[0],
                                                                         sizeof(void*) * size_t(n)) == 0)));
        assert(changed_ || nonstatic_kin_.size() == m_nonStaticRigidBodies.size());
        if (!changed_) return;
        changed_ = false;
        seen_.resize(n);
        live_.resize(0);
        live_kin_.resize(0);
        for (int i = 0; i < n; ++i) {
            btCollisionObject* o = seen_[i] = m_collisionObjects[i];
            if (!fixed(*o)) {
                live_.push_back(i);
                live_kin_.push_back(kin_of(*o));
            } else {
                o->setIslandTag(-1);
                o->setCompanionId(-2);
                o->setHitFraction(btScalar(1));
            }
        }
        nonstatic_kin_.resize(0);
        for (int i = 0; i < m_nonStaticRigidBodies.size(); ++i) nonstatic_kin_.push_back(kin_of(*m_nonStaticRigidBodies[i]));
        // A body that joined (a weld ended, say) has a new broadphase proxy: what its rest
        // holds is looked at again.
        for (int k = 0; k < live_kin_.size(); ++k)
            if (live_kin_[k].rest >= 0) ++writes_[live_kin_[k].body];
    }

    // Whether o's broadphase box is the one updateSingleAabb works out now.
    bool same_box(const btCollisionObject& o) const {
        btVector3 lo, hi;
        o.getCollisionShape()->getAabb(o.getWorldTransform(), lo, hi);
        const btVector3 m(gContactBreakingThreshold, gContactBreakingThreshold, gContactBreakingThreshold);
        lo -= m, hi += m;
        const btBroadphaseProxy& p = *o.getBroadphaseHandle();
        auto same = [](const btVector3& a, const btVector3& b) { return std::memcmp(a.m_floats, b.m_floats, 3 * sizeof(btScalar)) == 0; };
        return same(lo, p.m_aabbMin) && same(hi, p.m_aabbMax);
    }

    template <class T>
    static bool same_bits(const T& a, const T& b) {
        return std::memcmp(&a, &b, sizeof(T)) == 0;
    }
    // Everything Bullet's saveKinematicState reads and writes, as it left them at `rest`.
    static bool unchanged(const btRigidBody& body, const KinematicRest& rest, btScalar dt) {
        return same_bits(dt, rest.dt) && same_bits(body.getWorldTransform(), rest.at) &&
               same_bits(body.getInterpolationWorldTransform(), rest.at) &&
               same_bits(body.getLinearVelocity(), rest.lin) && same_bits(body.getAngularVelocity(), rest.ang) &&
               same_bits(body.getInterpolationLinearVelocity(), rest.lin) &&
               same_bits(body.getInterpolationAngularVelocity(), rest.ang);
    }

    // A body the graph declares static: never active in Bullet's sense.
    bool fixed(const btCollisionObject& o) const {
        const int b = o.getUserIndex();
        return b >= 0 && b < g_.bodies.count() && g_.bodies[BodyId(b)].mode == BodyMode::Static;
    }

    IslandSolver islands_;
    const Graph& g_;
    std::vector<KinematicRest>& rest_;  // Physics::kin_rest_: each body's entry touched by its world only
    IdVector<BodyId, uint32_t>& writes_;  // Physics::writes_: each body's counted by its world only
    btDbvtBroadphase* const dbvt_;      // the broadphase, where it is Bullet's two trees (keep_box)
    bool changed_ = true;               // objects added or removed since live_ was found
    btAlignedObjectArray<btCollisionObject*> seen_;  // the world's objects when live_ was found
    btAlignedObjectArray<int> live_;                 // the indices of those that are not static bodies
    btAlignedObjectArray<Kin> live_kin_;             // beside live_
    btAlignedObjectArray<Kin> nonstatic_kin_;        // beside m_nonStaticRigidBodies
};

// Bullet's dispatcher, whose near callback (Bullet's own) is called for the pairs of its
// world's pair cache in their order: for each, this one first asks for what the callback of a
// pair a few ahead reads (the pair's two bodies: pose, shape, flags, activation; its
// algorithm), which it would otherwise miss on, a static body most of all (nothing else in the
// step reads a band or a rail). A hint: it changes no result.
class AheadDispatcher : public btCollisionDispatcher {
public:
    explicit AheadDispatcher(btCollisionConfiguration* c) : btCollisionDispatcher(c) { setNearCallback(near); }
    btOverlappingPairCache* pairs = nullptr;  // its world's

private:
    // Each pair asks for what a later one reads first, in stages: for the pair 4 ahead, its
    // proxies and its algorithm's first two lines; 3 ahead, what that algorithm reads first
    // (contact_ahead's stage 2: a compound's list of its children's algorithms); 2 ahead, the
    // bodies (body) and stage 1 (those algorithms); 1 ahead, stage 0 (their manifolds).
    static void near(btBroadphasePair& pair, btCollisionDispatcher& d, const btDispatcherInfo& info) {
        const AheadDispatcher& self = static_cast<const AheadDispatcher&>(d);
        if (self.pairs && self.pairs->getNumOverlappingPairs() > 0) {
            const btBroadphasePairArray& all = self.pairs->getOverlappingPairArray();
            const auto at = reinterpret_cast<uintptr_t>(&pair), first = reinterpret_cast<uintptr_t>(&all[0]);
            const auto i = int64_t((at - first) / sizeof(btBroadphasePair)), n = int64_t(all.size());
            auto ahead = [&](int64_t k) { return at >= first && i + k < n ? &all[int(i + k)] : nullptr; };
            if (const btBroadphasePair* p = ahead(4)) {
                __builtin_prefetch(p->m_pProxy0);
                __builtin_prefetch(p->m_pProxy1);
                if (p->m_algorithm) {
                    __builtin_prefetch(p->m_algorithm);
                    __builtin_prefetch(reinterpret_cast<const char*>(p->m_algorithm) + 64);
                }
            }
            if (const btBroadphasePair* p = ahead(3)) contact_ahead(p->m_algorithm, 2);
            if (const btBroadphasePair* p = ahead(2)) {
                body(p->m_pProxy0->m_clientObject);
                body(p->m_pProxy1->m_clientObject);
                contact_ahead(p->m_algorithm, 1);
            }
            if (const btBroadphasePair* p = ahead(1)) contact_ahead(p->m_algorithm, 0);
        }
        btCollisionDispatcher::defaultNearCallback(pair, d, info);
    }
    // Where in a collision object the near callback reads, past its transform: from its
    // broadphase handle to its activation, and whether it collides with the other (found on an
    // object of Bullet's class, whose layout is the one this program was built with).
    struct Layout : btCollisionObject {
        size_t from() const { return size_t(reinterpret_cast<const char*>(&m_broadphaseHandle) - reinterpret_cast<const char*>(this)); }
        size_t to() const { return size_t(reinterpret_cast<const char*>(&m_activationState1) - reinterpret_cast<const char*>(this)); }
        size_t check() const { return size_t(reinterpret_cast<const char*>(&m_checkCollideWith) - reinterpret_cast<const char*>(this)); }
    };
    struct Lines {
        size_t from, to, check;
    };
    static const Lines& lines() {
        static const Lines l = [] {
            const Layout probe;
            return Lines{probe.from(), probe.to(), probe.check()};
        }();
        return l;
    }
    static void body(const void* o) {
        const char* c = static_cast<const char*>(o);
        const char* t = reinterpret_cast<const char*>(&static_cast<const btCollisionObject*>(o)->getWorldTransform());
        const Lines& l = lines();
        __builtin_prefetch(t);
        __builtin_prefetch(t + sizeof(btTransform) - 1);
        __builtin_prefetch(c + l.from);
        __builtin_prefetch(c + l.to);
        __builtin_prefetch(c + l.check);
    }
};

bool pooled(const Graph& g, const Tables& t, DoId d) {
    for (size_t guard = 0; d.valid() && guard <= g.dos.size(); ++guard, d = g.dos[d].parent)
        if (t.do_source[d].valid()) return true;
    return false;
}

}  // namespace

Physics::World::World() = default;
Physics::World::~World() = default;
Physics::World::World(World&&) noexcept = default;
Physics::World& Physics::World::operator=(World&&) noexcept = default;

void Physics::make_world(World& w, Broadphase bp, size_t bodies) {  // bodies: for SAP's handles
    // Bullet's pools of contact manifolds and pair algorithms: 4,096 each by default, about
    // 5 MiB a world. A region's world gets 256 (a line of the bottling plant has up to about
    // 150 pair algorithms alive at once); past them Bullet takes blocks from its allocator
    // (above), which recycles them.
    btDefaultCollisionConstructionInfo ci;
    if (void_ >= 0) {
        ci.m_defaultMaxPersistentManifoldPoolSize = 256;
        ci.m_defaultMaxCollisionAlgorithmPoolSize = 256;
    }
    auto config = std::make_unique<btDefaultCollisionConfiguration>(ci);
    auto dispatcher = std::make_unique<AheadDispatcher>(config.get());
    AheadDispatcher& ahead = *dispatcher;
    w.dispatcher = std::move(dispatcher);
    if (bp == Broadphase::Sap) {
        // 32-bit handles: a 2 km world quantised in 16 bits would be 3 cm coarse.
        unsigned handles = unsigned(std::max<size_t>(1024, 2 * bodies + 16));
        w.broadphase = std::make_unique<bt32BitAxisSweep3>(btVector3(-1000, -1000, -1000),
                                                           btVector3(1000, 1000, 1000), handles);
    } else {
        w.broadphase = std::make_unique<LeanDbvt>();
    }
    ahead.pairs = w.broadphase->getOverlappingPairCache();
    w.world = std::make_unique<IslandWorld>(g_, kin_rest_, writes_, w.dispatcher.get(), w.broadphase.get(), solvers_[0].get(), config.get());
    w.world->setGravity(gravity_);
    w.world->setForceUpdateAllAabbs(false);  // sleeping statics keep their AABBs
    // Contact normals between boxes and hulls from the separating-axis test on their
    // polyhedra (see shapes.cpp), not from GJK/EPA: EPA's normals for a bottle sliding
    // over a belt's band are tilted now and then, and each tilted normal kicks the bottle
    // (single-body bottles on a running belt fell over within seconds; docs/runtime.md).
    w.world->getDispatchInfo().m_enableSatConvex = true;
    // The same contacts for box against hull (a bottle on a band) at a fraction of the cost of
    // Bullet's separating-axis test: contact.cpp.
    contacts_->attach(*w.dispatcher, *config);
    w.config = std::move(config);
}

Physics::Physics(const Graph& g, const Tables& t, Broadphase bp, int threads)
    : g_(g), gravity_(to_bt(g.settings.gravity)), contacts_(std::make_unique<BoxHullContacts>()) {
    const int32_t nb = g.bodies.count();
    local_.resize(nb);
    local_inv_.resize(nb);
    inertia_.resize(nb);
    mass_.resize(nb);
    in_world_.assign(nb, 0);
    group_.assign(nb, 0);
    mask_.assign(nb, 0);
    dyn_on_.assign(nb, 1);
    coll_on_.assign(nb, 1);
    mode_.resize(nb);
    for (BodyId b : ids_of(g.bodies)) mode_[b] = g.bodies[b].mode;
    coast_.assign(nb, 0);
    writes_.assign(nb, 0);
    for (BodyId b : ids_of(g.bodies)) {
        const Body& body = g.bodies[b];
        BodyShape bs = shapes_.build(g, body);
        contacts_->prepare(*bs.shape);
        local_[b] = bs.local;
        local_inv_[b] = bs.local.inverse();
        inertia_[b] = bs.inertia;
        mass_[b] = bs.mass;
        btRigidBody::btRigidBodyConstructionInfo ci(btScalar(bs.mass), nullptr, bs.shape, bs.inertia);
        ci.m_startWorldTransform = to_bt(body.pose) * bs.local;
        ci.m_friction = btScalar(body.friction);
        ci.m_restitution = btScalar(body.restitution);
        ci.m_linearDamping = btScalar(body.linear_damping);
        ci.m_angularDamping = btScalar(body.angular_damping);
        auto rb = std::make_unique<btRigidBody>(ci);
        rb->setUserIndex(b.v);
        if (body.mode == BodyMode::Kinematic) {
            rb->setUserIndex2(int(kin_rest_.size()));
            kin_rest_.emplace_back();
        }
        if (body.mode == BodyMode::Static) {
            rb->setActivationState(ISLAND_SLEEPING);
        } else {
            // Belts push with forces that do not wake sleepers; kinematics must stay active.
            rb->forceActivationState(DISABLE_DEACTIVATION);
        }
        bodies_.push_back(std::move(rb));
        if (!body.collision) set_collision(b, false);
        if (!body.dynamics) set_dynamics(b, false);
    }

    std::vector<std::pair<BodyId, JointId>> pairs;
    joint_in_.assign(g.joints.size(), 0);
    joint_on_.assign(g.joints.size(), 0);
    joints_.resize(g.joints.size());
    for (JointId j : ids_of(g.joints)) {
        const Joint& jt = g.joints[j];
        joint_on_[j] = jt.enabled;
        pairs.emplace_back(jt.body_a, j);
        if (jt.body_b.valid() && jt.body_b != jt.body_a) pairs.emplace_back(jt.body_b, j);
    }
    std::stable_sort(pairs.begin(), pairs.end(),
                     [](auto& x, auto& y) { return x.first < y.first; });
    body_joints_.adr.assign(nb, 0);
    body_joints_.num.assign(nb, 0);
    for (auto& [b, j] : pairs) {
        if (body_joints_.num[b]++ == 0) body_joints_.adr[b] = count_of(body_joints_.list);
        body_joints_.list.push_back(j);
    }
    find_welds();
    // A weld's fixed joint is made only while Bullet's world holds it (make_joint): a bottle's
    // weld holds nearly always, and the joint is 2 KiB of Bullet's per pooled bottle.
    for (JointId j : ids_of(g.joints))
        if (weld_joint_[j] < 0) make_joint(j);

    // The regions and their worlds (regions.cpp), then every body joins its world once, in id
    // order; pooled ones are parked. A pool's objects all start at one pose: they join without
    // a filter, or the broadphase would pair each with every other at once (a million pairs
    // for a pool of 1,000 bottles).
    find_regions(bp != Broadphase::Sap);
    contacts_->freeze();
    {
        std::vector<size_t> count(worlds_.size());
        for (BodyId b : ids_of(g.bodies)) ++count[world_of_[b]];
        solvers_.push_back(std::make_unique<btSequentialImpulseConstraintSolver>());
        for (size_t w = 0; w < worlds_.size(); ++w) make_world(worlds_[w], bp, count[w]);
    }
    PerBody<char> pool(nb);
    for (BodyId b : ids_of(g.bodies)) {
        pool[b] = pooled(g, t, t.body_do[b]);
        in_world_[b] = 1;
        set_mode_flags(b);  // before joining: Bullet files a body as static or not then
        add_to_world(b, !pool[b]);
    }
    add_joints_at_start(pool);
    reserve_joint_refs(pool);
    for (BodyId b : ids_of(g.bodies))
        if (pool[b]) take_out(b);
    int n = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
    workers_ = std::make_unique<Workers>(std::min(n, std::max(1, int(worlds_.size()) - (void_ >= 0))));
    while (int(solvers_.size()) < workers_->threads())
        solvers_.push_back(std::make_unique<btSequentialImpulseConstraintSolver>());
}

// Bullet's constraint for joint j, made from the graph (make_joint); a weld's is made when
// Bullet's world takes it and dropped when the weld forms again (its memory goes back to
// Bullet's recycled blocks).
void Physics::make_joint(JointId j) {
    const Joint& jt = g_.joints[j];
    btRigidBody& a = *bodies_[jt.body_a];
    btTransform fa = local_inv_[jt.body_a] * to_bt(jt.frame_a);
    btRigidBody& b = jt.body_b.valid() ? *bodies_[jt.body_b] : btTypedConstraint::getFixedBody();
    btTransform fb = jt.body_b.valid() ? local_inv_[jt.body_b] * to_bt(jt.frame_b) : to_bt(jt.frame_b);
    const bool limited = jt.lower <= jt.upper;
    std::unique_ptr<btTypedConstraint> c;
    switch (jt.kind) {
    case JointKind::Fixed: c = std::make_unique<btFixedConstraint>(a, b, fa, fb); break;
    case JointKind::Hinge: {  // about the joint frame's z axis
        auto h = std::make_unique<btHingeConstraint>(a, b, fa, fb, false);
        if (limited) h->setLimit(btScalar(jt.lower), btScalar(jt.upper));
        c = std::move(h);
        break;
    }
    case JointKind::Slider: {  // along the joint frame's x axis; Bullet: lower > upper is free
        auto s = std::make_unique<btSliderConstraint>(a, b, fa, fb, true);
        s->setLowerLinLimit(limited ? btScalar(jt.lower) : 1);
        s->setUpperLinLimit(limited ? btScalar(jt.upper) : -1);
        c = std::move(s);
        break;
    }
    }
    c->setUserConstraintId(j.v);
    c->setEnabled(joint_on_[j]);
    joints_[j] = std::move(c);
}

void Physics::add_joint(JointId j) {
    if (!joints_[j]) make_joint(j);
    world_at(g_.joints[j].body_a).world->addConstraint(joints_[j].get(), true);  // linked bodies do not collide
    joint_in_[j] = 1;
}

void Physics::remove_joint(JointId j) {
    world_at(g_.joints[j].body_a).world->removeConstraint(joints_[j].get());
    joint_in_[j] = 0;
    if (weld_joint_[j] >= 0) joints_[j].reset();
}

// The joints whose bodies are not pooled join their worlds at the start, in id order; a pooled
// body's join when it is first issued. The order of a world's constraints reaches no result:
// the solver takes each island's joints by their ids (IslandWorld::solveConstraints).
void Physics::add_joints_at_start(const PerBody<char>& pool) {
    for (JointId j : ids_of(g_.joints)) {
        const Joint& jt = g_.joints[j];
        if (!pool[jt.body_a] && !(jt.body_b.valid() && pool[jt.body_b])) add_joint(j);
    }
}

// A pooled body's joints join the world only when it is first issued (above), and Bullet then
// grows two arrays of each of the joint's bodies: its list of constraints and its list of bodies
// it does not collide with (btRigidBody::addConstraintRef). Their blocks (16 B each) stay with
// the body, so every pooled bottle's first issue asked Bullet's pools for four more, and the
// 1,000-bottle plant's pools were still growing 70 s in, as its storages issued bottles for
// the first time. Grown here instead: each body gets as many stand-in joints to the fixed body
// as it has joints with a pooled body, added after its own and removed again (Bullet keeps an
// array's capacity; the lists hold what they held before, in the same order).
void Physics::reserve_joint_refs(const PerBody<char>& pool) {
    if (body_joints_.num.empty()) return;
    std::vector<std::unique_ptr<btPoint2PointConstraint>> stand_in;
    for (BodyId b : ids_of(pool)) {
        int32_t more = 0;  // its joints that join the world at a pooled body's issue
        for (JointId j : body_joints_[b]) {
            const Joint& jt = g_.joints[j];
            more += pool[jt.body_a] || (jt.body_b.valid() && pool[jt.body_b]);
        }
        if (more == 0) continue;
        btRigidBody& rb = *bodies_[b];
        [[maybe_unused]] const int held = rb.getNumConstraintRefs();
        stand_in.clear();
        for (int32_t k = 0; k < more; ++k) {
            stand_in.push_back(std::make_unique<btPoint2PointConstraint>(rb, btVector3(0, 0, 0)));
            rb.addConstraintRef(stand_in.back().get());
        }
        for (auto& c : stand_in) rb.removeConstraintRef(c.get());
        assert(rb.getNumConstraintRefs() == held);
    }
}

Physics::~Physics() {
    workers_.reset();
    for (JointId j(joints_.count()); j.v-- > 0;)
        if (joint_in_[j]) world_at(g_.joints[j].body_a).world->removeConstraint(joints_[j].get());
    for (BodyId b(bodies_.count()); b.v-- > 0;) world_at(b).world->removeRigidBody(bodies_[b].get());
    worlds_.clear();
    joints_.clear();
    bodies_.clear();
}

int Physics::threads() const { return workers_->threads(); }

std::span<const int> Physics::live_objects(int w) const {
    return static_cast<const IslandWorld&>(*worlds_[w].world).live();  // make_world's
}

void Physics::step(double dt) { step(dt, StepHooks{}); }

void Physics::step(double dt, const StepHooks& h) {
    ++steps_;
    StepProfile& prof = workers_->profile();
    auto one = [this, dt, &h](int i) {
        const int w = to_step_[i];
        if (h.before) h.before(h.ctx, w);
        worlds_[w].world->setConstraintSolver(solvers_[worker_slot()].get());  // this thread's
        worlds_[w].world->stepSimulation(btScalar(dt), 0, btScalar(dt));
        follow_world(w);
    };
    to_step_.clear();
    if (void_ < 0) {
        if (h.ready) h.ready(h.ctx);
        prof.lap(StepProfile::FieldsPrep);
        to_step_.push_back(0);
        workers_->run(1, one);  // on this thread (timed as the job's item when profiling)
        return;
    }
    assign_worlds();
    prof.lap(StepProfile::Regions);
    if (h.ready) h.ready(h.ctx);
    prof.lap(StepProfile::FieldsPrep);
    // The worlds with the most movers first: the threads claim them in this order, so the
    // longest jobs do not come last. The order changes nothing in the results.
    // Every world in that order (a total one), sorted again from the last step's: the counts
    // change little from step to step, so an insertion sort does little more than look.
    auto before = [this](int32_t a, int32_t b) {
        return worlds_[a].movers != worlds_[b].movers ? worlds_[a].movers > worlds_[b].movers : a < b;
    };
    for (size_t i = 1; i < by_movers_.size(); ++i) {
        const int32_t w = by_movers_[i];
        size_t j = i;
        for (; j > 0 && before(w, by_movers_[j - 1]); --j) by_movers_[j] = by_movers_[j - 1];
        by_movers_[j] = w;
    }
    for (const int32_t w : by_movers_)
        if (worlds_[w].active) to_step_.push_back(w);
    workers_->run(int(to_step_.size()), one);
}

}  // namespace plant::engine
