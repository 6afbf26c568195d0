// The slot table of every component kind: the plugin contract shared by the compiler
// (which checks flows against it) and the runtime (which finds a slot as
// comp.slot_adr + its index here). Slots that depend on the component's content
// (places, transitions, animations, variants, routes, connector inputs) follow the
// fixed ones, in declaration order.
//
// Each kind's fixed slots are declared once, in its kinds/NAME/graph.h (a plugin kind: in
// its descriptor), as a list
//   S(index name, slot name, SlotType, Dir, documentation)
// from which both the index constants (`bodyslot::pose`) and the table returned by
// fixed_slots() are generated; docs/language.md's slot tables are checked against it.
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
    std::string_view unit = {};  // a real slot's SI unit where its kind says ("s"); "" none known
};

// One S(...) of a PLANT_SLOTS_ list as a SlotSpec: {PLANT_SLOTS_BODY(PLANT_SLOT_SPEC)}.
#define PLANT_SLOT_SPEC(id, name, type, dir, doc) ::plant::graph::SlotSpec{name, ::plant::graph::SlotType::type, ::plant::graph::Dir::dir, doc},

std::span<const SlotSpec> fixed_slots(CompKind kind);
// Index of a fixed slot by name, -1 if none.
int fixed_slot_index(CompKind kind, std::string_view name);

// The fixed slot indices the runtime relies on, `count` last.
#define PLANT_SLOT_INDEX(id, name, type, dir, doc) id,
// The kinds on the kind table (kinds/list.h): `wordslot` from PLANT_SLOTS_WORD.
#define PLANT_KIND_SLOT_INDEX(word, WORD) namespace word##slot { enum : int { PLANT_SLOTS_##WORD(PLANT_SLOT_INDEX) count }; }
PLANT_KINDS(PLANT_KIND_SLOT_INDEX)
#undef PLANT_KIND_SLOT_INDEX
#undef PLANT_SLOT_INDEX

}  // namespace plant::graph
