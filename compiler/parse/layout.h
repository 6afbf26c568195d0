// The tokens of a file as written, comments included, each marked with what `plant fmt`
// needs from the parse (compiler/fmt never sees ANTLR): where members start, which
// brackets open a call or an index, which operators are prefix ones, which tokens are
// the inside of a unit (they must stay adjacent: `cm/s`).
#pragma once

#include "diag/diagnostic.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace plant::parse {

enum class Lex : uint8_t { Code, LineComment, DocComment, BlockComment };
// What a member (or item, or component item) that starts at a token declares.
enum class Starts : uint8_t { None, Port, Instance, Transition, Animation, Other };

struct LayoutToken {
    uint32_t begin = 0, end = 0;  // bytes of the source
    Lex lex = Lex::Code;
    Starts starts = Starts::None;
    bool prefix = false;  // a prefix operator: `-x`, `not x`
    bool glued = false;   // never a space before it: `box(`, `seg[`, the `/s` of `cm/s`
};

// The file's tokens in order. Syntax errors go to `sink` exactly as parse_module reports
// them, and nothing is returned then.
std::optional<std::vector<LayoutToken>> layout_tokens(const SourceMap& sources, int32_t file, Sink& sink);

}  // namespace plant::parse
