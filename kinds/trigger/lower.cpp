// The trigger's lowering: a row of `triggers` with its box and its filter (its `object`
// slot is typed by the filter); its linking: the body it is `on`.
#include "sema/kinds/lowering.h"

#include "graph/graph.h"
#include "graph/kinds.h"

namespace plant::kinds::trigger {

using namespace plant::sema;

namespace {

void lower(Lowering& lw) {
    Elaborator& el = lw.el;
    graph::Graph& g = lw.el.g_;
    graph::Trigger t;
    t.comp = lw.comp;
    t.body = {};
    if (const Value* e = lw.props.get("extent")) t.extent = vec(*e);
    lw.positive_vec("extent");
    t.pose = lw.frame.pose();
    t.filter = {};
    if (const Value* f = lw.props.get("filter")) {
        t.filter = el.do_type(f->str, f->span);
        el.ref_types_[lw.slot_adr + graph::triggerslot::object] = t.filter;
    }
    lw.set_detail(g.triggers.push_back(t));
}

void link(Linking& lk) {
    if (lk.decl.on) lk.el.g_.triggers[lk.row<graph::Trigger>()].body = lk.on_body();
}

}  // namespace

constexpr KindLowering lowering{.lower = lower, .link = link};

}  // namespace plant::kinds::trigger
