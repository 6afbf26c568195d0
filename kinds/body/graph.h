// The body's part of the graph contract (docs/language.md, "physics"): its fixed slots and
// the fields of its graph records (a row of `bodies`; its shapes, rows of `shapes`, a hull's
// points rows of `points`). A body is written `physics` in plant files (its row's word). The
// rest of the kind is in this folder: kind.cpp (its descriptor row), lower.cpp (the
// compiler's lowering) and run.cpp (its sensing and acting in the step). Its world (the
// Bullet bodies) is the physics phase's (engine/physics.h), shared with every kind that
// moves or reads bodies.
#pragma once

// clang-format off
#define PLANT_SLOTS_BODY(S) \
    S(set_pose, "set_pose", Pose, In, "teleports the body") \
    S(set_position, "set_position", Vec3, In, "teleports the body's origin") \
    S(set_orientation, "set_orientation", Quat, In, "sets the orientation") \
    S(set_velocity, "set_velocity", Vec3, In, "sets the linear velocity (dynamic or kinematic body)") \
    S(set_angular_velocity, "set_angular_velocity", Vec3, In, "sets the angular velocity (dynamic or kinematic body)") \
    S(collision_on, "collision_on", Void, In, "the body collides again") \
    S(collision_off, "collision_off", Void, In, "other bodies pass through it") \
    S(dynamics_on, "dynamics_on", Void, In, "the body is simulated again") \
    S(dynamics_off, "dynamics_off", Void, In, "taken out of the simulation, moved kinematically") \
    S(pose, "pose", Pose, Out, "world pose") \
    S(position, "position", Vec3, Out, "world position of the body frame") \
    S(orientation, "orientation", Quat, Out, "world orientation") \
    S(velocity, "velocity", Vec3, Out, "linear velocity") \
    S(angular_velocity, "angular_velocity", Vec3, Out, "angular velocity")

#define PLANT_FIELDS_BODY(F)                                                             \
    F(CompId, comp)                                                                     \
    F(BodyMode, mode)                                                                    \
    F(double, mass)                                                                      \
    F(Vec3, inertia)        /* principal moments; used when inertia_set */               \
    F(bool, inertia_set)                                                                 \
    F(double, friction)                                                                  \
    F(double, restitution)                                                               \
    F(double, linear_damping)                                                            \
    F(double, angular_damping)                                                           \
    F(bool, collision)      /* initial collision on/off */                               \
    F(bool, dynamics)       /* initial dynamics on/off */                                \
    F(Adr<Shape>, shape_adr)                                                                \
    F(int32_t, shape_num)                                                                \
    F(Pose, pose)           /* world pose of the body frame at start */                  \
    F(Pose, com)            /* centre of mass relative to the body frame */

#define PLANT_FIELDS_SHAPE(F)                                                        \
    F(ShapeKind, kind)                                                              \
    F(Vec3, size)        /* box: full extents; sphere: r,-,-; cylinder/capsule: r,h,- (axis z) */ \
    F(Adr<Point>, point_adr) /* hull: into points */                                   \
    F(int32_t, point_num)                                                           \
    F(Pose, local)       /* relative to the body frame */
// clang-format on
