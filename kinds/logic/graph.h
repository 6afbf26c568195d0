// The connector's part of the graph contract (docs/language.md, "logic"): its fixed slot and
// the fields of its graph records (a row of `logics`; its inputs, rows of `logic_inputs`,
// each one of its own void input slots). A connector is declared by a form of its own,
// `logic NAME = TERM and TERM ...` (its row's `own_form`), not `logic NAME { ... }`. The
// rest of the kind is in this folder: kind.cpp (its descriptor row), lower.cpp (the
// compiler's lowering of that form) and run.cpp (no hooks). It is a node of the logic
// network (graph/network.h), evaluated by the logic phase (engine/logic.cpp).
#pragma once

// clang-format off
#define PLANT_SLOTS_LOGIC(S) \
    S(out, "out", Void, Out, "active in a step the operation is true")

#define PLANT_FIELDS_LOGIC(F)                                     \
    F(CompId, comp)                                              \
    F(LogicOp, op)                                                \
    F(Adr<LogicIn>, in_adr) /* into logic_inputs */                    \
    F(int32_t, in_num)                                            \
    F(SlotId, out_slot)

#define PLANT_FIELDS_LOGICIN(F) \
    F(SlotId, slot)  /* the connector's own void input slot */ \
    F(bool, negated)
// clang-format on
