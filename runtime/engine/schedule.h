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
    graph::SlotId from{}, to{};          // from: the ref slot of a dynamic source
    graph::Adr<graph::Value> from_val, to_val;  // value_adr, -1 for void or dynamic ends
    graph::AccessId from_access{}, to_access{};
    int32_t width = 0;                   // doubles copied
    graph::Cond cond = graph::Cond::Source;
    bool once = false;
};

// Pulse: a static flow that runs whenever its source is active (condition `source`, not
// `once`) and carries no value — most flows; the logic phase runs it from the Op alone.
enum class OpKind : uint8_t { Flow, Pulse, Logic, Router, Label };

struct Op {
    OpKind kind;
    int32_t index;          // flow id, logic id, router comp id, label id: as the accessors read it
    graph::SlotId from{}, to{};  // a Pulse's slots

    graph::FlowId flow() const { return graph::FlowId(index); }
    graph::LogicId logic() const { return graph::LogicId(index); }
    graph::CompId router() const { return graph::CompId(index); }
    graph::Id<graph::Label> label() const { return graph::Id<graph::Label>(index); }
};

// Most ops do nothing in a step where none of the slots they read is active (a flow whose
// source is not, a router not queried, a connector whose inputs are all off): the logic
// phase runs only those due, in the program's order. Due are the ops in `always` (an `and`
// whose inputs are all negated, an `or` with a negated input, a connector with no input)
// and each op that reads a slot active at the phase's start or made active by an op before
// it (its position in `readers`, by slot; a flow through a dynamic end reads every slot of
// its access's group). With a forced output the phase runs every op (a force may take an
// activity back mid-phase), and so it does when `dense_at` or more slots are active at the
// phase's start: then most ops are due anyway, and finding them costs more than running
// an op with nothing to do (the logic bench, where every cell ticks each step).
struct Schedule {
    graph::IdVector<graph::FlowId, FlowOp> flows;
    std::vector<Op> ops;           // the logic phase, in order
    std::vector<graph::FlowId> delayed;  // flows cut out of cycles
    std::vector<uint64_t> always;  // bit per op position: due every step
    std::vector<int32_t> reader_adr;  // per slot, +1: its readers' positions in `readers`
    std::vector<int32_t> readers;     // op positions, each slot's ascending
    // A flow with a dynamic end reads whichever slot of its access's group (graph/network.h)
    // the reference names: each slot's groups, and each group's readers.
    std::vector<int32_t> group_adr, groups;              // per slot, +1; group ids
    std::vector<int32_t> group_reader_adr, group_readers;  // per group, +1; op positions
    size_t dense_at = 0;  // active slots at the phase's start from which every op runs: ops / 8 + 1
};

Schedule build_schedule(const graph::Graph& g, const Tables& t);

}  // namespace plant::engine
