// The field's behaviour: its outputs are published at the start and whenever they change,
// the speed it drives at (its target while enabled, 0 while not: a stopped belt's band
// stands still) and whether it is enabled; in phase 5 it acts on its inputs. The conveyor
// law it exerts on the bodies in its box is the physics phase's (engine/fields.cpp,
// engine/conveyor.cpp), which reads its target speed and on/off from the shared state.
#include "engine/plugin.h"
#include "engine/runtime.h"

#include "graph/kinds.h"

namespace plant::kinds::field {

using namespace plant::engine;
using graph::FieldId;
namespace slot = plant::graph::fieldslot;

namespace {

void start_all(Runtime& r) {
    for (FieldId f : graph::ids_of(r.g.fields)) {
        const graph::CompId c = r.g.fields[f].comp;
        r.emit(r.comp_slot(c, slot::speed), r.st.field_on[f] ? r.st.field_speed[f] : 0.0);
        r.emit(r.comp_slot(c, slot::enabled), r.st.field_on[f] ? 1.0 : 0.0);
    }
}

void act_one(Runtime& r, const graph::Comp& c) {
    const FieldId i = graph::detail_of<graph::Field>(c);
    const uint8_t* a = r.st.act.slice(c.slot_adr, c.slot_num).data();
    const uint8_t was_on = r.st.field_on[i];
    const double was = was_on ? r.st.field_speed[i] : 0.0;
    if (a[slot::disable]) r.st.field_on[i] = 0;
    if (a[slot::enable]) r.st.field_on[i] = 1;
    if (a[slot::set_speed] && input_in_range(r, c, c.slot_adr + slot::set_speed))
        r.st.field_speed[i] = *r.val(c.slot_adr + slot::set_speed);
    const double now = r.st.field_on[i] ? r.st.field_speed[i] : 0.0;
    if (now != was || a[slot::set_speed]) r.emit(c.slot_adr + slot::speed, now);
    if (r.st.field_on[i] != was_on) r.emit(c.slot_adr + slot::enabled, r.st.field_on[i] ? 1.0 : 0.0);
    if (!r.st.field_is_touched[i]) {  // the physics phase looks at it again (engine/fields.cpp)
        r.st.field_is_touched[i] = 1;
        r.st.field_touched.push_back(i);
    }
}

}  // namespace

constexpr KindBehaviour behaviour{.start_all = start_all, .act_one = act_one};

}  // namespace plant::kinds::field
