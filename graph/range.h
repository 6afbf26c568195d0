// The range a plant's places, sizes, masses and belts lie in. Shared by the compiler (E0308
// at the declaration that puts a value out of range) and the graph loader (validate.cpp), so
// both refuse the same graphs. The physics is single precision: far out, or far too large, a
// number is rounded beyond use (at 100 km a float's step is 8 mm) or overflows to infinity;
// far too small, it rounds to zero (a mass of 1e-300 kg is a float 0: a static body).
#pragma once

#include "graph/graph.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace plant::graph {

// Every coordinate of a place (a world pose at start, or an offset from a body, a graphics
// or a shape's origin) and every size lies within this (100 km, in metres).
constexpr double kMaxLength = 1e5;
// Every size (each extent of a box, field or trigger; a sphere's radius; a cylinder's or a
// capsule's radius and height) is at least this (0.1 mm): below it Bullet's contact margins
// and a float's rounding leave no shape.
constexpr double kMinLength = 1e-4;
// Every body's mass is at most this (1,000 t, in kg), and every principal moment of inertia
// at most kMaxMass · kMaxLength².
constexpr double kMaxMass = 1e6;
// A dynamic body's mass is at least this (1 mg), and every principal moment of inertia set at
// least kMinInertia (kMinMass · kMinLength², written out: the product rounds above it).
constexpr double kMinMass = 1e-6;
constexpr double kMinInertia = 1e-14;
// A field's target speed is at most this (100 km/s, in m/s: a body at it leaves the world
// within a second) ...
constexpr double kMaxSpeed = 1e5;
// ... and its gain at most this (kg/s, kMaxMass · kMaxRate): at it the speed error of even
// the heaviest body at the fastest step rate shrinks e-fold in each step, of any lighter one
// faster; beyond, k · speed leaves the range of the law's arithmetic.
constexpr double kMaxGain = 1e12;
// Every component of the plant's gravity is at most this (1 km/s², about 100 g).
constexpr double kMaxGravity = 1e3;
// A body's angular velocity set from outside is at most this on each axis (rad/s): Bullet
// turns a body by at most a quarter turn a step, which at the fastest rate is 1.6e6 rad/s.
constexpr double kMaxTurnRate = 1e6;

// What Bullet would clamp or ignore, refused instead of run silently otherwise:
// a body's linear and angular damping lie in [0, 1] (btRigidBody::setDamping clamps them);
constexpr double kMaxDamping = 1;
// a body's friction is at most 10 (a contact's friction, the product of its two bodies', is
// capped at 10 by btManifoldResult::calculateCombinedFriction);
constexpr double kMaxFriction = 10;
// a hinge's limits span at most a turn, in radians (wider, btAngularLimit never acts);
constexpr double kMaxHingeSpan = 6.283185307179586;
// a static or kinematic body has no mass, inertia or damping (Bullet moves it by its pose
// alone): validate.cpp and the compiler refuse them on such a body.

// Whether a place or an offset (x, y, z in metres) lies within kMaxLength on every axis.
bool place_in_range(const double* p);
// Whether a gravity (m/s²) lies within kMaxGravity on every axis.
bool gravity_in_range(const double* g);
// What a value put into `slot` from outside (an event, a forced value, a PLC write) must lie
// in where the slot moves the physics: a body's or a graphics' set_pose and a body's
// set_position a place within kMaxLength, a body's set_velocity kMaxSpeed and
// set_angular_velocity kMaxTurnRate on each axis, a field's set_speed kMaxSpeed. Empty when
// `v` (the slot's width of finite values) is in range; else the range, in words. A static
// body's set_velocity and set_angular_velocity take no value at all (kStaticVelocity).
std::string_view input_range(const Graph& g, SlotId slot, const double* v);
// The same, for a slot of component `c` (the step's act hooks have it at hand).
std::string_view input_range(const Graph& g, const Comp& c, SlotId slot, const double* v);
// A static body's set_velocity or set_angular_velocity (compile error E0316 for a flow).
bool static_velocity(const Graph& g, SlotId slot);
inline constexpr std::string_view kStaticVelocity =
    "no value: the body is static and does not move (declare it kinematic to command its velocity)";

struct RangeFlaw {
    std::string_view table;  // as in the text form's tables: "dos", "bodies", ...
    int32_t row = -1;
    std::string_view field;
    std::string_view what;  // the field in words: "place", "size of a shape", "key frame", ...
    CompId comp;            // the component the record belongs to; none (-1) for a DO
    std::string text;       // to follow the field: "is 200000 m out along x, beyond 100 km"
};

// Every field of `g` out of range: the DOs first (so an object comes before what it holds),
// then each component's records, a body's shapes after the body and an animation's keys with
// their graphics. Assumes every number finite and every list inside its table (validate.h
// checks both first); hull points are hull.h's.
std::vector<RangeFlaw> range_flaws(const Graph& g);

}  // namespace plant::graph
