// The exit's lowering: a row of `exits`; its linking: the trigger whose objects it takes.
#include "sema/kinds/lowering.h"

#include "graph/graph.h"

namespace plant::kinds::exit {

using namespace plant::sema;

namespace {

void lower(Lowering& lw) {
    graph::Graph& g = lw.el.g_;
    lw.set_detail(g.exits.push_back({lw.comp, {}}));
}

void link(Linking& lk) {
    if (const auto* p = lk.prop("trigger"); p && !lk.ref_name(*p).empty())
        lk.el.g_.exits[lk.row<graph::Exit>()].trigger =
            lk.find<graph::Trigger>(lk.ref_name(*p), p->value->span, "'trigger'");
}

}  // namespace

constexpr KindLowering lowering{.lower = lower, .link = link};

}  // namespace plant::kinds::exit
