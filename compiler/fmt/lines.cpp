// Lines and the spaces between the pieces of a line.
#include "fmt/lines.h"

#include <algorithm>

namespace plant::formatter {
namespace {

using parse::Lex;

bool one_of(std::string_view s, std::initializer_list<std::string_view> set) {
    return std::find(set.begin(), set.end(), s) != set.end();
}

// Spaces between two pieces on one line: one, except around what binds tightly.
int space_between(const Piece& a, const Piece& b) {
    if (!b.comment() && one_of(b.text, {",", ";", ")", "]"})) return 0;
    if (!a.comment() && one_of(a.text, {"(", "["})) return 0;
    if (a.comment() || b.comment()) return 1;
    if (b.tok->glued) return 0;                                   // box(  seg[i  cm/s
    if (one_of(b.text, {".", ":"}) || a.text == ".") return 0;
    if (a.tok->prefix && a.text == "-") return 0;                 // -x, but `not x`
    if (a.text == "{" && b.text == "}") return 0;                 // {}
    return 1;
}

// A `///` block documents the object or plant declared right below it (hover shows it,
// docs/language.md): no blank line between them.
bool documents(const Line& doc, const Piece& next) {
    return doc.pieces.size() == 1 && doc.first().tok->lex == Lex::DocComment &&
           next.tok->starts != parse::Starts::None && (next.is("object") || next.is("plant"));
}

}  // namespace

int width(std::string_view s) {
    return static_cast<int>(std::count_if(s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

std::vector<Line> split_lines(std::string_view text, const std::vector<parse::LayoutToken>& tokens) {
    std::vector<Line> lines;
    uint32_t prev_end = 0, line_start = 0;
    for (const auto& t : tokens) {
        const std::string_view gap = text.substr(prev_end, t.begin - prev_end);
        const auto newlines = std::count(gap.begin(), gap.end(), '\n');
        if (newlines > 0) line_start = prev_end + static_cast<uint32_t>(gap.rfind('\n')) + 1;
        Piece p;
        p.tok = &t;
        p.text = text.substr(t.begin, t.end - t.begin);
        p.orig_col = width(text.substr(line_start, t.begin - line_start));
        if (lines.empty() || newlines > 0) {
            Line l;
            l.blank_before = !lines.empty() && newlines > 1 && !lines.back().last().is("{") && !p.is("}") &&
                             !documents(lines.back(), p);
            l.orig_indent = p.orig_col;
            lines.push_back(std::move(l));
        } else {
            p.space = space_between(lines.back().last(), p);
        }
        lines.back().pieces.push_back(p);
        prev_end = t.end;
    }
    return lines;
}

std::string print_lines(const std::vector<Line>& lines) {
    std::string out;
    for (const auto& l : lines) {
        if (l.blank_before) out += '\n';
        out.append(static_cast<size_t>(l.indent), ' ');
        for (size_t i = 0; i < l.pieces.size(); ++i) {
            if (i > 0) out.append(static_cast<size_t>(l.pieces[i].space), ' ');
            std::string_view s = l.pieces[i].text;
            // A comment keeps its words, not trailing blanks.
            if (l.pieces[i].comment())
                while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
            out += s;
        }
        out += '\n';
    }
    return out;
}

}  // namespace plant::formatter
