// The state's part of the graph contract (docs/language.md, "state"): a Petri net. It has
// no fixed slots and no record of its own (its components' detail is none: KindDesc's table
// is empty); its places, transitions and their arcs are rows of `places`, `transitions` and
// `arcs`, each place and transition with slots of its own. The rest of the kind is in this
// folder: kind.cpp (its descriptor row), lower.cpp (the compiler's lowering) and run.cpp
// (its start). The nets step in phase 4 (engine/petri.cpp); the compiler analyses them
// (sema/checks.cpp, compiler/petri/).
#pragma once

// clang-format off
#define PLANT_SLOTS_STATE(S)

#define PLANT_FIELDS_PLACE(F)  \
    F(CompId, comp)           \
    F(Name, name)              \
    F(int32_t, initial)        \
    F(OptId<Slot>, put_slot)       /* void in: adds one token */ \
    F(OptId<Slot>, entered_slot)   /* void out: active in a step a token was put */ \
    F(OptId<Slot>, tokens_slot)    /* int out: the marking */ \
    F(Src, src)

#define PLANT_FIELDS_TRANSITION(F) \
    F(CompId, comp)               \
    F(Name, name)                  \
    F(Adr<Arc>, in_adr)  /* into arcs: consumed */ \
    F(int32_t, in_num)             \
    F(Adr<Arc>, out_adr) /* into arcs: produced */ \
    F(int32_t, out_num)            \
    F(OptId<Slot>, fired_slot) /* void out */ \
    F(Src, src)

#define PLANT_FIELDS_ARC(F) \
    F(PlaceId, place)       \
    F(int32_t, weight)
// clang-format on
