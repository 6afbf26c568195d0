// Hands: a trainee holding a dynamic body with the mouse (docs/runtime.md, "Hands"). A
// hand holds a point of the body and pulls it towards a target with a bounded force, the
// way a person would: it carries the object's weight, follows at a limited speed (so that
// nothing it carries can pass through a belt's band in one step), and holds the body
// upright. Grabs, moves, drops and removals are events (events.cpp), applied between
// steps; the pull acts in phase 1, after the conveyor law and before Bullet's step.
#include "engine/runtime.h"

#include <algorithm>
#include <cmath>

namespace plant::engine {

using namespace plant::graph;

namespace {

constexpr double kHandTauPos = 0.08;   // s: the held point closes a gap in about this time
constexpr double kHandTauVel = 0.02;   // s: how fast the hand takes up a speed difference
constexpr double kHandSpeed = 1.0;     // m/s; also at most 7.5 mm a step (a band is 1 cm thick)
constexpr double kHandStep = 0.0075;   // m
constexpr double kHandAccel = 30;      // m/s² beyond carrying the weight: the hand's strength
constexpr double kHandTurn = 150;      // 1/s²: the pull back to upright, per radian
constexpr double kHandTurnDamp = 24;   // 1/s: critically damped with kHandTurn
constexpr double kHandMaxTurn = 300;   // rad/s²
constexpr double kHandReach = 1.0;     // m: a grab point further from the body holds its origin

btVector3 hand_clamped(const btVector3& v, double most) {
    const double n = v.length();
    return n > most ? v * btScalar(most / n) : v;
}

// The hand's pull on what it holds: a uniform acceleration of the whole object (its weight
// carried, the held point driven towards the target), and a torque on the held body that
// turns it back upright (the axis that was up when the plant was built).
void hand_pull(Runtime& r, const Hand& h) {
    const BodyId b = h.body;
    const double dt = r.dt;
    const btTransform frame = r.phys.frame(b);
    const btVector3 p = frame * h.anchor;
    const btVector3 w = r.phys.angular_velocity(b);
    const btVector3 v = r.phys.velocity(b) + w.cross(p - r.phys.com(b));
    const double tau = std::max(kHandTauPos, 2 * dt);
    const btVector3 wanted = hand_clamped((h.target - p) / btScalar(tau), std::min(kHandSpeed, kHandStep / dt));
    // The velocity step's exact decay over dt, as the conveyor law's: stable at any rate.
    btVector3 a = hand_clamped((wanted - v) * btScalar(-std::expm1(-dt / kHandTauVel) / dt), kHandAccel);
    a -= to_bt(r.g.settings.gravity);
    for (BodyId x : r.tab.do_bodies[r.tab.body_do[b]])
        if (r.phys.dynamic_now(x)) r.phys.apply(x, a * btScalar(r.phys.mass(x)), btVector3(0, 0, 0));

    const Vec3 up_local = qrot(qconj(r.g.bodies[b].pose.q), Vec3{0, 0, 1});
    const btVector3 axis = frame.getBasis() * to_bt(up_local);
    const btVector3 c = axis.cross(btVector3(0, 0, 1));
    const double s = c.length(), angle = std::atan2(s, double(axis.z()));
    btVector3 err(0, 0, 0);
    if (s > 1e-6) err = c * btScalar(angle / s);
    else if (axis.z() < 0) err = btVector3(btScalar(angle), 0, 0);  // upside down: any horizontal axis
    const double k = std::min(kHandTurn, 0.1 / (dt * dt)), damp = std::min(kHandTurnDamp, 0.5 / dt);
    const btVector3 alpha = hand_clamped(err * btScalar(k) - w * btScalar(damp), kHandMaxTurn);
    r.phys.apply(b, btVector3(0, 0, 0), r.phys.inertia_world(b) * alpha);
}

// Marks the bodies of the held body's object as in a hand (or not): the conveyor law leaves
// them alone while held (fields.cpp).
void mark_object(Runtime& r, BodyId b, uint8_t on) {
    for (BodyId x : r.tab.do_bodies[r.tab.body_do[b]]) r.st.in_hand[x] = on;
}

// A body a hand may take: declared dynamic, in the world, simulated, not in a gripper.
bool hand_free_to_take(const Runtime& r, BodyId b) {
    return r.phys.declared_dynamic(b) && r.phys.dynamic_now(b) && !r.st.held_by[b].valid();
}

}  // namespace

void apply_hands(Runtime& r) {
    std::vector<Hand>& hands = r.st.hands;
    size_t keep = 0;
    for (const Hand& h : hands) {
        if (!hand_free_to_take(r, h.body)) {  // taken away (an exit, a gripper): the hand is empty
            mark_object(r, h.body, 0);
            continue;
        }
        hands[keep++] = h;
        hand_pull(r, h);
    }
    hands.resize(keep);  // shrinks: no allocation
}

void Engine::hand_grab(BodyId b, const Vec3& at) {
    Runtime& r = *rt_;
    if (!hand_free_to_take(r, b)) {
        r.st.warn.hand_refused++;
        return;
    }
    btVector3 anchor = r.phys.frame(b).inverse() * to_bt(at);
    if (anchor.length() > kHandReach) anchor = btVector3(0, 0, 0);
    mark_object(r, b, 1);
    for (Hand& h : r.st.hands)
        if (h.body == b) {
            h = Hand{b, anchor, to_bt(at)};
            return;
        }
    r.st.hands.push_back(Hand{b, anchor, to_bt(at)});
}

void Engine::hand_move(BodyId body, const Vec3& to) {
    for (Hand& h : rt_->st.hands)
        if (h.body == body) h.target = to_bt(to);
}

void Engine::hand_drop(BodyId body) {
    std::vector<Hand>& hands = rt_->st.hands;
    if (held(body)) mark_object(*rt_, body, 0);
    hands.erase(std::remove_if(hands.begin(), hands.end(), [&](const Hand& h) { return h.body == body; }),
                hands.end());
}

void Engine::remove_object(DoId object) {
    Runtime& r = *rt_;
    DoId root = object;
    for (DoId d = object; d.valid(); d = r.g.dos[d].parent)
        if (r.tab.do_source[d].valid()) {
            root = d;
            break;
        }
    for (BodyId b : r.tab.do_bodies[root])
        if (r.st.held_by[b].valid()) {  // in a gripper: the arm holds it
            r.st.warn.hand_refused++;
            return;
        }
    for (BodyId b : r.tab.do_bodies[root]) hand_drop(b);
    if (take_object(r, root).valid()) r.st.removed++;
}

bool Engine::held(BodyId body) const {
    for (const Hand& h : rt_->st.hands)
        if (h.body == body) return true;
    return false;
}

int64_t Engine::removed() const { return rt_->st.removed; }

}  // namespace plant::engine
