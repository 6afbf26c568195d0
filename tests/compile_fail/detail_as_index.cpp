// A component's detail is its row in the table of its kind, read through that table's id
// (graph.h: detail_of<Timer>(comp)): compiled by the ctests detail_typed (as it is: it
// compiles) and detail_as_index (with PLANT_RAW, which indexes the timers by the detail
// itself, as an integer: it must not compile).
#include "graph/graph.h"

namespace plant::graph {

double timer_period(const Graph& g, const Comp& c) {
#ifdef PLANT_RAW
    return g.timers[c.detail].period;
#else
    return g.timers[detail_of<Timer>(c)].period;
#endif
}

}  // namespace plant::graph
