// The bodies that triggers look at (declared dynamic and in the world), sorted by
// (y cell, x) of their centre of mass — y cells 1 m wide — so that a box volume visits
// only the bodies in its x range within the cells its y range covers, instead of all of
// them. (Sorted by x alone, plants of many lines side by side made every trigger visit
// the bottles of every line at its x.) Fields go the other way: each body looks up its
// fields (fields.cpp). The order barely changes
// between steps, so an insertion sort keeps it sorted in about linear time.
#pragma once

#include "engine/physics.h"
#include "engine/workers.h"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace plant::engine {

class Spatial {
public:
    Spatial(const Tables& t, int32_t bodies);

    // Reads positions and bounding boxes from Bullet and sorts, a slice of the
    // bodies per item of a job on `w`'s threads; the calling thread sorts the whole list again
    // only where two slices overlap (spatial.cpp). Where Physics has not stepped since the last
    // refresh, only the bodies written since (Physics::writes) and those new to the world are
    // read again: the rest are as they were, and so is what was read of them.
    void refresh(const Physics& ph, Workers& w);
    // How many bodies the last refresh read from Bullet (for tests).
    size_t last_read() const { return read_; }
    // Calls f(body) for every body whose centre has x in [xlo, xhi] and lies in a y cell
    // that [ylo, yhi] touches (a superset of the bodies with y in [ylo, yhi]).
    template <class F>
    void for_each(btScalar xlo, btScalar xhi, btScalar ylo, btScalar yhi, F&& f) const {
        const int32_t c0 = cell(ylo), c1 = cell(yhi);
        if (int64_t(c1) - int64_t(c0) > kMaxCells) {  // a huge volume: all cells, by x
            for (const Entry& e : order_)
                if (e.x >= xlo && e.x <= xhi) f(e.body);
            return;
        }
        for (int32_t c = c0; c <= c1; ++c)
            for (size_t i = first(c, xlo); i < order_.size() && order_[i].cell == c && order_[i].x <= xhi; ++i)
                f(order_[i].body);
    }
    const btVector3& com(graph::BodyId b) const { return com_[b]; }
    const btVector3& lo(graph::BodyId b) const { return lo_[b]; }
    const btVector3& hi(graph::BodyId b) const { return hi_[b]; }
    // Largest distance along x or y from a body's centre to its bounding box (for triggers).
    btScalar reach() const { return reach_; }
    // The largest speed of the bodies (NaN skipped), as of the last refresh.
    btScalar vmax() const { return vmax_; }

private:
    static constexpr int64_t kMaxCells = 256;
    struct Entry {
        int32_t cell;
        btScalar x;
        graph::BodyId body;
        uint32_t seen;   // Physics::writes(body) when it was read
        btScalar v2;     // the square of its speed, then
        btScalar span;   // and the largest distance along x or y from its centre to its box
    };
    static constexpr size_t kSlices = kMaxSlices;
    static int32_t cell(btScalar y);
    // Entries [begin, end): their centres, cells and boxes, read from Bullet (with
    // `all`, every entry's; else only where the body was written since); the largest reach and
    // square of a speed. Counts what it read into `read`; `moved` when one's cell changed.
    std::pair<btScalar, btScalar> measure(const Physics& ph, bool all, size_t begin, size_t end, size_t& read,
                                          bool& moved);
    // The list to the bodies in the world now: those that left taken out (the order of the rest
    // kept), those that came appended to be read.
    void relist(const Physics& ph);
    size_t first(int32_t cell, btScalar x) const;  // first position with (cell, x) or after
    // Where each y cell's entries begin in order_, after a refresh: begin_[c - cell0_] for the
    // cells from the first entry's to the last's, and one past the last. Empty where those
    // cells are more than its room (reserved at the start: no allocation in a step), and then
    // `first` searches the whole list.
    void index_cells();
    const Tables& t_;
    std::vector<Entry> order_;
    std::vector<uint32_t> begin_;
    int32_t cell0_ = 0;
    graph::IdVector<graph::BodyId, btVector3> com_, lo_, hi_;
    btScalar reach_ = 0, vmax_ = 0;
    std::array<std::pair<btScalar, btScalar>, kSlices> slice_max_{};
    std::array<size_t, kSlices> slice_read_{};
    std::array<bool, kSlices> slice_moved_{};
    size_t read_ = 0;
    graph::IdVector<graph::BodyId, uint8_t> listed_;  // per body: in order_
    uint64_t version_ = ~uint64_t(0);  // Physics::version of the membership
    uint64_t steps_ = ~uint64_t(0);    // Physics::steps at the last refresh
};

}  // namespace plant::engine
