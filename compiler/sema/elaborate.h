// Program (parsed modules) -> checked flat graph. Reports every error it can find.
#pragma once

#include "diag/diagnostic.h"
#include "graph/graph.h"
#include "sema/modules.h"

namespace plant::sema {

// Loops may produce this many members, and run this many iterations, in one compile.
constexpr long long kMaxMembers = 2'000'000;

// Without a plant in the root file and with require_plant false (plant check on a
// library), every object type whose parameters all have defaults is instantiated alone.
graph::Graph elaborate(const Program& prog, const SourceMap& sources, Sink& sink, bool require_plant = true,
                       long long max_members = kMaxMembers);

}  // namespace plant::sema
