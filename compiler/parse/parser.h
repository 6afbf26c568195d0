// Text -> AST. The only door to ANTLR: nothing outside compiler/parse includes it.
#pragma once

#include "ast/ast.h"
#include "diag/diagnostic.h"

#include <optional>

namespace plant::parse {

// Parses one file already added to `sources`. Syntax errors go to `sink` (E0001) with
// the expected tokens in words; the module returned then holds what could be built.
ast::Module parse_module(const SourceMap& sources, int32_t file, Sink& sink);

// Parses one `--set` value, NAME=VALUE (a file of its own in `sources`), into a named
// argument for the plant. Syntax errors go to `sink` (E0001); nothing is returned then.
std::optional<ast::Arg> parse_set(const SourceMap& sources, int32_t file, Sink& sink);

}  // namespace plant::parse
