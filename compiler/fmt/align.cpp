// Columns: consecutive ports, instances, transitions and one-line animations, and
// trailing comments.
#include "fmt/lines.h"

#include <algorithm>

namespace plant::formatter {
namespace {

using parse::Starts;

// Width of pieces [0, n] of a line as printed (without its indent).
int prefix_width(const Line& l, size_t n) {
    int w = 0;
    for (size_t i = 0; i <= n && i < l.pieces.size(); ++i) w += (i > 0 ? l.pieces[i].space : 0) + width(l.pieces[i].text);
    return w;
}

// The `:` after a port's, instance's or transition's name: its index, or 0 when the line
// is not laid out so (the name's parts and the colon must be code on this line).
size_t colon_of(const Line& l) {
    for (size_t i = 1; i + 1 < l.pieces.size(); ++i) {
        if (l.pieces[i].comment()) return 0;
        if (l.pieces[i].is(":")) return l.pieces[i + 1].comment() ? 0 : i;
    }
    return 0;
}

//   in  to_base:    void => net.MoveToBasePos.put
//   out in_working: void => net.WorkingPos.entered
void align_ports(std::vector<Line*>& group) {
    int dir = 0, name = 0, type = 0;
    for (const Line* l : group) {
        dir = std::max(dir, width(l->pieces[0].text));
        name = std::max(name, width(l->pieces[1].text));
        type = std::max(type, width(l->pieces[3].text));
    }
    for (Line* l : group) {
        auto& p = l->pieces;
        p[1].space = dir - width(p[0].text) + 1;
        p[3].space = name - width(p[1].text) + 1;
        if (p.size() > 4 && p[4].is("=>")) p[4].space = type - width(p[3].text) + 1;
    }
}

//   left:  Wedge(...)        transition tw:  BasePos + ...
//   right: Wedge(...)        transition tcw: WorkingPos + ...
void align_after_colon(std::vector<Line*>& group) {
    int widest = 0;
    for (const Line* l : group) widest = std::max(widest, prefix_width(*l, colon_of(*l)));
    for (Line* l : group) {
        const size_t c = colon_of(*l);
        l->pieces[c + 1].space = widest - prefix_width(*l, c) + 1;
    }
}

//   animation lift  { duration = 100 ms; move (0 m, 0 m, 6 cm) }
//   animation lower { key 0 s at (0 m, 0 m, 6 cm); key 100 ms at (0 m, 0 m, 0 m) }
void align_braces(std::vector<Line*>& group) {
    int widest = 0;
    for (const Line* l : group) widest = std::max(widest, width(l->pieces[1].text));
    for (Line* l : group) l->pieces[2].space = widest - width(l->pieces[1].text) + 1;
}

// An animation written on one line: `animation NAME { ... }`.
bool one_line_animation(const Line& l) {
    auto last = std::find_if(l.pieces.rbegin(), l.pieces.rend(), [](const Piece& p) { return !p.comment(); });
    return l.pieces.size() > 3 && l.pieces[2].is("{") && last->is("}");
}

// A line that may join a group of its kind.
bool fits(const Line& l) {
    const Starts s = l.first().tok->starts;
    if (s == Starts::Port) return l.pieces.size() >= 4 && l.pieces[2].is(":") && !l.pieces[3].comment();
    if (s == Starts::Instance || s == Starts::Transition) return colon_of(l) > 0;
    if (s == Starts::Animation) return one_line_animation(l);
    return false;
}

// A line inside a member (not its first): it neither joins nor ends a group.
bool continues(const Line& l) {
    return l.first().tok->starts == Starts::None && !l.first().comment() && !l.first().is("}") && !l.blank_before;
}

}  // namespace

void align_members(std::vector<Line>& lines) {
    std::vector<Line*> group;
    auto flush = [&] {
        if (group.size() > 1) {
            const Starts kind = group[0]->first().tok->starts;
            if (kind == Starts::Port) align_ports(group);
            else if (kind == Starts::Animation) align_braces(group);
            else align_after_colon(group);
        }
        group.clear();
    };
    for (auto& l : lines) {
        if (!group.empty() && continues(l)) continue;
        const bool joins = !group.empty() && !l.blank_before && fits(l) &&
                           l.first().tok->starts == group[0]->first().tok->starts;
        if (!joins) flush();
        if (fits(l)) group.push_back(&l);
    }
    flush();
}

void align_comments(std::vector<Line>& lines) {
    // A trailing comment keeps the column it was written at (moved with its line's
    // indent), at least two spaces after the code. Comments lined up on consecutive lines
    // of one indent stay lined up: when one of them must move right, they all do.
    auto written = [](const Line& l) { return l.last().orig_col + l.indent - l.orig_indent; };
    auto code_end = [](const Line& l) { return l.indent + prefix_width(l, l.pieces.size() - 2); };
    for (size_t i = 0; i < lines.size();) {
        if (!lines[i].has_trailing_comment()) {
            ++i;
            continue;
        }
        size_t j = i;
        int column = 0;
        while (j < lines.size() && lines[j].has_trailing_comment() &&
               (j == i || (!lines[j].blank_before && lines[j].indent == lines[i].indent &&
                           written(lines[j]) == written(lines[i])))) {
            column = std::max({column, written(lines[j]), code_end(lines[j]) + 2});
            ++j;
        }
        for (size_t k = i; k < j; ++k) lines[k].pieces.back().space = column - code_end(lines[k]);
        i = j;
    }
}

}  // namespace plant::formatter
