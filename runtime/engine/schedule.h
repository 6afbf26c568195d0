// The logic phase as a precomputed program: every flow, connector, router and label
// once, in the order and with the cycle cuts of the graph library's analysis
// (graph/network.h), packed so one step is a single pass without lookups.
#pragma once

#include "engine/tables.h"
#include "graph/graph.h"

#include <cstdint>
#include <vector>

namespace plant::engine {

struct FlowOp {
    int32_t from = -1, to = -1;          // slots (from: the ref slot of a dynamic source)
    int32_t from_val = -1, to_val = -1;  // value_adr, -1 for void or dynamic ends
    int32_t from_access = -1, to_access = -1;
    int32_t width = 0;                   // doubles copied
    graph::Cond cond = graph::Cond::Source;
    bool once = false;
};

// Pulse: a static flow that runs whenever its source is active (condition `source`, not
// `once`) and carries no value — most flows; the logic phase runs it from the Op alone.
enum class OpKind : uint8_t { Flow, Pulse, Logic, Router, Label };

struct Op {
    OpKind kind;
    int32_t index;          // flow id, logic id, router comp id, label id
    int32_t from = -1, to = -1;  // a Pulse's slots
};

struct Schedule {
    std::vector<FlowOp> flows;     // by flow id
    std::vector<Op> ops;           // the logic phase, in order
    std::vector<int32_t> delayed;  // flows cut out of cycles
};

Schedule build_schedule(const graph::Graph& g, const Tables& t);

}  // namespace plant::engine
