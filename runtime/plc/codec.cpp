#include "plc/codec.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace plant::plc {

void put_u32(uint32_t v, uint16_t* regs) {
    regs[0] = uint16_t(v >> 16);
    regs[1] = uint16_t(v & 0xffff);
}

uint32_t get_u32(const uint16_t* regs) { return (uint32_t(regs[0]) << 16) | regs[1]; }

void put_float(float v, uint16_t* regs) {
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    put_u32(bits, regs);
}

float get_float(const uint16_t* regs) {
    const uint32_t bits = get_u32(regs);
    float v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

namespace {

// A number rounded and saturated to [lo, hi]; NaN reads as 0.
int64_t saturate(double v, int64_t lo, int64_t hi) {
    if (std::isnan(v)) return 0;
    v = std::round(v);
    if (v <= double(lo)) return lo;
    if (v >= double(hi)) return hi;
    return int64_t(v);
}

}  // namespace

void encode(const Entry& e, std::span<const double> value, std::string_view text, bool active, uint64_t count,
            uint16_t* regs) {
    const double v = value.empty() ? 0 : value[0];
    switch (e.encoding) {
    case Encoding::Bit:
        regs[0] = e.type == graph::SlotType::Void ? (active ? 1 : 0) : (v != 0 ? 1 : 0);
        break;
    case Encoding::Int16: regs[0] = uint16_t(int16_t(saturate(v, INT16_MIN, INT16_MAX))); break;
    case Encoding::Int32: put_u32(uint32_t(int32_t(saturate(v, INT32_MIN, INT32_MAX))), regs); break;
    case Encoding::Scaled: regs[0] = uint16_t(int16_t(saturate(v * e.scale, INT16_MIN, INT16_MAX))); break;
    case Encoding::Float32: put_float(float(v), regs); break;
    case Encoding::Count: regs[0] = uint16_t(count & 0xffff); break;
    case Encoding::String:
        for (int32_t r = 0; r < e.length; ++r) {
            const size_t i = 2 * size_t(r);
            const uint8_t hi = i < text.size() ? uint8_t(text[i]) : 0;
            const uint8_t lo = i + 1 < text.size() ? uint8_t(text[i + 1]) : 0;
            regs[r] = uint16_t((hi << 8) | lo);
        }
        break;
    }
}

double decode(const Entry& e, const uint16_t* regs) {
    switch (e.encoding) {
    case Encoding::Bit:
    case Encoding::Count: return regs[0] != 0 ? 1 : 0;
    case Encoding::Int16: return double(int16_t(regs[0]));
    case Encoding::Int32: return double(int32_t(get_u32(regs)));
    case Encoding::Scaled: return double(int16_t(regs[0])) / e.scale;
    case Encoding::Float32: return double(get_float(regs));
    case Encoding::String: return 0;
    }
    return 0;
}

void decode_text(const Entry& e, const uint16_t* regs, std::string& out) {
    out.clear();
    for (int32_t r = 0; r < e.length; ++r)
        for (uint8_t c : {uint8_t(regs[r] >> 8), uint8_t(regs[r] & 0xff)}) {
            if (c == 0) return;
            out += char(c);
        }
}

}  // namespace plant::plc
