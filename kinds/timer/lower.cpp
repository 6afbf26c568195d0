// The timer's lowering: a row of `timers` from its period, its mode and `autostart`.
#include "sema/kinds/lowering.h"

#include "graph/graph.h"

namespace plant::kinds::timer {

namespace {

void lower(sema::Lowering& lw) {
    graph::Graph& g = lw.el.g_;
    graph::Timer t;
    t.comp = lw.comp;
    t.period = lw.num("period", 0);
    lw.positive("period");
    t.periodic = lw.mode != "oneshot";
    t.autostart = lw.boolean("autostart", false);
    lw.set_detail(g.timers.push_back(t));
}

}  // namespace

constexpr sema::KindLowering lowering{.lower = lower};

}  // namespace plant::kinds::timer
