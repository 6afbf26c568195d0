#include "kinds.h"

#include "plugin.h"

namespace plant::graph {

// A built-in kind's are its row's; a plugin's are its descriptor's (graph/plugin.h: slots_of).
std::span<const SlotSpec> fixed_slots(CompKind kind) {
    const KindDesc* d = builtin_kind(kind);
    return d ? d->slots : std::span<const SlotSpec>{};
}

int fixed_slot_index(CompKind kind, std::string_view name) {
    auto slots = fixed_slots(kind);
    for (size_t i = 0; i < slots.size(); ++i)
        if (slots[i].name == name) return static_cast<int>(i);
    return -1;
}

}  // namespace plant::graph
