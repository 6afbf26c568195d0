// The OPC UA link as a component kind (docs/plc.md, "OPC UA"):
//
//   opcua ua {
//       endpoint = "opc.tcp://127.0.0.1:4840"
//       namespace = "urn:plant:bottling"
//       node 1 => line[0].s2.seen                      // a counter and its events
//       node 2 => line[0].s2.id                        // a String variable
//       node 3 => line[0].s2.to_working                // a method
//       node 4 => line[0].b1.speed_now(unit = "mm/s")  // a Double in mm/s
//   }
//
// Its entries are the node map: the key is the node's numeric NodeId in the plant's
// namespace, the path the slot it stands for. The kind has no behaviour in the step:
// `plant run` and `plant serve` serve the map (link.h), and what clients write arrives as
// events.
#pragma once

#include "graph/plugin.h"
#include "opcua/nodes.h"

namespace plant::opcua {

constexpr std::string_view kWord = "opcua";

// Registers the kind (descriptor and check) once per process; every program that compiles
// or loads plants with an OPC UA link calls it first.
void register_opcua_kind();

}  // namespace plant::opcua
