// The router's lowering: one output per named entry of its table (`route NAME: PATTERN`),
// and a row of `routes` per pattern, in order.
#include "sema/kinds/lowering.h"

#include "graph/build.h"
#include "graph/kinds.h"

#include <fmt/format.h>

namespace plant::kinds::router {

using namespace plant::sema;
using graph::Dir;
using graph::SlotType;

namespace {

void lower(Lowering& lw) {
    Elaborator& el = lw.el;
    graph::Graph& g = lw.el.g_;
    const ast::ComponentDecl& c = lw.decl;
    const Env& env = lw.env;
    std::map<std::string, graph::SlotId> outs;
    for (const auto& r : c.routes) {
        auto it = outs.find(r.output.text);
        if (it == outs.end()) {
            if (graph::fixed_slot_index(graph::CompKind::Router, r.output.text) >= 0) {
                el.sink_.report(DiagId::DuplicateName, r.output.span,
                                fmt::format("'{}' is the router's own input; name the entry otherwise", r.output.text));
                continue;
            }
            it = outs.emplace(r.output.text, el.add_slot(lw.comp, r.output.text, SlotType::Void, Dir::Out, r.output.span)).first;
        }
        if (!r.pattern_expr) {
            g.routes.push_back({lw.comp, el.name("*"), it->second});
            continue;
        }
        // A string, or a list of strings (one entry each), from parameters and lets too.
        Value v = el.ev_.eval(*r.pattern_expr, env);
        if (v.kind == Value::Kind::None) continue;
        std::vector<Value> patterns = v.kind == Value::Kind::List ? v.items : std::vector<Value>{v};
        if (patterns.empty())
            el.sink_.report(DiagId::ValueTypeMismatch, r.pattern_span,
                            "a routing entry needs at least one pattern; this list is empty");
        for (const Value& pv : patterns) {
            if (!el.ev_.expect_string(pv, "a routing pattern")) break;
            g.routes.push_back({lw.comp, el.name(pv.str), it->second});
        }
    }
}

}  // namespace

constexpr KindLowering lowering{.lower = lower};

}  // namespace plant::kinds::router
