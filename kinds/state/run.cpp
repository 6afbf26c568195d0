// The state's behaviour at the start: each place's tokens are published once. Its nets
// step in phase 4 (engine/petri.cpp: puts, then every enabled transition fires), which
// reads the places' `put` inputs, so it has no act hook.
#include "engine/plugin.h"
#include "engine/runtime.h"

namespace plant::kinds::state {

using namespace plant::engine;

namespace {

void start_all(Runtime& r) {
    for (graph::PlaceId p : graph::ids_of(r.g.places))
        if (r.g.places[p].tokens_slot.valid()) r.emit(r.g.places[p].tokens_slot, double(r.st.tokens[p]));
}

}  // namespace

constexpr KindBehaviour behaviour{.start_all = start_all};

}  // namespace plant::kinds::state
