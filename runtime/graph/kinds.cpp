#include "kinds.h"

#include <array>

namespace plant::graph {
namespace {

using T = SlotType;
constexpr Dir I = Dir::In;
constexpr Dir O = Dir::Out;

constexpr std::array kGraphics = {
    SlotSpec{"set_pose", T::Pose, I, "moves the graphics (and its children) to a pose"},
    SlotSpec{"pose", T::Pose, O, "the current world pose"},
    SlotSpec{"shown", T::String, O, "name of the model variant shown (the model itself when none)"},
};
constexpr std::array kBody = {
    SlotSpec{"set_pose", T::Pose, I, "teleports the body"},
    SlotSpec{"set_position", T::Vec3, I, "teleports the body's origin"},
    SlotSpec{"set_orientation", T::Quat, I, "sets the orientation"},
    SlotSpec{"set_velocity", T::Vec3, I, "sets the linear velocity"},
    SlotSpec{"set_angular_velocity", T::Vec3, I, "sets the angular velocity"},
    SlotSpec{"collision_on", T::Void, I, "the body collides again"},
    SlotSpec{"collision_off", T::Void, I, "other bodies pass through it"},
    SlotSpec{"dynamics_on", T::Void, I, "the body is simulated again"},
    SlotSpec{"dynamics_off", T::Void, I, "taken out of the simulation, moved kinematically"},
    SlotSpec{"pose", T::Pose, O, "world pose"},
    SlotSpec{"position", T::Vec3, O, "world position of the body frame"},
    SlotSpec{"orientation", T::Quat, O, "world orientation"},
    SlotSpec{"velocity", T::Vec3, O, "linear velocity"},
    SlotSpec{"angular_velocity", T::Vec3, O, "angular velocity"},
};
constexpr std::array kField = {
    SlotSpec{"set_speed", T::Real, I, "target speed along the direction, m/s"},
    SlotSpec{"enable", T::Void, I, "the field pushes"},
    SlotSpec{"disable", T::Void, I, "the field stops pushing"},
    SlotSpec{"speed", T::Real, O, "the current target speed"},
};
constexpr std::array kJoint = {
    SlotSpec{"enable", T::Void, I, "the constraint holds"},
    SlotSpec{"disable", T::Void, I, "the constraint is released"},
    SlotSpec{"enabled", T::Bool, O, "whether it holds"},
};
constexpr std::array kTrigger = {
    SlotSpec{"on_enter", T::Void, O, "an object entered the volume this step"},
    SlotSpec{"on_stay", T::Void, O, "at least one object is inside"},
    SlotSpec{"on_leave", T::Void, O, "an object left the volume this step"},
    SlotSpec{"object", T::Ref, O, "the object that last entered (or is inside)"},
    SlotSpec{"count", T::Int, O, "how many objects are inside"},
};
constexpr std::array kTimer = {
    SlotSpec{"start", T::Void, I, "starts (or restarts) the timer"},
    SlotSpec{"stop", T::Void, I, "stops the timer"},
    SlotSpec{"tick", T::Void, O, "the period or delay elapsed"},
    SlotSpec{"elapsed", T::Real, O, "seconds since start"},
    SlotSpec{"running", T::Bool, O, "whether the timer runs"},
};
constexpr std::array kGripper = {
    SlotSpec{"grip", T::Void, I, "take the object in the gripper's trigger"},
    SlotSpec{"release", T::Void, I, "hand the object back to the dynamics"},
    SlotSpec{"gripped", T::Void, O, "an object was taken"},
    SlotSpec{"released", T::Void, O, "an object was handed back"},
    SlotSpec{"object", T::Ref, O, "the object held, -1 for none"},
};
constexpr std::array kSource = {
    SlotSpec{"issue", T::Void, I, "issue one object from the pool"},
    SlotSpec{"issued", T::Void, O, "an object was issued"},
    SlotSpec{"object", T::Ref, O, "the object issued last"},
    SlotSpec{"id", T::String, O, "the bar code of the object issued last"},
    SlotSpec{"count", T::Int, O, "objects issued so far"},
};
constexpr std::array kExit = {
    SlotSpec{"taken", T::Void, O, "an object was taken out of the world"},
    SlotSpec{"object", T::Ref, O, "the object taken last"},
    SlotSpec{"id", T::String, O, "its bar code"},
    SlotSpec{"count", T::Int, O, "objects taken so far"},
};
constexpr std::array kRouter = {
    SlotSpec{"query", T::String, I, "an ID to route; activates the first matching entry"},
};
constexpr std::array kLogic = {
    SlotSpec{"out", T::Void, O, "active in a step the operation is true"},
};
constexpr std::array kLabel = {
    SlotSpec{"set", T::String, I, "replaces the text"},
    SlotSpec{"value", T::String, O, "the text (a bottle's bar code)"},
};

}  // namespace

std::span<const SlotSpec> fixed_slots(CompKind kind) {
    switch (kind) {
    case CompKind::Graphics: return kGraphics;
    case CompKind::Body: return kBody;
    case CompKind::Field: return kField;
    case CompKind::Constraint: return kJoint;
    case CompKind::State: return {};
    case CompKind::Trigger: return kTrigger;
    case CompKind::Timer: return kTimer;
    case CompKind::Gripper: return kGripper;
    case CompKind::Source: return kSource;
    case CompKind::Exit: return kExit;
    case CompKind::Router: return kRouter;
    case CompKind::Logic: return kLogic;
    case CompKind::Label: return kLabel;
    case CompKind::Plugin: return {};  // its descriptor's (graph/plugin.h: slots_of)
    }
    return {};
}

int fixed_slot_index(CompKind kind, std::string_view name) {
    auto slots = fixed_slots(kind);
    for (size_t i = 0; i < slots.size(); ++i)
        if (slots[i].name == name) return static_cast<int>(i);
    return -1;
}

}  // namespace plant::graph
