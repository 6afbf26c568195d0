// An id does not read as a number unless asked (graph/ids.h: TypedId's explicit conversion):
// compiled by the ctests id_as_number (as it is: it compiles, reading `.v`) and, each with
// one define, id_to_int_param (an id passed for an int32_t), id_to_int_init (an int32_t
// initialised from an id), id_plus_int (arithmetic on an id) and id_as_vector_index (an id
// indexing a std::vector): none of them may compile.
#include <cstdint>
#include <vector>

#include "graph/graph.h"

namespace plant::graph {

namespace {
int32_t twice(int32_t n) { return 2 * n; }
}  // namespace

int32_t numbers(const Graph& g, SlotId s, const std::vector<double>& values) {
    int32_t sum = 0;
#if defined(PLANT_PARAM)
    sum += twice(s);
#elif defined(PLANT_INIT)
    const int32_t n = s;
    sum += n;
#elif defined(PLANT_PLUS)
    sum += s + 1;
#elif defined(PLANT_VECTOR)
    sum += int32_t(values[s]);
#else
    sum += twice(s.v) + s.v + 1 + int32_t(values[size_t(s.v)]);
#endif
    return sum + int32_t(g.slots.size());
}

}  // namespace plant::graph
