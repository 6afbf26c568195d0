// The range a plant's places, sizes and masses lie in. Shared by the compiler (E0308 at the
// declaration that puts a value out of range) and the graph loader (validate.cpp), so both
// refuse the same graphs. The physics is single precision: far out, or far too large, a
// number is rounded beyond use (at 100 km a float's step is 8 mm) or overflows to infinity.
#pragma once

#include "graph/graph.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace plant::graph {

// Every coordinate of a place (a world pose at start, or an offset from a body, a graphics
// or a shape's origin) and every size lies within this (100 km, in metres).
constexpr double kMaxLength = 1e5;
// Every body's mass is at most this (1,000 t, in kg), and every principal moment of inertia
// at most kMaxMass · kMaxLength².
constexpr double kMaxMass = 1e6;

// Whether a place or an offset (x, y, z in metres) lies within kMaxLength on every axis.
bool place_in_range(const double* p);

struct RangeFlaw {
    std::string_view table;  // as in the text form's tables: "dos", "bodies", ...
    int32_t row = -1;
    std::string_view field;
    std::string_view what;  // the field in words: "place", "size of a shape", "key frame", ...
    int32_t comp = -1;      // the component the record belongs to; -1 for a DO
    std::string text;       // to follow the field: "is 200000 m out along x, beyond 100 km"
};

// Every field of `g` out of range: the DOs first (so an object comes before what it holds),
// then each component's records, a body's shapes after the body and an animation's keys with
// their graphics. Assumes every number finite and every list inside its table (validate.h
// checks both first); hull points are hull.h's.
std::vector<RangeFlaw> range_flaws(const Graph& g);

}  // namespace plant::graph
