// The bodies that fields and triggers look at (declared dynamic and in the world),
// sorted by the x of their centre of mass, so that a box volume visits only the
// bodies in its x range instead of all of them. The order barely changes between
// steps, so an insertion sort keeps it sorted in about linear time.
#pragma once

#include "engine/physics.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace plant::engine {

class Spatial {
public:
    Spatial(const Tables& t, size_t bodies);

    // Reads positions (and, with `aabbs`, bounding boxes) from Bullet and re-sorts.
    void refresh(const Physics& ph, bool aabbs);
    // [first, last) positions in the sorted order whose centre lies in [lo, hi].
    std::pair<size_t, size_t> range(btScalar lo, btScalar hi) const;

    int32_t body_at(size_t i) const { return order_[i].body; }
    const btVector3& com(int32_t b) const { return com_[b]; }
    const btVector3& lo(int32_t b) const { return lo_[b]; }
    const btVector3& hi(int32_t b) const { return hi_[b]; }
    // Largest distance along x from a body's centre to its bounding box (for triggers).
    btScalar reach() const { return reach_; }

private:
    struct Entry {
        btScalar x;
        int32_t body;
    };
    const Tables& t_;
    std::vector<Entry> order_;
    std::vector<btVector3> com_, lo_, hi_;
    btScalar reach_ = 0;
    uint64_t version_ = ~uint64_t(0);  // Physics::version of the membership
};

}  // namespace plant::engine
