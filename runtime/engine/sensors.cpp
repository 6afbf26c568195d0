// Phase 2: what the world looks like after the physics step, as output activity: the kinds
// on the kind table in its order (bodies first: their outputs, and warnings for bodies that
// left the world), then plugins. Each kind's sensing lives with the rest of its behaviour
// (its kinds/NAME/run.cpp).
#include "engine/runtime.h"
#include "engine/workers.h"

namespace plant::engine {

void phase_sensors(Runtime& r) {
    StepProfile& p = r.phys.workers().profile();
    sense_kinds(r);  // the kind table's, in its order (kinds/kinds.cmake): the bodies first
    sense_plugins(r);
    p.lap(StepProfile::Others);
}

}  // namespace plant::engine
