// The formatter's working form: the file as lines of pieces (tokens and comments), with
// the spaces before each piece. Built from the layout tokens, then aligned, indented and
// printed (lines.cpp, align.cpp, indent.cpp).
#pragma once

#include "parse/layout.h"

#include <string_view>
#include <vector>

namespace plant::formatter {

struct Piece {
    std::string_view text;
    const parse::LayoutToken* tok = nullptr;
    int space = 0;       // spaces before it; ignored for a line's first piece
    int orig_col = 0;    // its column as written (code points)
    bool is(std::string_view s) const { return tok->lex == parse::Lex::Code && text == s; }
    bool comment() const { return tok->lex != parse::Lex::Code; }
};

struct Line {
    std::vector<Piece> pieces;  // never empty
    bool blank_before = false;  // one empty line before it
    int indent = 0;             // set by indent.cpp
    int orig_indent = 0;        // as written
    const Piece& first() const { return pieces.front(); }
    const Piece& last() const { return pieces.back(); }
    bool has_trailing_comment() const { return pieces.size() > 1 && last().comment() && last().tok->lex != parse::Lex::BlockComment; }
};

// Width in columns: code points.
int width(std::string_view s);

// Splits the file into lines as written (at most one blank line kept between two, none
// after `{` or before `}`) and sets the canonical spaces between the pieces of a line.
std::vector<Line> split_lines(std::string_view text, const std::vector<parse::LayoutToken>& tokens);

// Pads consecutive port declarations, instances, transitions and one-line animations
// into columns.
void align_members(std::vector<Line>& lines);

// Sets each line's indent: 4 spaces per open brace, continuation lines deeper.
void indent_lines(std::vector<Line>& lines);

// Lines up trailing comments (after indent_lines).
void align_comments(std::vector<Line>& lines);

std::string print_lines(const std::vector<Line>& lines);

}  // namespace plant::formatter
