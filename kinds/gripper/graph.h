// The gripper's part of the graph contract (docs/language.md, "gripper"): its fixed slots
// and the fields of its graph record (a row of `grippers`). The rest of the kind is in this
// folder: kind.cpp (its descriptor row), lower.cpp (the compiler's lowering and linking) and
// run.cpp (its behaviour in the step).
#pragma once

// clang-format off
#define PLANT_SLOTS_GRIPPER(S) \
    S(grip, "grip", Void, In, "take the object in the gripper's trigger") \
    S(release, "release", Void, In, "hand the object back to the dynamics") \
    S(gripped, "gripped", Void, Out, "an object was taken") \
    S(released, "released", Void, Out, "an object was handed back") \
    S(object, "object", Ref, Out, "the object held (none: no object); typed by the trigger's `filter`")

#define PLANT_FIELDS_GRIPPER(F)                                  \
    F(CompId, comp)                                             \
    F(TriggerId, trigger)  /* Trigger that catches objects */     \
    F(OptId<Body>, body)     /* Body whose pose the gripped object follows, -1: the graphics/DO pose */ \
    F(OptId<Graphics>, graphics) /* Graphics whose pose it follows when body is -1 */
// clang-format on
