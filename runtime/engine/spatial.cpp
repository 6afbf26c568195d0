#include "engine/spatial.h"

#include "engine/workers.h"

#include <algorithm>
#include <cmath>

namespace plant::engine {

Spatial::Spatial(const Tables& t, int32_t bodies) : t_(t), com_(bodies), lo_(bodies), hi_(bodies), listed_(bodies) {
    order_.reserve(t.dyn_bodies.size());
    begin_.reserve(t.dyn_bodies.size() + 1024);
}

int32_t Spatial::cell(btScalar y) {
    constexpr btScalar kCell = 1;  // metres
    if (!(std::abs(y) < btScalar(1e6))) return 0;  // NaN or far away: one cell for all
    return int32_t(std::floor(y / kCell));
}

std::pair<btScalar, btScalar> Spatial::measure(const Physics& ph, bool all, size_t begin, size_t end, size_t& read,
                                              bool& moved) {
    constexpr size_t kAhead = 4;  // how many bodies ahead each one's pose is asked for
    btScalar reach = 0, vmax = 0;
    for (size_t i = begin; i < end; ++i) {
        if (i + kAhead < end && (all || order_[i + kAhead].seen != ph.writes(order_[i + kAhead].body)))
            ph.prefetch(order_[i + kAhead].body);  // in order of place, not of memory
        Entry& e = order_[i];
        if (all || e.seen != ph.writes(e.body)) {
            ++read;
            const btRigidBody& r = ph.rb(e.body);
            e.seen = ph.writes(e.body);
            e.v2 = r.getLinearVelocity().length2();  // its square: the root once, of the largest
            com_[e.body] = ph.com(e.body);
            e.x = com_[e.body].x();
            const int32_t in = cell(com_[e.body].y());
            moved = moved || in != e.cell;
            e.cell = in;
            r.getCollisionShape()->getAabb(r.getWorldTransform(), lo_[e.body], hi_[e.body]);
            const btVector3 c = com_[e.body];
            e.span = std::max({btScalar(0), c.x() - lo_[e.body].x(), hi_[e.body].x() - c.x(), c.y() - lo_[e.body].y(),
                               hi_[e.body].y() - c.y()});
        }
        vmax = std::max(vmax, e.v2);
        reach = std::max(reach, e.span);
    }
    return {reach, vmax};
}

void Spatial::relist(const Physics& ph) {
    size_t k = 0;
    for (const Entry& e : order_) {
        if (ph.in_world(e.body)) order_[k++] = e;
        else listed_[e.body] = 0;
    }
    order_.resize(k);  // smaller: no allocation
    for (graph::BodyId b : t_.dyn_bodies)
        if (ph.in_world(b) && !listed_[b]) {
            listed_[b] = 1;
            order_.push_back({0, 0, b, ph.writes(b) + 1, 0, 0});  // within its room; read below (seen differs)
        }
    version_ = ph.version();
}

void Spatial::refresh(const Physics& ph, Workers& w) {
    // Between two physics steps a body's state changes only by a writer that counts (Physics::
    // writes) and membership only with Physics::version: a body not written since it was read
    // is as it was then (its pose, speed and box, its own and its carrier's), and so is what
    // was read. After a step every body is read again.
    const bool all = steps_ != ph.steps();
    steps_ = ph.steps();
    // The cells' table changes only where the cells in the list do: with the same bodies
    // listed, none of them in another cell.
    bool moved = version_ != ph.version();
    if (moved) relist(ph);
    // Ordered by (cell, x, id): a total order (no two entries tie), so the sorted list is one
    // whatever sorts it (a NaN x aside, which orders nothing: then the list is still the same
    // on any number of threads, the slices being cut alike). Slices of at least 32 bodies,
    // four per thread on 16 at most: each measures its own entries and sorts them by
    // insertion (they were in order the step before, and bodies move little in a step).
    // Where every slice ends before the next begins, the list is in order; otherwise this
    // thread sorts it whole the same way.
    auto before = [](const Entry& a, const Entry& b) {
        if (a.cell != b.cell) return a.cell < b.cell;
        if (a.x != b.x) return a.x < b.x;
        return a.body < b.body;
    };
    // Entry i moved back to its place among those from `begin` on, which are in order.
    auto put_back = [this, &before](size_t begin, size_t i) {
        const Entry e = order_[i];
        size_t j = i;
        for (; j > begin && before(e, order_[j - 1]); --j) order_[j] = order_[j - 1];
        order_[j] = e;
    };
    auto insertion = [&put_back](size_t begin, size_t end) {
        for (size_t i = begin + 1; i < end; ++i) put_back(begin, i);
    };
    const size_t n = order_.size();
    const size_t slices = slice_count(n, 32, kSlices);
    auto measuring = [this, &ph, &insertion, all, n, slices](int i) {
        const auto [b, e] = slice_of(n, slices, i);
        slice_read_[i] = 0;
        slice_moved_[i] = false;
        slice_max_[i] = measure(ph, all, b, e, slice_read_[i], slice_moved_[i]);
        insertion(b, e);
    };
    run_slices(w, slices, measuring);
    std::pair<btScalar, btScalar> most{0, 0};
    bool sorted = true;
    read_ = 0;
    for (size_t i = 0; i < slices; ++i) {
        read_ += slice_read_[i];
        moved = moved || slice_moved_[i];
        most = {std::max(most.first, slice_max_[i].first), std::max(most.second, slice_max_[i].second)};
        const size_t b = slice_of(n, slices, i).first;
        if (i > 0 && b > 0 && b < n && before(order_[b], order_[b - 1])) sorted = false;
    }
    reach_ = most.first;
    vmax_ = std::sqrt(most.second);
    // Each slice in order, out of order only where one ends after the next begins: from each
    // such start on, its entries go back to their places until one is in order already (the
    // ones before it are in order then, and the rest of its slice follow it): the same list as
    // a whole insertion sort, for the work of the entries out of place.
    if (!sorted) {
        size_t i = 1;
        for (size_t k = 1; k < slices; ++k) {
            i = std::max(i, slice_of(n, slices, k).first);
            for (; i < n && before(order_[i], order_[i - 1]); ++i) put_back(0, i);
        }
    }
    if (moved) index_cells();
}

// The list is in cell order whatever its x (a NaN x orders nothing, but cells are compared
// first): each cell's entries are one run of it.
void Spatial::index_cells() {
    begin_.clear();
    if (order_.empty()) return;
    const int64_t c0 = order_.front().cell, span = int64_t(order_.back().cell) - c0 + 1;
    if (span + 1 > int64_t(begin_.capacity())) return;
    cell0_ = int32_t(c0);
    begin_.resize(size_t(span) + 1);  // within its room
    size_t k = 0;
    for (int64_t c = 0; c <= span; ++c) {
        while (k < order_.size() && order_[k].cell - c0 < c) ++k;
        begin_[size_t(c)] = uint32_t(k);
    }
}

size_t Spatial::first(int32_t c, btScalar x) const {
    if (!begin_.empty()) {  // within c's own run of the list: the same position
        const int64_t i = int64_t(c) - cell0_;
        if (i < 0) return 0;
        if (i + 1 >= int64_t(begin_.size())) return order_.size();
        const auto b = order_.begin() + begin_[size_t(i)], e = order_.begin() + begin_[size_t(i) + 1];
        return size_t(std::lower_bound(b, e, x, [](const Entry& en, btScalar v) { return en.x < v; }) - order_.begin());
    }
    auto it = std::lower_bound(order_.begin(), order_.end(), std::pair(c, x), [](const Entry& e, std::pair<int32_t, btScalar> v) {
        return e.cell != v.first ? e.cell < v.first : e.x < v.second;
    });
    return size_t(it - order_.begin());
}

}  // namespace plant::engine
