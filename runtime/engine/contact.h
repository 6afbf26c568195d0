// Our collision algorithm for a box against a convex hull (a bottle on a belt's band): Bullet's
// polyhedral contacts with a faster separating-axis test (contact.cpp says why and how).
#pragma once

#include <memory>

class btCollisionConfiguration;
class btCollisionDispatcher;
class btCollisionShape;

namespace plant::engine {

// Registers the algorithm on `dispatcher` for box-hull and hull-box pairs, for contacts and for
// closest-point queries; `config` supplies Bullet's algorithm for shapes without polyhedral
// features. Owns what the dispatcher calls and what the algorithms share (per-polyhedron data),
// so it must outlive every algorithm the dispatcher creates: create it right after the
// dispatcher, destroy it after the dispatcher. The algorithm is Bullet's polyhedral path, which
// Bullet takes only with m_enableSatConvex: register it only on such worlds.
class BoxHullContacts {
public:
    BoxHullContacts(btCollisionDispatcher& dispatcher, btCollisionConfiguration& config);
    ~BoxHullContacts();
    BoxHullContacts(const BoxHullContacts&) = delete;
    BoxHullContacts& operator=(const BoxHullContacts&) = delete;

    // Computes what the algorithm keeps per polyhedron for a shape (a compound's children)
    // now, instead of at the shape's first contact inside a step (which would allocate).
    void prepare(const btCollisionShape& shape);

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace plant::engine
