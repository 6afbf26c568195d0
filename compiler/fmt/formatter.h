// `plant fmt`: one canonical layout for plant files (docs/editors.md, "plant fmt").
// (Not named format.h: this folder is on the include path, and <fmt/format.h> is libfmt.)
#pragma once

#include "diag/diagnostic.h"

#include <optional>
#include <string>

namespace plant::formatter {

// The formatted text of a file already in `sources`, or nothing when it has syntax errors
// (reported to `sink`, as `plant check` reports them). Formatting keeps every token and
// comment in order: the compiled graph does not change.
std::optional<std::string> format_source(const SourceMap& sources, int32_t file, Sink& sink);

// The same for a text that is not in a SourceMap yet: adds it under `name` (a byte-order
// mark is dropped; text that is not UTF-8 is an error, E0008).
std::optional<std::string> format_text(const std::string& name, std::string text, SourceMap& sources, Sink& sink);

}  // namespace plant::formatter
