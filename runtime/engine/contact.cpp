// Box against convex hull: Bullet's polyhedral contacts with a cheaper separating-axis test.
//
// Why: with m_enableSatConvex (physics.cpp), Bullet's convex-convex algorithm runs
// btPolyhedralContactClipping::findSeparatingAxis for every bottle near a band or a rail,
// every step. It tests each face normal of both polyhedra (6 + 10 for box and bottle, opposite
// faces twice) and each pair of unique edges (3 x 5), and for every axis moves all 24 vertices
// to world space to project them, behind a bound on inner boxes (TestInternalObjects). On the
// 4-line plant (70 s, a bottle a second) that was 27 % of the run (perf:
// btConvexPolyhedron::project 10.4 %, findSeparatingAxis 7.2 %, TestInternalObjects 7.0 %,
// InverseTransformPoint3x3 2.0 %); with this file the whole test is 10.7 % and the run takes
// 3.1-3.3 s instead of 3.8-4.1 s (one pair: 1.3 instead of 2.5 us, clipping included).
//
// What: the same candidate axes in Bullet's order with Bullet's rule (least overlap wins, the
// first of equals; any separating axis ends the test), over unique axes: the box's 3 face
// normals, the hull's face normals with opposite faces merged (5 for the bottle), Bullet's
// edge pairs. The box projects analytically (centre and half extents, read from its
// polyhedron's vertices); the hull projects its vertices in its own frame (the axis is
// rotated once); along their own face normals both use extents computed once per
// polyhedron. The winning axis is the vector Bullet computes for it, Bullet's edge-edge
// contact point is added as Bullet adds it, and the contacts come from Bullet's own clipping
// (clipHullAgainstHull) with btConvexConvexAlgorithm's arguments and manifold handling.
//
// Same contacts as Bullet, bit for bit, except where two axes overlap equally to within
// Bullet's rounding. Bullet projects world coordinates in float (1e-6 m resolution 10 m from
// the origin) and mostly sees such axes tie, so its first one wins; here the overlaps are
// computed near each shape's origin and the smaller one wins. The clipped points are then the
// same and the normal differs by the angle between the two axes (a bottle's tilt against a
// rail: up to 0.025 rad seen); where the least overlap is within that resolution of 0, one may
// find the pair apart and the other touching. The unit tests compare with Bullet over random
// poses (contact_test.cpp); on the 4-line plant 97.5 % of the tests give identical contacts.
#include "engine/contact.h"

#include <BulletCollision/BroadphaseCollision/btBroadphaseProxy.h>
#include <BulletCollision/CollisionDispatch/btActivatingCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionConfiguration.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btCompoundCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btConvexConvexAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>
#include <BulletCollision/CollisionShapes/btPolyhedralConvexShape.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btPolyhedralContactClipping.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>

#include <cfloat>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <new>
#include <typeinfo>
#include <unordered_map>
#include <utility>
#include <vector>

namespace plant::engine {

namespace {

using Result = btDiscreteCollisionDetectorInterface::Result;

// ---- Per polyhedron, computed once (shapes are shared: one hull per bottle kind).

struct Interval {
    btScalar lo, hi;
};

// A direction of face normals in the polyhedron's frame. Opposite faces give the same
// overlap (min(maxA - minB, maxB - minA) does not depend on the axis' sign): one test.
struct FaceAxis {
    btVector3 normal;  // of the first face in Bullet's order with it, as read from the plane
    Interval extent;   // of the polyhedron along it
};

struct Polytope {
    const btConvexPolyhedron* poly = nullptr;
    bool solid = false;  // else the pair goes to GJK (see solid_polyhedron)
    std::vector<FaceAxis> axes;
    btVector3 mid, half;  // the vertices' bounding box: for a box shape, the box itself
    // The vertices' coordinates, each in an array of its own, padded with the first vertex to
    // a multiple of 4: a hull's extent is then found 4 vertices at a time (hull_extent).
    std::vector<btScalar> x, y, z;
};

// Two face normals at an angle under 1e-6 rad are one axis: their overlaps differ by less
// than 1e-6 of the shapes' size.
constexpr btScalar kSameAxis2 = btScalar(1e-12);

// The polyhedron's vertices along `dir`, given in its frame.
Interval vertex_extent(const btConvexPolyhedron& p, const btVector3& dir) {
    Interval e{FLT_MAX, -FLT_MAX};
    for (int i = 0; i < p.m_vertices.size(); ++i) {
        const btScalar d = p.m_vertices[i].dot(dir);
        e.lo = btMin(e.lo, d);
        e.hi = btMax(e.hi, d);
    }
    return e;
}

Polytope describe(const btConvexPolyhedron& p) {
    Polytope out;
    out.poly = &p;
    out.solid = solid_polyhedron(p);
    if (!out.solid) return out;
    btVector3 lo(FLT_MAX, FLT_MAX, FLT_MAX), hi = -lo;
    for (int i = 0; i < p.m_vertices.size(); ++i) {
        lo.setMin(p.m_vertices[i]);
        hi.setMax(p.m_vertices[i]);
    }
    out.mid = (lo + hi) * btScalar(0.5);
    out.half = (hi - lo) * btScalar(0.5);
    const int n = p.m_vertices.size(), padded = (n + 3) / 4 * 4;
    for (int i = 0; i < padded; ++i) {
        const btVector3& v = p.m_vertices[i < n ? i : 0];  // a repeated vertex changes no extent
        out.x.push_back(v.x()), out.y.push_back(v.y()), out.z.push_back(v.z());
    }
    for (int f = 0; f < p.m_faces.size(); ++f) {
        const btScalar* plane = p.m_faces[f].m_plane;
        const btVector3 n(plane[0], plane[1], plane[2]);
        bool known = false;
        for (const FaceAxis& a : out.axes) known = known || a.normal.cross(n).length2() < kSameAxis2;
        if (!known) out.axes.push_back({n, vertex_extent(p, n)});
    }
    return out;
}

// ---- The separating-axis test for one pair in one step.

// One shape of the pair, A or B in Bullet's sense (the dispatcher's order).
struct Side {
    const Polytope& shape;
    const btTransform& tr;
    bool box;
};

// A solid polytope's vertices along `dir`, given in its frame: vertex_extent's interval, the
// same floats (each vertex's product is formed as btVector3::dot forms it, x·dx + y·dy, then
// + z·dz; the least and the greatest of a set do not depend on the order they are looked at
// in), 4 vertices at a time. Where the packed instructions are missing, vertex_extent itself.
[[gnu::always_inline]] inline Interval hull_extent(const Polytope& p, const btVector3& dir) {
#if defined(__SSE2__) && !defined(BT_USE_DOUBLE_PRECISION)
    const __m128 dx = _mm_set1_ps(dir.x()), dy = _mm_set1_ps(dir.y()), dz = _mm_set1_ps(dir.z());
    __m128 lo = _mm_set1_ps(FLT_MAX), hi = _mm_set1_ps(-FLT_MAX);
    for (size_t i = 0; i < p.x.size(); i += 4) {
        const __m128 xy = _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(&p.x[i]), dx), _mm_mul_ps(_mm_loadu_ps(&p.y[i]), dy));
        const __m128 d = _mm_add_ps(xy, _mm_mul_ps(_mm_loadu_ps(&p.z[i]), dz));
        lo = _mm_min_ps(lo, d);
        hi = _mm_max_ps(hi, d);
    }
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, lo);
    _mm_store_ps(h, hi);
    return {btMin(btMin(l[0], l[1]), btMin(l[2], l[3])), btMax(btMax(h[0], h[1]), btMax(h[2], h[3]))};
#else
    return vertex_extent(*p.poly, dir);
#endif
}

// The box's extent along `dir`, given in its frame: centre ± the projected half extents.
Interval box_extent(const Polytope& box, const btVector3& dir) {
    const btScalar c = box.mid.dot(dir);
    const btScalar r = btFabs(dir.x()) * box.half.x() + btFabs(dir.y()) * box.half.y() + btFabs(dir.z()) * box.half.z();
    return {c - r, c + r};
}

// Overlap of the pair along world axes; negative when the axis separates them. Extents are
// taken relative to each shape's origin, and the hull's shifted by the origins' offset.
class Overlaps {
public:
    Overlaps(const Side& box, const Side& hull)
        : box_(box), hull_(hull), shift_(hull.tr.getOrigin() - box.tr.getOrigin()) {}

    // Along `axis`, a face axis of `owner` in world space: its own extent is known.
    btScalar face(const Side& owner, const FaceAxis& f, const btVector3& axis) const {
        if (owner.box) return overlap(f.extent, hull_along(axis), shift_.dot(axis));
        return overlap(box_along(axis), f.extent, shift_.dot(axis));
    }
    btScalar along(const btVector3& axis) const {
        return overlap(box_along(axis), hull_along(axis), shift_.dot(axis));
    }

private:
    // `v * basis` is the transpose's product: the world axis in the shape's frame.
    Interval box_along(const btVector3& axis) const { return box_extent(box_.shape, axis * box_.tr.getBasis()); }
    Interval hull_along(const btVector3& axis) const {
        return hull_extent(hull_.shape, axis * hull_.tr.getBasis());
    }
    static btScalar overlap(Interval box, Interval hull, btScalar shift) {
        return btMin(box.hi - (hull.lo + shift), (hull.hi + shift) - box.lo);
    }

    const Side& box_;
    const Side& hull_;
    btVector3 shift_;
};

// The axis of least overlap so far: in world space as Bullet computes it (not yet oriented),
// and for an edge pair which one (Bullet's extra contact needs the edges).
struct Best {
    btVector3 axis{0, 0, 0};
    btScalar overlap = FLT_MAX;  // Bullet's start
    bool edges = false;
    int edge_a = 0, edge_b = 0;

    // Bullet's rule: the least overlap wins, the first of equal ones. A candidate parallel to
    // the best one (an edge pair whose cross product is a face normal, as for a bottle standing
    // upright on a band; two parallel faces) is the same axis: in exact arithmetic it ties and
    // loses, and only rounding could make it win. It does not win here; in Bullet its inner-box
    // bound (TestInternalObjects) skips it. An edge pair winning that way would add Bullet's
    // edge contact where the two edges' lines cross, centimetres away from either shape.
    void consider(const btVector3& candidate, btScalar depth, bool is_edges, int a = 0, int b = 0) {
        if (!(depth < overlap)) return;
        if (overlap < FLT_MAX && axis.cross(candidate).length2() < kSameAxis2) return;
        *this = {candidate, depth, is_edges, a, b};
    }
};

btVector3 world_edge(const Side& s, int i) { return s.tr.getBasis() * s.shape.poly->m_uniqueEdges[i]; }

// Bullet's edge-edge axis: the edges' cross product in world space, normalised; none when
// every component is within 1e-6 (Bullet's IsAlmostZero: the edges are parallel).
bool edge_axis(const btVector3& edge_a, const btVector3& edge_b, btVector3& axis) {
    axis = edge_a.cross(edge_b);
    if (btFabs(axis.x()) <= 1e-6 && btFabs(axis.y()) <= 1e-6 && btFabs(axis.z()) <= 1e-6) return false;
    axis.normalize();
    return true;
}

// Bullet's candidates in Bullet's order: A's face axes, B's, then each of A's unique edges
// against each of B's. False as soon as one separates. Bullet also skips axes whose inner-box
// bound shows they cannot win; apart from ties (see Best) that does not change the choice.
bool least_overlap(const Side& a, const Side& b, const Overlaps& overlaps, Best& best) {
    for (const Side* s : {&a, &b})
        for (const FaceAxis& f : s->shape.axes) {
            const btVector3 axis = s->tr.getBasis() * f.normal;  // as Bullet turns it to world
            const btScalar depth = overlaps.face(*s, f, axis);
            if (depth < 0) return false;
            best.consider(axis, depth, false);
        }
    for (int i = 0; i < a.shape.poly->m_uniqueEdges.size(); ++i) {
        const btVector3 edge_a = world_edge(a, i);
        for (int j = 0; j < b.shape.poly->m_uniqueEdges.size(); ++j) {
            btVector3 axis;
            if (!edge_axis(edge_a, world_edge(b, j), axis)) continue;
            const btScalar depth = overlaps.along(axis);
            if (depth < 0) return false;
            best.consider(axis, depth, true, i, j);
        }
    }
    return true;
}

// Bullet's extra contact point when an edge pair wins: the closest points of the two edges'
// lines, each through the vertex where its shape overlaps the other along the axis; none when
// the lines are within sqrt(SIMD_EPSILON) (0.35 mm, Bullet's test). The vertices come from
// Bullet's own projection (once per test, so its cost does not matter): it settles ties
// between the vertices of an edge as Bullet does, and the result is ill-conditioned enough
// (the lines' offset cancels) that another vertex of the same line moves the normal by 1e-4.
// Bullet clamps the lines' parameters to ±1e30; they never get there (at most the offset
// over 6e-8, the least nonzero 1 - cos² of unit directions).
void add_edge_contact(const Side& a, const Side& b, const btVector3& axis, const btVector3& dir_a,
                      const btVector3& dir_b, const btVector3& b_to_a, Result& out) {
    btScalar min_a, max_a, min_b, max_b;
    btVector3 lo_a, hi_a, lo_b, hi_b;
    a.shape.poly->project(a.tr, axis, min_a, max_a, lo_a, hi_a);
    b.shape.poly->project(b.tr, axis, min_b, max_b, lo_b, hi_b);
    const bool a_below = max_a - min_b < max_b - min_a;
    const btVector3& pa = a_below ? hi_a : lo_a;
    const btVector3& pb = a_below ? lo_b : hi_b;
    const btVector3 offset = pb - pa;
    const btScalar c = dir_a.dot(dir_b), oa = dir_a.dot(offset), ob = dir_b.dot(offset);
    const btScalar denom = 1 - c * c;
    const btScalar s = denom == 0 ? 0 : (oa - ob * c) / denom;  // along A's line
    const btScalar t = s * c - ob;                               // along B's line
    btVector3 gap = offset - dir_a * s + dir_b * t;
    const btScalar len2 = gap.length2();
    if (!(len2 > SIMD_EPSILON)) return;
    const btScalar len = btSqrt(len2);
    gap *= 1 / len;
    if (gap.dot(b_to_a) < 0) gap = -gap;
    out.addContactPoint(gap, pb + dir_b * t, -len);
}

// btPolyhedralContactClipping::findSeparatingAxis: false when an axis separates the pair;
// else the axis of least overlap, pointing from B to A, and for an edge pair Bullet's contact.
bool separating_axis(const Side& a, const Side& b, btVector3& normal, Result& out) {
    const Overlaps overlaps(a.box ? a : b, a.box ? b : a);
    Best best;
    if (!least_overlap(a, b, overlaps, best)) return false;
    // Bullet orients every candidate from B's centre towards A's.
    const btVector3 b_to_a = a.tr * a.shape.poly->m_localCenter - b.tr * b.shape.poly->m_localCenter;
    normal = b_to_a.dot(best.axis) < 0 ? -best.axis : best.axis;
    if (best.edges)
        add_edge_contact(a, b, normal, world_edge(a, best.edge_a), world_edge(b, best.edge_b), b_to_a, out);
    return true;
}

// ---- The algorithm: btConvexConvexAlgorithm's polyhedral branch with the test above.

class BoxHullAlgorithm : public btActivatingCollisionAlgorithm {
public:
    BoxHullAlgorithm(const btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* w0,
                     const btCollisionObjectWrapper* w1, const Polytope& a, const Polytope& b, bool box_first)
        : btActivatingCollisionAlgorithm(ci, w0, w1), manifold_(ci.m_manifold), a_(&a), b_(&b), box_first_(box_first) {}
    ~BoxHullAlgorithm() override {
        if (own_ && manifold_) m_dispatcher->releaseManifold(manifold_);
    }

    void processCollision(const btCollisionObjectWrapper* w0, const btCollisionObjectWrapper* w1,
                          const btDispatcherInfo&, btManifoldResult* out) override {
        if (!manifold_) {  // unless the creator was handed one to share (ci.m_manifold)
            manifold_ = m_dispatcher->getNewManifold(w0->getCollisionObject(), w1->getCollisionObject());
            own_ = true;
        }
        out->setPersistentManifold(manifold_);
        if (!a_->solid || !b_->solid) {
            closest_points(w0, w1, *out);
            if (own_) out->refreshContactPoints();
            return;
        }
        const Side a{*a_, w0->getWorldTransform(), box_first_}, b{*b_, w1->getWorldTransform(), !box_first_};
        btVector3 normal;
        if (separating_axis(a, b, normal, *out)) {
            // Bullet's bounds: any depth, and points up to the contact threshold apart.
            const btScalar threshold = manifold_->getContactBreakingThreshold() + out->m_closestPointDistanceThreshold;
            btPolyhedralContactClipping::clipHullAgainstHull(normal, *a_->poly, *b_->poly, a.tr, b.tr,
                                                             btScalar(-1e30) - threshold, threshold, verts1_,
                                                             verts2_, *out);
        }
        if (own_) out->refreshContactPoints();
    }

    // Only called for continuous collision detection, which the world does not use.
    btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                   btManifoldResult*) override {
        return 1;
    }

    void getAllContactManifolds(btManifoldArray& manifolds) override {
        if (manifold_ && own_) manifolds.push_back(manifold_);
    }
    const btPersistentManifold* manifold() const { return own_ ? manifold_ : nullptr; }

private:
    // What Bullet does for convex shapes without polyhedral features: GJK and EPA on the
    // shapes' support functions, which need no faces.
    void closest_points(const btCollisionObjectWrapper* w0, const btCollisionObjectWrapper* w1, btManifoldResult& out) {
        const auto* s0 = static_cast<const btConvexShape*>(w0->getCollisionShape());
        const auto* s1 = static_cast<const btConvexShape*>(w1->getCollisionShape());
        btVoronoiSimplexSolver simplex;
        btGjkEpaPenetrationDepthSolver epa;
        btGjkPairDetector gjk(s0, s1, &simplex, &epa);
        btGjkPairDetector::ClosestPointInput input;
        const btScalar reach = s0->getMargin() + s1->getMargin() + manifold_->getContactBreakingThreshold() +
                               out.m_closestPointDistanceThreshold;
        input.m_maximumDistanceSquared = reach * reach;
        input.m_transformA = w0->getWorldTransform();
        input.m_transformB = w1->getWorldTransform();
        gjk.getClosestPoints(input, out, nullptr);
    }

    btVertexArray verts1_, verts2_;  // clipping scratch, kept so that a step allocates nothing
    btPersistentManifold* manifold_;
    const Polytope* a_;
    const Polytope* b_;
    bool own_ = false;
    bool box_first_;
};

// The dispatcher's pool hands out blocks the size of its largest built-in algorithm and does
// not check the size asked for (a btAssert only).
static_assert(sizeof(BoxHullAlgorithm) <= sizeof(btConvexConvexAlgorithm));

// Node-based: the algorithms keep pointers to its values.
class Polytopes {
public:
    const Polytope* of(const btConvexPolyhedron& p) {
        auto it = map_.find(&p);
        if (it == map_.end()) {
            if (frozen_) return nullptr;
            it = map_.emplace(&p, describe(p)).first;
        }
        return &it->second;
    }
    void freeze() { frozen_ = true; }

private:
    std::unordered_map<const btConvexPolyhedron*, Polytope> map_;
    bool frozen_ = false;
};

// The shape's polyhedron if it is a box or a hull with polyhedral features.
const btConvexPolyhedron* polyhedron(const btCollisionShape& s) {
    const int type = s.getShapeType();
    if (type != BOX_SHAPE_PROXYTYPE && type != CONVEX_HULL_SHAPE_PROXYTYPE) return nullptr;
    return static_cast<const btPolyhedralConvexShape&>(s).getConvexPolyhedron();
}

class Creator : public btCollisionAlgorithmCreateFunc {
public:
    Creator(Polytopes& polytopes, btCollisionAlgorithmCreateFunc* bullet) : polytopes_(polytopes), bullet_(bullet) {}

    btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& ci,
                                                   const btCollisionObjectWrapper* w0,
                                                   const btCollisionObjectWrapper* w1) override {
        const btConvexPolyhedron* p0 = polyhedron(*w0->getCollisionShape());
        const btConvexPolyhedron* p1 = polyhedron(*w1->getCollisionShape());
        const Polytope* a = p0 && p1 ? polytopes_.of(*p0) : nullptr;
        const Polytope* b = a ? polytopes_.of(*p1) : nullptr;
        if (!b) return bullet_->CreateCollisionAlgorithm(ci, w0, w1);  // no polyhedral features (known)
        const bool box_first = w0->getCollisionShape()->getShapeType() == BOX_SHAPE_PROXYTYPE;
        void* mem = ci.m_dispatcher1->allocateCollisionAlgorithm(sizeof(BoxHullAlgorithm));
        return new (mem) BoxHullAlgorithm(ci, w0, w1, *a, *b, box_first);
    }

private:
    Polytopes& polytopes_;
    btCollisionAlgorithmCreateFunc* bullet_;
};

// The list of a compound algorithm's children's algorithms (protected in Bullet's class; read
// through a pointer to the member, formed in a class derived from it).
struct CompoundKids : btCompoundCollisionAlgorithm {
    static const btAlignedObjectArray<btCollisionAlgorithm*>& of(const btCompoundCollisionAlgorithm& a) {
        return a.*(&CompoundKids::m_childCollisionAlgorithms);
    }
};

void ask(const void* p) { __builtin_prefetch(p); }

}  // namespace

void contact_ahead(const btCollisionAlgorithm* a, int stage) {
    if (!a || typeid(*a) != typeid(btCompoundCollisionAlgorithm)) return;
    const auto& kids = CompoundKids::of(static_cast<const btCompoundCollisionAlgorithm&>(*a));
    const int n = kids.size();
    if (n == 0) return;
    if (stage == 2) {
        for (int i = 0; i < n; i += 8) ask(&kids[i]);  // 8 pointers to a line
        return;
    }
    for (int i = 0; i < n; ++i) {
        const btCollisionAlgorithm* k = kids[i];
        if (!k) continue;
        if (stage == 1) {  // its class (the first line) and, in ours, the manifold's pointer
            ask(k);
            ask(reinterpret_cast<const char*>(k) + 64);
        } else if (typeid(*k) == typeid(BoxHullAlgorithm)) {
            if (const btPersistentManifold* m = static_cast<const BoxHullAlgorithm*>(k)->manifold()) {
                ask(&m->m_companionIdA);  // beside its count of points (private), which is read first
                ask(&m->getContactPoint(0));
            }
        }
    }
}

bool solid_polyhedron(const btConvexPolyhedron& p) {
    const int vertices = p.m_vertices.size();
    if (vertices < 4 || p.m_faces.size() < 4 || p.m_uniqueEdges.size() < 1) return false;
    for (int f = 0; f < p.m_faces.size(); ++f) {
        const auto& indices = p.m_faces[f].m_indices;
        if (indices.size() < 3) return false;
        for (int i = 0; i < indices.size(); ++i)
            if (indices[i] < 0 || indices[i] >= vertices) return false;
    }
    return true;
}

struct BoxHullContacts::State {
    Polytopes polytopes;
    std::vector<std::unique_ptr<Creator>> creators;
};

BoxHullContacts::BoxHullContacts() : state_(std::make_unique<State>()) {}

void BoxHullContacts::attach(btCollisionDispatcher& dispatcher, btCollisionConfiguration& config) {
    constexpr int kBox = BOX_SHAPE_PROXYTYPE, kHull = CONVEX_HULL_SHAPE_PROXYTYPE;
    for (auto [t0, t1] : {std::pair{kBox, kHull}, std::pair{kHull, kBox}}) {
        auto& contacts = state_->creators.emplace_back(
            std::make_unique<Creator>(state_->polytopes, config.getCollisionAlgorithmCreateFunc(t0, t1)));
        dispatcher.registerCollisionCreateFunc(t0, t1, contacts.get());
        auto& closest = state_->creators.emplace_back(
            std::make_unique<Creator>(state_->polytopes, config.getClosestPointsAlgorithmCreateFunc(t0, t1)));
        dispatcher.registerClosestPointsCreateFunc(t0, t1, closest.get());
    }
}

BoxHullContacts::~BoxHullContacts() = default;

void BoxHullContacts::freeze() { state_->polytopes.freeze(); }

void BoxHullContacts::prepare(const btCollisionShape& shape) {
    if (shape.isCompound()) {
        const auto& compound = static_cast<const btCompoundShape&>(shape);
        for (int i = 0; i < compound.getNumChildShapes(); ++i) prepare(*compound.getChildShape(i));
    } else if (const btConvexPolyhedron* p = polyhedron(shape)) {
        state_->polytopes.of(*p);
    }
}

}  // namespace plant::engine
