// What the kinds share about bodies (docs/runtime.md): whether an active input's value may
// move the physics, and taking a body out of the world (an object that left it, an exit or
// a trainee's hand taking it back to its pool). The body's own behaviour (its sensing in
// phase 2, its acting in phase 5) is the kind table's: kinds/body/run.cpp.
#include "engine/runtime.h"

#include "graph/range.h"

#include <atomic>

namespace plant::engine {

using namespace plant::graph;

// Only the plant's logic can send a value out of range: events are refused when read.
bool input_in_range(Runtime& r, const graph::Comp& c, graph::SlotId slot) {
    if (graph::input_range(r.g, c, slot, r.val(slot)).empty()) return true;
    // Counted by the jobs of phase 5 too (components acting alone, actuators.cpp): the same sum in any order.
    std::atomic_ref(r.st.warn.out_of_range).fetch_add(1, std::memory_order_relaxed);
    return false;
}

void take_body_out(Runtime& r, BodyId b) {
    const GripperId gr = r.st.held_by[b];
    r.st.held_by[b] = GripperId{};
    if (gr.valid()) {  // a gripper loses what it held when it is taken away
        bool any = false;
        for (BodyId x : r.tab.do_bodies[r.st.gripper_held[gr]])
            any = any || r.st.held_by[x] == gr;
        if (!any) r.st.gripper_held[gr] = DoId{};
    }
    r.st.cmd_lin[b] = Vec3{0, 0, 0};
    r.st.cmd_ang[b] = Vec3{0, 0, 0};
    r.phys.take_out(b);
}

}  // namespace plant::engine
