// Values of mapped slots to and from Modbus registers (docs/plc.md, "Encodings"):
// no allocation, so the step thread can encode every step.
#pragma once

#include "plc/map.h"

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace plant::plc {

// An output entry's registers (width(e) of them; a bit as 0 / 1 in regs[0]) from the
// slot's value (`text` for strings) and, for void slots, whether it was active in the
// last step and how many steps it has been active in so far.
void encode(const Entry& e, std::span<const double> value, std::string_view text, bool active, uint64_t count,
            uint16_t* regs);
// The number an input entry's registers hold (a bit: 0 or 1; a void slot: 1 = fire).
double decode(const Entry& e, const uint16_t* regs);
// A string entry's text: up to the first NUL.
void decode_text(const Entry& e, const uint16_t* regs, std::string& out);

// Two registers, high word first.
void put_u32(uint32_t v, uint16_t* regs);
uint32_t get_u32(const uint16_t* regs);
void put_float(float v, uint16_t* regs);
float get_float(const uint16_t* regs);

}  // namespace plant::plc
