// Graphviz view of a compiled plant graph (`plant dot`, then `dot -Tsvg`): one
// cluster per DO, components as records whose ports are their slots, flows as
// edges, logic connectors as diamonds and every Petri net as its own cluster.
#pragma once

#include "graph/graph.h"

#include <iosfwd>

namespace plant::dot {

// Writes one `digraph`. Node ids come from table ids, never from names, and the
// output depends only on the graph, so it can be diffed and golden-tested.
void write_dot(const graph::Graph&, std::ostream&);

}  // namespace plant::dot
