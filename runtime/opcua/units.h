// Engineering units of OPC UA nodes (docs/plc.md, "OPC UA"): the units a real node may be
// served in, each with its UNECE common code (OPC UA carries units as EUInformation made
// from it, Part 8 5.6.3) and its factor to SI, and the SI unit of the built-in real slots.
//
// A slot's value is in SI units (graph::SlotSpec carries no unit); a node declared with
// `unit = "mm/s"` serves it divided by that unit's factor and takes writes multiplied by it.
#pragma once

#include "graph/graph.h"

#include <cstdint>
#include <span>
#include <string_view>

namespace plant::opcua {

struct Unit {
    std::string_view symbol;       // as written in a plant file and shown to clients: "mm/s"
    std::string_view code;         // UNECE common code: "C16"
    std::string_view description;  // "millimetre per second"
    std::string_view si;           // the SI unit it measures in: "m/s"
    double factor;                 // value in SI = value in this unit x factor
};

std::span<const Unit> units();
const Unit* find_unit(std::string_view symbol);
// OPC UA's UnitId for a UNECE code (Part 8: the code's characters, high byte first).
int32_t unit_id(std::string_view code);

// The SI unit of a built-in real slot ("m/s" for a force field's speed; what a kind's row
// says, graph::SlotSpec::unit); "" when the slot has none we know of (an int, a bool).
std::string_view slot_si_unit(const graph::Graph& g, graph::SlotId slot);

}  // namespace plant::opcua
