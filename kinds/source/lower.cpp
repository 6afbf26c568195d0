// The source's lowering: a row of `sources` with its rate, its pool's size (the DOs are
// built by make_pools once the object is elaborated) and its bar codes.
#include "sema/kinds/lowering.h"

#include "graph/build.h"
#include "graph/kinds.h"

#include <fmt/format.h>

namespace plant::kinds::source {

using namespace plant::sema;

namespace {

constexpr int32_t kMaxPool = 100000;

void lower(Lowering& lw) {
    Elaborator& el = lw.el;
    graph::Graph& g = lw.el.g_;
    const ast::ComponentDecl& c = lw.decl;
    graph::Source s;
    s.comp = lw.comp;
    s.do_type = {};
    s.pose = lw.frame.pose();
    s.rate = lw.num("rate", 0);
    if (const Value* r = lw.props.get("rate"); r && r->num < 0)
        el.sink_.report(DiagId::OutOfRange, r->span, "'rate' cannot be negative");
    int32_t pool = 0;
    if (const Value* p = lw.props.get("pool")) {
        if (p->num < 1 || p->num > kMaxPool)
            el.sink_.report(p->num < 1 ? DiagId::NonPositive : DiagId::LoopTooLarge, p->span,
                            fmt::format("'pool' must be between 1 and {}", kMaxPool));
        else pool = static_cast<int32_t>(p->num);
    }
    s.pool_num = pool;  // the DOs are built by make_pools
    s.pool_adr = {};
    if (const Value* t = lw.props.get("object")) {
        s.do_type = el.do_type(t->str, t->span);
        el.ref_types_[lw.slot_adr + graph::sourceslot::object] = s.do_type;
    }
    s.id_adr = graph::next_adr(g.ids);
    if (const Value* ids = lw.props.get("ids")) {
        for (const auto& it : ids->items) g.ids.push_back({el.name(it.str)});
        if (ids->items.empty()) el.sink_.report(DiagId::OutOfRange, ids->span, "'ids' is empty");
    } else {
        for (int32_t i = 1; i <= pool; ++i) g.ids.push_back({el.name(fmt::format("{}-{}", c.name.text, i))});
    }
    s.id_num = graph::rows_since(g.ids, s.id_adr);
    lw.set_detail(g.sources.push_back(s));
}

}  // namespace

constexpr KindLowering lowering{.lower = lower};

}  // namespace plant::kinds::source
