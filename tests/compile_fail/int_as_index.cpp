// A table is indexed by its own id and by nothing else (graph/ids.h: IdVector): compiled by
// the ctests table_by_id (as it is: it compiles) and table_by_int (with PLANT_INT, which
// indexes the bodies by a plain integer: it must not compile).
#include "graph/graph.h"

namespace plant::graph {

double first_mass(const Graph& g) {
#ifdef PLANT_INT
    return g.bodies[0].mass;
#else
    return g.bodies[BodyId(0)].mass;
#endif
}

}  // namespace plant::graph
