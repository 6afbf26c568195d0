// Target `graph`: the text form of a compiled graph -> the loader and its validator, then,
// for what loads, the runtime for a few hundred steps.
// Invariant: no crash, no sanitizer report, no hang; a refused graph says why ("line N: ...");
// a graph that loads round-trips (to_text(load(text)) loads again to the same text) and
// runs: whatever the loader accepts, the engine must be able to step.
#include "engine/engine.h"
#include "fuzz.h"
#include "graph/text.h"
#include "faults/kind.h"
#include "faults/operable.h"
#include "opcua/kind.h"
#include "panel/kind.h"
#include "plc/kind.h"

#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const bool kinds = (plant::plc::register_modbus_kind(), plant::opcua::register_opcua_kind(),
                                plant::faults::register_faults_kind(), plant::faults::register_operable_kind(),
                                plant::panel::register_panel_kinds(), true);  // the plugin kinds it has
    (void)kinds;
    if (size > 256 * 1024) return 0;
    std::istringstream in{std::string(plant::fuzz::text(data, size))};
    plant::graph::Graph g;
    std::string error;
    if (!plant::graph::read_text(in, g, error)) {
        if (error.empty()) plant::fuzz::broken("a graph refused without a reason");
        return 0;
    }
    const std::string once = plant::graph::to_text(g);
    std::istringstream again(once);
    plant::graph::Graph g2;
    if (!plant::graph::read_text(again, g2, error)) plant::fuzz::broken("a loaded graph's own text is refused");
    if (plant::graph::to_text(g2) != once) plant::fuzz::broken("the text form does not round-trip");
    if (g.bodies.size() > 2000 || g.slots.size() > 200000) return 0;  // big plants only slow the search
    plant::engine::Options opt;
    opt.threads = 1;
    plant::engine::Engine e(g, opt);
    for (int i = 0; i < 300; ++i) e.step();
    return 0;
}
