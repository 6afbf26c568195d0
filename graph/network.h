// The logic network, analysed once for the compiler's warnings, the runtime's logic
// phase and `plant info --schedule`: which slots a flow end can be, who makes each
// slot active and who reads that activity, and the order the logic phase runs in.
//
// Order: a node that makes a slot active runs before the nodes that read that
// activity (flows into a connector input before the connector, the connector before
// flows from its output). A flow whose condition reads its target's activity runs
// after the flows into that target whose condition does not. Ties go by node id
// (flows, then connectors, routers, labels). A cycle is broken at its lowest-numbered
// flow, which becomes "delayed": it is evaluated after all others and its effect lands
// in the next step (one step delay).
#pragma once

#include "graph/graph.h"

#include <cstdint>
#include <string>
#include <vector>

namespace plant::graph {

// The slots one end of a flow can be: the slot itself when static, every target of its
// access when dynamic (then `from`/`to` hold the access's reference slot, see Flow).
// Calls fn(slot) for each until fn returns false; returns whether none did.
template <class Fn>
bool each_end_slot(const Graph& g, SlotId slot, AccessId access, Fn&& fn) {
    if (!access.valid()) return fn(slot);
    const Access& a = g.accesses[access];
    for (Id<AccessTarget> t : children(a.target_adr, a.target_num))
        if (!fn(g.access_targets[t].v)) return false;
    return true;
}

// Every slot a flow may write.
template <class Fn>
void each_written_slot(const Graph& g, const Flow& f, Fn&& fn) {
    each_end_slot(g, f.to, f.to_access, [&](SlotId s) { fn(s); return true; });
}

// Every slot a flow reads: its source, or for a dynamic source the reference slot
// (which object to read from) and every slot the source may be.
template <class Fn>
void each_read_slot(const Graph& g, const Flow& f, Fn&& fn) {
    if (f.from_access.valid()) fn(g.accesses[f.from_access].ref_slot);
    each_end_slot(g, f.from, f.from_access, [&](SlotId s) { fn(s); return true; });
}

// Accesses whose targets are the same slots (the same member of every object of one type)
// form one group: `of` per access its group, `first` per group its first access.
struct AccessGroup;
using AccessGroupId = Id<AccessGroup>;
struct AccessGroups {
    IdVector<AccessId, AccessGroupId> of;
    IdVector<AccessGroupId, AccessId> first;
    // The slots group k's ends may be.
    auto targets(const Graph& g, AccessGroupId k) const {
        const Access& a = g.accesses[first[k]];
        return g.access_targets.slice(a.target_adr, a.target_num);
    }
};
AccessGroups access_groups(const Graph& g);

// One node of the logic phase.
enum class NodeKind : uint8_t { Flow, Logic, Router, Label };

struct Node {
    NodeKind kind;
    int32_t index;  // flow id, logic id, router comp id, label id: as the accessors read it

    FlowId flow() const { return FlowId(index); }
    LogicId logic() const { return LogicId(index); }
    CompId router() const { return CompId(index); }
    Id<Label> label() const { return Id<Label>(index); }
};

struct Network {
    std::vector<Node> order;       // the logic phase, delayed flows left out
    std::vector<FlowId> delayed;   // flows cut out of cycles, in the order cut
    std::vector<std::vector<CompId>> cycles;  // per delayed flow: the comps on its cycle
};

Network analyse_network(const Graph& g);

// One line per node in order, then the delayed flows, for `plant info --schedule`.
std::string network_text(const Graph& g, const Network& n);

}  // namespace plant::graph
