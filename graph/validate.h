// What the records of a Graph promise each other, checked before the runtime relies on
// it: every id names a row of its table (or is -1 where "none" is allowed), every
// (adr, num) range lies inside its table, every slot's values lie inside `values`, every
// component has its kind's fixed slots (kinds.h) and points at a record that points back
// at it, flows join slots of the same width, and every number is finite and in its range.
// A graph the compiler wrote always passes; a hand-edited or damaged `.graph` file fails
// here, with the record at fault, instead of crashing the runtime. read_text calls it.
#pragma once

#include "graph.h"

#include <string>

namespace plant::graph {

struct GraphProblem {
    std::string table;    // the table's member name ("comps"); empty for the settings
    int32_t row = -1;     // the record's id in it
    std::string message;  // e.g. "field 'key_adr' .. 'key_num' (99 + 2) is outside keys (4 rows)"
};

// True when `g` keeps every promise above; otherwise false with the first problem found.
bool validate(const Graph& g, GraphProblem& problem);

}  // namespace plant::graph
