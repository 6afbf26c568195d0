// The router's behaviour: none of its own hooks. Its `query` is read by the logic phase,
// which fires the first route whose pattern matches (a node of the logic network:
// graph/network.h, engine/logic.cpp), so it has no act hook and its input never acts in
// phase 5.
#include "engine/plugin.h"

namespace plant::kinds::router {

constexpr engine::KindBehaviour behaviour{};

}  // namespace plant::kinds::router
