// The gripper's lowering: a row of `grippers`; its linking: the trigger it grips from (its
// `object` slot is typed by the trigger's) and the body or graphics it is `on`.
#include "sema/kinds/lowering.h"

#include "graph/graph.h"
#include "graph/kinds.h"

namespace plant::kinds::gripper {

using namespace plant::sema;

namespace {

void lower(Lowering& lw) {
    graph::Graph& g = lw.el.g_;
    graph::Gripper gr;
    gr.comp = lw.comp;
    gr.trigger = {};
    gr.body = {};
    gr.graphics = {};
    lw.set_detail(g.grippers.push_back(gr));
}

// A gripper holds what its trigger caught: its `object` slot is typed by the trigger's.
void link(Linking& lk) {
    graph::Graph& g = lk.el.g_;
    auto& gr = g.grippers[lk.row<graph::Gripper>()];
    if (const auto* p = lk.prop("trigger"); p && !lk.ref_name(*p).empty()) {
        gr.trigger = lk.find<graph::Trigger>(lk.ref_name(*p), p->value->span, "'trigger'");
        if (gr.trigger.valid()) {
            const graph::SlotId tslot = g.comps[g.triggers[gr.trigger].comp].slot_adr + graph::triggerslot::object;
            if (auto it = lk.el.ref_types_.find(tslot); it != lk.el.ref_types_.end())
                lk.el.ref_types_[lk.rec.slot_adr + graph::gripperslot::object] = it->second;
        }
    }
    if (lk.decl.on) {
        auto it = lk.scope.comps.find(lk.on);
        if (it != lk.scope.comps.end() && g.comps[it->second].kind == graph::CompKind::Graphics)
            gr.graphics = graph::detail_of<graph::Graphics>(g.comps[it->second]);
        else
            gr.body = lk.on_body();
    }
}

}  // namespace

constexpr KindLowering lowering{.lower = lower, .link = link};

}  // namespace plant::kinds::gripper
