// Steady transport: bottles the conveyor law alone moves leave Bullet's solver.
//
// A unit is a lone dynamic body or a welded pair's host with its passenger (a bottle). It is
// steady when, at the start of a physics phase (after the fields' state of this step is known):
//
//   * it is simulated (dynamic, in the world, collision on), not held by a gripper or a hand,
//     and nothing reads its outputs (no record, flow or watch: what is measured is Bullet's);
//   * it stands upright (its body frame's z within 2° of vertical), rocks slower than 1 rad/s
//     about the horizontal axes (a bottle standing on a band rocks by contact noise that
//     fast, by hundredths of a degree) and turns slower than 10 rad/s about the vertical;
//   * the centre of mass of each of its bodies lies, this step and on its path two steps on,
//     1 mm clear of every field's faces and inside one acting field at most, the same one;
//     in a field, the field is level and the unit's velocity in the field's frame is within
//     2 mm/s of the target on the driven axes and within 5 cm/s of 0 on the others (nothing
//     acts across a frictionless band; a turning field's target is the one the law last
//     pulled it towards, half a step back from where it is); in none, it is at rest (within 5 mm/s along each
//     axis: a bottle standing on a table jiggles that fast in Bullet, about a fixed place),
//     and its centre's path stays over its support's box;
//   * its bounding box grown by its sweep (two steps of its motion along each axis, and of its
//     turning about the vertical) plus 2 mm meets one static body below its bottom + 1 cm (the
//     band it stands on: a box whose top face is within 3° of level, frictionless against it;
//     where it meets two, one whose top face's plane lies more than 0.5 mm below its shape over
//     two steps is passed over: clear_below) and otherwise only rails it slides along or comes
//     up to at 1 cm/s at most (guide_by; each piece of a compound on its own, the band's too;
//     a box turned about the vertical, a curve's rail, or a convex hull, a separator's funnel,
//     is met only where it is within the unit's reach of its centre's path: meets_obb,
//     outline_clear); grown by its sweep plus 1 cm, it meets no kinematic part's room (its box
//     when filed, grown by 5 cm) but of parts whose collision is off and parts at rest where
//     they were filed, which count as static pieces met by that box;
//   * no other body's bounding box grown by that body's reach (two steps plus 1 cm, 5 cm more
//     for one that Bullet does not move itself) meets its own grown by its sweep plus 1 cm.
//
// A unit steady for 5 steps in a row leaves the solver: flagged static in no pair, its
// broadphase box parked (Physics::coast). Then in each step the law's exact solution moves it:
// along each driven axis of its field the speed error decays by exp(-k·dt/m) (k the sum of
// its bodies' gains, m its mass; a turning field's target taken as the law takes it), the
// free axes keep their speed, the centre of mass keeps its height above the band's top face
// (a band rises 2 mm along its length), it turns about the vertical as it did when it left
// (nothing acts about that axis), no other way, and a rail
// it slides along stops its motion into the rail (an inelastic, frictionless contact). In no
// field it stays where it was, at rest.
// Its pose, velocity and bounding box are written every step, so triggers, sensors, graphics
// and records see it as any body (a trigger only reads: it does not land it). It returns to
// the solver (Physics::land) with that state at the start of the first physics phase in which
// it is not steady (a neighbour, a static or kinematic part, a field's end or change come
// within reach; the reach covers two steps, so nothing but its band and rails meets it while
// it is off), and at once when an event, a gripper or a hand writes its state or mode
// (Physics::unweld lands it first). Whether each unit is steady reads only this step's state
// as the check starts (leaving or rejoining the solver changes nothing a verdict reads: not a
// pose, a velocity, a box or whether a body is dynamic), so the verdicts are found on the
// physics threads, a slice of the units per item; they are then acted on grouped by world, in
// body id order within each, one world per item (landing and leaving touch only the unit's
// world): the results do not depend on the number of threads.
//
// A unit that is not steady may rest when it is held still (rest_now): still (2 cm/s, 1 rad/s),
// upright, in one acting field at most (one that would speed it up by 1 cm/s in a step were it
// free: something holds it), every static body and kinematic part within 1 cm of it there to
// stay (collision on, a part at rest where filed), every body within reach still too. Still so
// for 0.1 s, and within 0.5 mm of where it was then, it rests (Physics::rest): static and of
// infinite mass to Bullet, velocity 0, its broadphase box and pairs kept, so what meets it
// meets a fixed body. It lands when it may no longer rest, its field or target changes, or an
// event writes it, and with it, in the same step, every resting unit within 2 cm of a landing
// one (a queue moves off at once), found on the calling thread from the landing ones in id
// order.
#include "engine/transport.h"

#include "engine/cells.h"
#include "engine/contact.h"
#include "engine/runtime.h"
#include "engine/workers.h"

#include <BulletCollision/BroadphaseCollision/btBroadphaseInterface.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace plant::engine {

using namespace plant::graph;

// ---- Physics: leaving the solver and coming back.

void Physics::coast(BodyId b) {
    coast_[b] = 1;
    btRigidBody& r = *bodies_[b];
    r.clearForces();
    r.forceActivationState(DISABLE_SIMULATION);  // not active: Bullet leaves its broadphase box alone
    set_mode_flags(b);                           // static: Bullet does not integrate it
    park(b);
}

void Physics::rest(BodyId b) {
    coast_[b] = kResting;
    btRigidBody& r = *bodies_[b];
    r.clearForces();
    r.setLinearVelocity(btVector3(0, 0, 0));
    r.setAngularVelocity(btVector3(0, 0, 0));
    r.setInterpolationWorldTransform(r.getWorldTransform());
    r.forceActivationState(DISABLE_SIMULATION);  // not active: its box stays, and so do its pairs
    r.setMassProps(0, btVector3(0, 0, 0));       // to the solver a fixed body, as a static one
    set_mode_flags(b);                           // static: Bullet does not integrate it
    if (weld_of_[b] >= 0 && welds_[weld_of_[b]].on) follow(welds_[weld_of_[b]]);
}

void Physics::land(BodyId b) {
    if (!coast_[b]) return;
    if (coast_[b] == kResting) {  // its mass as it had it (a carrier's is the pair's: welds.cpp)
        const BodyShape* both = carries_[b].valid() ? &shape_of(welds_[weld_of_[b]]).both : nullptr;
        bodies_[b]->setMassProps(btScalar(both ? both->mass : mass_[b]), both ? both->inertia : inertia_[b]);
        bodies_[b]->setGravity(gravity_);
    }
    coast_[b] = 0;
    btRigidBody& r = *bodies_[b];
    r.forceActivationState(DISABLE_DEACTIVATION);
    set_mode_flags(b);
    r.setInterpolationWorldTransform(r.getWorldTransform());
    r.setInterpolationLinearVelocity(r.getLinearVelocity());
    r.setInterpolationAngularVelocity(r.getAngularVelocity());
    refilter(b);  // its pairs are found again in this step
}

void Physics::coast_to(BodyId b, const btTransform& t, const btVector3& v, const btVector3& w) {
    wrote(b);
    btRigidBody& r = *bodies_[b];
    r.setWorldTransform(t);
    r.setInterpolationWorldTransform(t);
    r.setLinearVelocity(v);
    r.setAngularVelocity(w);
    if (weld_of_[b] >= 0 && welds_[weld_of_[b]].on) follow(welds_[weld_of_[b]]);
}

namespace {

constexpr btScalar kMargin = btScalar(0.01);        // m, between bodies, beyond their two steps of motion
constexpr btScalar kStaticMargin = btScalar(0.002); // m, to a static body (a rail), beyond two steps
constexpr btScalar kNotSimulated = btScalar(0.05);  // m, more for a body Bullet does not move itself
constexpr btScalar kSpeedTol = btScalar(0.002);     // m/s, off the field's target along its driven axes
constexpr btScalar kDrift = btScalar(0.05);         // m/s, across them (nothing acts there: it keeps it)
constexpr btScalar kApproach = btScalar(0.01);      // m/s, towards a rail it slides along
constexpr btScalar kRest = btScalar(0.005);         // m/s, along each axis: at rest where no field acts (a
                                                    // bottle standing on a table jiggles at up to 3 mm/s)
constexpr btScalar kRockTol = btScalar(1);          // rad/s about horizontal axes: contact noise, not tipping
constexpr btScalar kYawTol = btScalar(10);          // rad/s about the vertical
constexpr btScalar kTilt = btScalar(0.99939);       // cos 2°: a body's z axis from vertical
constexpr btScalar kUpright = btScalar(0.9986);     // cos 3°: a field's or a band's top from level
constexpr btScalar kFieldMargin = btScalar(0.001);  // m
constexpr btScalar kSink = btScalar(0.01);          // m: how far a base's bounding box may reach into its support's
constexpr btScalar kRoom = btScalar(0.05);          // m: a kinematic part's room
constexpr btScalar kTouch = btScalar(0.001);        // m: how far a shape may reach into a rail it slides along
constexpr btScalar kBelow = btScalar(0.0005);       // m: a level piece this far below a unit's shape is not its support
constexpr int16_t kSettle = 5;                      // steps steady before leaving the solver
constexpr btScalar kJiggle = btScalar(0.02);        // m/s, along each axis: still (a bottle pressed into a
                                                    // queue by its band jiggles at about 1 cm/s in Bullet)
constexpr double kStillFor = 0.1;                   // s still before resting ...
constexpr btScalar kCreep = btScalar(0.0005);       // m: ... and moved no farther over that time
static_assert(kStaticMargin <= kMargin);             // a static piece's box inside the other (steady_now)
bool overlap(const btVector3& alo, const btVector3& ahi, const btVector3& blo, const btVector3& bhi) {
    return alo.x() <= bhi.x() && blo.x() <= ahi.x() && alo.y() <= bhi.y() && blo.y() <= ahi.y() &&
           alo.z() <= bhi.z() && blo.z() <= ahi.z();
}
bool inside(const btVector3& lo, const btVector3& hi, const btVector3& blo, const btVector3& bhi) {
    return lo.x() >= blo.x() && lo.y() >= blo.y() && lo.z() >= blo.z() && hi.x() <= bhi.x() && hi.y() <= bhi.y() &&
           hi.z() <= bhi.z();
}

void body_box(const Physics& ph, BodyId b, btVector3& lo, btVector3& hi) {
    const btRigidBody& r = ph.rb(b);
    r.getCollisionShape()->getAabb(r.getWorldTransform(), lo, hi);
}

// Whether a rotation maps each axis onto a world axis (its box's bounding box is the box).
bool on_axes(const btMatrix3x3& R) {
    for (int i = 0; i < 3; ++i) {
        const btVector3 c = R.getColumn(i).absolute();
        if (c[c.maxAxis()] < btScalar(1) - btScalar(1e-9)) return false;
    }
    return true;
}

// A body's shape, or piece `piece` of its compound (-1: a compound's only piece), and where it
// is in the world; null if there is no such piece.
const btCollisionShape* piece_of(const btRigidBody& rb, int piece, btTransform& t) {
    const btCollisionShape* shape = rb.getCollisionShape();
    t = rb.getWorldTransform();
    if (shape->getShapeType() != COMPOUND_SHAPE_PROXYTYPE) return shape;
    const auto* c = static_cast<const btCompoundShape*>(shape);
    if (piece < 0 && c->getNumChildShapes() == 1) piece = 0;
    if (piece < 0 || piece >= c->getNumChildShapes()) return nullptr;
    t = t * c->getChildTransform(piece);
    return c->getChildShape(piece);
}

// Whether a body's shape (or a compound's only piece) is a box with its faces on the world's axes.
bool axis_box(const btRigidBody& rb) {
    btTransform t;
    const btCollisionShape* shape = piece_of(rb, -1, t);
    return shape && shape->getShapeType() == BOX_SHAPE_PROXYTYPE && on_axes(t.getBasis());
}

bool top_face(const Physics& ph, BodyId b, int piece, btVector3& point, btVector3& normal);

// A box's or a hull's polyhedral features when they describe a solid: then contact.cpp's
// contacts between two such shapes are found on the polyhedra, without the shapes' margins.
const btConvexPolyhedron* polyhedron_of(const btCollisionShape& s) {
    const int type = s.getShapeType();
    if (type != BOX_SHAPE_PROXYTYPE && type != CONVEX_HULL_SHAPE_PROXYTYPE) return nullptr;
    const btConvexPolyhedron* p = static_cast<const btPolyhedralConvexShape&>(s).getConvexPolyhedron();
    return p && solid_polyhedron(*p) ? p : nullptr;
}

// A static piece's outline seen from above (Hazard::poly): a convex polygon, counter-clockwise,
// appended to `xy`, and the margin the shape adds around it.
using Corner = std::pair<btScalar, btScalar>;
void add_outline(Steady::Hazard& h, const Corner* c, int k, btScalar margin, std::vector<btScalar>& xy) {
    h.poly = int32_t(xy.size() / 2), h.corners = int16_t(k), h.poly_margin = margin;
    for (int i = 0; i < k; ++i) xy.push_back(c[i].first), xy.push_back(c[i].second);
}

// A box turned about the vertical (a curve's rail piece, Hazard::obb): its four corners; its
// margin is inside its extents.
void box_outline(Steady::Hazard& h, std::vector<btScalar>& xy) {
    const btScalar ux = h.oc * h.ohx, uy = h.os * h.ohx, wx = -h.os * h.ohy, wy = h.oc * h.ohy;
    const Corner c[4] = {{h.ocx - ux - wx, h.ocy - uy - wy},
                         {h.ocx + ux - wx, h.ocy + uy - wy},
                         {h.ocx + ux + wx, h.ocy + uy + wy},
                         {h.ocx - ux + wx, h.ocy - uy + wy}};
    add_outline(h, c, 4, 0, xy);
}

// A static convex hull (a separator's funnel): the convex hull of its points' (x, y) in the
// world. Nothing for a hull of more than kOutline points, or one seen edge on.
constexpr int kOutline = 32;
void hull_outline(const btConvexHullShape& hull, const btTransform& t, Steady::Hazard& h, std::vector<btScalar>& xy) {
    const int n = hull.getNumPoints();
    if (n < 3 || n > kOutline) return;
    std::array<Corner, kOutline> p;
    for (int i = 0; i < n; ++i) {
        const btVector3 w = t * (hull.getUnscaledPoints()[i] * hull.getLocalScaling());
        p[size_t(i)] = {w.x(), w.y()};
    }
    std::sort(p.begin(), p.begin() + n);
    // Andrew's monotone chain: the lower hull, then the upper one.
    std::array<Corner, 2 * kOutline> c;
    int k = 0;
    auto cross = [](const Corner& o, const Corner& a, const Corner& b) {
        return (a.first - o.first) * (b.second - o.second) - (a.second - o.second) * (b.first - o.first);
    };
    for (int i = 0; i < n; ++i) {
        while (k >= 2 && cross(c[size_t(k - 2)], c[size_t(k - 1)], p[size_t(i)]) <= 0) --k;
        c[size_t(k++)] = p[size_t(i)];
    }
    for (int i = n - 2, low = k + 1; i >= 0; --i) {
        while (k >= low && cross(c[size_t(k - 2)], c[size_t(k - 1)], p[size_t(i)]) <= 0) --k;
        c[size_t(k++)] = p[size_t(i)];
    }
    --k;  // the last point is the first
    if (k >= 3) add_outline(h, c.data(), k, hull.getMargin(), xy);
}

// Files the static geometry into cells (when starting and after a static body was placed or a
// kinematic one left its room). Allocates only when it covers more cells than before.
void build_grid(Runtime& r) {
    Steady& S = r.steady;
    const Physics& ph = r.phys;
    S.hazards.clear();
    S.kinematic.clear();
    S.poly_xy.clear();
    for (BodyId b : ids_of(r.g.bodies)) {
        const BodyMode mode = r.g.bodies[b].mode;
        if (mode == BodyMode::Dynamic) continue;
        Steady::Hazard h{{0, 0, 0}, {0, 0, 0}, b, mode == BodyMode::Static};
        const btRigidBody& rb = ph.rb(b);
        h.friction = rb.getFriction(), h.restitution = rb.getRestitution();
        if (mode == BodyMode::Static && rb.getCollisionShape()->getShapeType() == COMPOUND_SHAPE_PROXYTYPE) {
            // Each piece on its own: a belt's two rails are one body, the band between them.
            const auto* c = static_cast<const btCompoundShape*>(rb.getCollisionShape());
            for (int k = 0; k < c->getNumChildShapes(); ++k) {
                btTransform t;
                const btCollisionShape* piece = piece_of(rb, k, t);
                piece->getAabb(t, h.lo, h.hi);
                h.box = piece->getShapeType() == BOX_SHAPE_PROXYTYPE && on_axes(t.getBasis());
                h.obb = false;
                if (piece->getShapeType() == BOX_SHAPE_PROXYTYPE && !h.box &&
                    std::abs(t.getBasis()[2][2]) > btScalar(0.999999)) {  // turned about z only
                    const btVector3 half = static_cast<const btBoxShape*>(piece)->getHalfExtentsWithMargin();
                    h.obb = true;
                    h.ocx = t.getOrigin().x(), h.ocy = t.getOrigin().y();
                    h.oc = t.getBasis()[0][0], h.os = t.getBasis()[1][0];
                    h.ohx = half.x(), h.ohy = half.y();
                }
                h.piece = int16_t(k);
                h.poly = -1;
                if (h.obb) box_outline(h, S.poly_xy);
                else if (piece->getShapeType() == CONVEX_HULL_SHAPE_PROXYTYPE)
                    hull_outline(*static_cast<const btConvexHullShape*>(piece), t, h, S.poly_xy);
                S.hazards.push_back(h);
            }
            continue;
        }
        body_box(ph, b, h.lo, h.hi);
        h.box = axis_box(rb);  // a kinematic part's too: it counts while at rest where filed (steady_now)
        if (mode == BodyMode::Static && rb.getCollisionShape()->getShapeType() == CONVEX_HULL_SHAPE_PROXYTYPE)
            hull_outline(*static_cast<const btConvexHullShape*>(rb.getCollisionShape()), rb.getWorldTransform(), h,
                         S.poly_xy);
        if (mode == BodyMode::Kinematic) {
            const btVector3 room(kRoom, kRoom, kRoom);
            h.lo -= room, h.hi += room;
            S.home_lo[b] = h.lo, S.home_hi[b] = h.hi;
            S.home_tr[b] = rb.getWorldTransform();
            S.kinematic.push_back(b);
        }
        S.hazards.push_back(h);
    }
    // Whether each static piece's top face is level (top_face): a unit may stand on it.
    S.level_top.resize(S.hazards.size());
    S.top_plane.resize(S.hazards.size());
    for (size_t i = 0; i < S.hazards.size(); ++i) {
        const Steady::Hazard& h = S.hazards[i];
        btVector3 point, normal;
        S.level_top[i] = h.fixed && top_face(ph, h.body, h.piece, point, normal);
        if (S.level_top[i]) {  // 2: a box with polyhedral features (contact.cpp's contacts meet it so)
            btTransform t;
            if (polyhedron_of(*piece_of(ph.rb(h.body), h.piece, t))) S.level_top[i] = 2;
        }
        S.top_plane[i] = S.level_top[i] ? btVector4(normal.x(), normal.y(), normal.z(), normal.dot(point))
                                        : btVector4(0, 0, 0, 0);
    }
    S.filed.clear();
    S.big.clear();
    for (int32_t i = 0; i < count_of(S.hazards); ++i) {
        const Steady::Hazard& h = S.hazards[i];
        file_box(h.lo.x(), h.lo.y(), h.hi.x(), h.hi.y(), i, S.filed, S.big);
    }
    index_cells(S.filed, S.cells, S.cell_adr, S.cell_list);
    box_cells(S.cell_list, S.cell_box, [&S](int32_t i) {
        const Steady::Hazard& h = S.hazards[i];
        return std::array<btScalar, 4>{h.lo.x(), h.lo.y(), h.hi.x(), h.hi.y()};
    });
    S.grid_valid = true;
    S.grid_statics = ph.statics_placed();
    ++S.grid_builds;
}

// Unit b's Near (transport.h) for a walk over cells [x0, x1] × [y0, y1]. Made again when the
// filings changed or those cells are not all among its own: then for them and for the cells of
// b's box grown by kNearBy (so that its other walks, this step and while it moves less than
// that, find theirs among them). Null when more is filed there than it holds (the caller walks
// the cells). Writes only b's entry.
constexpr btScalar kNearBy = btScalar(0.02);  // m
constexpr int64_t kNearCells = 16;            // at most, else the cells are walked
const Steady::Near* near_of(Runtime& r, BodyId b, int64_t x0, int64_t y0, int64_t x1, int64_t y1) {
    Steady& S = r.steady;
    const State& s = r.st;
    if (!S.near_on) return nullptr;
    Steady::Near& n = S.near[b];
    const uint64_t epoch = S.grid_builds + s.field_builds;
    if (n.epoch == epoch && x0 >= n.x0 && y0 >= n.y0 && x1 <= n.x1 && y1 <= n.y1)
        return n.hazards == Steady::kFull ? nullptr : &n;
    btVector3 lo, hi;
    body_box(r.phys, b, lo, hi);
    int64_t bx0, by0, bx1, by1;
    if (cell_of(lo.x() - kNearBy, lo.y() - kNearBy, bx0, by0) && cell_of(hi.x() + kNearBy, hi.y() + kNearBy, bx1, by1))
        x0 = std::min(x0, bx0), y0 = std::min(y0, by0), x1 = std::max(x1, bx1), y1 = std::max(y1, by1);
    n.x0 = int32_t(x0), n.y0 = int32_t(y0), n.x1 = int32_t(x1), n.y1 = int32_t(y1);  // within 4e6 (cell_of)
    n.epoch = epoch;
    n.hazards = n.fields = 0;
    if ((x1 - x0 + 1) * (y1 - y0 + 1) > kNearCells) {
        n.hazards = Steady::kFull;
        return nullptr;
    }
    // Adds id once to the fields (`count`: n.fields) or the hazards after them; false when
    // there is no room.
    auto add = [&n](uint8_t& count, int32_t id) {
        const uint8_t from = &count == &n.fields ? 0 : n.fields, end = uint8_t(n.fields + n.hazards);
        for (uint8_t k = from; k < end; ++k)
            if (n.id[k] == id) return true;
        if (end == n.id.size()) return false;
        n.id[end] = id;
        ++count;
        return true;
    };
    if (!each_in_cells(s.field_cells, s.field_cell_adr, s.field_cell_list, x0, y0, x1, y1,
                       [&](int32_t f) { return add(n.fields, f); }) ||
        !each_in_cells(S.cells, S.cell_adr, S.cell_list, x0, y0, x1, y1,
                       [&](int32_t i) { return add(n.hazards, i); })) {
        n.hazards = Steady::kFull;
        return nullptr;
    }
    return &n;
}

// Calls f(i) for the static pieces i that may meet [glo, ghi] (in cells [x0, x1] × [y0, y1]),
// until f returns false; returns whether none did. From unit b's list (Near, `n`) when it has
// one for these cells: every piece filed under them, and some more that f must pass over (its
// box does not meet [glo, ghi]), in another order. Else from the cells, those whose box meets
// [glo, ghi] in (x, y).
template <class F>
bool each_piece(const Steady& S, const Steady::Near* n, const btVector3& glo, const btVector3& ghi, int64_t x0,
                int64_t y0, int64_t x1, int64_t y1, F&& f) {
    if (n) {
        for (uint8_t k = n->fields; k < n->fields + n->hazards; ++k)
            if (!f(n->id[k])) return false;
        return true;
    }
    return each_meeting(S.cells, S.cell_adr, S.cell_list, S.cell_box, glo.x(), glo.y(), ghi.x(), ghi.y(), x0, y0, x1,
                        y1, f);
}

// Whether the path from p over two steps at v has no field's face within 1 mm of it and lies in
// one acting field's box at most (1 mm inside); then `found` is that field, or none (-1): no
// field acts there. Every field whose bounding box lies
// within `clear` of p is looked at: those filed under p's cell (fields are filed grown by
// kNear), or, for a path longer than that allows, under every cell within `clear` of p.
bool field_at(Runtime& r, BodyId unit, const btVector3& p, const btVector3& v, FieldId& found) {
    State& s = r.st;
    found = FieldId{};
    int64_t ix, iy;
    if (!cell_of(p.x(), p.y(), ix, iy)) return false;
    const btVector3 q = p + v * btScalar(2 * r.dt);
    // A field whose bounding box is farther from p in x or y than twice the margin and the
    // path's length is 'out' below: p's distance to its box is at least that, so p lies beyond
    // one of its faces by more than that over the square root of 3, and q too (it is no farther
    // from p along any axis than the path's length). Twice, not the root of 3: room for rounding.
    const btScalar clear = btScalar(2) * (kFieldMargin + (q - p).length());
    // False when p's path is at a face of f, or in f and in another acting field.
    auto look = [&](FieldId f) {
        if (s.field_xy[f].beyond(p) >= clear) return true;
        const State::FieldFrame& ff = s.field_frame[f];
        const btMatrix3x3& R = ff.pose.getBasis();
        const btVector3& h = ff.half;
        const btVector3& c = ff.pose.getOrigin();
        const btVector3 a = (p - c) * R, b = (q - c) * R;
        bool in = true, out = false;
        for (int i = 0; i < 3; ++i) {
            in = in && std::abs(a[i]) + kFieldMargin <= h[i] && std::abs(b[i]) + kFieldMargin <= h[i];
            out = out || (a[i] - h[i] >= kFieldMargin && b[i] - h[i] >= kFieldMargin) ||
                  (-a[i] - h[i] >= kFieldMargin && -b[i] - h[i] >= kFieldMargin);
        }
        if (!in && !out) return false;  // at a face
        if (in && s.field_act[f]) {
            if (found.valid() && found != f) return false;  // two acting fields
            found = f;
        }
        return true;
    };
    for (int32_t f : s.field_big)
        if (!look(FieldId(f))) return false;
    // p's cell, or for a fast unit every cell within `clear` (a field filed under several is
    // looked at again).
    int64_t x0 = ix, y0 = iy, x1 = ix, y1 = iy;
    if (clear > kNear && (!cell_of(p.x() - clear, p.y() - clear, x0, y0) ||
                          !cell_of(p.x() + clear, p.y() + clear, x1, y1) || (x1 - x0 + 1) * (y1 - y0 + 1) > kMaxCells))
        return false;
    // The unit's own list holds every field filed under these cells, and others farther than
    // `clear` (look passes over them): the same verdict and field, in any order.
    if (const Steady::Near* n = near_of(r, unit, x0, y0, x1, y1)) {
        for (uint8_t k = 0; k < n->fields; ++k)
            if (!look(FieldId(n->id[k]))) return false;
        return true;
    }
    return each_in_cells(s.field_cells, s.field_cell_adr, s.field_cell_list, x0, y0, x1, y1,
                         [&](int32_t f) { return look(FieldId(f)); });
}

// The top face of a box (or of a compound of one box): a point of it and its normal.
bool top_face(const Physics& ph, BodyId b, int piece, btVector3& point, btVector3& normal) {
    btTransform t;
    const btCollisionShape* shape = piece_of(ph.rb(b), piece, t);
    if (!shape || shape->getShapeType() != BOX_SHAPE_PROXYTYPE) return false;
    const btVector3 h = static_cast<const btBoxShape*>(shape)->getHalfExtentsWithMargin();
    int best = 0;
    for (int i = 1; i < 3; ++i)
        if (std::abs(t.getBasis().getColumn(i).z()) > std::abs(t.getBasis().getColumn(best).z())) best = i;
    btVector3 n = t.getBasis().getColumn(best);
    if (n.z() < 0) n = -n;
    if (n.z() < kUpright) return false;
    normal = n;
    point = t.getOrigin() + n * h[best];
    return true;
}

// How far unit b's bounding box [lo, hi] can reach over time t at its velocity, per axis: its
// motion along each axis, and in x and y what turning about the vertical moves its farthest
// point by (the distance from its centre of mass to the box's farthest corner, times the angle).
btVector3 swept(const Physics& ph, BodyId b, const btVector3& lo, const btVector3& hi, btScalar t) {
    const btRigidBody& rb = ph.rb(b);
    const btVector3& c = rb.getCenterOfMassPosition();
    const btScalar fx = std::max(c.x() - lo.x(), hi.x() - c.x()), fy = std::max(c.y() - lo.y(), hi.y() - c.y());
    const btScalar turn = std::sqrt(fx * fx + fy * fy) * std::abs(rb.getAngularVelocity().z()) * t;
    return rb.getLinearVelocity().absolute() * t + btVector3(turn, turn, 0);
}

struct Verdict {
    OnSolver why = OnSolver::kCount;  // when not steady, the first test it failed
    FieldId field;
    BodyId support;
    int16_t piece = -1;  // the support's piece, in a compound
    int8_t guide_axis = 0, guide_side = 0;  // the rail it slides along (Steady::guide_*), if any
    btScalar guide_face = 0;
};

// The point of unit b's shape farthest along `side` times world axis a, at transform t (its
// centre of mass's; Bullet's support point, with the shape's margin, as Bullet's contacts see
// it), and how far it reaches that way.
btVector3 support_along(const btConvexShape& shape, const btTransform& t, int a, int side) {
    btVector3 dir(0, 0, 0);
    dir[a] = btScalar(side);
    return t * shape.localGetSupportingVertex(dir * t.getBasis());
}
btScalar reach_along(const btConvexShape& shape, const btTransform& t, int a, int side) {
    return support_along(shape, t, a, side)[a];
}

// Whether static box h, which unit b's grown box meets, is a rail b slides along: a box on the
// world's axes, frictionless and inelastic against b, whose face b's shape touches from outside
// along x or y (reaching into it by kTouch at most), or comes up to it, and does not move
// towards faster than kApproach, and on no other side (not at its end). Then `out` holds the
// face; else out.why says why not.
bool guide_by(const Physics& ph, BodyId b, const Steady::Hazard& h, Verdict& out) {
    const btRigidBody& rb = ph.rb(b);
    out.why = OnSolver::kInTheWay;
    if (!h.box || !rb.getCollisionShape()->isConvex() || rb.getFriction() * h.friction != 0 ||
        rb.getRestitution() * h.restitution != 0)
        return false;
    const auto& shape = *static_cast<const btConvexShape*>(rb.getCollisionShape());
    const btTransform& t = rb.getWorldTransform();
    int axis = -1, side = 0;
    btScalar face = 0;
    // The last support point found, a point of the shape: it reaches along +a at least as far as
    // that point and along -a no less, so a side the point is past by more than kTouch is one
    // the shape is past too, and needs no support point of its own (a unit along a rail: two of
    // the four).
    btVector3 known;
    bool have = false;
    for (int a = 0; a < 2; ++a)
        for (int sd = -1; sd <= 1; sd += 2) {
            const btScalar f = sd > 0 ? h.lo[a] : h.hi[a];
            if (have && btScalar(sd) * (known[a] - f) > kTouch) continue;
            known = support_along(shape, t, a, sd), have = true;
            const btScalar into = btScalar(sd) * (known[a] - f);
            if (into > kTouch) continue;
            if (axis >= 0) return false;  // outside it along both axes: by its end
            axis = a, side = sd, face = f + btScalar(sd) * std::max(into, btScalar(0));
        }
    if (axis < 0) return false;
    if (btScalar(side) * rb.getLinearVelocity()[axis] > kApproach) {
        out.why = OnSolver::kRailFast;
        return false;
    }
    if (out.guide_side != 0 && (out.guide_axis != axis || out.guide_side != side || out.guide_face != face)) {
        out.why = out.guide_axis == axis && out.guide_side == -side ? OnSolver::kChannel : OnSolver::kInTheWay;
        return false;  // two rails
    }
    out.guide_axis = int8_t(axis), out.guide_side = int8_t(side), out.guide_face = face;
    return true;
}

// Whether unit b's shape stays above the plane of static piece i's level top face by more than
// kBelow over its next two steps (closing on it along the face's normal at its velocity, and by
// its rocking at its lowest point): it cannot touch that piece then (a box lies below its top
// face's plane), and Bullet's contact there, were it on the solver, would push only on a body
// closing faster than kBelow a step. The shape as the contacts see it: a box's or a hull's
// polyhedron against a box (contact.cpp), else with its margin. False for a piece without a
// level top face.
bool clear_below(const Physics& ph, const Steady& S, BodyId b, int32_t i, btScalar two_steps) {
    if (!S.level_top[size_t(i)]) return false;
    const btRigidBody& rb = ph.rb(b);
    if (!rb.getCollisionShape()->isConvex()) return false;
    const auto& shape = *static_cast<const btConvexShape*>(rb.getCollisionShape());
    const btVector4& plane = S.top_plane[size_t(i)];
    const btVector3 n(plane.x(), plane.y(), plane.z());
    const btTransform& t = rb.getWorldTransform();
    const btVector3 d = -n * t.getBasis();
    const bool polyhedra = S.level_top[size_t(i)] == 2 && polyhedron_of(shape);
    const btVector3 low =
        t * (polyhedra ? shape.localGetSupportingVertexWithoutMargin(d) : shape.localGetSupportingVertex(d));
    const btVector3& w = rb.getAngularVelocity();
    const btScalar rock = std::sqrt(w.x() * w.x() + w.y() * w.y()) * (low - rb.getCenterOfMassPosition()).length();
    const btScalar closing = std::max(-n.dot(rb.getLinearVelocity()), btScalar(0)) + rock;
    return n.dot(low) - plane.w() - two_steps * closing > kBelow;
}

// Records why a unit is not steady (or may not rest): returns false.
bool fail(Verdict& out, OnSolver why) {
    out.why = why;
    return false;
}

// Whether unit b (with passenger p, or -1) is simulated (dynamic, in the world, collision on),
// free (not gone, not held by a gripper or a hand) and unread (nothing reads its outputs).
bool free_unit(const Runtime& r, BodyId b, BodyId p, Verdict& out) {
    const Physics& ph = r.phys;
    const State& s = r.st;
    if (!ph.dynamic_now(b) || !ph.collision_on(b) || s.gone[b] || s.held_by[b].valid() || s.in_hand[b] ||
        (p.valid() && (s.gone[p] || s.held_by[p].valid() || s.in_hand[p])))
        return fail(out, OnSolver::kHeld);
    if (s.body_outputs[b] || (p.valid() && s.body_outputs[p])) return fail(out, OnSolver::kRead);
    return true;
}

// Whether kinematic part k is at rest exactly where it was filed (it then counts as a static
// piece for steady transport).
bool at_home(const Physics& ph, const Steady& S, BodyId k) {
    const btRigidBody& kb = ph.rb(k);
    return kb.getWorldTransform() == S.home_tr[k] && kb.getLinearVelocity().fuzzyZero() &&
           kb.getAngularVelocity().fuzzyZero();
}

// Calls f(o) for every body o but b and p, in the world with its collision on, whose bounding box
// grown by its reach (two steps at its speed plus 1 cm, 5 cm more for a body Bullet does not
// move itself) meets [glo, ghi], until f returns false; returns whether none did. `grown`: how
// far [glo, ghi] reaches beyond the unit's box; `vmax`: the bodies' largest speed.
template <class F>
bool each_in_reach(const Runtime& r, BodyId b, BodyId p, const btVector3& glo, const btVector3& ghi, btScalar grown,
                   btScalar vmax, F&& f) {
    const Physics& ph = r.phys;
    const btScalar far = grown + r.index.reach() + kMargin + kNotSimulated + btScalar(2 * r.dt) * vmax;
    bool go_on = true;
    r.index.for_each(glo.x() - far, ghi.x() + far, glo.y() - far, ghi.y() + far, [&](BodyId o) {
        if (!go_on || o == b || o == p || !ph.in_world(o) || !ph.collision_on(o)) return;
        const btScalar ro = kMargin + btScalar(2 * r.dt) * ph.velocity(o).length() + (ph.dynamic_now(o) ? 0 : kNotSimulated);
        const btVector3 g(ro, ro, ro);
        if (overlap(glo, ghi, r.index.lo(o) - g, r.index.hi(o) + g)) go_on = f(o);
    });
    return go_on;
}

// Whether box [lo, hi] meets static box h, turned about z (Hazard::obb), in (x, y): the
// separating axes of the two boxes (the world's x and y are its bounding box's, tested first).
bool meets_obb(const Steady::Hazard& h, const btVector3& lo, const btVector3& hi) {
    const btScalar ax = (hi.x() - lo.x()) / 2, ay = (hi.y() - lo.y()) / 2;
    const btScalar dx = h.ocx - (lo.x() + hi.x()) / 2, dy = h.ocy - (lo.y() + hi.y()) / 2;
    const btScalar c = std::abs(h.oc), s = std::abs(h.os);
    if (std::abs(dx * h.oc + dy * h.os) > ax * c + ay * s + h.ohx) return false;
    if (std::abs(-dx * h.os + dy * h.oc) > ax * s + ay * c + h.ohy) return false;
    return true;
}

// Whether unit b's shape, grown by `grow` in x and y, keeps clear of static piece h's outline
// seen from above (Hazard::poly: a curve's turned rail, a hull) grown by its margin, while its
// centre of mass moves along `path` (in x and y, from where it is): the distance from that
// segment to the polygon against the shape's reach about its centre of mass in (x, y), however
// it turns about the vertical (reach_bound of what the shape cache measured when it made the
// shape; asked once per check: reach < 0 until then). The distance from a segment to
// a convex polygon that it does not cross is the least from the segment's ends to the polygon
// and from the polygon's corners to the segment. The outline contains the piece seen from
// above, so a unit clear of it is clear of the piece at any height.
bool outline_clear(const Physics& ph, const Steady& S, BodyId b, const Steady::Hazard& h, const btVector3& path,
                   btScalar grow, btScalar& reach) {
    const btRigidBody& rb = ph.rb(b);
    if (reach < 0) {
        const ShapeReach* m = ph.reach(*rb.getCollisionShape());
        if (!m) return false;  // not convex (a compound): in the way
        reach = reach_bound(*m, rb.getWorldTransform().getBasis());
    }
    const btScalar r = reach + grow + h.poly_margin, r2 = r * r;
    const btScalar* xy = S.poly_xy.data() + 2 * size_t(h.poly);
    const int n = h.corners;
    const btVector3 c = rb.getWorldTransform().getOrigin();
    const btScalar ax = c.x(), ay = c.y(), ux = path.x(), uy = path.y();
    // Squared distance from (px, py) to the segment from (x0, y0) by (dx, dy).
    auto to_segment = [](btScalar px, btScalar py, btScalar x0, btScalar y0, btScalar dx, btScalar dy) {
        const btScalar l2 = dx * dx + dy * dy;
        const btScalar k = l2 > 0 ? std::clamp(((px - x0) * dx + (py - y0) * dy) / l2, btScalar(0), btScalar(1)) : 0;
        const btScalar ex = px - x0 - k * dx, ey = py - y0 - k * dy;
        return ex * ex + ey * ey;
    };
    auto to_outline = [&](btScalar px, btScalar py) {  // 0 inside
        bool inside = true;
        btScalar best = std::numeric_limits<btScalar>::max();
        for (int i = 0; i < n; ++i) {
            const int j = (i + 1) % n;
            const btScalar x0 = xy[2 * i], y0 = xy[2 * i + 1], dx = xy[2 * j] - x0, dy = xy[2 * j + 1] - y0;
            if (dx * (py - y0) - dy * (px - x0) < 0) inside = false;
            best = std::min(best, to_segment(px, py, x0, y0, dx, dy));
        }
        return inside ? btScalar(0) : best;
    };
    if (to_outline(ax, ay) <= r2 || to_outline(ax + ux, ay + uy) <= r2) return false;
    auto side = [](btScalar x0, btScalar y0, btScalar dx, btScalar dy, btScalar px, btScalar py) {
        const btScalar v = dx * (py - y0) - dy * (px - x0);
        return (v > 0) - (v < 0);
    };
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        const btScalar x0 = xy[2 * i], y0 = xy[2 * i + 1], dx = xy[2 * j] - x0, dy = xy[2 * j + 1] - y0;
        if (to_segment(x0, y0, ax, ay, ux, uy) <= r2) return false;  // a corner near the path
        if (side(ax, ay, ux, uy, x0, y0) * side(ax, ay, ux, uy, x0 + dx, y0 + dy) < 0 &&
            side(x0, y0, dx, dy, ax, ay) * side(x0, y0, dx, dy, ax + ux, ay + uy) < 0)
            return false;  // the path crosses an edge
    }
    return true;
}

// Whether unit b (with passenger p, or -1) is steady now (see the top of the file).
bool steady_now(Runtime& r, BodyId b, BodyId p, btScalar vmax, Verdict& out) {
    Physics& ph = r.phys;
    State& s = r.st;
    Steady& S = r.steady;
    if (!free_unit(r, b, p, out)) return false;
    const btRigidBody& rb = ph.rb(b);
    const btVector3 v = rb.getLinearVelocity();
    const btVector3& w = rb.getAngularVelocity();
    if (w.x() * w.x() + w.y() * w.y() > kRockTol * kRockTol || std::abs(w.z()) > kYawTol) return fail(out, OnSolver::kTurning);
    if (ph.frame(b).getBasis()[2][2] < kTilt) return fail(out, OnSolver::kTilted);
    FieldId f, fp;
    if (!field_at(r, b, ph.com(b), v, f) || (p.valid() && (!field_at(r, b, ph.com(p), v, fp) || fp != f)))
        return fail(out, OnSolver::kFieldEdge);
    if (f.valid()) {
        const btMatrix3x3& R = s.field_frame[f].pose.getBasis();
        const btVector3& gain = r.tab.field_gain[f];
        if (R[2][2] < kUpright || gain.z() > 0) return fail(out, OnSolver::kFieldSlope);
        const btVector3 vl = v * R;
        if (r.tab.field_turns[f]) {
            // A turning field: the law pulled towards the band's rotation half a step on from
            // where the unit was at the last step's start (turning_target), which is half a step
            // back from where it is now; steady, it moves at that target (the rest of its
            // speed-up decayed).
            const btVector3 local = (ph.com(b) - s.field_frame[f].pose.getOrigin()) * R;
            const btVector3 want = turning_target(s.field_spin[f], r.tab.field_pivot[f], local, vl, btScalar(-r.dt / 2));
            for (int i = 0; i < 2; ++i)
                if (std::abs(vl[i] - want[i]) > kSpeedTol) return fail(out, OnSolver::kSpeed);
        } else {
            for (int i = 0; i < 2; ++i) {
                const btScalar target = gain[i] > 0 ? s.field_target[f][i] : 0;
                if (std::abs(vl[i] - target) <= (gain[i] > 0 ? kSpeedTol : kDrift)) continue;
                if (gain[i] <= 0) return fail(out, OnSolver::kDrift);
                return fail(out, std::abs(vl[i] - target) > btScalar(0.5) * std::abs(target) ? OnSolver::kHeldBack
                                                                                             : OnSolver::kSpeed);
            }
        }
    } else if (std::abs(v.x()) > kRest || std::abs(v.y()) > kRest || std::abs(v.z()) > kRest) {
        return fail(out, OnSolver::kMoving);  // no field acts: at rest, or it stays on the solver
    }

    // Statics and kinematic parts.
    btVector3 lo, hi;
    body_box(ph, b, lo, hi);
    const btVector3 sweep = swept(ph, b, lo, hi, btScalar(2 * r.dt));
    const btVector3 g = sweep + btVector3(kMargin, kMargin, kMargin), glo = lo - g, ghi = hi + g;
    const btVector3 sg = sweep + btVector3(kStaticMargin, kStaticMargin, kStaticMargin), slo = lo - sg, shi = hi + sg;
    const btScalar reach = g[g.maxAxis()];
    BodyId support;
    int16_t piece = -1;
    btVector3 sup_lo, sup_hi;  // the support's box (its piece's, in a compound)
    // A kinematic part whose room is in reach: none if its collision is off; at rest where it was
    // filed, a static piece (a rail it slides along, or in the way) with a margin of 1 cm; moving,
    // in the way.
    auto part = [&](const Steady::Hazard& h) {
        const BodyId k = h.body;
        if (!ph.collision_on(k)) return true;
        if (!at_home(ph, S, k)) return fail(out, OnSolver::kPart);
        Steady::Hazard now = h;  // its box, not its room
        body_box(ph, k, now.lo, now.hi);
        if (!overlap(glo, ghi, now.lo, now.hi)) return true;
        return guide_by(ph, b, now, out);
    };
    int32_t sup = -1;  // the support's hazard
    int sup_below = -1;  // whether it lies clear below the unit (clear_below), once asked
    bool lower = false;  // whether a second piece under it was met
    const btScalar two_steps = btScalar(2 * r.dt);
    btScalar reach_xy = -1;  // the shape's reach about its centre of mass in (x, y), once asked (outline_clear)
    // Where two steps take its centre of mass in (x, y): along its velocity, off that line by
    // what the law's turn of it does (a turning field's spin, over a chord of two steps: an arc
    // bulges by at most a quarter of the turn's angle times its length) and what its speed may
    // change by while it is steady (its target's tolerance, a rail it comes up to).
    const btVector3 path(v.x() * two_steps, v.y() * two_steps, 0);
    const btScalar spin = f.valid() && r.tab.field_turns[f] ? std::abs(s.field_spin[f]) : btScalar(0);
    const btScalar bulge = path.length() * spin * two_steps / 4 + (kSpeedTol + kApproach) * two_steps;
    auto hazard = [&](int32_t i) {
        const Steady::Hazard& h = S.hazards[size_t(i)];
        if (h.fixed ? !overlap(slo, shi, h.lo, h.hi) : !overlap(glo, ghi, h.lo, h.hi)) return true;
        if (h.fixed && h.obb && !meets_obb(h, slo, shi)) return true;
        if (h.fixed && h.poly >= 0 && outline_clear(ph, S, b, h, path, bulge + kStaticMargin, reach_xy)) return true;
        if (!h.fixed) return part(h);
        if (h.hi.z() > lo.z() + kSink) return guide_by(ph, b, h, out);  // a rail, or in the way
        if (ph.rb(b).getFriction() * h.friction != 0) return fail(out, OnSolver::kSupport);  // it would hold it back
        if (support.valid() && (support != h.body || piece != h.piece)) {
            // Two pieces under it (two bands at a joint, two pieces of one): one that lies clear
            // below its shape (the next band, 2 mm lower, while its centre is over the one it
            // stands on) is passed over; the one it stands on is its support. Two that it
            // touches, or none (when all were passed over, below), fail. The same in any order.
            lower = true;
            if (clear_below(ph, S, b, i, two_steps)) return true;
            if (sup_below < 0) sup_below = clear_below(ph, S, b, sup, two_steps);
            if (!sup_below) return fail(out, OnSolver::kSupport);  // two supports (two pieces of one)
            sup_below = 0;  // h, which it touches, takes the place of the one below
        }
        support = h.body, piece = h.piece, sup = i;
        sup_lo = h.lo, sup_hi = h.hi;
        return true;
    };
    // Only the hazards whose box meets the grown box in (x, y) can fail (a static piece is met
    // by the box grown by the smaller margin, inside that one): those filed under its cells,
    // found in the unit's own list of them (Near) when it has one, else by walking the cells.
    // Both find the same support and rail when it passes (hazard passes over a piece the box
    // does not meet, and fails on a second support or rail unlike the first, in any order); a
    // failure is found again by the cells, so `why` is the first in their order.
    int64_t x0, y0, x1, y1;
    const bool in_grid = cell_of(glo.x(), glo.y(), x0, y0) && cell_of(ghi.x(), ghi.y(), x1, y1);
    auto walk = [&](const Steady::Near* n) {
        support = BodyId{}, piece = -1, sup = -1, sup_below = -1, lower = false;
        out.guide_axis = 0, out.guide_side = 0, out.guide_face = 0;
        for (int32_t i : S.big)
            if (!hazard(i)) return false;
        if (!in_grid) return fail(out, OnSolver::kNoSupport);
        return each_piece(S, n, glo, ghi, x0, y0, x1, y1, hazard);
    };
    const Steady::Near* n = in_grid ? near_of(r, b, x0, y0, x1, y1) : nullptr;
    if (!walk(n) && (!n || !walk(nullptr))) return false;
    if (sup < 0 || !S.level_top[size_t(sup)]) return fail(out, OnSolver::kNoSupport);
    if (lower && (sup_below < 0 ? clear_below(ph, S, b, sup, two_steps) : sup_below != 0))
        return fail(out, OnSolver::kSupport);  // over two pieces and touching neither
    // No field holds it to its band, or it reaches over a piece below: its path must stay above
    // its support (a field may reach past the band's end, and the unit tips off it there).
    if (!f.valid() || lower) {
        const btVector3 c = rb.getCenterOfMassPosition(), q = c + v * btScalar(2 * r.dt);
        for (int i = 0; i < 2; ++i)
            if (std::min(c[i], q[i]) < sup_lo[i] + kFieldMargin || std::max(c[i], q[i]) > sup_hi[i] - kFieldMargin)
                return fail(out, OnSolver::kEdge);
    }

    // Other bodies.
    if (!each_in_reach(r, b, p, glo, ghi, reach, vmax, [](BodyId) { return false; })) return fail(out, OnSolver::kNeighbour);
    out.field = f;
    out.support = support;
    out.piece = piece;
    return true;
}

// Whether unit b (with passenger p, or -1) may rest off the solver now: simulated, not held,
// nothing reading its outputs, upright and still (within 2 cm/s along each axis, turning slower
// than 1 rad/s), its centre of mass 1 mm clear of every field's faces and in one acting field
// at most (its passenger's in the same), one that would speed it up by 1 cm/s in a step were it
// free; every static body and kinematic part (its room) that its box grown by 1 cm meets with
// its collision on, each part at rest where it was filed; and every other body whose box meets
// its own grown by 1 cm (and that body's two steps of motion, 5 cm more for one Bullet does
// not move itself) still too: resting, or still on the solver and not held, or a part that
// does not move. Then nothing moves it before one of those changes: what holds it still (a
// pin, a rail, the bodies before it) still holds it.
bool rest_now(Runtime& r, BodyId b, BodyId p, btScalar vmax, Verdict& out) {
    Physics& ph = r.phys;
    State& s = r.st;
    Steady& S = r.steady;
    auto still = [&ph](BodyId o) {
        const btRigidBody& rb = ph.rb(o);
        const btVector3 &v = rb.getLinearVelocity(), &w = rb.getAngularVelocity();
        return std::abs(v.x()) <= kJiggle && std::abs(v.y()) <= kJiggle && std::abs(v.z()) <= kJiggle &&
               w.length2() <= kRockTol * kRockTol;
    };
    if (!free_unit(r, b, p, out)) return false;
    if (!ph.resting(b) && !still(b)) return fail(out, OnSolver::kMoving);
    if (ph.frame(b).getBasis()[2][2] < kTilt) return fail(out, OnSolver::kTilted);
    const btVector3 zero(0, 0, 0);
    FieldId f, fp;
    if (!field_at(r, b, ph.com(b), zero, f) || (p.valid() && (!field_at(r, b, ph.com(p), zero, fp) || fp != f)))
        return fail(out, OnSolver::kFieldEdge);
    // A turning field at speed (its target differs from place to place): not held still by one
    // target. Halted (spin 0), its target is 0 everywhere, as a straight field's at speed 0.
    if (f.valid() && r.tab.field_turns[f] && r.st.field_spin[f] != 0) return fail(out, OnSolver::kFieldTurns);
    if (f.valid()) {
        // Still against a field that drives it, it is held: were it free, the law would speed it
        // up by at least 1 cm/s in a step along each driven axis with a target (a slow field, a
        // weak gain or force: it may be speeding up, and it stays on the solver).
        const btVector3& gain = r.tab.field_gain[f];
        const btVector3& target = s.field_target[f];
        const Field& fd = r.g.fields[f];
        const int n = p.valid() ? 2 : 1;
        const double m = ph.mass(b) + (p.valid() ? ph.mass(p) : 0.0);
        const double cap = fd.max_force > 0 ? n * fd.max_force * r.dt / m : HUGE_VAL;
        for (int i = 0; i < 3; ++i) {
            if (gain[i] <= 0 || target[i] == 0) continue;
            const double dv = std::abs(double(target[i])) * -std::expm1(-double(gain[i]) * n * r.dt / m);
            if (std::min(dv, cap) < 2 * double(kRest)) return fail(out, OnSolver::kSpeed);
        }
    }
    btVector3 lo, hi;
    body_box(ph, b, lo, hi);
    const btVector3 g(kMargin, kMargin, kMargin), glo = lo - g, ghi = hi + g;
    // What may hold it still must not go: a static body or a part within reach whose collision
    // is off (a pin opened by switching it off) fails it as one that moves.
    auto part = [&](const Steady::Hazard& h) {
        if (!overlap(glo, ghi, h.lo, h.hi)) return true;
        const BodyId k = h.body;
        if (!ph.collision_on(k)) return fail(out, OnSolver::kPart);
        return h.fixed || at_home(ph, S, k) || fail(out, OnSolver::kPart);
    };
    for (int32_t i : S.big)
        if (!part(S.hazards[i])) return false;
    int64_t x0, y0, x1, y1;
    if (!cell_of(glo.x(), glo.y(), x0, y0) || !cell_of(ghi.x(), ghi.y(), x1, y1)) return fail(out, OnSolver::kPart);
    // Each piece fails as kPart, in any order: the list's order is the cells' verdict.
    if (!each_piece(S, near_of(r, b, x0, y0, x1, y1), glo, ghi, x0, y0, x1, y1,
                    [&](int32_t k) { return part(S.hazards[size_t(k)]); }))
        return false;
    const bool clear = each_in_reach(r, b, p, glo, ghi, kMargin, vmax, [&](BodyId o) {
        const BodyId u = ph.unit_of(o);
        if (ph.resting(u)) return true;
        if (ph.coasting(u)) return false;  // riding its field
        if (ph.dynamic_now(o)) return still(u) && !s.held_by[o].valid() && !s.in_hand[o];
        return ph.rb(o).getLinearVelocity().fuzzyZero() && ph.rb(o).getAngularVelocity().fuzzyZero();
    });
    if (!clear) return fail(out, OnSolver::kNeighbour);
    out.field = f;
    return true;
}

void ride(Runtime& r, BodyId b, FieldId f) {
    State& s = r.st;
    s.ride_field[b] = f;
    s.ride_step[b] = s.step;
    s.ride_at[b] = r.phys.com(b);
}

// A resting unit in field f, each step: the loss bookkeeping and the count of the time it
// stalled, as the law keeps them on the solver (fields.cpp: slower than a tenth of the running
// field it is in).
void rests_in(Runtime& r, BodyId b, BodyId p, FieldId f) {
    if (!f.valid()) return;
    State& s = r.st;
    for (const BodyId x : {b, p}) {
        if (!x.valid()) continue;
        ride(r, x, f);
        if (s.field_speed[f] != 0) {
            if (s.slow_step[x] + 1 < s.step) s.stall_since[x] = s.time;
            s.slow_step[x] = s.step;
        }
    }
}

void guide(Steady& S, BodyId b, const Verdict& v) {
    S.guide_axis[b] = v.guide_axis;
    S.guide_side[b] = v.guide_side;
    S.guide_face[b] = v.guide_face;
}

enum : uint8_t { kStay = 0, kLand, kCoast, kKeep, kToRest };

// What field f drives at, in the world: its target velocity; a turning field's angular
// velocity about its pivot's vertical, (0, 0, spin) in its frame (its target is that spin
// about the pivot where the unit is, found by the mover each step); none (no field acts): 0.
// The callers compare it within one field, so the two meanings never meet: it changes exactly
// when the law's target does (a speed, an enable, the field's turn).
btVector3 target_of(const State& s, const Tables& tab, FieldId f) {
    if (!f.valid()) return btVector3(0, 0, 0);
    const btMatrix3x3& R = s.field_frame[f].pose.getBasis();
    return tab.field_turns[f] ? R * btVector3(0, 0, s.field_spin[f]) : R * s.field_target[f];
}

// Unit b's verdict this step and what follows from it: its count of steady steps, and when it
// leaves the solver or goes on coasting, what it rides (S.field ... S.relax, State::ride_*).
// Writes only the unit's own entries; the caller lands or coasts it (kLand, kCoast).
// `why`: why the unit is on the solver after this step's check; kCount when it is not a unit
// in the world, or off the solver.
uint8_t decide(Runtime& r, BodyId b, btScalar vmax, OnSolver& why) {
    Physics& ph = r.phys;
    State& s = r.st;
    Steady& S = r.steady;
    const BodyId p = ph.passenger(b);
    why = OnSolver::kCount;
    if (!ph.in_world(b) || (!p.valid() && !ph.lone(b))) {
        S.settled[b] = 0, S.still[b] = 0;
        return kStay;
    }
    const bool was = ph.coasting(b);
    Verdict v;
    if (ph.resting(b)) {  // it stays while it may rest, in the same field with the same target
        if (rest_now(r, b, p, vmax, v) && v.field == S.field[b] && target_of(s, r.tab, v.field) == S.target[b]) {
            rests_in(r, b, p, v.field);
            return kKeep;
        }
        S.settled[b] = 0;
        why = v.why == OnSolver::kCount ? OnSolver::kChanged : v.why;
        return kLand;
    }
    bool ok = steady_now(r, b, p, vmax, v);
    uint8_t action = kKeep;
    if (was) {
        const bool same = ok && v.field == S.field[b] && v.support == S.support[b] && v.piece == S.piece[b] &&
                          target_of(s, r.tab, v.field) == S.target[b];
        if (!same) {
            S.settled[b] = 0;
            why = ok ? OnSolver::kChanged : v.why;
            return kLand;
        }
        guide(S, b, v);
    } else {
        if (!ok) {
            // Not riding its field alone: still, and held still (by a pin, the bodies before
            // it, its band), it may rest.
            Verdict still;
            S.settled[b] = 0;
            if (v.why != OnSolver::kHeld && v.why != OnSolver::kRead && rest_now(r, b, p, vmax, still)) {
                // Still for 0.1 s, and no farther than 0.5 mm from where it was then (not creeping
                // in a queue that closes up): then it rests.
                const btVector3 c = ph.com(b);
                if (S.still[b]++ == 0) S.rest_from[b] = c;
                if (double(S.still[b]) * r.dt < kStillFor) {
                    why = OnSolver::kStill;
                    return kStay;
                }
                if ((c - S.rest_from[b]).length2() > kCreep * kCreep) {
                    S.still[b] = 1, S.rest_from[b] = c;
                    why = OnSolver::kCreeping;
                    return kStay;
                }
                S.still[b] = 0;
                S.field[b] = still.field;
                S.target[b] = target_of(s, r.tab, still.field);
                S.guide_side[b] = 0;
                rests_in(r, b, p, still.field);
                return kToRest;
            }
            S.still[b] = 0;
            why = v.why;
            return kStay;
        }
        S.still[b] = 0;
        if (++S.settled[b] < kSettle) {
            why = OnSolver::kSettling;
            return kStay;
        }
        const FieldId f = v.field;  // none: no field acts, and every axis is free
        btVector3 point, normal;
        top_face(ph, v.support, v.piece, point, normal);
        S.field[b] = v.field;
        S.support[b] = v.support;
        S.piece[b] = v.piece;
        S.target[b] = target_of(s, r.tab, f);
        S.normal[b] = normal;
        S.top[b] = point;
        S.height[b] = normal.dot(ph.rb(b).getCenterOfMassPosition() - point);
        S.yaw[b] = f.valid() ? ph.rb(b).getAngularVelocity().z() : 0;  // in no field: held at rest
        guide(S, b, v);
        const double m = ph.mass(b) + (p.valid() ? ph.mass(p) : 0.0);
        const btVector3 gain = f.valid() ? r.tab.field_gain[f] : btVector3(0, 0, 0);
        for (int i = 0; i < 3; ++i)
            S.relax[b][i] = gain[i] > 0 ? btScalar(std::exp(-double(gain[i]) * (p.valid() ? 2 : 1) * r.dt / m)) : 1;
        action = kCoast;
    }
    if (v.field.valid()) {  // the conveyor's loss bookkeeping, as the law keeps it on the solver
        ride(r, b, v.field);
        if (p.valid()) ride(r, p, v.field);
    }
    return action;
}

}  // namespace

const char* on_solver_name(OnSolver w) {
    switch (w) {
    case OnSolver::kHeld: return "not simulated, or held";
    case OnSolver::kRead: return "its outputs are read";
    case OnSolver::kTurning: return "rocking or spinning";
    case OnSolver::kTilted: return "tilted";
    case OnSolver::kFieldEdge: return "at a field's face, or in two fields";
    case OnSolver::kFieldSlope: return "its field not level";
    case OnSolver::kFieldTurns: return "its field turns";
    case OnSolver::kHeldBack: return "held back: below half its field's speed (queued, at a pin)";
    case OnSolver::kSpeed: return "speeding up or slowing down";
    case OnSolver::kDrift: return "drifting across its field faster than 5 cm/s";
    case OnSolver::kMoving: return "in no field, moving faster than 5 mm/s";
    case OnSolver::kPart: return "a moving part within reach";
    case OnSolver::kSupport: return "on two supports, or one with friction";
    case OnSolver::kRailFast: return "coming up to a rail faster than 1 cm/s";
    case OnSolver::kChannel: return "between two rails";
    case OnSolver::kInTheWay: return "a static piece in the way";
    case OnSolver::kNoSupport: return "no level support";
    case OnSolver::kEdge: return "at its support's edge";
    case OnSolver::kNeighbour: return "another body within reach";
    case OnSolver::kChanged: return "its field or support changed";
    case OnSolver::kSettling: return "steady for fewer than 5 steps";
    case OnSolver::kStill: return "still for less than 0.1 s (a creeping queue is found so again every 0.1 s)";
    case OnSolver::kCreeping: return "still, but creeping (more than 0.5 mm in 0.1 s)";
    case OnSolver::kCount: break;
    }
    return "?";
}

void start_steady(Runtime& r, bool on) {
    Steady& S = r.steady;
    S.on = on;
    const size_t nb = r.g.bodies.size();
    S.settled.assign(nb, 0);
    S.still.assign(nb, 0);
    S.rest_from.assign(nb, btVector3(0, 0, 0));
    S.field.assign(nb, FieldId{});
    S.support.assign(nb, BodyId{});
    S.piece.assign(nb, -1);
    S.target.assign(nb, btVector3(0, 0, 0));
    S.normal.assign(nb, btVector3(0, 0, 1));
    S.top.assign(nb, btVector3(0, 0, 0));
    S.height.assign(nb, 0);
    S.yaw.assign(nb, 0);
    S.relax.assign(nb, btVector3(1, 1, 1));
    S.guide_axis.assign(nb, 0);
    S.guide_side.assign(nb, 0);
    S.guide_face.assign(nb, 0);
    S.joined.reserve(nb);
    S.stack.reserve(nb);
    S.events.assign(r.tab.dyn_bodies.size(), BodyId{});
    S.found.assign(r.tab.dyn_bodies.size(), BodyId{});
    S.by_world.assign(r.tab.dyn_bodies.size(), BodyId{});
    S.world_adr.assign(size_t(r.phys.worlds()) + 1, 0);
    S.world_fill.assign(size_t(r.phys.worlds()), 0);
    S.busy.reserve(size_t(r.phys.worlds()));
    S.action.assign(nb, 0);
    S.why_of.assign(nb, OnSolver::kCount);
    S.kinematic.reserve(nb);
    S.home_lo.assign(nb, btVector3(0, 0, 0));
    S.home_hi.assign(nb, btVector3(0, 0, 0));
    S.home_tr.assign(nb, btTransform::getIdentity());
    S.in_room_grid.assign(nb, 0);
    S.in_room_writes.assign(nb, 0);
    S.near.assign(on ? nb : 0, Steady::Near{});
    if (!on) return;
    build_grid(r);  // and room for kinematic parts that move to more cells later
    S.filed.reserve(2 * S.filed.size() + 64);
    S.cells.reserve(2 * S.cells.size() + 64);
    S.cell_adr.reserve(2 * S.cell_adr.size() + 64);
    S.cell_list.reserve(2 * S.cell_list.size() + 64);
    S.big.reserve(S.hazards.size());
    S.poly_xy.reserve(2 * S.poly_xy.size() + 64);
}

bool kinematic_left(Runtime& r, size_t begin, size_t end) {
    Steady& S = r.steady;
    const Physics& ph = r.phys;
    if (!S.on || !S.grid_valid) return false;
    // Whether k is in its room: its box, grown by two steps of its motion, inside it.
    auto in_room = [&S, &ph, dt = r.dt](BodyId k) {
        const btScalar m = kMargin + btScalar(2 * dt) * ph.rb(k).getLinearVelocity().length();
        // Where it was filed and slow: its box grown by m is inside the room (rounding is monotonic).
        if (m <= kRoom && ph.rb(k).getWorldTransform() == S.home_tr[k]) return true;
        btVector3 lo, hi;
        body_box(ph, k, lo, hi);
        const btVector3 g(m, m, m);
        return inside(lo - g, hi + g, S.home_lo[k], S.home_hi[k]);
    };
    for (size_t i = begin; i < end && i < S.kinematic.size(); ++i) {
        const BodyId k = S.kinematic[i];
        if (S.in_room_grid[k] == S.grid_builds && S.in_room_writes[k] == ph.writes(k)) {  // as last found
            assert(in_room(k));
            continue;
        }
        if (!in_room(k)) return true;
        S.in_room_grid[k] = S.grid_builds;
        S.in_room_writes[k] = ph.writes(k);
    }
    return false;
}

// Hints for check_steady's pass (no result changes): unit b's list of what lies near it, and
// the hazards and fields that list names, as it stood when last made (the pass over the units
// reads them in id order, a unit's from wherever it rides: scattered over tables too large to
// stay cached from one step to the next).
namespace {
void prefetch_near_list(const Steady& S, BodyId b) {
    const char* n = reinterpret_cast<const char*>(&S.near[b]);
    __builtin_prefetch(n);
    __builtin_prefetch(n + 64);
}
void prefetch_near(const Runtime& r, BodyId b) {
    const Steady& S = r.steady;
    if (const FieldId f = S.field[b]; f.valid()) {  // the field it rode: its frame, gain and target
        const char* ff = reinterpret_cast<const char*>(&r.st.field_frame[f]);
        __builtin_prefetch(ff);
        __builtin_prefetch(ff + offsetof(State::FieldFrame, half));
        __builtin_prefetch(&r.tab.field_gain[f]);
        __builtin_prefetch(&r.st.field_target[f]);
    }
    const Steady::Near& n = S.near[b];
    if (n.hazards == Steady::kFull || n.epoch != S.grid_builds + r.st.field_builds) return;  // to be made again
    for (uint8_t k = 0; k < n.fields; ++k) __builtin_prefetch(&r.st.field_xy[FieldId(n.id[k])]);
    for (uint8_t k = n.fields; k < n.fields + n.hazards; ++k) {
        const char* h = reinterpret_cast<const char*>(&S.hazards[size_t(n.id[k])]);
        __builtin_prefetch(h);
        __builtin_prefetch(h + offsetof(Steady::Hazard, fixed));
    }
}
}  // namespace

void check_steady(Runtime& r, bool left) {
    Steady& S = r.steady;
    S.found_slices = 0;
    if (!S.on) return;
    Physics& ph = r.phys;
    // A part that left its room: the static geometry filed again (a part found out of the
    // room just after filing would find the same filing again).
    if (!S.grid_valid || S.grid_statics != ph.statics_placed() || left) build_grid(r);
    r.index.refresh(ph, ph.workers());
    btScalar vmax = r.index.vmax();
    if (!std::isfinite(vmax)) vmax = btScalar(1e6);
    // Each unit's verdict and what follows from it, in slices of the units on the physics
    // threads (each writes its units' own entries and reads what no verdict changes); then
    // leaving and rejoining the solver, which touch the worlds, world by world (below).
    const std::vector<BodyId>& dyn = r.tab.dyn_bodies;
    const size_t slices = slice_count(dyn.size(), 64, kMaxSlices);
    // Each slice lists, from its own first index on, its units that land or leave (`events`)
    // and those off the solver after this step (`found`), both in id order.
    auto deciding = [&r, &dyn, vmax, slices](int i) {
        Steady& St = r.steady;
        const auto [b, e] = slice_of(dyn.size(), slices, i);
        size_t events = 0, found = 0;
        int64_t guided = 0, rested = 0;
        std::array<int64_t, kOnSolverReasons>& whys = St.slice_why[size_t(i)];
        // Asked for ahead (hints; no result changes): a unit's Bullet state and its list of what
        // lies near it eight units on, and what that list names four units on.
        constexpr size_t kAhead = 4;
        for (size_t k = b; k < e; ++k) {
            if (k + 2 * kAhead < e && r.phys.in_world(dyn[k + 2 * kAhead])) {
                r.phys.prefetch(dyn[k + 2 * kAhead]);
                prefetch_near_list(St, dyn[k + 2 * kAhead]);
            }
            if (k + kAhead < e && r.phys.in_world(dyn[k + kAhead])) prefetch_near(r, dyn[k + kAhead]);
            const BodyId u = dyn[k];
            OnSolver why;
            const uint8_t a = St.action[u] = decide(r, u, vmax, why);
            St.why_of[u] = why;
            if (why != OnSolver::kCount) ++whys[size_t(why)];
            if (a == kLand || a == kCoast || a == kToRest) St.events[b + events++] = u;
            if (a == kCoast || a == kKeep || a == kToRest) {
                St.found[b + found++] = u;
                guided += St.guide_side[u] != 0;
                rested += a == kToRest || (a == kKeep && r.phys.resting(u));
            }
        }
        St.slice_events[i] = events, St.slice_found[i] = found, St.slice_guided[i] = guided;
        St.slice_rested[i] = rested;
    };
    run_slices(ph.workers(), slices, deciding);
    // Units at rest hold one another still (a queue: each bottle pressed against the one before,
    // the first against a pin): when one lands, those resting within 2 cm of it land with it, and
    // theirs, in the same step, and those about to rest stay on the solver. So a queue moves
    // off at once as on the solver, and a bottle that comes up to a queue strikes bottles the
    // solver moves, not a wall. On this thread, from the landing ones in id order.
    S.joined.clear();
    for (size_t i = 0; i < slices; ++i) {
        const size_t b = slice_of(dyn.size(), slices, i).first;
        for (size_t k = b; k < b + S.slice_events[i]; ++k)
            if (S.action[S.events[k]] == kLand && ph.resting(S.events[k])) S.stack.push_back(S.events[k]);
    }
    while (!S.stack.empty()) {
        const BodyId u = S.stack.back();
        S.stack.pop_back();
        const btVector3 lo = r.index.lo(u), hi = r.index.hi(u);
        const btScalar g = 2 * kMargin;
        r.index.for_each(lo.x() - g, hi.x() + g, lo.y() - g, hi.y() + g, [&](BodyId o) {
            const BodyId w = ph.unit_of(o);
            if (w == u || !ph.in_world(w)) return;
            const btVector3 wlo = r.index.lo(o) - btVector3(g, g, g), whi = r.index.hi(o) + btVector3(g, g, g);
            if (!overlap(lo, hi, wlo, whi)) return;
            if (S.action[w] == kKeep && ph.resting(w)) {
                S.action[w] = kLand;
                S.joined.push_back(w);
            } else if (S.action[w] == kToRest) {
                S.action[w] = kStay;
                S.still[w] = 0;
                S.joined.push_back(w);
            } else {
                return;
            }
            S.stack.push_back(w);
            S.why_of[w] = OnSolver::kNeighbour;
            ++S.neighbours;
        });
    }
    // Landing and leaving touch only the unit's own world (its broadphase and dispatcher): the
    // units are grouped by world, in id order within each (those landing with a neighbour
    // after them, in the order found), and each world's are handled as an item on the physics
    // threads.
    std::fill(S.world_adr.begin(), S.world_adr.end(), 0);
    for (size_t i = 0; i < slices; ++i) {
        const size_t b = slice_of(dyn.size(), slices, i).first;
        for (size_t k = b; k < b + S.slice_events[i]; ++k)
            if (S.action[S.events[k]] != kStay) ++S.world_adr[ph.world_of(S.events[k]) + 1];
        if (S.joined.empty()) {  // as found (most steps)
            S.rested += S.slice_rested[i];
        } else {  // less those landing or staying with a neighbour, in place
            size_t kept = 0;
            for (size_t k = b; k < b + S.slice_found[i]; ++k) {
                const BodyId u = S.found[k];
                const uint8_t a = S.action[u];
                if (a != kKeep && a != kCoast && a != kToRest) continue;
                S.found[b + kept++] = u;
                S.rested += a == kToRest || (a == kKeep && ph.resting(u));
            }
            S.slice_found[i] = kept;
        }
        S.guided += S.slice_guided[i];
    }
    S.found_slices = slices;
    for (const BodyId u : S.joined)
        if (S.action[u] == kLand) ++S.world_adr[ph.world_of(u) + 1];
    S.coasted += int64_t(S.coasting_count());
    S.busy.clear();
    for (size_t w = 0; w + 1 < S.world_adr.size(); ++w) {
        if (S.world_adr[w + 1] > 0) S.busy.push_back(int(w));
        S.world_adr[w + 1] += S.world_adr[w];
    }
    if (S.busy.empty()) return;
    std::copy(S.world_adr.begin(), S.world_adr.end() - 1, S.world_fill.begin());
    for (size_t i = 0; i < slices; ++i) {
        const size_t b = slice_of(dyn.size(), slices, i).first;
        for (size_t k = b; k < b + S.slice_events[i]; ++k) {
            const BodyId u = S.events[k];
            if (S.action[u] == kStay) continue;  // was to rest, stays on the solver with a neighbour
            S.by_world[size_t(S.world_fill[ph.world_of(u)]++)] = u;
            if (S.action[u] == kLand) ++S.rejoined;
            else ++S.left;
        }
    }
    for (const BodyId u : S.joined) {
        if (S.action[u] != kLand) continue;
        S.by_world[size_t(S.world_fill[ph.world_of(u)]++)] = u;
        ++S.rejoined;
    }
    auto applying = [&r](int i) {
        Steady& St = r.steady;
        const int w = St.busy[size_t(i)];
        for (int32_t k = St.world_adr[w]; k < St.world_adr[w + 1]; ++k) {
            const BodyId u = St.by_world[size_t(k)];
            if (St.action[u] == kLand) r.phys.land(u);
            else if (St.action[u] == kToRest) r.phys.rest(u);
            else r.phys.coast(u);
        }
    };
    run_slices(ph.workers(), S.busy.size(), applying, "engine::check_steady: landing and leaving, by world");
}

namespace {

// Coasting unit b moves by the law's exact solution over the step (writes only b and its passenger).
void advance(Runtime& r, BodyId b) {
    Steady& S = r.steady;
    Physics& ph = r.phys;
    const btScalar dt = btScalar(r.dt);
    if (ph.resting(b)) return;  // held still, static to Bullet: nothing to write
    const FieldId f = S.field[b];
    const btRigidBody& rb = ph.rb(b);
    if (!f.valid()) {  // no field acts: at rest, where it was when it left
        ph.coast_to(b, rb.getWorldTransform(), btVector3(0, 0, 0), btVector3(0, 0, 0));
        return;
    }
    btVector3 v = rb.getLinearVelocity();
    {
        const btMatrix3x3& R = r.st.field_frame[f].pose.getBasis();
        btVector3 vl = v * R;
        // A turning field's target as the law takes it (turning_target: half a step on).
        const btVector3 target =
            r.tab.field_turns[f]
                ? turning_target(r.st.field_spin[f], r.tab.field_pivot[f],
                                 (rb.getCenterOfMassPosition() - r.st.field_frame[f].pose.getOrigin()) * R, vl,
                                 btScalar(r.dt / 2))
                : r.st.field_target[f];
        for (int k = 0; k < 3; ++k)
            if (S.relax[b][k] < 1) vl[k] = target[k] + (vl[k] - target[k]) * S.relax[b][k];
        v = R * vl;
    }
    const btVector3& n = S.normal[b];
    v.setZ(-(n.x() * v.x() + n.y() * v.y()) / n.z());  // along the band's top face
    btTransform t = rb.getWorldTransform();
    btVector3 c = t.getOrigin() + v * dt;
    c.setZ(c.z() + (S.height[b] - n.dot(c - S.top[b])) / n.z());
    t.setOrigin(c);
    // It turns about the vertical as it turned when it left (no torque about it), no other way.
    const btScalar yaw = S.yaw[b];
    if (yaw != 0) t.setBasis(btMatrix3x3(btQuaternion(btVector3(0, 0, 1), yaw * dt)) * t.getBasis());
    // A rail it slides along stops what would take its shape into it: an inelastic,
    // frictionless contact (its velocity towards the rail ends; along the rail it is free).
    if (const int side = S.guide_side[b]; side != 0) {
        const int a = S.guide_axis[b];
        const auto& shape = *static_cast<const btConvexShape*>(rb.getCollisionShape());
        const btScalar into = btScalar(side) * (reach_along(shape, t, a, side) - S.guide_face[b]);
        if (into > 0) {
            c[a] -= btScalar(side) * into;
            t.setOrigin(c);
            if (btScalar(side) * v[a] > 0) v[a] = 0;
        }
    }
    ph.coast_to(b, t, v, btVector3(0, 0, yaw));
}

}  // namespace

void advance_steady(Runtime& r) {
    // Each unit on its own, on the physics threads, in the check's slices (Steady::found).
    const Steady& S = r.steady;
    auto moving = [&r, &S](int i) {
        // The units lie scattered in memory: each one's Bullet body, and its passenger's, which
        // the move writes, are asked for a few units ahead (a hint: no result changes).
        constexpr size_t kAhead = 4;
        const std::span<const BodyId> us = S.coasting_in(size_t(i));
        for (size_t k = 0; k < us.size(); ++k) {
            if (k + kAhead < us.size()) {
                r.phys.prefetch(us[k + kAhead]);
                if (const BodyId p = r.phys.passenger(us[k + kAhead]); p.valid()) r.phys.prefetch(p);
            }
            advance(r, us[k]);
        }
    };
    if (S.found_slices > 0) run_slices(r.phys.workers(), S.found_slices, moving);
}

}  // namespace plant::engine
