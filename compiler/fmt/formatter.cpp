// The formatter's pipeline: layout tokens -> lines -> aligned -> indented -> text.
#include "fmt/formatter.h"

#include "fmt/lines.h"
#include "graph/utf8.h"
#include "parse/layout.h"
#include "sema/modules.h"

namespace plant::formatter {

std::optional<std::string> format_source(const SourceMap& sources, int32_t file, Sink& sink) {
    auto tokens = parse::layout_tokens(sources, file, sink);
    if (!tokens) return std::nullopt;
    std::vector<Line> lines = split_lines(sources.text(file), *tokens);
    align_members(lines);
    indent_lines(lines);
    align_comments(lines);
    return print_lines(lines);
}

std::optional<std::string> format_text(const std::string& name, std::string text, SourceMap& sources, Sink& sink) {
    if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
    const size_t bad = graph::invalid_utf8(text);
    const int32_t file = sources.add(name, std::move(text));
    if (bad != std::string::npos) {
        sema::report_invalid_utf8(sources, file, bad, sink);
        return std::nullopt;
    }
    return format_source(sources, file, sink);
}

}  // namespace plant::formatter
