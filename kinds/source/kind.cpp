// The source's row of the kind table (graph/plugin.h): what the compiler, the loader, the
// language server and the docs know of it.
#include "graph/kinds.h"
#include "graph/plugin.h"

#include <fmt/format.h>

namespace plant::kinds::source {

using namespace plant::graph;

namespace {

constexpr SlotSpec kSlots[] = {PLANT_SLOTS_SOURCE(PLANT_SLOT_SPEC)};
constexpr ParamSpec kParams[] = {
    {"object", ParamType::Type, "", true, 0, "object type issued, e.g. Bottle(mass = 40 g)"},
    {"pool", ParamType::Int, "", true, 0, "objects pre-built at compile time"},
    {"rate", ParamType::Number, "Hz", false, 0, "issues per second; 0 (default): only on 'issue'"},
    {"ids", ParamType::StringList, "", false, 0, "bar codes handed out in turn; default NAME-1 ... NAME-pool"},
};

// Its pool: the DOs the compiler built for it, each a pooled object of its type.
bool check(const Graph& g, int32_t row, PluginProblem& problem) {
    const Source& s = g.sources[SourceId(row)];
    if (s.rate < 0) {
        problem.message = "field 'rate' is negative";
        return false;
    }
    for (DoId pooled : children(s.pool_adr, s.pool_num)) {
        const Do& d = g.dos[pooled];
        if (d.pool != s.comp || d.type != s.do_type) {
            problem.message = fmt::format("DO {} in its pool is not a pooled {} of this source", pooled,
                                          std::string(g.str(g.do_types[s.do_type].name)));
            return false;
        }
    }
    return true;
}

}  // namespace

constexpr KindDesc desc{
    .word = "source",
    .doc = "issues objects of a type into the plant, from a pool built at compile time",
    .slots = kSlots,
    .params = kParams,
    .check = check,
    .placed = true,  // where it issues its objects
    .kind = CompKind::Source,
    PLANT_KIND_TABLE(sources),
    .idle_input = sourceslot::issue,
    .runs_alone = [](const Graph& g, int32_t row) { return g.sources[SourceId(row)].rate > 0; },
    .idle_warning = "source '{}' never issues: its rate is 0 and nothing drives 'issue'",
};

}  // namespace plant::kinds::source
