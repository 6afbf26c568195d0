// The constraint's part of the graph contract (docs/language.md, "constraint"): its fixed
// slots and the fields of its graph record (a row of `joints`, which the physics also reads:
// runtime/engine/physics.cpp makes the Bullet constraint). The rest of the kind is in this
// folder: kind.cpp (its descriptor row), lower.cpp (the compiler's lowering and linking)
// and run.cpp (its behaviour in the step).
#pragma once

// clang-format off
#define PLANT_SLOTS_CONSTRAINT(S) \
    S(enable, "enable", Void, In, "the constraint holds") \
    S(disable, "disable", Void, In, "the constraint is released") \
    S(enabled, "enabled", Bool, Out, "whether it holds")

#define PLANT_FIELDS_CONSTRAINT(F)                                                    \
    F(CompId, comp)                                                             \
    F(JointKind, kind)                                                           \
    F(BodyId, body_a)                                                           \
    F(OptId<Body>, body_b)                                                         \
    F(Pose, frame_a)     /* joint frame relative to body a */                    \
    F(Pose, frame_b)     /* joint frame relative to body b */                    \
    F(double, lower)     /* hinge: rad, slider: m; lower > upper means free */   \
    F(double, upper)                                                             \
    F(bool, enabled)
// clang-format on
