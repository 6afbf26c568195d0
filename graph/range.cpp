#include "range.h"

#include "kinds.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace plant::graph {

namespace {

double largest(const double* v) { return std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])}); }

class Ranges {
public:
    explicit Ranges(std::vector<RangeFlaw>& out) : out_(out) {}

    // The record the checks that follow are of, and the component it belongs to (-1: a DO).
    void at(std::string_view table, int32_t row, CompId comp) {
        table_ = table;
        row_ = row;
        comp_ = comp;
    }
    // A world pose at start: every coordinate within kMaxLength of the origin.
    void place(std::string_view field, std::string_view what, const Pose& p) {
        if (!place_in_range(p.p.data()))
            add(field, what, fmt::format("is {} out along {}, beyond 100 km", along(p.p), axis(p.p)));
    }
    // An offset from another frame.
    void offset(std::string_view field, std::string_view what, const Pose& p) {
        if (!place_in_range(p.p.data()))
            add(field, what, fmt::format("is {} along {}, beyond 100 km", along(p.p), axis(p.p)));
    }
    // The first `used` components of a size (a sphere uses one, a cylinder two, a box three).
    void size(std::string_view field, std::string_view what, const Vec3& v, int used = 3) {
        const double* end = v.data() + used;
        if (const double d = *std::max_element(v.data(), end); d > kMaxLength)
            add(field, what, fmt::format("is {:g} m, beyond 100 km", d));
        else if (const double e = *std::min_element(v.data(), end); e > 0 && e < kMinLength)  // 0: validate.h's
            add(field, what, fmt::format("is {:g} m, below 0.1 mm", e));
    }
    // A box volume (a field's, a trigger's): its extents, then its place.
    template <class V>
    void volume(const V& v) {
        size("extent", "size", v.extent);
        place("pose", "place", v.pose);
    }
    void mass(const Body& b) {
        if (b.mass > kMaxMass) add("mass", "mass", fmt::format("is {:g} kg, above 1,000 t", b.mass));
        else if (b.mode == BodyMode::Dynamic && b.mass > 0 && b.mass < kMinMass)
            add("mass", "mass", fmt::format("is {:g} kg, below 1 mg", b.mass));
    }
    void inertia(const Vec3& i) {
        if (const double d = largest(i.data()); d > kMaxMass * kMaxLength * kMaxLength)
            add("inertia", "inertia", fmt::format("has a moment of {:g} kg·m², above 1e16 kg·m² (1,000 t at 100 km)", d));
        else if (const double e = std::min({i[0], i[1], i[2]}); e > 0 && e < kMinInertia)
            add("inertia", "inertia", fmt::format("has a moment of {:g} kg·m², below 1e-14 kg·m² (1 mg at 0.1 mm)", e));
    }
    void belt(const Field& f) {
        if (std::abs(f.speed) > kMaxSpeed) add("speed", "speed", fmt::format("is {:g} m/s, beyond 100 km/s", f.speed));
        if (f.gain > kMaxGain) add("gain", "gain", fmt::format("is {:g} kg/s, above 1e12 kg/s", f.gain));
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
    void add(std::string_view field, std::string_view what, std::string text) {
        out_.push_back({table_, row_, field, what, comp_, std::move(text)});
    }
    std::vector<RangeFlaw>& out_;
    std::string_view table_;
    int32_t row_ = -1;
    CompId comp_;
};

}  // namespace

bool place_in_range(const double* p) { return largest(p) <= kMaxLength; }
bool gravity_in_range(const double* g) { return largest(g) <= kMaxGravity; }

namespace {

bool static_velocity(const Graph& g, const Comp& c, SlotId slot) {
    const int32_t i = slot.v - c.slot_adr.v;
    return c.kind == CompKind::Body && (i == bodyslot::set_velocity || i == bodyslot::set_angular_velocity) &&
           g.bodies[detail_of<Body>(c)].mode == BodyMode::Static;
}

}  // namespace

bool static_velocity(const Graph& g, SlotId slot) { return static_velocity(g, g[g.slots[slot].comp], slot); }

std::string_view input_range(const Graph& g, SlotId slot, const double* v) {
    return input_range(g, g[g.slots[slot].comp], slot, v);
}

std::string_view input_range(const Graph& g, const Comp& c, SlotId slot, const double* v) {
    const int32_t i = slot.v - c.slot_adr.v;  // which of its kind's slots
    const bool body = c.kind == CompKind::Body, field = c.kind == CompKind::Field;
    // Each axis within `limit`; NaN is never (a value the plant's logic computed may be one).
    auto within = [v](int n, double limit) {
        for (int k = 0; k < n; ++k)
            if (!(std::abs(v[k]) <= limit)) return false;
        return true;
    };
    if ((body && (i == bodyslot::set_pose || i == bodyslot::set_position)) ||
        (c.kind == CompKind::Graphics && i == graphicsslot::set_pose))
        return within(3, kMaxLength) ? "" : "a place within 100 km";
    // A static body does not move (its box in Bullet and steady transport's grid stay where it
    // was placed): a velocity is for a dynamic or kinematic body, whatever its value.
    if (static_velocity(g, c, slot)) return kStaticVelocity;
    if (body && i == bodyslot::set_velocity) return within(3, kMaxSpeed) ? "" : "a velocity within 100 km/s on each axis";
    if (body && i == bodyslot::set_angular_velocity)
        return within(3, kMaxTurnRate) ? "" : "an angular velocity within 1e6 rad/s on each axis";
    if (field && i == fieldslot::set_speed) return within(1, kMaxSpeed) ? "" : "a speed within 100 km/s";
    return "";
}

std::vector<RangeFlaw> range_flaws(const Graph& g) {
    std::vector<RangeFlaw> out;
    Ranges r(out);
    for (const auto i : ids_of(g.dos)) {
        r.at("dos", i.v, CompId{});
        r.place("pose", "place", g.dos[i].pose);
    }
    for (const auto i : ids_of(g.bodies)) {
        const Body& b = g.bodies[i];
        r.at("bodies", i.v, b.comp);
        r.place("pose", "place", b.pose);
        r.offset("com", "centre of mass", b.com);
        r.mass(b);
        if (b.inertia_set) r.inertia(b.inertia);
        for (Id<Shape> s : children(b.shape_adr, b.shape_num)) {
            r.at("shapes", s.v, b.comp);
            r.offset("local", "offset of a shape", g.shapes[s].local);
            if (const Shape& sh = g.shapes[s]; sh.kind != ShapeKind::Hull)
                r.size("size", "size of a shape", sh.size,
                       sh.kind == ShapeKind::Sphere ? 1 : sh.kind == ShapeKind::Box ? 3 : 2);
        }
    }
    for (const auto i : ids_of(g.fields)) {
        r.at("fields", i.v, g.fields[i].comp);
        r.volume(g.fields[i]);
        r.belt(g.fields[i]);
    }
    for (const auto i : ids_of(g.joints)) {
        r.at("joints", i.v, g.joints[i].comp);
        r.offset("frame_a", "frame on body a", g.joints[i].frame_a);
        r.offset("frame_b", "frame on body b", g.joints[i].frame_b);
    }
    for (const auto i : ids_of(g.triggers)) {
        r.at("triggers", i.v, g.triggers[i].comp);
        r.volume(g.triggers[i]);
    }
    for (const auto i : ids_of(g.sources)) {
        r.at("sources", i.v, g.sources[i].comp);
        r.place("pose", "place", g.sources[i].pose);
    }
    for (const auto i : ids_of(g.plugins))
        if (g.plugins[i].placed) {
            r.at("plugins", i.v, g.plugins[i].comp);
            r.place("pose", "place", g.plugins[i].pose);
        }
    for (const auto i : ids_of(g.graphics)) {
        r.at("graphics", i.v, g.graphics[i].comp);
        r.place("pose", "place", g.graphics[i].pose);
    }
    for (const Animation& a : g.animations)
        for (Id<Key> key : children(a.key_adr, a.key_num)) {
            r.at("keys", key.v, g.graphics[a.graphics].comp);
            r.offset("pose", "key frame", g.keys[key].pose);
        }
    return out;
}

}  // namespace plant::graph
