#include "lsp/protocol.h"

#include <algorithm>
#include <cctype>

namespace plant::lsp {
namespace {

int hex_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

size_t line_start(const std::string& text, uint32_t line) {
    size_t pos = 0;
    for (uint32_t l = 0; l < line; ++l) {
        size_t nl = text.find('\n', pos);
        if (nl == std::string::npos) return text.size();
        pos = nl + 1;
    }
    return pos;
}

}  // namespace

std::string uri_to_path(const std::string& uri) {
    const std::string scheme = "file://";
    if (uri.rfind(scheme, 0) != 0) return "";
    std::string path;
    for (size_t i = scheme.size(); i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex_value(uri[i + 1]) >= 0 && hex_value(uri[i + 2]) >= 0) {
            path += static_cast<char>(hex_value(uri[i + 1]) * 16 + hex_value(uri[i + 2]));
            i += 2;
        } else {
            path += uri[i];
        }
    }
    return path;
}

std::string path_to_uri(const std::string& path) {
    static const char* kHex = "0123456789ABCDEF";
    std::string uri = "file://";
    for (unsigned char c : path) {
        if (std::isalnum(c) || c == '/' || c == '-' || c == '.' || c == '_' || c == '~') {
            uri += static_cast<char>(c);
        } else {
            uri += '%';
            uri += kHex[c >> 4];
            uri += kHex[c & 15];
        }
    }
    return uri;
}

size_t offset_of(const std::string& text, uint32_t line, uint32_t character) {
    size_t pos = line_start(text, line);
    uint32_t units = 0;
    while (pos < text.size() && text[pos] != '\n' && units < character) {
        unsigned char c = static_cast<unsigned char>(text[pos]);
        size_t len = c < 0x80 ? 1 : c < 0xE0 ? 2 : c < 0xF0 ? 3 : 4;
        units += len == 4 ? 2 : 1;
        pos = std::min(text.size(), pos + len);
    }
    return pos;
}

nlohmann::json position_of(const SourceMap& sm, int32_t file, uint32_t offset) {
    const std::string& text = sm.text(file);
    offset = std::min<uint32_t>(offset, static_cast<uint32_t>(text.size()));
    auto lc = sm.line_col(file, offset);
    size_t start = offset - (lc.col - 1);
    uint32_t units = 0;
    for (size_t i = start; i < offset;) {
        unsigned char c = static_cast<unsigned char>(text[i]);
        size_t len = c < 0x80 ? 1 : c < 0xE0 ? 2 : c < 0xF0 ? 3 : 4;
        units += len == 4 ? 2 : 1;
        i += len;
    }
    return {{"line", lc.line - 1}, {"character", units}};
}

nlohmann::json range_of(const SourceMap& sm, const Span& s) {
    return {{"start", position_of(sm, s.file, s.begin)}, {"end", position_of(sm, s.file, std::max(s.begin, s.end))}};
}

}  // namespace plant::lsp
