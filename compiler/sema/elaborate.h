// Program (parsed modules) -> checked flat graph. Reports every error it can find.
#pragma once

#include "diag/diagnostic.h"
#include "graph/graph.h"
#include "sema/modules.h"

namespace plant::sema {

graph::Graph elaborate(const Program& prog, const SourceMap& sources, Sink& sink);

}  // namespace plant::sema
