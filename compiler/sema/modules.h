// Loads the root file and, transitively, every module it imports.
// `import std.belts` names stdlib/belts.plant; `import parts.rail` names parts/rail.plant
// next to the importing file. Each file is parsed once.
#pragma once

#include "ast/ast.h"
#include "diag/diagnostic.h"

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace plant::sema {

struct LoadedModule {
    std::string key;          // canonical path on disk, for identity
    // Never changed after parsing: a later load of the same text may share it (Reuse).
    std::shared_ptr<const ast::Module> ast;
    std::vector<int> imports; // indices of directly imported modules
    bool clean = false;       // parsed without a diagnostic
};

struct Program {
    std::vector<LoadedModule> modules;  // dependencies before dependents
    int root = -1;
    std::vector<ast::Arg> overrides;    // `--set NAME=VALUE`: arguments for the root file's plant
    std::string stdlib_dir;             // where `import std.x` looks
};

// The standard-library module that declares object type `name` ("std.separator"), or ""
// (the stdlib's files read as text: for "add `import std.x`" on an unknown type).
std::string stdlib_module_declaring(const std::string& stdlib_dir, const std::string& name);
// Reads a regular file of a module's size at most; `why` says what is wrong otherwise
// (": it is a directory"), empty when it cannot be opened.
bool read_file(const std::filesystem::path& p, std::string& out, std::string& why);

// A plant file's text that is not UTF-8 (`bad` from graph::invalid_utf8): its error
// (E0008), the one every reader of plant files reports.
void report_invalid_utf8(const SourceMap& sources, int32_t file, size_t bad, Sink& sink);

// Unsaved editor buffers by canonical path: a file found here is read from here, not from disk.
using Overlay = std::map<std::string, std::string>;

// An earlier load whose parsed modules a new load shares instead of parsing again (the
// language server re-checks after every keystroke): a module is shared when it parsed
// without a diagnostic and its text, display name and file number are the same again.
struct Reuse {
    const Program* program = nullptr;
    const SourceMap* sources = nullptr;
};

Program load_program(const std::string& root_path, const std::string& stdlib_dir, SourceMap& sources,
                     Sink& sink, const Overlay* overlay = nullptr, Reuse reuse = {});

}  // namespace plant::sema
