#include "kinds.h"

#include "plugin.h"

#include <array>

namespace plant::graph {
namespace {

constexpr std::array kLogic = {PLANT_SLOTS_LOGIC(PLANT_SLOT_SPEC)};

}  // namespace

std::span<const SlotSpec> fixed_slots(CompKind kind) {
    if (const KindDesc* d = builtin_kind(kind)) return d->slots;  // a kind on the kind table
    switch (kind) {
    case CompKind::Logic: return kLogic;
    case CompKind::Plugin: return {};  // its descriptor's (graph/plugin.h: slots_of)
    default: return {};
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
