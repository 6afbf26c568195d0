// The constraint's row of the kind table (graph/plugin.h): what the compiler, the loader,
// the language server and the docs know of it.
#include "graph/kinds.h"
#include "graph/plugin.h"
#include "graph/range.h"

namespace plant::kinds::constraint {

using namespace plant::graph;

namespace {

constexpr SlotSpec kSlots[] = {PLANT_SLOTS_CONSTRAINT(PLANT_SLOT_SPEC)};
constexpr std::string_view kModes[] = {"fixed", "hinge", "slider"};
constexpr ParamSpec kParams[] = {
    {"a", ParamType::CompRef, "", true, 0, "first body"},
    {"b", ParamType::CompRef, "", true, 0, "second body"},
    {"axis", ParamType::Vec3, "", false, 0, "hinge/slider axis in the object's frame, default (0, 0, 1)"},
    {"lower", ParamType::Number, "", false, 0, "lower limit (angle or length)"},
    {"upper", ParamType::Number, "", false, 0, "upper limit (angle or length)"},
    {"enabled", ParamType::Bool, "", false, 0, "default true"},
};

bool check(const Graph& g, int32_t row, PluginProblem& problem) {
    const Joint& j = g.joints[JointId(row)];
    if (j.body_a == j.body_b) problem.message = "a joint joins two different bodies";
    else if (j.kind == JointKind::Hinge && j.lower <= j.upper && j.upper - j.lower > kMaxHingeSpan)
        problem.message = "a hinge's limits span more than a turn (Bullet's hinge would have none)";
    return problem.message.empty();
}

}  // namespace

constexpr KindDesc desc{
    .word = "constraint",
    .doc = "a joint between two bodies: fixed, a hinge or a slider",
    .slots = kSlots,
    .params = kParams,
    .check = check,
    .placed = true,  // the joint's frame
    .kind = CompKind::Constraint,
    .modes = kModes,
    PLANT_KIND_TABLE(joints),
};

}  // namespace plant::kinds::constraint
