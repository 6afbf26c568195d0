#include "hull.h"

#include <cmath>

namespace plant::graph {

namespace {

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

// The point farthest by `distance`, and how far it is.
template <class F>
size_t farthest(const Point* points, size_t n, F&& distance, double& best) {
    size_t at = 0;
    best = -1;
    for (size_t i = 0; i < n; ++i)
        if (const double d = distance(points[i].p); d > best) best = d, at = i;
    return at;
}

}  // namespace

// The span is grown one dimension at a time from extreme points, so that rounding in a
// nearly flat hull cannot hide its thickness: a diameter's end, the farthest point from
// it, the farthest from their line, the farthest from their plane.
HullFlaw hull_flaw(const Point* points, size_t n) {
    if (n == 0) return HullFlaw::OnePoint;
    for (size_t i = 0; i < n; ++i)
        for (const double x : points[i].p)
            if (!(std::abs(x) <= kMaxHullReach)) return HullFlaw::TooFar;
    double d = 0;
    const Vec3 a = points[farthest(points, n, [&](const Vec3& p) { return norm(sub(p, points[0].p)); }, d)].p;
    const Vec3 b = points[farthest(points, n, [&](const Vec3& p) { return norm(sub(p, a)); }, d)].p;
    if (!(d > kHullTolerance)) return HullFlaw::OnePoint;
    const Vec3 ab = sub(b, a);
    const double ab_len = norm(ab);
    const Vec3 c = points[farthest(points, n, [&](const Vec3& p) { return norm(cross(ab, sub(p, a))) / ab_len; }, d)].p;
    if (!(d > kHullTolerance)) return HullFlaw::Line;
    const Vec3 normal = cross(ab, sub(c, a));
    const double normal_len = norm(normal);
    farthest(points, n, [&](const Vec3& p) { return std::abs(dot(normal, sub(p, a))) / normal_len; }, d);
    if (!(d > kHullTolerance)) return HullFlaw::Plane;
    return HullFlaw::None;
}

std::string_view hull_flaw_text(HullFlaw flaw) {
    switch (flaw) {
    case HullFlaw::None: return "";
    case HullFlaw::OnePoint: return "encloses no volume: all its points coincide";
    case HullFlaw::Line: return "encloses no volume: its points lie on one line";
    case HullFlaw::Plane: return "encloses no volume: its points lie in one plane";
    case HullFlaw::TooFar: return "is too large: a point lies more than 100 km from the shape's origin";
    }
    return "";
}

}  // namespace plant::graph
