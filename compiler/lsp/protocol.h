// Positions, ranges and URIs as the Language Server Protocol has them: 0-based lines,
// characters counted in UTF-16 code units, `file://` URIs with percent-escapes. Our spans
// are byte offsets; these convert at the edge.
#pragma once

#include "diag/diagnostic.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace plant::lsp {

// "file:///a/b%20c.plant" -> "/a/b c.plant"; "" for anything but a file URI.
std::string uri_to_path(const std::string& uri);
std::string path_to_uri(const std::string& path);

// The byte offset of an LSP position in `text` (clamped to its line and to the text).
size_t offset_of(const std::string& text, uint32_t line, uint32_t character);

nlohmann::json position_of(const SourceMap& sm, int32_t file, uint32_t offset);
nlohmann::json range_of(const SourceMap& sm, const Span& s);

}  // namespace plant::lsp
