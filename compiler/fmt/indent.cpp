// Indentation: a member starts at 4 spaces per open brace; a line that continues a
// member lines up inside its open bracket, or goes 4 deeper.
#include "fmt/lines.h"

namespace plant::formatter {
namespace {

using parse::Starts;

struct Open {
    bool brace = false;
    int align = -1;        // a bracket followed by more on its line: the column after it
    int line_indent = 0;   // the indent of the line it is on
};

class Indenter {
public:
    // The indent of a line whose first code piece is `p`; `comment`: the line before it
    // holds only comments, which go where the code inside would.
    int indent_for(const Piece& p, bool comment) const {
        const int body = 4 * braces_;
        const bool closes = p.is(")") || p.is("]");
        if (p.is("}")) return comment ? body : body - 4;
        if (p.tok->starts != Starts::None || p.is("else")) return body;
        if (!stack_.empty() && !stack_.back().brace) {
            const Open& o = stack_.back();
            if (o.align >= 0) return closes && !comment ? o.align - 1 : o.align;
            return closes && !comment ? o.line_indent : o.line_indent + 4;
        }
        return body + 4;
    }

    // Opens and closes brackets along a printed line.
    void scan(const Line& l) {
        int col = l.indent;
        for (size_t i = 0; i < l.pieces.size(); ++i) {
            const Piece& p = l.pieces[i];
            col += (i > 0 ? p.space : 0) + width(p.text);
            if (p.is("{")) {
                stack_.push_back({true, -1, l.indent});
                ++braces_;
            } else if (p.is("(") || p.is("[")) {
                const bool more = i + 1 < l.pieces.size() && l.pieces[i + 1].tok->lex != parse::Lex::LineComment &&
                                  l.pieces[i + 1].tok->lex != parse::Lex::DocComment;
                stack_.push_back({false, more ? col : -1, l.indent});
            } else if ((p.is("}") || p.is(")") || p.is("]")) && !stack_.empty()) {
                braces_ -= stack_.back().brace ? 1 : 0;
                stack_.pop_back();
            }
        }
    }

private:
    std::vector<Open> stack_;
    int braces_ = 0;
};

// The first code piece at or after line i, or null at the end of the file.
const Piece* next_code(const std::vector<Line>& lines, size_t i) {
    for (; i < lines.size(); ++i)
        for (const auto& p : lines[i].pieces)
            if (!p.comment()) return &p;
    return nullptr;
}

}  // namespace

void indent_lines(std::vector<Line>& lines) {
    Indenter ind;
    for (size_t i = 0; i < lines.size(); ++i) {
        Line& l = lines[i];
        const Piece* p = next_code(lines, i);
        const bool comment_first = l.first().comment();
        l.indent = p ? ind.indent_for(*p, comment_first) : 0;
        ind.scan(l);
    }
}

}  // namespace plant::formatter
