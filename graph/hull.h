// Whether a convex hull's points enclose a volume. Shared by the compiler (a diagnostic at
// the shape) and the graph loader (validate.cpp), so both refuse the same hulls.
#pragma once

#include "graph/graph.h"
#include "graph/range.h"

#include <cstddef>
#include <string_view>

namespace plant::graph {

// Points closer than this are one point; a hull must reach further than this out of the
// line, and then out of the plane, of its other points (1 µm, in metres).
constexpr double kHullTolerance = 1e-6;

// No hull point lies further than this from its shape's origin (100 km, range.h): the
// physics is single precision, and Bullet's hull builder does not return from a point
// beyond float's range (found by the graph fuzz campaign).
constexpr double kMaxHullReach = kMaxLength;

enum class HullFlaw : uint8_t { None, OnePoint, Line, Plane, TooFar };

// The first way the points fail to span a solid, or None: every coordinate within
// kMaxHullReach, and after merging points within kHullTolerance, at least four must not lie
// in one plane.
HullFlaw hull_flaw(const Point* points, size_t n);

// What is wrong with the hull, to follow "this hull ": "encloses no volume: all its points
// coincide", "is too large: a point lies more than 100 km ..."; empty for None.
std::string_view hull_flaw_text(HullFlaw flaw);

}  // namespace plant::graph
