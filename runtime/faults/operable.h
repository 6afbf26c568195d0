// Inputs a trainee may operate (docs/viewer.md, "Roles"): the plant file lists them in an
// `operable` component, the training room's other plugin kind beside `faults`.
//
//   operable desk {
//       input 0 => line[0].b1.stop(label = "stop belt 1")
//       input 1 => line[0].s1.to_working
//   }
//
// The key is the control's place in the trainee page's list of controls (0 first); the path
// any input (a port: every input it forwards to). The kind has no behaviour in the step:
// `plant serve` reads the table and lets a trainee's page fire exactly these inputs (with
// the hand's grabs); everything else a trainee sends is refused.
#pragma once

#include "graph/graph.h"

#include <string>
#include <vector>

namespace plant::faults {

// Registers the kind once per process, as register_faults_kind.
void register_operable_kind();

struct Operable {
    double key = 0;              // its place in the list
    std::vector<graph::SlotId> slots;  // the inputs it names
    std::string label;           // "" when not given
};
// Every `operable` entry of the graph, in key order (then as written).
std::vector<Operable> operable_inputs(const graph::Graph& g);

}  // namespace plant::faults
