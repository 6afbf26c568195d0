// The compiler's front door: a plant file in, a checked flat graph and diagnostics out.
#pragma once

#include "ast/ast.h"
#include "diag/diagnostic.h"
#include "graph/graph.h"
#include "sema/elaborate.h"
#include "sema/modules.h"
#include "sema/names.h"

#include <string>
#include <vector>

namespace plant {

struct CompileOptions {
    std::string stdlib_dir;     // where `import std.x` looks
    bool require_plant = true;  // false: a library file is checked type by type
    // `--set NAME=VALUE`, in order: values for the plant's parameters. Each is parsed as
    // a source of its own named "--set", so its diagnostics have a line and column.
    std::vector<std::string> overrides;
    const sema::Overlay* overlay = nullptr;  // unsaved editor buffers (plant lsp)
    sema::Reuse reuse;                       // an earlier compilation's parsed modules (plant lsp)
    long long max_members = sema::kMaxMembers;  // loops beyond it are an error (the fuzzer lowers it)
};

struct Compilation {
    SourceMap sources;
    Sink sink;
    sema::Program program;  // the parsed modules (for --emit=ast)
    graph::Graph graph;
    sema::Names names;  // filled on request (plant lsp: sema::survey_names)
    bool ok() const { return !sink.has_errors(); }
};

// Parses, checks and lowers `path`; never throws on bad input.
void compile_file(const std::string& path, const CompileOptions& options, Compilation& out);

// The standard library folder: $PLANT_STDLIB, else the one this build was made from.
std::string default_stdlib_dir();

}  // namespace plant
