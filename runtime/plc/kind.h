// The Modbus TCP link as a component kind (docs/plc.md, "Declaring the link in a plant"):
//
//   modbus plc {
//       port = 1502
//       coil 0 => line[0].s1.to_working
//       discrete 0 => line[0].s2.seen
//       input 4 => line[0].s2.reader.id(registers = 8)
//       holding 10 => line[0].b1.set_speed(scale = 1000, unit = "mm/s")
//   }
//
// Its entries are the register map: `coil` and `holding` name inputs the PLC drives,
// `discrete` and `input` outputs it reads; the key is the 0-based address. The kind has
// no behaviour in the step: `plant run` serves the map (run_link.h) and what clients
// write arrives as events.
#pragma once

#include "graph/plugin.h"
#include "plc/map.h"

namespace plant::plc {

// Registers the kind (descriptor, check and behaviour) once per process; every program
// that compiles or loads plants with a link calls it first.
void register_modbus_kind();

// The map of the link component `plugin` (a row of Graph::plugins of kind modbus), its
// declared port (0: none) and host (""): false with `problem` when an entry's options do
// not make an encoding. check_map has not run on it.
bool link_map(const graph::Graph& g, graph::PluginId plugin, Map& out, graph::PluginProblem& problem);

}  // namespace plant::plc
