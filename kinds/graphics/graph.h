// The graphics' part of the graph contract (docs/language.md, "graphics"): its fixed slots
// and the fields of its graph records (a row of `graphics`; its animations, their keys and
// its variants, rows of `animations`, `keys` and `variants`). The rest of the kind is in this
// folder: kind.cpp (its descriptor row), lower.cpp (the compiler's lowering and linking) and
// run.cpp (its behaviour in the step). Its poses (State::graphics) are read by what follows
// or moves a graphics: a gripper, a source issuing an object, Engine::graphics_pose.
#pragma once

// clang-format off
#define PLANT_SLOTS_GRAPHICS(S) \
    S(set_pose, "set_pose", Pose, In, "moves the graphics (and its children) to a pose") \
    S(pose, "pose", Pose, Out, "the current world pose") \
    S(shown, "shown", String, Out, "the name of the variant shown (the model's name while none is selected)")

#define PLANT_FIELDS_GRAPHICS(F)                           \
    F(CompId, comp)                                       \
    F(OptId<Graphics>, parent)    /* parent Graphics, -1 */        \
    F(Name, model)                                         \
    F(Pose, pose)         /* world pose at start */        \
    F(OptId<Body>, body)      /* Body it is attached to, -1 */ \
    F(Adr<Animation>, anim_adr)                                   \
    F(int32_t, anim_num)                                   \
    F(Adr<Variant>, variant_adr)                                \
    F(int32_t, variant_num)                                \
    F(int32_t, variant)   /* initial variant, among its own (variant_adr + variant), -1: model */

#define PLANT_FIELDS_ANIMATION(F)                            \
    F(GraphicsId, graphics)                                     \
    F(Name, name)                                            \
    F(double, duration)                                      \
    F(Adr<Key>, key_adr)                                      \
    F(int32_t, key_num)                                      \
    F(SlotId, play_slot)                                    \
    F(SlotId, finished_slot)

#define PLANT_FIELDS_KEY(F) \
    F(double, t)            \
    F(Pose, pose)           /* relative to the graphics' start pose */

#define PLANT_FIELDS_VARIANT(F) \
    F(GraphicsId, graphics)        \
    F(Name, name)               \
    F(Name, model)              \
    F(SlotId, select_slot)
// clang-format on
