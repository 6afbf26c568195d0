// The constraint's lowering: a row of `joints` from its mode, limits, axis and frame; its
// linking: the bodies `a` and `b` it joins, and the joint frame relative to each.
#include "sema/kinds/lowering.h"

#include "graph/graph.h"
#include "graph/range.h"

#include <fmt/format.h>

namespace plant::kinds::constraint {

using namespace plant::sema;

namespace {

void lower(Lowering& lw) {
    Elaborator& el = lw.el;
    graph::Graph& g = lw.el.g_;
    const ast::ComponentDecl& c = lw.decl;
    graph::Joint j;
    j.comp = lw.comp;
    j.kind = lw.mode == "hinge" ? graph::JointKind::Hinge : lw.mode == "slider" ? graph::JointKind::Slider : graph::JointKind::Fixed;
    j.body_a = j.body_b = {};
    j.lower = 1;
    j.upper = -1;  // free unless limited
    units::Dim want = j.kind == graph::JointKind::Slider ? units::dims::length : units::dims::angle;
    int limits = 0, written = 0;  // valid ones; written ones (a wrong one is reported once)
    for (const char* n : {"lower", "upper"})
        if (lw.props.has(n)) ++written;
    for (const char* n : {"lower", "upper"})
        if (const Value* v = lw.props.get(n)) {
            if (j.kind == graph::JointKind::Fixed)
                el.sink_.report(DiagId::UnknownProperty, v->span, fmt::format("a fixed constraint has no '{}' limit", n));
            else if (el.ev_.expect_number(*v, want, fmt::format("'{}'", n)))
                (std::string(n) == "lower" ? j.lower : j.upper) = v->num, ++limits;
        }
    if (written == 1 && j.kind != graph::JointKind::Fixed)
        el.sink_.report(DiagId::LimitsIncomplete, c.name.span,
                        fmt::format("constraint '{}' has one limit; give both 'lower' and 'upper', or neither for a free joint",
                                    c.name.text));
    else if (limits == 2 && j.lower > j.upper)
        el.sink_.report(DiagId::LimitsIncomplete, lw.props.get("lower")->span,
                        fmt::format("'lower' ({} {}) is above 'upper' ({} {})", j.lower, units::si_unit(want), j.upper,
                                    units::si_unit(want)));
    else if (limits == 2 && j.kind == graph::JointKind::Hinge && j.upper - j.lower > graph::kMaxHingeSpan)
        el.sink_.report(DiagId::OutOfRange, lw.props.get("upper")->span,
                        fmt::format("the limits span {:g} deg, more than a turn: Bullet's hinge would then have no "
                                    "limit (give a span of at most 360 deg, or no limits for a free hinge)",
                                    (j.upper - j.lower) * 180 / 3.141592653589793));
    // The joint lw.frame: its z axis is the hinge axis, its x axis the slider axis.
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    if (const Value* av = lw.props.get("axis")) {
        axis = Eigen::Vector3d(av->items[0].num, av->items[1].num, av->items[2].num);
        if (axis.norm() < 1e-12) {
            el.sink_.report(DiagId::ZeroVector, av->span, "'axis' is the zero vector");
            axis = Eigen::Vector3d::UnitZ();
        }
    }
    Eigen::Vector3d base = j.kind == graph::JointKind::Slider ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ();
    Frame jf = lw.frame;
    jf.q = (lw.frame.q * Eigen::Quaterniond::FromTwoVectors(base, axis.normalized())).normalized();
    j.frame_a = jf.pose();  // world for now; made relative in link_component
    j.frame_b = jf.pose();
    j.enabled = lw.boolean("enabled", true);
    lw.set_detail(g.joints.push_back(j));
}

// The joint frame, in world coordinates until now, becomes relative to each body.
void link(Linking& lk) {
    graph::Graph& g = lk.el.g_;
    auto& j = g.joints[lk.row<graph::Joint>()];
    auto body_frame = [&](graph::BodyId body) {
        const auto& p = g.bodies[body].pose;
        Frame f;
        f.p = Eigen::Vector3d(p.p[0], p.p[1], p.p[2]);
        f.q = Eigen::Quaterniond(p.q[3], p.q[0], p.q[1], p.q[2]);
        return f;
    };
    Frame world;
    world.p = Eigen::Vector3d(j.frame_a.p[0], j.frame_a.p[1], j.frame_a.p[2]);
    world.q = Eigen::Quaterniond(j.frame_a.q[3], j.frame_a.q[0], j.frame_a.q[1], j.frame_a.q[2]);
    if (const auto* p = lk.prop("a"); p && !lk.ref_name(*p).empty())
        j.body_a = lk.find<graph::Body>(lk.ref_name(*p), p->value->span, "'a'");
    if (const auto* p = lk.prop("b"); p && !lk.ref_name(*p).empty())
        j.body_b = lk.find<graph::Body>(lk.ref_name(*p), p->value->span, "'b'");
    if (j.body_a.valid()) j.frame_a = (body_frame(j.body_a).inverse() * world).pose();
    if (j.body_b.valid()) j.frame_b = (body_frame(j.body_b).inverse() * world).pose();
    if (j.body_a.valid() && j.body_a == j.body_b)
        lk.el.sink_.report(DiagId::OutOfRange, lk.decl.name.span, "a constraint needs two different bodies");
}

}  // namespace

constexpr KindLowering lowering{.lower = lower, .link = link};

}  // namespace plant::kinds::constraint
