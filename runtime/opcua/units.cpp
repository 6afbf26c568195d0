#include "opcua/units.h"

#include "graph/plugin.h"

#include <array>

namespace plant::opcua {
namespace {

// The SI unit of each dimension first, then the units people use for it on a line.
constexpr std::array kUnits = {
    Unit{"m", "MTR", "metre", "m", 1},
    Unit{"mm", "MMT", "millimetre", "m", 1e-3},
    Unit{"cm", "CMT", "centimetre", "m", 1e-2},
    Unit{"km", "KMT", "kilometre", "m", 1e3},
    Unit{"m/s", "MTS", "metre per second", "m/s", 1},
    Unit{"mm/s", "C16", "millimetre per second", "m/s", 1e-3},
    Unit{"cm/s", "2M", "centimetre per second", "m/s", 1e-2},
    Unit{"m/min", "2X", "metre per minute", "m/s", 1.0 / 60},
    Unit{"km/h", "KMH", "kilometre per hour", "m/s", 1.0 / 3.6},
    Unit{"m/s2", "MSK", "metre per second squared", "m/s2", 1},
    Unit{"s", "SEC", "second", "s", 1},
    Unit{"ms", "C26", "millisecond", "s", 1e-3},
    Unit{"min", "MIN", "minute", "s", 60},
    Unit{"h", "HUR", "hour", "s", 3600},
    Unit{"kg", "KGM", "kilogram", "kg", 1},
    Unit{"g", "GRM", "gram", "kg", 1e-3},
    Unit{"kg/s", "KGS", "kilogram per second", "kg/s", 1},
    Unit{"N", "NEW", "newton", "N", 1},
    Unit{"1/s", "C97", "reciprocal second", "1/s", 1},
    Unit{"Hz", "HTZ", "hertz", "1/s", 1},
    Unit{"1/min", "C94", "reciprocal minute", "1/s", 1.0 / 60},
    Unit{"rad", "C81", "radian", "rad", 1},
    Unit{"deg", "DD", "degree", "rad", 3.14159265358979323846 / 180},
    Unit{"rad/s", "2A", "radian per second", "rad/s", 1},
    Unit{"deg/s", "E96", "degree per second", "rad/s", 3.14159265358979323846 / 180},
};

}  // namespace

std::span<const Unit> units() { return kUnits; }

const Unit* find_unit(std::string_view symbol) {
    for (const Unit& u : kUnits)
        if (u.symbol == symbol) return &u;
    return nullptr;
}

int32_t unit_id(std::string_view code) {
    int32_t id = 0;
    for (char c : code) id = (id << 8) | int32_t(static_cast<unsigned char>(c));
    return id;
}

std::string_view slot_si_unit(const graph::Graph& g, graph::SlotId slot) {
    const graph::Slot& s = g.slots[slot];
    if (s.type != graph::SlotType::Real) return "";
    // A kind's row may say (graph::SlotSpec::unit: a field's speeds are in m/s).
    const auto fixed = graph::slots_of(g, s.comp);
    const int32_t k = slot.v - g.comps[s.comp].slot_adr.v;
    if (k >= 0 && size_t(k) < fixed.size()) return fixed[size_t(k)].unit;
    return "";
}

}  // namespace plant::opcua
