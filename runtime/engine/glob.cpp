// Route patterns: '*' matches any run of characters (also none), '?' one character,
// anything else itself. Iterative, with one backtrack point: linear for these patterns.
#include "engine/runtime.h"

namespace plant::engine {

bool glob_match(std::string_view pat, std::string_view text) {
    size_t p = 0, t = 0, star = std::string_view::npos, mark = 0;
    while (t < text.size()) {
        if (p < pat.size() && (pat[p] == '?' || pat[p] == text[t])) {
            ++p;
            ++t;
        } else if (p < pat.size() && pat[p] == '*') {
            star = p++;
            mark = t;
        } else if (star != std::string_view::npos) {
            p = star + 1;
            t = ++mark;
        } else {
            return false;
        }
    }
    while (p < pat.size() && pat[p] == '*') ++p;
    return p == pat.size();
}

}  // namespace plant::engine
