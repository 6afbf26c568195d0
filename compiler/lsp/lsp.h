// `plant lsp`: a Language Server Protocol server over stdio. Diagnostics as the user types
// (the same codes, spans, messages and notes as `plant check`), with unsaved buffers read
// before the files on disk; hover, definition, completion, the outline and references
// (lsp/symbols.h), formatting (compiler/fmt). JSON-RPC framing with Content-Length headers; JSON from
// nlohmann-json. Never writes anything but protocol messages to `out`.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace plant::lsp {

// Serves until `exit` or the end of `in`; returns the process exit code (0 after a
// `shutdown` request, 1 otherwise, as the protocol asks).
int serve(std::istream& in, std::ostream& out, const std::string& stdlib_dir);

}  // namespace plant::lsp
