// Rendering diagnostics: text in the style of clang/rustc, or one JSON document.
#include "diag/diagnostic.h"

#include <fmt/format.h>

#include <iterator>
#include <nlohmann/json.hpp>

namespace plant {

namespace {

std::string_view severity_name(Severity s) {
    switch (s) {
        case Severity::Note: return "note";
        case Severity::Warning: return "warning";
        case Severity::Error: return "error";
    }
    return "error";
}

// A span whose file is not in the map is treated like "no position".
bool has_position(const Span& s, const SourceMap& sm) { return s.valid() && s.file < sm.size(); }

// "file:line:col: " or "plant: " for a diagnostic without a position.
std::string location(const Span& s, const SourceMap& sm) {
    if (!has_position(s, sm)) return "plant: ";
    auto [line, col] = sm.line_col(s.file, s.begin);
    return fmt::format("{}:{}:{}: ", sm.name(s.file), line, col);
}

// A UTF-8 continuation byte does not start a new character on screen.
bool continuation_byte(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

// The source line of the span's start, then a caret under the start and '~' under
// the rest of the span on that line (a span over several lines is marked up to the
// end of its first line). Tabs before the caret are copied so that the caret lines
// up whatever the tab width; a tab inside the span is marked as one '~'.
void render_snippet(std::string& out, const Span& s, const SourceMap& sm) {
    auto [line, col] = sm.line_col(s.file, s.begin);
    std::string_view text = sm.line_text(s.file, line);
    std::string number = std::to_string(line);
    std::size_t width = std::max<std::size_t>(5, number.size());

    std::size_t start = std::min<std::size_t>(col - 1, text.size());
    // A very long line (a binary file, a generated one) shows a window around the caret.
    constexpr std::size_t kWindow = 100;
    std::string shown_text;
    if (text.size() > 2 * kWindow) {
        std::size_t from = start > kWindow / 2 ? start - kWindow / 2 : 0;
        while (from > 0 && continuation_byte(text[from])) --from;
        std::size_t to = std::min(text.size(), from + kWindow);
        while (to < text.size() && continuation_byte(text[to])) ++to;
        shown_text = (from > 0 ? "..." : "") + std::string(text.substr(from, to - from)) + (to < text.size() ? "..." : "");
        start = start - from + (from > 0 ? 3 : 0);
        text = shown_text;
    }
    // Control characters would move the cursor or ring the bell: shown as '?'.
    std::string clean(text);
    for (char& c : clean)
        if ((static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f) c = '?';
    text = clean;
    std::size_t length = s.end > s.begin ? s.end - s.begin : 1;
    std::size_t stop = std::min(start + length, text.size());
    std::string marker;
    for (std::size_t i = 0; i < start; ++i) {
        if (text[i] == '\t') marker += '\t';
        else if (!continuation_byte(text[i])) marker += ' ';
    }
    marker += '^';
    for (std::size_t i = start + 1; i < stop; ++i) {
        if (!continuation_byte(text[i])) marker += '~';
    }

    auto it = std::back_inserter(out);
    // No trailing blank after the bar when the line is empty.
    fmt::format_to(it, "{:>{}} |{}{}\n", number, width, text.empty() ? "" : " ", text);
    fmt::format_to(it, "{:>{}} | {}\n", "", width, marker);
}

}  // namespace

std::string render_text(const Diagnostic& d, const SourceMap& sm) {
    std::string out = fmt::format("{}{}[{}]: {}\n", location(d.span, sm), severity_name(d.severity),
                                  info(d.id).code, d.message);
    if (has_position(d.span, sm)) render_snippet(out, d.span, sm);
    for (const Note& n : d.notes) {
        if (has_position(n.span, sm)) {
            out += fmt::format("{}note: {}\n", location(n.span, sm), n.message);
            render_snippet(out, n.span, sm);
        } else if (has_position(d.span, sm)) {
            // A note of its own place belongs to the error: indented under its snippet.
            out += fmt::format("{:>5} = note: {}\n", "", n.message);
        } else {
            out += fmt::format("plant: note: {}\n", n.message);
        }
    }
    return out;
}

// Renders `ds` in the order given (pass Sink::sorted()), then a summary line such as
// "2 errors, 1 warning generated." when there is at least one diagnostic.
std::string render_all_text(const std::vector<Diagnostic>& ds, const SourceMap& sm) {
    std::string out;
    int counts[3] = {0, 0, 0};  // indexed by Severity
    for (const Diagnostic& d : ds) {
        out += render_text(d, sm);
        ++counts[static_cast<int>(d.severity)];
    }
    if (ds.empty()) return out;

    std::string summary;
    for (Severity s : {Severity::Error, Severity::Warning, Severity::Note}) {
        int n = counts[static_cast<int>(s)];
        if (n == 0) continue;
        if (!summary.empty()) summary += ", ";
        summary += fmt::format("{} {}{}", n, severity_name(s), n == 1 ? "" : "s");
    }
    return out + summary + " generated.\n";
}

// Lines and columns are 1-based; end_line/end_col are the position of the span's
// (exclusive) end. Position fields are null for a diagnostic without one; a note without
// one has its diagnostic's.
std::string render_json(const std::vector<Diagnostic>& ds, const SourceMap& sm) {
    using nlohmann::ordered_json;
    auto put_position = [&sm](ordered_json& j, const Span& s, bool with_end) {
        if (!has_position(s, sm)) {
            j["file"] = nullptr;
            j["line"] = nullptr;
            j["col"] = nullptr;
            if (with_end) {
                j["end_line"] = nullptr;
                j["end_col"] = nullptr;
            }
            return;
        }
        auto begin = sm.line_col(s.file, s.begin);
        j["file"] = sm.name(s.file);
        j["line"] = begin.line;
        j["col"] = begin.col;
        if (with_end) {
            auto end = sm.line_col(s.file, std::max(s.begin, s.end));
            j["end_line"] = end.line;
            j["end_col"] = end.col;
        }
    };

    ordered_json list = ordered_json::array();
    for (const Diagnostic& d : ds) {
        ordered_json j;
        j["severity"] = severity_name(d.severity);
        j["code"] = info(d.id).code;
        put_position(j, d.span, true);
        j["message"] = d.message;
        ordered_json notes = ordered_json::array();
        for (const Note& n : d.notes) {
            ordered_json jn;
            // A note without a place of its own is at its diagnostic's.
            put_position(jn, has_position(n.span, sm) ? n.span : d.span, false);
            jn["message"] = n.message;
            notes.push_back(std::move(jn));
        }
        j["notes"] = std::move(notes);
        list.push_back(std::move(j));
    }
    ordered_json doc;
    doc["diagnostics"] = std::move(list);
    // Messages quote source text, which may not be valid UTF-8: replace, don't throw.
    return doc.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace plant
