// The state's row of the kind table (graph/plugin.h): what the compiler, the loader, the
// language server and the docs know of it.
#include "graph/kinds.h"
#include "graph/plugin.h"
#include "graph/validate.h"

#include <fmt/format.h>

namespace plant::kinds::state {

using namespace plant::graph;

namespace {

// The loader's check of its places, transitions and arcs.
bool check_tables(const Graph& g, GraphProblem& problem) {
    auto of_state = [&](CompId c) { return g[c].kind == CompKind::State; };
    // Each arc's transition's component: a net's arcs are on its own places (the runtime steps
    // each net on its own, engine/petri.cpp).
    IdVector<Id<Arc>, CompId> arc_comp(g.arcs.count(), CompId{});
    for (const Transition& t : g.transitions)
        for (const auto& [adr, num] : {std::pair{t.in_adr, t.in_num}, std::pair{t.out_adr, t.out_num}})
            for (int32_t k = 0; k < num; ++k) arc_comp[adr + k] = t.comp;
    return each_record(g.places, problem, [&](const Place& p) {
        if (!of_state(p.comp)) return std::string("field 'comp' is not a state component");
        if (!(p.initial >= 0 && p.initial <= kMaxInitialTokens))
            return fmt::format("field 'initial' must lie in [0, {}]", kMaxInitialTokens);
        std::string flaw = slot_flaw(g, "put_slot", p.put_slot, SlotType::Void, Dir::In);
        if (flaw.empty()) flaw = slot_flaw(g, "entered_slot", p.entered_slot, SlotType::Void, Dir::Out);
        if (flaw.empty()) flaw = slot_flaw(g, "tokens_slot", p.tokens_slot, SlotType::Int, Dir::Out);
        return flaw;
    }) && each_record(g.transitions, problem, [&](const Transition& t) {
        if (!of_state(t.comp)) return std::string("field 'comp' is not a state component");
        if (t.in_num <= 0) return std::string("a transition needs an input place (it would fire in every step)");
        return slot_flaw(g, "fired_slot", t.fired_slot, SlotType::Void, Dir::Out);
    }) && each_record(g.arcs, problem, [&](const Arc& a) {
        return a.weight >= 1 && a.weight <= kMaxArcWeight ? std::string()
                                                          : fmt::format("field 'weight' must lie in [1, {}]", kMaxArcWeight);
    }) && [&] {
        for (Id<Arc> i : g.arcs.ids())
            if (arc_comp[i].valid() && g.places[g.arcs[i].place].comp != arc_comp[i]) {
                problem = {std::string(table_name<Arc>()), i.v,
                           fmt::format("field 'place' = {}: a place of another state component than its transition's",
                                       g.arcs[i].place)};
                return false;
            }
        return true;
    }();
}

}  // namespace

constexpr KindDesc desc{
    .word = "state",
    .doc = "a Petri net: places holding tokens and transitions that move them",
    .slots = {},
    .params = {},
    .kind = CompKind::State,
    .blocks = kPlaces,
    .check_tables = check_tables,
};

}  // namespace plant::kinds::state
