// SourceMap: byte offsets to 1-based line:col. Line starts are computed once, when
// a file is added; a lookup is a binary search.
#include "diag/diagnostic.h"

#include <algorithm>
#include <cassert>
#include <limits>

namespace plant {

int32_t SourceMap::add(std::string display_name, std::string text) {
    // Spans hold 32-bit offsets.
    assert(text.size() < std::numeric_limits<uint32_t>::max());
    File f{std::move(display_name), std::move(text), {0}};
    for (uint32_t i = 0; i < f.text.size(); ++i) {
        if (f.text[i] == '\n') f.line_starts.push_back(i + 1);
    }
    files_.push_back(std::move(f));
    return size() - 1;
}

// An offset past the end is clamped to the end; offset == size is the position
// just after the last character (on an empty last line if the text ends in '\n').
SourceMap::LineCol SourceMap::line_col(int32_t file, uint32_t offset) const {
    const File& f = files_[file];
    offset = std::min(offset, static_cast<uint32_t>(f.text.size()));
    // The last line start that is <= offset; line_starts[0] == 0, so it exists.
    auto it = std::upper_bound(f.line_starts.begin(), f.line_starts.end(), offset) - 1;
    auto line = static_cast<uint32_t>(it - f.line_starts.begin()) + 1;
    return {line, offset - *it + 1};
}

// The text of a 1-based line without its "\n" or "\r\n"; empty for a line that
// does not exist.
std::string_view SourceMap::line_text(int32_t file, uint32_t line) const {
    const File& f = files_[file];
    if (line == 0 || line > f.line_starts.size()) return {};
    std::size_t begin = f.line_starts[line - 1];
    std::size_t end = line < f.line_starts.size() ? f.line_starts[line] - 1 : f.text.size();
    if (end > begin && f.text[end - 1] == '\r') --end;
    return std::string_view(f.text).substr(begin, end - begin);
}

}  // namespace plant
