// Target `compile`: plant source text -> the whole compiler (parse, elaborate, check,
// lower), with the standard library importable.
// Invariant: no crash, no sanitizer report, no hang (the driver's time limit per input);
// the compiler either succeeds or reports errors, and every error has a location inside
// the input or inside a file it imports (never an invalid span), and a non-empty message.
#include "paths.h"
#include "compiler.h"
#include "fuzz.h"
#include "faults/kind.h"
#include "faults/operable.h"
#include "opcua/kind.h"
#include "panel/kind.h"
#include "plc/kind.h"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const bool kinds = (plant::plc::register_modbus_kind(), plant::opcua::register_opcua_kind(),
                                plant::faults::register_faults_kind(), plant::faults::register_operable_kind(),
                                plant::panel::register_panel_kinds(), true);  // the plugin kinds it has
    (void)kinds;
    if (size > 64 * 1024) return 0;  // larger inputs only slow the search
    static const std::string path = "/nonexistent-plant-fuzz/input.plant";
    plant::sema::Overlay overlay{{path, std::string(plant::fuzz::text(data, size))}};
    plant::CompileOptions opts;
    opts.stdlib_dir = PLANT_STDLIB_DIR;
    opts.overlay = &overlay;
    // The loop limit, lowered: the same code paths reach it 100 times sooner, so an input
    // that runs loops to the limit takes milliseconds, not the 10-45 s of 2,000,000
    // iterations in this instrumented build.
    opts.max_members = 20'000;
    plant::Compilation c;
    plant::compile_file(path, opts, c);
    for (const auto& d : c.sink.all()) {
        if (d.severity != plant::Severity::Error) continue;
        if (!d.span.valid() || d.span.file >= c.sources.size()) plant::fuzz::broken("an error without a location");
        const size_t file_size = c.sources.text(d.span.file).size();
        if (d.span.begin > d.span.end || d.span.end > file_size) plant::fuzz::broken("an error located outside its file");
        if (d.message.empty()) plant::fuzz::broken("an error without a message");
    }
    return 0;
}
