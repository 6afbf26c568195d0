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
#include <string_view>
#include <utility>

namespace plant::graph {

struct GraphProblem {
    std::string table;    // the table's member name ("comps"); empty for the settings
    int32_t row = -1;     // the record's id in it
    std::string message;  // e.g. "field 'key_adr' .. 'key_num' (99 + 2) is outside keys (4 rows)"
};

// True when `g` keeps every promise above; otherwise false with the first problem found.
bool validate(const Graph& g, GraphProblem& problem);

// For a kind's own checks (graph/plugin.h, KindDesc::check_tables), which run once every
// id and range is known to be a row of its table: why slot `s`, written in `field`, is not
// of `type` and `dir` ("" when it is, or when it is none).
std::string slot_flaw(const Graph& g, std::string_view field, OptId<Slot> s, SlotType type, Dir dir);
// Each record of `rows` by `flaw(record)`, its first problem ("" for none): false with the
// first record that has one, as `problem` (the table's name and the row).
template <class R, class F>
bool each_record(const Table<R>& rows, GraphProblem& problem, F&& flaw) {
    for (Id<R> i : rows.ids())
        if (std::string why = flaw(rows[i]); !why.empty()) {
            problem = {std::string(table_name<R>()), i.v, std::move(why)};
            return false;
        }
    return true;
}

}  // namespace plant::graph
