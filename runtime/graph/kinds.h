// The slot table of every component kind: the plugin contract shared by the compiler
// (which checks flows against it) and the runtime (which finds a slot as
// comp.slot_adr + its index here). Slots that depend on the component's content
// (places, transitions, animations, variants, routes, connector inputs) follow the
// fixed ones, in declaration order.
#pragma once

#include "graph.h"

#include <span>
#include <string_view>

namespace plant::graph {

struct SlotSpec {
    std::string_view name;
    SlotType type;
    Dir dir;
    std::string_view doc;
};

std::span<const SlotSpec> fixed_slots(CompKind kind);
// Index of a fixed slot by name, -1 if none.
int fixed_slot_index(CompKind kind, std::string_view name);

// Fixed slot indices the runtime relies on (checked against the tables in a test).
namespace bodyslot {
enum : int { set_pose, set_position, set_orientation, set_velocity, set_angular_velocity,
             collision_on, collision_off, dynamics_on, dynamics_off,
             pose, position, orientation, velocity, angular_velocity, count };
}
namespace graphicsslot {
enum : int { set_pose, pose, shown, count };
}
namespace fieldslot {
enum : int { set_speed, enable, disable, speed, count };
}
namespace jointslot {
enum : int { enable, disable, enabled, count };
}
namespace triggerslot {
enum : int { on_enter, on_stay, on_leave, object, count_inside, count };
}
namespace timerslot {
enum : int { start, stop, tick, elapsed, running, count };
}
namespace gripperslot {
enum : int { grip, release, gripped, released, object, count };
}
namespace sourceslot {
enum : int { issue, issued, object, id, issued_count, count };
}
namespace exitslot {
enum : int { taken, object, id, taken_count, count };
}
namespace routerslot {
enum : int { query, count };
}
namespace logicslot {
enum : int { out, count };
}
namespace labelslot {
enum : int { set, value, count };
}

}  // namespace plant::graph
