// The label's behaviour at the start: its value is published once. Its `set` is read by
// the logic phase (engine/logic.cpp), so it has no act hook.
#include "engine/plugin.h"
#include "engine/runtime.h"

#include "graph/kinds.h"

namespace plant::kinds::label {

using namespace plant::engine;

namespace {

void start_all(Runtime& r) {
    for (const graph::Label& l : r.g.labels) r.emit(r.comp_slot(l.comp, graph::labelslot::value), l.value.id);
}

}  // namespace

constexpr KindBehaviour behaviour{.start_all = start_all};

}  // namespace plant::kinds::label
