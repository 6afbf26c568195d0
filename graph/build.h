// Appending to a graph as the compiler lays it out, for the compiler and for tests that
// build graphs by hand. The layout rules live here once:
// - a DO's components are contiguous (comp_adr, comp_num): add them right after the DO;
// - a component's slots are contiguous: its kind's fixed slots (kinds.h) first, then its
//   dynamic ones, added before the next component;
// - every non-void slot owns slot_width(type) doubles in Graph::values, starting at
//   value_adr, all 0 except: a ref or string reads -1 (no object, no text: not the first
//   name), a quat or pose ends in w = 1 (the identity).
// Kind-specific records (Body, Trigger, ...) and their `detail` index are the caller's.
// Every id is typed (ids.h): a call with two ids swapped does not compile
// (tests/compile_fail/swapped_ids.cpp); DoId{}, DoTypeId{}, AccessId{} are "none".
#pragma once

#include "graph.h"

#include <string_view>

namespace plant::graph {

// A DO with no components yet; its ordinal counts the DOs of its type so far.
DoId add_do(Graph& g, std::string_view path, DoId parent, DoTypeId type, const Pose& pose, Src src = {});

// A component of DO `owner` with its kind's fixed slots (their src is the component's),
// detail -1. Extends the owner's component range.
CompId add_comp(Graph& g, DoId owner, CompKind kind, std::string_view name, Src src = {});

// A dynamic slot of `comp`, which must be the last component added.
SlotId add_slot(Graph& g, CompId comp, std::string_view name, SlotType type, Dir dir, Src src = {});

// A dynamic end (a valid from_access/to_access) passes its access's ref_slot as from/to.
FlowId add_flow(Graph& g, SlotId from, SlotId to, Cond cond, bool once, AccessId from_access = {},
                AccessId to_access = {}, Src src = {});

// The first value of a non-void slot (its start value, as the loader reads it).
double& slot_value(Graph& g, SlotId slot);

}  // namespace plant::graph
