// A component's detail is its row in the table of its kind, read through that table's id
// (graph.h: detail_of<Timer>(comp)): compiled by the ctests detail_typed (as it is: it
// compiles), detail_as_index (with PLANT_RAW, which indexes the timers by the detail
// itself, as an integer: it must not compile) and detail_vs_int (with PLANT_CMP, which
// compares the detail with a number instead of asking valid(): it must not compile).
#include "graph/graph.h"

namespace plant::graph {

double timer_period(const Graph& g, const Comp& c) {
#if defined(PLANT_RAW)
    return g.timers[c.detail].period;
#elif defined(PLANT_CMP)
    return c.detail >= 0 ? g.timers[detail_of<Timer>(c)].period : 0.0;
#else
    return c.detail.valid() ? g.timers[detail_of<Timer>(c)].period : 0.0;
#endif
}

}  // namespace plant::graph
