// The parser builds nothing for a file with a syntax error. While the user types, the
// language server parses a repaired copy instead: the lines the parser stumbled on blanked
// (spaces, so every other offset stays where it is in the buffer), until it parses.
#pragma once

#include "compiler.h"

#include <memory>
#include <string>

namespace plant::lsp {

// The parsed modules of `path` (its text `text`, the other buffers in `overlay`) with the
// lines of its syntax errors blanked; null when it does not parse after a few rounds.
// `failed` is the compilation of `text` as it is: the modules it parsed are shared.
std::shared_ptr<Compilation> parse_repaired(const std::string& path, std::string text, const std::string& stdlib_dir,
                                            sema::Overlay overlay, const Compilation& failed);

// Whether `c` has a syntax error in the module read from `path`.
bool syntax_error_in(const Compilation& c, const std::string& path);

}  // namespace plant::lsp
