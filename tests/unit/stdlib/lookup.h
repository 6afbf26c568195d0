// Finding things in a compiled plant by their dotted paths, and measuring a bottle, for
// the tests that run plants written in the language (stdlib types, shipped plants).
#pragma once

#include "graph/graph.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string_view>
#include <vector>

namespace plant::test {

// The angle between a body's z axis and the vertical, in degrees.
inline double tilt_deg(const graph::Quat& q) {
    const double c = 1 - 2 * (q[0] * q[0] + q[1] * q[1]);
    return std::acos(std::clamp(c, -1.0, 1.0)) * 180 / std::numbers::pi;
}

// The slot at a dotted path (Graph::slot_path), or -1.
inline int32_t slot_named(const graph::Graph& g, std::string_view path) {
    for (plant::graph::SlotId s : plant::graph::ids_of(g.slots))
        if (g.slot_path(s) == path) return s.v;
    return -1;
}

// The place `name` of the net at component path `net`, or -1.
inline int32_t place_named(const graph::Graph& g, std::string_view net, std::string_view name) {
    for (graph::PlaceId p : graph::ids_of(g.places))
        if (g.comp_path(g.places[p].comp) == net && g.str(g.places[p].name) == name) return p.v;
    return -1;
}

// Rows of a table whose component path is `path`, or -1.
template <class Rows>
int32_t row_of_comp(const graph::Graph& g, const Rows& rows, std::string_view path) {
    for (auto i : graph::ids_of(rows))
        if (g.comp_path(rows[i].comp) == path) return i.v;
    return -1;
}

// Bodies whose component path ends with `suffix` (e.g. ".main"), in graph order.
inline std::vector<int32_t> bodies_ending(const graph::Graph& g, std::string_view suffix) {
    std::vector<int32_t> out;
    for (graph::BodyId b : graph::ids_of(g.bodies))
        if (g.comp_path(g.bodies[b].comp).ends_with(suffix)) out.push_back(b.v);
    return out;
}

}  // namespace plant::test
