#include "parse/braces.h"

namespace plant::parse {

std::vector<Note> unclosed_brace_notes(int32_t file, const std::vector<Brace>& braces, const std::string& where) {
    std::vector<const Brace*> open;
    const Brace* suspect = nullptr;  // the first block closed by a `}` indented as an outer one
    const Brace* suspect_close = nullptr;
    for (const Brace& b : braces) {
        if (b.open) {
            open.push_back(&b);
            continue;
        }
        if (open.empty()) continue;
        const Brace* o = open.back();
        open.pop_back();
        if (!suspect && b.indent < o->indent) suspect = o, suspect_close = &b;
    }
    std::vector<Note> notes;
    if (open.empty()) return notes;
    const Brace& unclosed = *open.back();
    notes.push_back({Span{file, unclosed.begin, unclosed.begin + 1}, "this '{' is not closed before " + where});
    // Only a block inside the unclosed one can have taken its `}`.
    if (suspect && suspect->begin > unclosed.begin)
        notes.push_back({Span{file, suspect->begin, suspect->begin + 1},
                         "maybe this block is the one missing its '}': the '}' on line " +
                             std::to_string(suspect_close->line) + " closes it, but is indented as an outer block"});
    return notes;
}

}  // namespace plant::parse
