#include "graph/utf8.h"

#include <cstdint>

#include <fmt/format.h>

namespace plant::graph {

size_t invalid_utf8(std::string_view s) {
    size_t i = 0;
    while (i < s.size()) {
        const auto c = static_cast<unsigned char>(s[i]);
        size_t n = 0;
        uint32_t cp = 0, min = 0;
        if (c < 0x80) n = 1;
        else if ((c & 0xE0) == 0xC0) n = 2, cp = c & 0x1F, min = 0x80;
        else if ((c & 0xF0) == 0xE0) n = 3, cp = c & 0x0F, min = 0x800;
        else if ((c & 0xF8) == 0xF0) n = 4, cp = c & 0x07, min = 0x10000;
        else return i;
        if (i + n > s.size()) return i;
        for (size_t k = 1; k < n; ++k) {
            const auto d = static_cast<unsigned char>(s[i + k]);
            if ((d & 0xC0) != 0x80) return i;
            cp = (cp << 6) | (d & 0x3F);
        }
        if (n > 1 && (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))) return i;
        i += n;
    }
    return std::string_view::npos;
}

std::string utf8_error(std::string_view text, size_t bad) {
    return fmt::format("not valid UTF-8: byte 0x{:02X} at column {}", static_cast<unsigned char>(text[bad]), bad + 1);
}

}  // namespace plant::graph
