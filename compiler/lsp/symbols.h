// What the language server reads from the parsed modules of a compilation (a file and its
// import closure): the outline of a file (textDocument/documentSymbol) and the references
// of a name (textDocument/references).
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
// instance's, a component's — and, for a slot of a component, its dotted name in the
// component ("tick", "Home.entered"; a built-in slot has no declaration of its own).
struct Target {
    std::string file;
    uint32_t at = 0;
    std::string slot;
    friend auto operator<=>(const Target&, const Target&) = default;
};

// The target of the name at `offset` in module `m`: an object type's name (declared, an
// instance's type, a cast, a source's `object`, a trigger's `filter`), a declared member's
// name, or a segment of a dotted path.
std::optional<Target> target_at(const Compilation& c, const sema::LoadedModule& m, size_t offset);

// Appends to `locations` (Location[]) every use of `t` in the modules of `c`, and its
// declaration when `include_declaration`; a location already there is not added again.
void add_references(const Compilation& c, const Target& t, bool include_declaration, nlohmann::json& locations);

}  // namespace plant::lsp
