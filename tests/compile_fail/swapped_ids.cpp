// Typed ids hold at the graph-building API (graph/build.h): compiled by the ctests
// typed_ids_hold (as it is: it compiles) and typed_ids_swapped (with PLANT_SWAP, which passes
// the parent DoId and the DoTypeId to add_do the other way round: it must not compile).
#include "graph/build.h"

namespace plant::graph {

DoId add_child(Graph& g, DoId parent, DoTypeId type) {
#ifdef PLANT_SWAP
    return add_do(g, "child", type, parent, Pose{});
#else
    return add_do(g, "child", parent, type, Pose{});
#endif
}

}  // namespace plant::graph
