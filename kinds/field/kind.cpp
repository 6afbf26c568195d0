// The field's row of the kind table (graph/plugin.h): what the compiler, the loader, the
// language server and the docs know of it.
#include "graph/kinds.h"
#include "graph/plugin.h"

#include <array>
#include <cmath>

namespace plant::kinds::field {

using namespace plant::graph;

namespace {

constexpr auto kSlots = [] {
    std::array slots = {PLANT_SLOTS_FIELD(PLANT_SLOT_SPEC)};
    slots[fieldslot::set_speed].unit = "m/s";
    slots[fieldslot::speed].unit = "m/s";
    return slots;
}();
constexpr ParamSpec kParams[] = {
    {"extent", ParamType::Vec3, "m", true, 0, "full extents of the box volume"},
    {"direction", ParamType::Vec3, "", false, 0, "unit direction in the field's frame, default (1, 0, 0)"},
    {"speed", ParamType::Number, "m/s", false, 0, "target speed, default 0"},
    {"gain", ParamType::Number, "kg/s", true, 0, "k in kg/s (N per m/s)"},
    {"max_force", ParamType::Number, "N", false, 0,
     "slip limit: the most the field pulls one body with; default unlimited"},
    {"enabled", ParamType::Bool, "", false, 0, "default true"},
    {"radius", ParamType::Number, "m", false, 0,
     "a turning field (a turntable, a curve's band): the target is the rigid rotation about the vertical "
     "through 'pivot' that moves at 'speed' at this distance from it, along both horizontal axes; no 'direction'"},
    {"pivot", ParamType::Vec3, "m", false, 0,
     "with 'radius': the point the field turns about, in the field's frame (from its centre); default its centre"},
};

bool check(const Graph& g, int32_t row, PluginProblem& problem) {
    const Field& f = g.fields[FieldId(row)];
    const double d = std::sqrt(f.dir[0] * f.dir[0] + f.dir[1] * f.dir[1] + f.dir[2] * f.dir[2]);
    problem.message = !(f.extent[0] > 0 && f.extent[1] > 0 && f.extent[2] > 0) ? "field 'extent' must be above 0"
                    : !(d > 0)                                                ? "field 'dir' is the zero vector"
                    : !(f.gain >= 0)                                          ? "field 'gain' is negative"
                    : !(f.max_force >= 0 && std::isfinite(f.max_force))
                        ? "field 'max_force' is negative or not finite"
                    : !(f.radius >= 0 && std::isfinite(f.radius)) ? "field 'radius' is negative or not finite"
                    : !(std::isfinite(f.pivot[0]) && std::isfinite(f.pivot[1]) && std::isfinite(f.pivot[2]))
                        ? "field 'pivot' is not finite"
                        : "";
    return problem.message.empty();
}

}  // namespace

constexpr KindDesc desc{
    .word = "field",
    .doc = "a box volume that pushes the bodies in it towards a speed (a belt's surface)",
    .slots = kSlots,
    .params = kParams,
    .check = check,
    .placed = true,  // its box stands where it is placed
    .kind = CompKind::Field,
    .on = true,      // `field f on BODY`: rides the body
    PLANT_KIND_TABLE(fields),
};

}  // namespace plant::kinds::field
