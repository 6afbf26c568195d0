// The body's lowering (written `physics`): a row of `bodies` from its mode, mass, inertia and
// surface, posed where it is placed, and its shapes, rows of `shapes` (a hull's points rows of
// `points`, shared with an earlier hull of the same points); its pose outputs start at its
// pose.
#include "sema/kinds/lowering.h"

#include "graph/build.h"
#include "graph/hull.h"
#include "graph/kinds.h"
#include "graph/range.h"

#include <algorithm>
#include <fmt/format.h>

namespace plant::kinds::body {

using namespace plant::sema;

namespace {

// One shape of a body: its arguments checked, appended to Graph::shapes unless wrong.
void lower_shape(Lowering& lw, const ast::ShapeDecl& sd) {
    Elaborator& el = lw.el;
    graph::Graph& g = lw.el.g_;
    const Env& env = lw.env;
    graph::Shape sh;
    sh.point_adr = graph::Adr<graph::Point>(0);  // no points but a hull's: 0, as the text form has always had it
    sh.local = el.placement(sd.placement ? &*sd.placement : nullptr, env).pose();
    std::vector<Value> a;
    bool ok = true;
    for (const auto& arg : sd.args) {
        if (arg.name && ok)  // once per shape
            el.sink_.report(DiagId::UnknownArgument, arg.name->span,
                            fmt::format("shape arguments are given in order, without names: {}(...)", sd.kind.text));
        ok = ok && !arg.name;
        a.push_back(el.ev_.eval(*arg.value, env));
        ok = ok && a.back().kind != Value::Kind::None;
    }
    if (!ok) return;
    auto lengths = [&](size_t n, const char* form) {
        if (a.size() != n) {
            el.sink_.report(DiagId::BadShape, sd.span, fmt::format("{} takes {}", sd.kind.text, form));
            return false;
        }
        for (size_t i = 0; i < n; ++i) {
            if (!el.ev_.expect_number(a[i], units::dims::length, fmt::format("{} size", sd.kind.text))) return false;
            if (a[i].num <= 0) {
                el.sink_.report(DiagId::NonPositive, a[i].span, fmt::format("{} sizes must be positive", sd.kind.text));
                return false;
            }
            sh.size[i] = a[i].num;
        }
        return true;
    };
    const std::string& k = sd.kind.text;
    if (k == "box") { sh.kind = graph::ShapeKind::Box; ok = lengths(3, "three full extents (x, y, z)"); }
    else if (k == "sphere") { sh.kind = graph::ShapeKind::Sphere; ok = lengths(1, "a radius"); }
    else if (k == "cylinder") { sh.kind = graph::ShapeKind::Cylinder; ok = lengths(2, "a radius and a height"); }
    else if (k == "capsule") { sh.kind = graph::ShapeKind::Capsule; ok = lengths(2, "a radius and a height"); }
    else if (k == "hull") {
        sh.kind = graph::ShapeKind::Hull;
        sh.point_adr = graph::next_adr(g.points);
        for (const auto& p : a) {
            if (!el.ev_.expect_vec3(p, units::dims::length, "hull point")) { ok = false; break; }
            g.points.push_back({vec(p)});
        }
        sh.point_num = graph::rows_since(g.points, sh.point_adr);
        const std::span<const graph::Point> points = g.points.slice(sh.point_adr, sh.point_num);
        if (ok && sh.point_num < 4) {
            el.sink_.report(DiagId::BadShape, sd.span, "a convex hull needs at least 4 points");
            ok = false;
        } else if (const auto flaw = ok ? graph::hull_flaw(points.data(), points.size())
                                        : graph::HullFlaw::None;
                   flaw != graph::HullFlaw::None) {
            auto& d = el.sink_.report(DiagId::BadShape, sd.span, fmt::format("this convex hull {}", graph::hull_flaw_text(flaw)));
            d.notes.push_back({{}, flaw == graph::HullFlaw::TooFar
                                       ? "the physics is single precision: model the plant within 100 km"
                                       : "a hull needs four points not in one plane (points within 1 µm count as one)"});
            ok = false;
        }
        if (ok) {  // the same points as a hull before it (the same object again): those rows
            std::vector<double> key;
            key.reserve(3 * points.size());
            for (const graph::Point& pt : points) key.insert(key.end(), std::begin(pt.p), std::end(pt.p));
            const auto [at, fresh] = el.hulls_.try_emplace(std::move(key), sh.point_adr);
            if (!fresh) {
                g.points.resize(graph::index(sh.point_adr));
                sh.point_adr = at->second;
            }
        }
    } else {
        auto& d = el.sink_.report(DiagId::BadShape, sd.kind.span, fmt::format("unknown shape '{}'", k));
        if (auto hint = closest_name(k, {"box", "sphere", "cylinder", "capsule", "hull"}); !hint.empty())
            d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
        else
            d.notes.push_back({{}, "shapes: box, sphere, cylinder, capsule, hull"});
        ok = false;
    }
    if (ok) g.shapes.push_back(sh);
}

void lower(Lowering& lw) {
    Elaborator& el = lw.el;
    graph::Graph& g = lw.el.g_;
    const ast::ComponentDecl& c = lw.decl;
    graph::Body b;
    b.comp = lw.comp;
    b.mode = lw.mode == "static" ? graph::BodyMode::Static
           : lw.mode == "kinematic" ? graph::BodyMode::Kinematic : graph::BodyMode::Dynamic;
    b.mass = lw.num("mass", 0);
    if (b.mode == graph::BodyMode::Dynamic && !lw.props.has("mass"))
        el.sink_.report(DiagId::MissingProperty, c.name.span,
                        fmt::format("dynamic body '{}' needs a 'mass'", c.name.text));
    lw.positive("mass");
    if (const Value* in = lw.props.get("inertia")) {
        b.inertia = vec(*in);
        b.inertia_set = true;
        lw.positive_vec("inertia");
    }
    b.friction = lw.num("friction", 0.5);
    b.restitution = lw.num("restitution", 0);
    b.linear_damping = lw.num("linear_damping", 0);
    b.angular_damping = lw.num("angular_damping", 0);
    for (const char* n : {"friction", "restitution", "linear_damping", "angular_damping"})
        if (const Value* v = lw.props.get(n); v && v->num < 0)
            el.sink_.report(DiagId::OutOfRange, v->span, fmt::format("'{}' cannot be negative", n));
    // What Bullet would clamp or ignore (graph/range.h), refused here as the loader refuses it.
    for (const char* n : {"linear_damping", "angular_damping"})
        if (const Value* v = lw.props.get(n); v && v->num > graph::kMaxDamping)
            el.sink_.report(DiagId::OutOfRange, v->span,
                            fmt::format("'{}' is {:g}, above 1: damping lies in [0, 1] (Bullet would clamp it to 1)", n, v->num));
    if (const Value* v = lw.props.get("friction"); v && v->num > graph::kMaxFriction)
        el.sink_.report(DiagId::OutOfRange, v->span,
                        fmt::format("'friction' is {:g}, above 10: Bullet caps a contact's friction (the product of "
                                    "the two bodies') at 10",
                                    v->num));
    if (b.mode != graph::BodyMode::Dynamic)
        for (const char* n : {"mass", "inertia", "linear_damping", "angular_damping"})
            if (const Value* v = lw.props.get(n))
                el.sink_.report(DiagId::UnknownProperty, v->span,
                                fmt::format("a {} body has no '{}': Bullet moves it by its pose alone and would ignore "
                                            "it (only a dynamic body has one)",
                                            b.mode == graph::BodyMode::Static ? "static" : "kinematic", n));
    b.collision = lw.boolean("collision", true);
    b.dynamics = lw.boolean("dynamics", true);
    b.pose = lw.frame.pose();
    b.shape_adr = graph::next_adr(g.shapes);
    for (const auto& sd : c.shapes) lower_shape(lw, sd);
    b.shape_num = graph::rows_since(g.shapes, b.shape_adr);
    if (c.shapes.empty())
        el.sink_.report(DiagId::MissingProperty, c.name.span,
                        fmt::format("body '{}' needs at least one shape, e.g. shape box(10 cm, 10 cm, 1 cm)", c.name.text));
    lw.set_detail(g.bodies.push_back(b));
    // Output values start at the body's pose.
    auto put = [&](int idx, std::initializer_list<double> xs) {
        const graph::Adr<graph::Value> adr = g.slots[lw.slot_adr + idx].value_adr;
        int k = 0;
        for (double x : xs) g.values[adr + k++].v = x;
    };
    put(graph::bodyslot::pose, {b.pose.p[0], b.pose.p[1], b.pose.p[2], b.pose.q[0], b.pose.q[1], b.pose.q[2], b.pose.q[3]});
    put(graph::bodyslot::position, {b.pose.p[0], b.pose.p[1], b.pose.p[2]});
    put(graph::bodyslot::orientation, {b.pose.q[0], b.pose.q[1], b.pose.q[2], b.pose.q[3]});
}

}  // namespace

constexpr KindLowering lowering{.lower = lower};

}  // namespace plant::kinds::body
