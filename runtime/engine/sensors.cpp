// Phase 2: what the world looks like after the physics step, as output activity:
// bodies (outputs, and warnings for bodies that left the world), the kinds on the kind table,
// plugins. Each kind's sensing lives with the rest of its behaviour (runtime.h lists where; a
// kind on the kind table: its kinds/NAME/run.cpp).
#include "engine/runtime.h"
#include "engine/workers.h"

namespace plant::engine {

void phase_sensors(Runtime& r) {
    StepProfile& p = r.phys.workers().profile();
    check_bodies(r);
    sense_bodies(r);
    p.lap(StepProfile::Bodies);
    sense_kinds(r);  // the kind table's, in its order (kinds/kinds.cmake)
    sense_plugins(r);
    p.lap(StepProfile::Others);
}

}  // namespace plant::engine
