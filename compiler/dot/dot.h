// Graphviz view of a compiled plant graph (`plant dot`, then `dot -Tsvg`): one
// cluster per DO, components as records whose ports are their slots, flows as
// edges, logic connectors as diamonds and every Petri net as its own cluster.
#pragma once

#include "graph/graph.h"

#include <iosfwd>
#include <string_view>

namespace plant::dot {

// Writes one `digraph`. Node ids come from table ids, never from names, and the
// output depends only on the graph, so it can be diffed and golden-tested.
void write_dot(const graph::Graph&, std::ostream&);

// The same for one object and what it holds (`plant graph --object PATH`): its cluster and
// the flows with both ends inside it. False when no object has that dotted path.
bool write_dot_object(const graph::Graph&, std::string_view path, std::ostream&);

// An overview (`plant graph`, the default): the children of one object as single nodes
// (`name: Type`), the object's own components as small nodes (a Petri net as one node), and
// the flows between them, bundled per pair of nodes with the slots they join or their
// count. The object is the plant, or the first object below it that holds more than one
// child (a plant that only wraps copies of a line shows the line).
void write_overview(const graph::Graph&, std::ostream&);

}  // namespace plant::dot
