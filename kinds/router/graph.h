// The router's part of the graph contract (docs/language.md, "router"): its fixed slot and
// the fields of its routes (rows of `routes`, each an entry of its table naming one of its
// own outputs). It has no record of its own: its components' detail is none (KindDesc's
// table is empty). The rest of the kind is in this folder: kind.cpp (its descriptor row),
// lower.cpp (the compiler's lowering) and run.cpp (no hooks). Its `query` is read by the
// logic phase (a node of the logic network, graph/network.h; engine/logic.cpp).
#pragma once

// clang-format off
#define PLANT_SLOTS_ROUTER(S) \
    S(query, "query", String, In, "an ID to route; activates the first matching entry")

#define PLANT_FIELDS_ROUTE(F)                                         \
    F(CompId, comp)                                                  \
    F(Name, pattern)  /* glob over the queried ID; "*" matches all */ \
    F(SlotId, out_slot)
// clang-format on
