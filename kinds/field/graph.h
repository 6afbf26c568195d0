// The field's part of the graph contract (docs/language.md, "field"): its fixed slots and
// the fields of its graph record (a row of `fields`). The rest of the kind is in this
// folder: kind.cpp (its descriptor row), lower.cpp (the compiler's lowering and linking) and
// run.cpp (its start and its act hook). The conveyor law it exerts is the physics phase's
// (engine/fields.cpp, engine/conveyor.cpp): its target speed and on/off (State::field_speed,
// field_on) are shared with it.
#pragma once

// clang-format off
#define PLANT_SLOTS_FIELD(S) \
    S(set_speed, "set_speed", Real, In, "target speed along the direction, m/s") \
    S(enable, "enable", Void, In, "the field pushes") \
    S(disable, "disable", Void, In, "the field stops pushing") \
    S(speed, "speed", Real, Out, "the speed it drives at: its target speed while enabled, 0 while not") \
    S(enabled, "enabled", Bool, Out, "whether the field pushes")

#define PLANT_FIELDS_FIELD(F)                                                       \
    F(CompId, comp)                                                                \
    F(OptId<Body>, body)     /* Body id the field is attached to, -1 for none */        \
    F(Vec3, extent)      /* full extents of the box volume */                       \
    F(Pose, pose)        /* world pose of the box centre */                         \
    F(Vec3, dir)         /* unit direction, in the field's local frame */           \
    F(double, speed)     /* target speed along dir, m/s */                          \
    F(double, gain)      /* k, kg/s (N per m/s of speed error) */                   \
    F(double, max_force) /* slip limit per body, N; 0: unlimited */                 \
    F(bool, enabled)                                                               \
    F(double, radius)    /* a turning field: where `speed` applies, m; 0: it does not turn */ \
    F(Vec3, pivot)       /* ... and the point it turns about, in its own frame, m */
// clang-format on
