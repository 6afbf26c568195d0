// Our collision algorithm for a box against a convex hull (a bottle on a belt's band): Bullet's
// polyhedral contacts with a faster separating-axis test (contact.cpp says why and how).
#pragma once

#include <memory>

class btCollisionAlgorithm;
class btCollisionConfiguration;
class btCollisionDispatcher;
class btCollisionShape;
class btConvexPolyhedron;

namespace plant::engine {

// Whether a shape's polyhedral features describe a solid (4 or more vertices and faces, every
// face a polygon over known vertices). Bullet's polyhedral contacts index a face that a
// degenerate hull (its points on a line or in a plane) does not have: such a hull must be
// left without polyhedral features, and the algorithm below does not use them.
bool solid_polyhedron(const btConvexPolyhedron& p);

// Owns what the dispatchers call and what the algorithms share (per-polyhedron data), so it
// must outlive every algorithm a dispatcher it is attached to creates: create it before the
// dispatchers, destroy it after them. The algorithm is Bullet's polyhedral path, which Bullet
// takes only with m_enableSatConvex: attach it only to such worlds.
class BoxHullContacts {
public:
    BoxHullContacts();
    ~BoxHullContacts();
    BoxHullContacts(const BoxHullContacts&) = delete;
    BoxHullContacts& operator=(const BoxHullContacts&) = delete;

    // Registers the algorithm on `dispatcher` for box-hull and hull-box pairs, for contacts and
    // for closest-point queries; `config` supplies Bullet's algorithm for shapes without
    // polyhedral features. Several dispatchers share one set of per-polyhedron data.
    void attach(btCollisionDispatcher& dispatcher, btCollisionConfiguration& config);
    // Computes what the algorithm keeps per polyhedron for a shape (a compound's children)
    // now, instead of at the shape's first contact inside a step (which would allocate).
    void prepare(const btCollisionShape& shape);
    // After this, the per-polyhedron data is only read, so worlds may step on several threads
    // at once: a polyhedron that was not prepared gets Bullet's own algorithm.
    void freeze();

private:
    struct State;
    std::unique_ptr<State> state_;
};

// Asks the memory for what a pair's algorithm reads first when its pair is processed, in
// stages, so that each stage finds in the cache what the one before asked for (the world's
// near callback calls it for the pairs 2, 1 and 0 ahead of the one it processes, after
// asking for the algorithm itself 3 ahead). For Bullet's compound algorithm (a bottle against
// a belt's band and rails): 2, the list of its children's algorithms; 1, those algorithms;
// 0, the contact manifolds of those that are ours. Reads nothing else, and changes nothing.
void contact_ahead(const btCollisionAlgorithm* a, int stage);

}  // namespace plant::engine
