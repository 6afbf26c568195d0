// The exit's part of the graph contract (docs/language.md, "exit"): its fixed slots and the
// fields of its graph record (a row of `exits`). The rest of the kind is in this folder:
// kind.cpp (its descriptor row), lower.cpp (the compiler's lowering and linking) and run.cpp
// (its behaviour in the step). An object it takes goes back to its source's pool
// (engine/objects.cpp: take_object).
#pragma once

// clang-format off
#define PLANT_SLOTS_EXIT(S) \
    S(taken, "taken", Void, Out, "an object was taken out of the world") \
    S(object, "object", Ref, Out, "the object taken last (untyped)") \
    S(id, "id", String, Out, "its bar code") \
    S(taken_count, "count", Int, Out, "objects taken so far")

#define PLANT_FIELDS_EXIT(F) \
    F(CompId, comp)         \
    F(TriggerId, trigger)
// clang-format on
