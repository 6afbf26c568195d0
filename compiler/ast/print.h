// A readable dump of the AST (`plant check --emit=ast`), one node per line.
#pragma once

#include "ast/ast.h"

#include <ostream>

namespace plant::ast {

void print(const Module& m, const SourceMap& sm, std::ostream& out);

}  // namespace plant::ast
