// The trigger's part of the graph contract (docs/language.md, "trigger"): its fixed slots and
// the fields of its graph record (a row of `triggers`). The rest of the kind is in this
// folder: kind.cpp (its descriptor row), lower.cpp (the compiler's lowering and linking) and
// run.cpp (its behaviour in the step). What it finds inside (State::triggers, inside) is
// read by the kinds that work on its objects: the gripper, the exit.
#pragma once

// clang-format off
#define PLANT_SLOTS_TRIGGER(S) \
    S(on_enter, "on_enter", Void, Out, "an object entered the volume this step") \
    S(on_stay, "on_stay", Void, Out, "at least one object is inside") \
    S(on_leave, "on_leave", Void, Out, "an object left the volume this step") \
    S(object, "object", Ref, Out, "the object that last entered (or is inside)") \
    S(count_inside, "count", Int, Out, "how many objects are inside")

#define PLANT_FIELDS_TRIGGER(F)                                                \
    F(CompId, comp)                                                           \
    F(OptId<Body>, body)       /* Body the volume moves with, -1 for fixed */      \
    F(Vec3, extent)                                                            \
    F(Pose, pose)          /* world pose of the box centre at start */         \
    F(OptId<DoType>, filter)     /* DoType whose bodies it reacts to, -1 for any */
// clang-format on
