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
    std::vector<int32_t> readers;     // op positions, each slot's ascending
    // A flow with a dynamic end reads whichever slot of its access's group (graph/network.h)
    // the reference names: each slot's groups, and each group's readers.
    std::vector<int32_t> groups;                           // group ids, each slot's
    std::vector<int32_t> group_reader_adr, group_readers;  // per group, +1; op positions
    // The slots some op reads, itself or through a group: a bit per slot, and per such slot a
    // row in `read_at` (its row is read_rank[x / 64] plus the bits below x in its word) with
    // the start of its readers and of its groups; the next row's starts end them. Most active
    // slots are read by no op (a trigger's on_stay, a body's outputs): one look at the small
    // bit table tells the phase so, and the rows take 8 bytes per read slot, not per slot.
    struct ReadAt {
        int32_t readers, groups;
    };
    std::vector<uint64_t> read_any;
    std::vector<int32_t> read_rank;  // per word of read_any: the read slots before it
    std::vector<ReadAt> read_at;     // per read slot, +1
    size_t dense_at = 0;  // active slots at the phase's start from which every op runs: ops / 8 + 1

    // Lanes: the program split for the physics threads (logic.cpp). Ops are joined when one
    // writes a slot the other reads or writes (a dynamic end: any slot of its access's group);
    // the sets so joined share nothing a step changes, and go whole to one of the lanes (the
    // largest first, each to the lane with the fewest ops). A lane runs its ops due in program
    // order and keeps what they activate with the op's position, so that the activity lists
    // can be joined in program order: the same lists, in the same order, as one pass gives.
    // In `lane_ops`, each lane's ops in program order from a multiple of 64 (a lane's due bits
    // are words of its own); `lane_readers` and `lane_group_readers` are `readers` and
    // `group_readers` as positions in `lane_ops`.
    std::vector<Op> lane_ops;
    std::vector<int32_t> lane_op_pos;  // per position in lane_ops: the op's position in `ops`, -1 padding
    std::vector<uint8_t> lane_of;      // per position in `ops`: its lane
    std::vector<int32_t> lane_adr;     // per lane, +1: its first position in lane_ops
    std::vector<int32_t> lane_writes;  // per lane: the slots its ops can activate
    std::vector<uint64_t> lane_always;  // `always`, by position in lane_ops
    std::vector<int32_t> lane_readers, lane_group_readers;
    static constexpr int32_t kLanes = 16;  // at most
    size_t lanes() const { return lane_adr.empty() ? 0 : lane_adr.size() - 1; }
};

Schedule build_schedule(const graph::Graph& g, const Tables& t);

}  // namespace plant::engine
