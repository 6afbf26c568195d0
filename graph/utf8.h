#pragma once
// The one UTF-8 check of text that enters a plant from outside: plant files and `--set`
// values (the compiler; ANTLR's input stream throws on anything else), events from the
// command line, events files, the viewer and forced values, strings a PLC writes.

#include <cstddef>
#include <string>
#include <string_view>

namespace plant::graph {

// The offset of the first byte that does not begin a well-formed UTF-8 sequence (overlong
// forms, surrogates and code points beyond U+10FFFF included), or npos when all of it is.
size_t invalid_utf8(std::string_view text);

// "not valid UTF-8: byte 0xFF at column 7" for a one-line text, `bad` from invalid_utf8.
std::string utf8_error(std::string_view text, size_t bad);

}  // namespace plant::graph
