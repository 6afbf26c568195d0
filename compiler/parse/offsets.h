// ANTLR counts code points; our spans count bytes. Shared by the builder and the layout.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace plant::parse {

// Maps ANTLR's code-point indices to byte offsets (they differ only for non-ASCII text).
class Offsets {
public:
    explicit Offsets(const std::string& text) {
        bool ascii = std::all_of(text.begin(), text.end(),
                                 [](char c) { return static_cast<unsigned char>(c) < 0x80; });
        if (ascii) return;
        for (uint32_t i = 0; i < text.size(); ++i)
            if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) starts_.push_back(i);
        starts_.push_back(static_cast<uint32_t>(text.size()));
    }
    uint32_t byte(size_t cp) const {
        if (starts_.empty()) return static_cast<uint32_t>(cp);
        return starts_[std::min(cp, starts_.size() - 1)];
    }

private:
    std::vector<uint32_t> starts_;
};

}  // namespace plant::parse
