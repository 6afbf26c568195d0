// A grid of 25 cm cells over (x, y), for finding what lies near a point without visiting
// everything: the conveyor law's fields (fields.cpp) and steady transport's hazards
// (transport.cpp). 25 cm: a bottle's query then visits a few belts' and curve pieces' fields
// and rails, not a whole corner of a line's loop (1 m cells: 0.7 % more instructions for the
// 20-line plant over 20 s; 12.5 cm cells: 0.2 % more, the lookups of more cells). Boxes are
// filed under the cells they cover as (cell key, id) pairs, then indexed as sorted cells with
// their ids in id order (a CSR table); a box covering more than kMaxCells cells is kept apart
// and tried for every query.
#pragma once

#include <LinearMath/btScalar.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace plant::engine {

constexpr btScalar kCell = btScalar(0.25);  // m
constexpr int64_t kMaxCells = 1024;         // a box covering more (8 m square) is tried for every query
constexpr btScalar kNear = btScalar(0.05);  // m: fields are filed grown by this (fields.cpp)

// The cell of (x, y); false for NaN or a point beyond 1,000 km.
inline bool cell_of(btScalar x, btScalar y, int64_t& ix, int64_t& iy) {
    if (!(std::abs(x) < btScalar(1e6) && std::abs(y) < btScalar(1e6))) return false;
    ix = int64_t(std::floor(x / kCell)), iy = int64_t(std::floor(y / kCell));
    return true;
}
inline uint64_t cell_key(int64_t ix, int64_t iy) { return (uint64_t(ix & 0xffffffff) << 32) | uint64_t(iy & 0xffffffff); }

using CellFiling = std::vector<std::pair<uint64_t, int32_t>>;

// Files `id` under the cells the box (x0, y0)-(x1, y1) covers, or in `big` when it covers
// too many or lies beyond the grid.
inline void file_box(btScalar x0, btScalar y0, btScalar x1, btScalar y1, int32_t id, CellFiling& filed,
                     std::vector<int32_t>& big) {
    int64_t ix0, iy0, ix1, iy1;
    if (!cell_of(x0, y0, ix0, iy0) || !cell_of(x1, y1, ix1, iy1) || (ix1 - ix0 + 1) * (iy1 - iy0 + 1) > kMaxCells) {
        big.push_back(id);
        return;
    }
    for (int64_t x = ix0; x <= ix1; ++x)
        for (int64_t y = iy0; y <= iy1; ++y) filed.emplace_back(cell_key(x, y), id);
}

// Sorts `filed` (by cell, then id) into `cells` and, per cell, its ids in
// list[adr[c]] .. list[adr[c + 1]]. Allocates only past the largest filing so far.
inline void index_cells(CellFiling& filed, std::vector<uint64_t>& cells, std::vector<int32_t>& adr,
                        std::vector<int32_t>& list) {
    std::sort(filed.begin(), filed.end());
    cells.clear();
    adr.clear();
    list.clear();
    for (size_t i = 0; i < filed.size(); ++i) {
        if (i == 0 || filed[i].first != filed[i - 1].first) {
            cells.push_back(filed[i].first);
            adr.push_back(int32_t(list.size()));
        }
        list.push_back(filed[i].second);
    }
    adr.push_back(int32_t(list.size()));
}

// The ids filed under `key`: [begin, end), both null when none.
inline void cell_ids(const std::vector<uint64_t>& cells, const std::vector<int32_t>& adr,
                     const std::vector<int32_t>& list, uint64_t key, const int32_t*& begin, const int32_t*& end) {
    begin = end = nullptr;
    const auto it = std::lower_bound(cells.begin(), cells.end(), key);
    if (it == cells.end() || *it != key) return;
    const size_t c = size_t(it - cells.begin());
    begin = list.data() + adr[c];
    end = list.data() + adr[c + 1];
}

// Calls f(k) for the places k in `list` of the ids filed under each cell of [x0, x1] × [y0, y1],
// cell by cell (an id filed under several of them once per cell), until f returns false;
// returns false then.
template <class F>
bool each_entry_in_cells(const std::vector<uint64_t>& cells, const std::vector<int32_t>& adr,
                         const std::vector<int32_t>& list, int64_t x0, int64_t y0, int64_t x1, int64_t y1, F&& f) {
    for (int64_t x = x0; x <= x1; ++x)
        for (int64_t y = y0; y <= y1; ++y) {
            const int32_t *id = nullptr, *end = nullptr;
            cell_ids(cells, adr, list, cell_key(x, y), id, end);
            for (; id != end; ++id)
                if (!f(size_t(id - list.data()))) return false;
        }
    return true;
}

// As each_entry_in_cells, calling f(id) for the ids themselves.
template <class F>
bool each_in_cells(const std::vector<uint64_t>& cells, const std::vector<int32_t>& adr,
                   const std::vector<int32_t>& list, int64_t x0, int64_t y0, int64_t x1, int64_t y1, F&& f) {
    return each_entry_in_cells(cells, adr, list, x0, y0, x1, y1, [&](size_t k) { return f(list[k]); });
}

// Beside a CSR table's `list`, each filed id's box in (x, y): x0, y0, x1, y1.
using CellBoxes = std::vector<std::array<btScalar, 4>>;

// The boxes of `list`'s entries, boxes_of(id) giving an id's (x0, y0, x1, y1).
template <class B>
void box_cells(const std::vector<int32_t>& list, CellBoxes& boxes, B&& boxes_of) {
    boxes.resize(list.size());
    for (size_t i = 0; i < list.size(); ++i) boxes[i] = boxes_of(list[i]);
}

// As each_in_cells, but only for the ids whose box (`boxes`, beside `list`) meets the box
// (bx0, by0)-(bx1, by1) in (x, y): the others are passed over without touching what they are.
template <class F>
bool each_meeting(const std::vector<uint64_t>& cells, const std::vector<int32_t>& adr,
                  const std::vector<int32_t>& list, const CellBoxes& boxes, btScalar bx0, btScalar by0,
                  btScalar bx1, btScalar by1, int64_t x0, int64_t y0, int64_t x1, int64_t y1, F&& f) {
    return each_entry_in_cells(cells, adr, list, x0, y0, x1, y1, [&](size_t k) {
        const std::array<btScalar, 4>& b = boxes[k];
        return !(b[0] <= bx1 && bx0 <= b[2] && b[1] <= by1 && by0 <= b[3]) || f(list[k]);
    });
}

}  // namespace plant::engine
