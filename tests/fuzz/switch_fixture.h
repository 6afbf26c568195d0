// The graph the event and message targets parse against: examples/switch.plant, compiled
// once per process, with its index of addressable slots.
#pragma once

#include "paths.h"
#include "compiler.h"
#include "engine/events.h"
#include "fuzz.h"

#include <string>

namespace plant::fuzz {

struct SwitchFixture {
    Compilation c;
    engine::SlotIndex idx;
    SwitchFixture() {
        CompileOptions opts;
        opts.stdlib_dir = PLANT_STDLIB_DIR;
        compile_file(std::string(PLANT_SOURCE_DIR) + "/examples/switch.plant", opts, c);
        if (!c.ok()) broken("examples/switch.plant does not compile");
        idx = engine::slot_index(c.graph);
    }
};

}  // namespace plant::fuzz
