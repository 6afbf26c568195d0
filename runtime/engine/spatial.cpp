#include "engine/spatial.h"

#include <algorithm>

namespace plant::engine {

Spatial::Spatial(const Tables& t, size_t bodies) : t_(t), com_(bodies), lo_(bodies), hi_(bodies) {
    order_.reserve(t.dyn_bodies.size());
}

void Spatial::refresh(const Physics& ph, bool aabbs) {
    if (version_ != ph.version()) {
        order_.clear();
        for (int32_t b : t_.dyn_bodies)
            if (ph.in_world(b)) order_.push_back({0, b});
        version_ = ph.version();
    }
    btScalar reach = 0;
    for (Entry& e : order_) {
        const btRigidBody& r = ph.rb(e.body);
        com_[e.body] = r.getWorldTransform().getOrigin();
        e.x = com_[e.body].x();
        if (aabbs) {
            r.getCollisionShape()->getAabb(r.getWorldTransform(), lo_[e.body], hi_[e.body]);
            reach = std::max({reach, e.x - lo_[e.body].x(), hi_[e.body].x() - e.x});
        }
    }
    if (aabbs) reach_ = reach;
    // Insertion sort by (x, id): ties by id keep the order independent of history.
    for (size_t i = 1; i < order_.size(); ++i) {
        Entry e = order_[i];
        size_t j = i;
        while (j > 0 && (order_[j - 1].x > e.x || (order_[j - 1].x == e.x && order_[j - 1].body > e.body))) {
            order_[j] = order_[j - 1];
            --j;
        }
        order_[j] = e;
    }
}

std::pair<size_t, size_t> Spatial::range(btScalar lo, btScalar hi) const {
    auto first = std::lower_bound(order_.begin(), order_.end(), lo,
                                  [](const Entry& e, btScalar v) { return e.x < v; });
    auto last = std::upper_bound(first, order_.end(), hi,
                                 [](btScalar v, const Entry& e) { return v < e.x; });
    return {size_t(first - order_.begin()), size_t(last - order_.begin())};
}

}  // namespace plant::engine
