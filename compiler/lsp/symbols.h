// What the language server reads from a compilation (a file and its import closure): the
// outline of a file (textDocument/documentSymbol) from its parsed modules; what a name
// stands for (definition, references, hover) from the names sema resolved in it
// (Compilation::names, filled by sema::survey_names).
#pragma once

#include "compiler.h"

#include <nlohmann/json.hpp>

#include <compare>
#include <cstdint>
#include <optional>
#include <string>

namespace plant::lsp {

// DocumentSymbol[] of module `m`: its object types and its plant, each with its
// parameters, ports, lets, instances, components (a net's places and transitions, child
// graphics), logic connectors and flows; the members of a `for` or an `if` under it.
nlohmann::json document_symbols(const Compilation& c, const sema::LoadedModule& m);

// What a name stands for, the same in every compilation of the same text: the file
// (module key) and byte offset of its declaration — an object type's, a port's, an
// instance's, a component's, a parameter's, a `let`'s, a loop variable's — and, for a slot of a component, its dotted name in the
// component ("tick", "Home.entered"; a built-in slot has no declaration of its own).
struct Target {
    std::string file;
    uint32_t at = 0;
    std::string slot;
    friend auto operator<=>(const Target&, const Target&) = default;
};

// The target of the name at `offset` in module `m`: an object type's name (declared, an
// instance's type, a cast, a source's `object`, a trigger's `filter`), a declared member's
// name, a segment of a dotted path, a named argument (the parameter), or a name in an
// expression (a parameter, `let` or loop variable).
std::optional<Target> target_at(const Compilation& c, const sema::LoadedModule& m, size_t offset);

// Appends to `locations` (Location[]) every use of `t` in the modules of `c`, and its
// declaration when `include_declaration`; a location already there is not added again.
void add_references(const Compilation& c, const Target& t, bool include_declaration, nlohmann::json& locations);

// The Location of the name that declares `t` (for a built-in slot, its component's), or null.
nlohmann::json declaration_of(const Compilation& c, const Target& t);

// Hover (a markdown MarkupContent result, or null) for the name at `offset` in `m`.
nlohmann::json hover(const Compilation& c, const sema::LoadedModule& m, size_t offset);

// CompletionItem[] at `offset` in `text` (the buffer as typed; `m` its last parse, may be
// null); `stdlib_dir` for the modules after `import`.
nlohmann::json completion(const Compilation* c, const sema::LoadedModule* m, const std::string& text, size_t offset,
                          const std::string& stdlib_dir);

}  // namespace plant::lsp
