// Small questions the language server asks of parsed modules: which object type a name
// declares, the members of a type (through its `for`s and `if`s), a span's text, the `///`
// comment above a declaration, a type's signature.
#pragma once

#include "compiler.h"

#include <string>
#include <vector>

namespace plant::lsp {

const ast::ObjectDecl* find_type(const Compilation& c, const std::string& name);

struct Members {
    std::vector<const ast::InstanceDecl*> instances;
    std::vector<const ast::PortDecl*> ports;
    std::vector<const ast::ComponentDecl*> components;
    std::vector<const ast::LetDecl*> lets;
};
Members members_of(const ast::ObjectDecl& o);

std::string slice(const Compilation& c, const Span& s);

// The `///` lines right above the declaration at `s` (blank lines between allowed), without
// the slashes.
std::string doc_comment(const Compilation& c, const Span& s);

// "object Belt(length: length = 1 m, ...)".
std::string signature(const Compilation& c, const ast::ObjectDecl& o);

inline bool inside(const Span& s, size_t offset) { return s.valid() && s.begin <= offset && offset <= s.end; }

}  // namespace plant::lsp
