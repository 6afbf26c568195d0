// A constraint's behaviour: `enabled` is published at the start, and in phase 5 it is
// switched off and on (the joint itself lives in Bullet, physics.cpp).
#include "engine/runtime.h"

#include "graph/kinds.h"

namespace plant::engine {

using namespace plant::graph;

void start_joints(Runtime& r) {
    for (const Joint& j : r.g.joints) r.emit(r.comp_slot(j.comp, jointslot::enabled), j.enabled ? 1 : 0);
}

void act_joint(Runtime& r, const Comp& c, int32_t i) {
    const uint8_t* a = r.st.act.data() + c.slot_adr;
    if (a[jointslot::disable]) r.phys.set_joint(i, false);
    if (a[jointslot::enable]) r.phys.set_joint(i, true);
    r.emit(c.slot_adr + jointslot::enabled, r.phys.joint_on(i) ? 1 : 0);
}

}  // namespace plant::engine
