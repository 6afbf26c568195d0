// The connector's behaviour: none of its own in the step's phases. It is a node of the logic
// network (graph/network.h), which the logic phase evaluates (engine/logic.cpp) with the
// labels' and routers' operations: its inputs are never read by phase 5 (tables.cpp:
// slot_in).
#include "engine/plugin.h"

namespace plant::kinds::logic {

constexpr engine::KindBehaviour behaviour{};

}  // namespace plant::kinds::logic
