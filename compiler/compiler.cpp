#include "compiler.h"

#include "parse/parser.h"
#include "sema/elaborate.h"

#include <cstdlib>

#ifndef PLANT_STDLIB_DIR
#define PLANT_STDLIB_DIR "stdlib"
#endif

namespace plant {

void compile_file(const std::string& path, const CompileOptions& options, Compilation& out) {
    out.program = sema::load_program(path, options.stdlib_dir, out.sources, out.sink, options.overlay, options.reuse);
    for (const auto& text : options.overrides) {
        const int32_t file = out.sources.add("--set", text);
        if (auto arg = parse::parse_set(out.sources, file, out.sink)) out.program.overrides.push_back(std::move(*arg));
    }
    // Name resolution needs every module; a syntax error anywhere stops here.
    if (out.sink.has_errors()) return;
    out.graph = sema::elaborate(out.program, out.sources, out.sink, options.require_plant,
                                 options.max_members);
}

std::string default_stdlib_dir() {
    if (const char* env = std::getenv("PLANT_STDLIB"); env && *env) return env;
    return PLANT_STDLIB_DIR;
}

}  // namespace plant
