// The field's lowering: a row of `fields` from its box, direction, speed, gain, slip limit
// and whether it starts enabled, posed where it is placed; its outputs start at the speed it
// drives at and whether it is enabled. Its linking: the body it is `on`.
#include "sema/kinds/lowering.h"

#include "graph/build.h"
#include "graph/kinds.h"

namespace plant::kinds::field {

using namespace plant::sema;

namespace {

void lower(Lowering& lw) {
    Elaborator& el = lw.el;
    graph::Graph& g = lw.el.g_;
    graph::Field f;
    f.comp = lw.comp;
    f.body = {};
    if (const Value* e = lw.props.get("extent")) f.extent = vec(*e);
    lw.positive_vec("extent");
    f.pose = lw.frame.pose();
    f.dir = {1, 0, 0};
    if (const Value* dv = lw.props.get("direction")) {
        Eigen::Vector3d d(dv->items[0].num, dv->items[1].num, dv->items[2].num);
        if (d.norm() < 1e-12) el.sink_.report(DiagId::ZeroVector, dv->span, "'direction' is the zero vector");
        else d.normalize();
        f.dir = {d.x(), d.y(), d.z()};
    }
    f.speed = lw.num("speed", 0);
    f.gain = lw.num("gain", 0);
    lw.positive("gain");
    f.max_force = lw.num("max_force", 0);  // 0 in the graph: unlimited
    lw.positive("max_force");
    f.enabled = lw.boolean("enabled", true);
    // A turning field drives along both horizontal axes of its frame, towards the band's rigid
    // rotation about its pivot: no direction of its own.
    f.radius = lw.num("radius", 0);
    lw.positive("radius");
    f.pivot = {0, 0, 0};
    if (const Value* pv = lw.props.get("pivot")) f.pivot = vec(*pv);
    if (f.radius > 0) {
        f.dir = {1, 0, 0};
        if (const Value* dv = lw.props.get("direction"))
            el.sink_.report(DiagId::KindCheck, dv->span,
                            "a field with a 'radius' turns, and drives along both horizontal axes: it takes no 'direction'");
    } else if (const Value* pv = lw.props.get("pivot")) {
        el.sink_.report(DiagId::KindCheck, pv->span, "'pivot' is the point a turning field turns about: give it a 'radius' too");
    }
    lw.set_detail(g.fields.push_back(f));
    graph::slot_value(g, lw.slot_adr + graph::fieldslot::speed) = f.enabled ? f.speed : 0;
    graph::slot_value(g, lw.slot_adr + graph::fieldslot::enabled) = f.enabled ? 1 : 0;
}

void link(Linking& lk) {
    if (lk.decl.on) lk.el.g_.fields[lk.row<graph::Field>()].body = lk.on_body();
}

}  // namespace

constexpr KindLowering lowering{.lower = lower, .link = link};

}  // namespace plant::kinds::field
