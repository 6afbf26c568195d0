// The router's row of the kind table (graph/plugin.h): what the compiler, the loader, the
// language server and the docs know of it.
#include "graph/kinds.h"
#include "graph/plugin.h"
#include "graph/validate.h"

namespace plant::kinds::router {

using namespace plant::graph;

namespace {

constexpr SlotSpec kSlots[] = {PLANT_SLOTS_ROUTER(PLANT_SLOT_SPEC)};

// The loader's check of its routes: each names a router and one of its own outputs.
bool check_tables(const Graph& g, GraphProblem& problem) {
    return each_record(g.routes, problem, [&](const Route& r) {
        if (g[r.comp].kind != CompKind::Router) return std::string("field 'comp' is not a router");
        return slot_flaw(g, "out_slot", r.out_slot, SlotType::Void, Dir::Out);
    });
}

}  // namespace

constexpr KindDesc desc{
    .word = "router",
    .doc = "a table from ID patterns to outputs: a query fires the first output whose pattern matches",
    .slots = kSlots,
    .params = {},
    .kind = CompKind::Router,
    .blocks = kRoutes,
    .check_tables = check_tables,
    .idle_input = routerslot::query,
    .idle_warning = "router '{}' is never queried: nothing drives its 'query'",
    .unused_output = "route '{}' of router '{}' drives nothing",
};

}  // namespace plant::kinds::router
