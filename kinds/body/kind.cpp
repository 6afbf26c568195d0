// The body's row of the kind table (graph/plugin.h): what the compiler, the loader, the
// language server and the docs know of it. A body is written `physics` in plant files (the
// row's word); the graph's text form calls its kind `body` (graph::word(CompKind::Body)).
#include "graph/hull.h"
#include "graph/kinds.h"
#include "graph/plugin.h"
#include "graph/range.h"
#include "graph/validate.h"

#include <fmt/format.h>

namespace plant::kinds::body {

using namespace plant::graph;

namespace {

constexpr SlotSpec kSlots[] = {PLANT_SLOTS_BODY(PLANT_SLOT_SPEC)};
constexpr std::string_view kModes[] = {"dynamic", "static", "kinematic"};
constexpr ParamSpec kParams[] = {
    {"mass", ParamType::Number, "kg", false, 0, "required for dynamic bodies"},
    {"inertia", ParamType::Vec3, "kg*m^2", false, 0, "principal moments; computed from the shapes when absent"},
    {"friction", ParamType::Number, "", false, 0, "default 0.5"},
    {"restitution", ParamType::Number, "", false, 0, "default 0"},
    {"linear_damping", ParamType::Number, "", false, 0, "default 0"},
    {"angular_damping", ParamType::Number, "", false, 0, "default 0"},
    {"collision", ParamType::Bool, "", false, 0, "default true"},
    {"dynamics", ParamType::Bool, "", false, 0, "default true"},
};

// The loader's check of one body: what the compiler refuses, and what Bullet would clamp or
// ignore (graph/range.h).
bool check(const Graph& g, int32_t row, PluginProblem& problem) {
    const Body& b = g.bodies[BodyId(row)];
    const bool dynamic = b.mode == BodyMode::Dynamic;
    problem.message =
        !(!dynamic || b.mass > 0) ? "a dynamic body needs a mass above 0"
        : !(b.shape_num > 0)      ? "a body needs at least one shape"
        : !(b.mass >= 0)          ? "field 'mass' is negative"
        : !(!b.inertia_set || (b.inertia[0] > 0 && b.inertia[1] > 0 && b.inertia[2] > 0))
            ? "field 'inertia' must be above 0 on every axis"
        : !(b.friction >= 0 && b.restitution >= 0) ? "friction and restitution must be 0 or more"
        : !(b.friction <= kMaxFriction)            ? "friction above 10 (Bullet caps a contact's at 10)"
        : !(b.linear_damping >= 0 && b.linear_damping <= kMaxDamping && b.angular_damping >= 0 &&
            b.angular_damping <= kMaxDamping)
            ? "damping must lie in [0, 1]"
        : !(dynamic || (b.mass == 0 && !b.inertia_set && b.linear_damping == 0 && b.angular_damping == 0))
            ? "a static or kinematic body has no mass, inertia or damping (Bullet ignores them)"
            : "";
    return problem.message.empty();
}

// The loader's check of its shapes: sizes above 0 where the shape uses them, a hull's points.
bool check_tables(const Graph& g, GraphProblem& problem) {
    return each_record(g.shapes, problem, [&](const Shape& s) {
        const Vec3& z = s.size;
        bool ok = true;
        switch (s.kind) {
        case ShapeKind::Box: ok = z[0] > 0 && z[1] > 0 && z[2] > 0; break;
        case ShapeKind::Sphere: ok = z[0] > 0; break;
        case ShapeKind::Cylinder:
        case ShapeKind::Capsule: ok = z[0] > 0 && z[1] > 0; break;
        case ShapeKind::Hull: {
            if (!(s.point_num > 0)) return std::string("a hull needs points");
            const std::span<const Point> points = g.points.slice(s.point_adr, s.point_num);
            if (const HullFlaw flaw = hull_flaw(points.data(), points.size()); flaw != HullFlaw::None)
                return fmt::format("a hull {}", hull_flaw_text(flaw));
            break;
        }
        }
        return ok ? std::string() : std::string("field 'size' must be above 0 where the shape uses it");
    });
}

}  // namespace

constexpr KindDesc desc{
    .word = "physics",
    .doc = "a rigid body in the physics world: its shapes, mass and surface",
    .slots = kSlots,
    .params = kParams,
    .check = check,
    .placed = true,  // its body frame starts where it is placed
    .kind = CompKind::Body,
    .modes = kModes,
    .blocks = kShapes,
    PLANT_KIND_TABLE(bodies),
    .check_tables = check_tables,
};

}  // namespace plant::kinds::body
