// The constraint's behaviour: `enabled` is published at the start, and in phase 5 it is
// switched off and on (the joint itself lives in Bullet, engine/physics.cpp).
#include "engine/plugin.h"
#include "engine/runtime.h"

#include "graph/kinds.h"

namespace plant::kinds::constraint {

using namespace plant::engine;
using graph::constraintslot::disable, graph::constraintslot::enable, graph::constraintslot::enabled;

namespace {

void start_all(Runtime& r) {
    for (const graph::Joint& j : r.g.joints) r.emit(r.comp_slot(j.comp, enabled), j.enabled ? 1 : 0);
}

void act_one(Runtime& r, const graph::Comp& c) {
    const graph::JointId i = graph::detail_of<graph::Joint>(c);
    const uint8_t* a = r.st.act.slice(c.slot_adr, c.slot_num).data();
    if (a[disable]) r.phys.set_joint(i, false);
    if (a[enable]) r.phys.set_joint(i, true);
    r.emit(c.slot_adr + enabled, r.phys.joint_on(i) ? 1 : 0);
}

}  // namespace

constexpr KindBehaviour behaviour{.start_all = start_all, .act_one = act_one};

}  // namespace plant::kinds::constraint
