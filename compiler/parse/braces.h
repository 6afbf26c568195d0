// Where a missing `}` belongs. A syntax error that a `}` would have avoided (the end of the
// file, or a declaration inside a block) names the `{` that is still open at that point;
// when a `}` before it closes a block less indented than the line that opened it, that
// block is likely the one the `}` is missing from, and is named too.
#pragma once

#include "diag/diagnostic.h"

#include <cstdint>
#include <string>
#include <vector>

namespace plant::parse {

struct Brace {
    uint32_t begin = 0;  // byte offset
    int line = 0;        // 1-based
    int indent = 0;      // the indent of its line, in columns
    bool open = false;   // `{` or `}`
};

// Notes for an error at `where` ("the end of the file", "'flow'") after `braces` (every
// brace before it, in order): none when every `{` is closed.
std::vector<Note> unclosed_brace_notes(int32_t file, const std::vector<Brace>& braces, const std::string& where);

}  // namespace plant::parse
