// The label's lowering: a row of `labels` with its text, which is also its `value`'s start.
#include "sema/kinds/lowering.h"

#include "graph/build.h"
#include "graph/kinds.h"

namespace plant::kinds::label {

namespace {

void lower(sema::Lowering& lw) {
    graph::Graph& g = lw.el.g_;
    const sema::Value* v = lw.props.get("value");
    graph::Label l{lw.comp, lw.el.name(v ? v->str : "")};
    lw.set_detail(g.labels.push_back(l));
    graph::slot_value(g, lw.slot_adr + graph::labelslot::value) = l.value.id;
}

}  // namespace

constexpr sema::KindLowering lowering{.lower = lower};

}  // namespace plant::kinds::label
