#include "range.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace plant::graph {

namespace {

double largest(const Vec3& v) { return std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])}); }

class Ranges {
public:
    explicit Ranges(std::vector<RangeFlaw>& out) : out_(out) {}

    // A world pose at start: every coordinate within kMaxLength of the origin.
    void place(std::string_view table, size_t row, std::string_view field, const Pose& p) {
        if (largest(p.p) > kMaxLength) add(table, row, field, fmt::format("is {} out along {}, beyond 100 km", along(p.p), axis(p.p)));
    }
    // An offset from another frame.
    void offset(std::string_view table, size_t row, std::string_view field, const Pose& p) {
        if (largest(p.p) > kMaxLength) add(table, row, field, fmt::format("is {} along {}, beyond 100 km", along(p.p), axis(p.p)));
    }
    void size(std::string_view table, size_t row, std::string_view field, const Vec3& v) {
        if (const double d = largest(v); d > kMaxLength)
            add(table, row, field, fmt::format("is {:g} m, beyond 100 km", d));
    }
    // A box volume (a field's, a trigger's): its extents, then its place.
    template <class V>
    void volume(std::string_view table, size_t row, const V& v) {
        size(table, row, "extent", v.extent);
        place(table, row, "pose", v.pose);
    }
    void mass(size_t row, double m) {
        if (m > kMaxMass) add("bodies", row, "mass", fmt::format("is {:g} kg, above 1,000 t", m));
    }
    void inertia(size_t row, const Vec3& i) {
        if (const double d = largest(i); d > kMaxMass * kMaxLength * kMaxLength)
            add("bodies", row, "inertia", fmt::format("has a moment of {:g} kg·m², above 1e16 kg·m² (1,000 t at 100 km)", d));
    }

private:
    // The coordinate of largest magnitude ("-2e+05 m"), and its axis.
    static size_t index(const Vec3& v) {
        size_t a = 0;
        for (size_t i = 1; i < 3; ++i)
            if (std::abs(v[i]) > std::abs(v[a])) a = i;
        return a;
    }
    static std::string along(const Vec3& v) { return fmt::format("{:g} m", v[index(v)]); }
    static char axis(const Vec3& v) { return "xyz"[index(v)]; }
    void add(std::string_view table, size_t row, std::string_view field, std::string text) {
        out_.push_back({table, int32_t(row), field, std::move(text)});
    }
    std::vector<RangeFlaw>& out_;
};

}  // namespace

std::vector<RangeFlaw> range_flaws(const Graph& g) {
    std::vector<RangeFlaw> out;
    Ranges r(out);
    for (size_t i = 0; i < g.dos.size(); ++i) r.place("dos", i, "pose", g.dos[i].pose);
    for (size_t i = 0; i < g.bodies.size(); ++i) {
        const Body& b = g.bodies[i];
        r.place("bodies", i, "pose", b.pose);
        r.offset("bodies", i, "com", b.com);
        r.mass(i, b.mass);
        if (b.inertia_set) r.inertia(i, b.inertia);
    }
    for (size_t i = 0; i < g.shapes.size(); ++i) {
        r.offset("shapes", i, "local", g.shapes[i].local);
        r.size("shapes", i, "size", g.shapes[i].size);
    }
    for (size_t i = 0; i < g.fields.size(); ++i) r.volume("fields", i, g.fields[i]);
    for (size_t i = 0; i < g.joints.size(); ++i) {
        r.offset("joints", i, "frame_a", g.joints[i].frame_a);
        r.offset("joints", i, "frame_b", g.joints[i].frame_b);
    }
    for (size_t i = 0; i < g.triggers.size(); ++i) r.volume("triggers", i, g.triggers[i]);
    for (size_t i = 0; i < g.sources.size(); ++i) r.place("sources", i, "pose", g.sources[i].pose);
    for (size_t i = 0; i < g.graphics.size(); ++i) r.place("graphics", i, "pose", g.graphics[i].pose);
    for (size_t i = 0; i < g.keys.size(); ++i) r.offset("keys", i, "pose", g.keys[i].pose);
    return out;
}

}  // namespace plant::graph
