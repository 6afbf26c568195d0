// The label's part of the graph contract (docs/language.md, "label"): its fixed slots and
// the fields of its graph record (a row of `labels`). The rest of the kind is in this
// folder: kind.cpp (its descriptor row), lower.cpp (the compiler's lowering) and run.cpp
// (its start in the step). Its `set` is read by the logic phase (a node of the logic
// network, graph/network.h; engine/logic.cpp), and a label inside an object is that
// object's bar code (engine/objects.cpp).
#pragma once

// clang-format off
#define PLANT_SLOTS_LABEL(S) \
    S(set, "set", String, In, "replaces the text") \
    S(value, "value", String, Out, "the text")

#define PLANT_FIELDS_LABEL(F) \
    F(CompId, comp)          \
    F(Name, value)
// clang-format on
