// The exit's behaviour: its `object` starts empty; in phase 2 it takes every object inside
// its trigger out of the world (back into its source's pool: engine/objects.cpp).
#include "engine/plugin.h"
#include "engine/runtime.h"

#include "graph/kinds.h"

namespace plant::kinds::exit {

using namespace plant::engine;
namespace slot = plant::graph::exitslot;

namespace {

void take(Runtime& r, graph::ExitId e, graph::DoId obj) {
    const graph::DoId root = take_object(r, obj);
    if (!root.valid()) return;
    const graph::Adr<graph::Slot> s0 = r.g.comps[r.g.exits[e].comp].slot_adr;
    r.activate(s0 + slot::taken);
    r.emit(s0 + slot::object, root.v);
    r.emit(s0 + slot::id, object_id(r, root));
    r.emit(s0 + slot::taken_count, double(++r.st.exit_count[e]));
}

void start_all(Runtime& r) {
    for (const graph::Exit& e : r.g.exits) *r.val(r.comp_slot(e.comp, slot::object)) = -1;
}

void sense_all(Runtime& r) {
    for (graph::ExitId e : ids_of(r.g.exits)) {
        const graph::TriggerId t = r.tab.exit_trigger[e];
        if (!t.valid() || !r.st.trigger_occupied[t]) continue;  // packed: no look at an empty trigger's state
        for (const graph::DoId obj : r.st.inside(r.st.triggers[t])) take(r, e, obj);
    }
}

}  // namespace

constexpr KindBehaviour behaviour{.start_all = start_all, .sense_all = sense_all};

}  // namespace plant::kinds::exit
