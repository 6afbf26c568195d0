#include "lsp/repair.h"

#include <algorithm>

namespace plant::lsp {
namespace {

constexpr int kRounds = 12;  // lines blanked at most

int32_t file_of(const Compilation& c, const std::string& path) {
    for (const auto& m : c.program.modules)
        if (m.key == path) return m.ast->file;
    return -1;
}

// Blanks the line of the error at `at`; when the error is the line's first token, the
// line before it that is not blank (`flow s1.` is reported at the `}` after it).
bool blank_line(std::string& text, size_t at) {
    at = std::min(at, text.size());
    size_t begin = at == 0 ? 0 : text.rfind('\n', at - 1) + 1;  // npos + 1 == 0
    if (text.find_first_not_of(" \t\r", begin) >= at) {
        while (begin > 0) {
            const size_t prev = begin - 1 == 0 ? 0 : text.rfind('\n', begin - 2) + 1;
            const bool blank = text.find_first_not_of(" \t\r", prev) >= begin - 1;
            begin = prev;
            if (!blank) break;
        }
    }
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    bool changed = false;
    for (size_t i = begin; i < end; ++i)
        if (text[i] != ' ' && text[i] != '\r') text[i] = ' ', changed = true;
    return changed;
}

}  // namespace

bool syntax_error_in(const Compilation& c, const std::string& path) {
    const int32_t file = file_of(c, path);
    for (const Diagnostic& d : c.sink.all())
        if (d.id == DiagId::Syntax && d.span.file == file) return true;
    return false;
}

std::shared_ptr<Compilation> parse_repaired(const std::string& path, std::string text, const std::string& stdlib_dir,
                                            sema::Overlay overlay, const Compilation& failed) {
    std::shared_ptr<Compilation> previous;
    for (int round = 0; round < kRounds; ++round) {
        auto c = std::make_shared<Compilation>();
        overlay[path] = text;
        const Compilation& last = previous ? *previous : failed;
        c->program = sema::load_program(path, stdlib_dir, c->sources, c->sink, &overlay, {&last.program, &last.sources});
        const int32_t file = file_of(*c, path);
        const Diagnostic* error = nullptr;
        for (const Diagnostic& d : c->sink.all())
            if (d.id == DiagId::Syntax && d.span.file == file && !error) error = &d;
        if (!error) return c;
        if (!blank_line(text, error->span.begin)) return nullptr;
        previous = c;
    }
    return nullptr;
}

}  // namespace plant::lsp
