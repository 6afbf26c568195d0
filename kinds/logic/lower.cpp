// The connector's lowering. A connector is declared by a form of its own (its row's
// own_form), `logic NAME = [not] PATH { and [not] PATH }` (or `or`), so it has no
// KindLowering::lower over a component declaration: make_logic makes the component, its
// void input per term and its row of `logics` when the object's members are made, and
// connect_logic resolves its terms into flows to those inputs once every component of the
// object exists (as a kind's linking would).
#include "sema/kinds/lowering.h"

#include "graph/build.h"
#include "graph/kinds.h"

#include <fmt/format.h>

namespace plant::sema {

using graph::CompKind;
using graph::Dir;
using graph::SlotType;

void Elaborator::make_logic(Scope& sc, const ast::LogicDecl& l) {
    name_declared(l.name.span);
    if (!declare(sc, l.name.text, l.name.span)) return;
    const graph::CompId comp = graph::add_comp(g_, sc.do_id, CompKind::Logic, l.name.text, src(l.name.span));
    sc.comps[l.name.text] = comp;
    comp_spans_[comp] = l.name.span;
    graph::Logic lg;
    lg.comp = comp;
    lg.op = graph::LogicOp::And;
    lg.out_slot = g_.comps[comp].slot_adr + graph::logicslot::out;
    for (size_t i = 0; i < l.ops.size(); ++i) {
        if (l.ops[i].text != l.ops[0].text) {
            sink_.report(DiagId::LogicMixedOps, l.ops[i].span,
                         "a connector is either 'and' or 'or'; split it into two logic declarations");
            break;
        }
    }
    if (!l.ops.empty() && l.ops[0].text == "or") lg.op = graph::LogicOp::Or;
    lg.in_adr = graph::next_adr(g_.logic_inputs);
    for (size_t i = 0; i < l.terms.size(); ++i) {
        const graph::SlotId s = add_slot(comp, fmt::format("in{}", i), SlotType::Void, Dir::In, l.terms[i].span);
        g_.logic_inputs.push_back({s, l.terms[i].negated});
    }
    lg.in_num = graph::count_of(l.terms);
    g_.comps[comp].detail = graph::Detail(graph::next_id(g_.logics));
    g_.logics.push_back(lg);
}

void Elaborator::connect_logic(Scope& s, const ast::LogicDecl& l, const Env& env) {
    auto it = s.comps.find(l.name.text);
    // Only the connector this declaration made: a duplicate name was reported and made none.
    if (it == s.comps.end() || g_.comps[it->second].kind != CompKind::Logic ||
        comp_spans_[it->second].begin != l.name.span.begin || comp_spans_[it->second].file != l.name.span.file)
        return;
    const auto& lg = g_.logics[graph::detail_of<graph::Logic>(g_.comps[it->second])];
    for (size_t i = 0; i < l.terms.size(); ++i) {
        Endpoint e = resolve(s.do_id, l.terms[i].path, env);
        if (!e.ok) continue;
        if (e.ref_slot.valid() || e.dir != Dir::Out || e.type != SlotType::Void) {
            sink_.report(DiagId::LogicInputNotVoid, l.terms[i].path.span,
                         fmt::format("a connector combines void outputs (events), but '{}' is {} {}", e.text,
                                     with_article(graph::word(e.type)),
                                     e.ref_slot.valid() ? "dynamic slot" : dir_word(e.dir)));
            continue;
        }
        emit_flow(e.slots, {g_.logic_inputs[lg.in_adr + i].slot}, {}, {}, graph::Cond::Source,
                  false, l.terms[i].span);
    }
}

}  // namespace plant::sema

namespace plant::kinds::logic {

constexpr sema::KindLowering lowering{};  // made by its own form: Elaborator::make_logic

}  // namespace plant::kinds::logic
