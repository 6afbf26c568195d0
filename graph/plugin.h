// Component kinds by descriptor: one row per kind, shared by the compiler and the runtime.
// The descriptor says what the kind is called in plant files, its slots (the SlotSpec
// table of graph/kinds.h), its parameters in one property vocabulary (ParamSpec) and their
// documentation; each side adds the kind's part of its own (the compiler its lowering,
// sema/kinds/lowering.h; the runtime its behaviour, engine/plugin.h).
//
// Two sorts of kinds have rows (docs/architecture.md, "The kind table"):
//  - kinds on the kind table that ship with plant (kinds/NAME/, listed in kinds/kinds.cmake):
//    a CompKind of their own, a typed graph table of their own, modes, a loader
//    check per row; found by builtin_kind();
//  - plugin kinds, registered by the program before any plant is compiled or loaded
//    (register_kind): in the graph a Comp of kind CompKind::Plugin whose detail is a row of
//    `plugins` (its kind word and its parameters in `plugin_params`). Its slots are the
//    descriptor's, in order, at comp.slot_adr. The loader refuses a plugin component whose
//    kind this program has not registered, or whose slots or parameters differ from the
//    descriptor's.
#pragma once

#include "graph.h"
#include "kinds.h"
#include "validate.h"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace plant::graph {

// Value: an entry option whose type is the entry's slot's (void and bool: true or false;
// int; real: a number in SI units; string), stored as a number or a text accordingly.
// Vec3 (three numbers in `unit`), StringList, Type (an object type, `Bottle(mass = 40 g)`)
// and CompRef (a component of the same object, by name). A plugin's parameters (any type
// but Value, which only an entry's option has) are rows of `plugin_params`, each in the
// field of its type (graph.h, PLANT_FIELDS_PARAM); an entry's options are Number, Int,
// Bool, String or Value.
enum class ParamType : uint8_t { Number, Int, Bool, String, Value, Vec3, StringList, Type, CompRef };

struct ParamSpec {
    std::string_view name;
    ParamType type;
    // Number, Vec3: the SI unit its values are in ("m/s", "Hz"; "" for a plain number);
    // the compiler checks a written value's dimension against it.
    std::string_view unit;
    bool required;
    double default_num;  // Number, Int, Bool (0/1) when not required and not given
    std::string_view doc;
};

// What an entry's KEY is: an index from 0 to max_key (a register address), or a time in
// seconds, 0 or more (when a scheduled fault begins).
enum class EntryKey : uint8_t { Index, Time };

// An entry a plugin kind's table takes: `WORD KEY => PATH (OPTION = VALUE, ...)`, e.g. a
// Modbus link's `coil 3 => s1.to_working`. PATH names a slot or port of the direction the
// entry takes (In: the entry drives inputs; Out: it reads an output; either when any_dir),
// of one of `types` (any when empty).
struct EntrySpec {
    std::string_view word;
    std::string_view doc;
    Dir target;
    std::span<const SlotType> types;
    std::span<const ParamSpec> options;
    int32_t max_key = 65535;
    EntryKey key = EntryKey::Index;
    bool any_dir = false;
};

// What a kind's own check (KindDesc::check) finds wrong with one of its components: the
// entry (a row index into its entries, from 0; -1: the component as a whole) and why.
struct PluginProblem {
    int32_t entry = -1;
    std::string message;
};

// When the runtime calls the kind (docs/runtime.md, "The step").
enum class PluginPhase : uint8_t { None, Sensors, Actuators };

// The sub-blocks of the language, each a grammar rule of its own, that a component of a kind
// on the kind table may hold (KindDesc::blocks, a set of these bits). kChildren: components
// of its own kind inside its block, named `parent.child` and placed relative to it (child
// graphics), whose lowering gets the parent's row (sema's Lowering::parent_row).
enum SubBlock : uint8_t { kShapes = 1, kAnimations = 2, kVariants = 4, kPlaces = 8, kRoutes = 16, kChildren = 32 };

struct KindDesc {
    std::string_view word;  // as written in plant files: `counter c { ... }`
    std::string_view doc;   // one line: what the kind is
    std::span<const SlotSpec> slots;
    std::span<const ParamSpec> params;
    std::span<const EntrySpec> entries = {};
    PluginPhase senses = PluginPhase::None;  // Sensors: called every step in phase 2
    PluginPhase acts = PluginPhase::None;    // Actuators: called in phase 5 when an input is active
    // Checks across a component's entries, or across components of the kind (two Modbus
    // links on one port), once the whole graph is built: the compiler reports a problem at
    // the entry (or the component), the loader refuses the graph. nullptr: nothing to check.
    // `row`: the component's row in its kind's table (Graph::plugins for a plugin kind,
    // which writes its check over a PluginId and names it plugin_check<its_check>).
    bool (*check)(const Graph& g, int32_t row, PluginProblem& problem) = nullptr;
    // Components of other plugin kinds written inside this one's block (a panel's buttons
    // and lamps): each becomes a component of its own, named `parent.child` like a child
    // graphics, so its slots are `parent.child.slot`. Empty: the kind holds none.
    std::span<const std::string_view> holds = {};
    // Non-empty: a component of this kind is written only inside a component of the kind
    // of that word (a button inside a panel), never on its own.
    std::string_view inside = {};
    // Whether a component of the kind takes a placement (`panel ops at (…) rotate z by …`):
    // a plugin's world pose is stored (Plugin::pose, placed) for the viewer to draw it in the
    // scene (an operator panel); a kind on the kind table uses it in its lowering (a
    // constraint's frame, where a source issues). A placement on a kind without it is
    // refused (E0311).
    bool placed = false;

    // ---- A kind on the kind table (kinds/NAME/kind.cpp); a plugin kind leaves these ----
    CompKind kind = CompKind::Plugin;                 // its kind in the graph
    std::span<const std::string_view> modes = {};     // `NAME n: MODE`; the first is the default
    bool on = false;                                  // written `NAME n on PATH`: rides a body (or graphics)
    uint8_t blocks = 0;                               // the sub-blocks it holds (SubBlock bits)
    // Declared by a form of the grammar of its own (a connector: `logic go = a and not b`),
    // not `WORD NAME { ... }`: its word is no component word of the compiler's, and its
    // lowering has no `lower` (kinds/logic/lower.cpp makes it from that form).
    bool own_form = false;
    // The graph table its components' `detail` indexes (PLANT_KIND_TABLE): its name, its row
    // count, each row's component. The loader checks that each row's component is of this
    // kind with the row as its detail, then calls `check` with the row. Left empty: the kind
    // has no table of its own (a router, a state), its components' detail is none (-1), and
    // the loader checks that.
    std::string_view table = {};
    size_t (*rows)(const Graph& g) = nullptr;
    CompId (*comp_of)(const Graph& g, int32_t row) = nullptr;
    // The loader's check of the other tables whose rows belong to the kind's components (a
    // state's places, transitions and arcs, a router's routes), after the rows of every
    // kind's own table: false with the table, row and why in `problem` (validate.h's
    // each_record and slot_flaw help). nullptr: nothing to check.
    bool (*check_tables)(const Graph& g, GraphProblem& problem) = nullptr;
    // The fixed slot a path naming just the component means (a connector's `out`: `go` is
    // `go.out`). -1: a path names one of its slots.
    int bare_slot = -1;
    // What the compiler's messages call one of its components where the graph's word of its
    // CompKind would not read (a `connector`). Empty: that word.
    std::string_view noun = {};
    // The input without which a component does nothing, unless `runs_alone` says it does
    // anyway (nullptr: it never does): the compiler warns (W0502) with `idle_warning`, `{}`
    // standing for the component's name. -1: none.
    int idle_input = -1;
    bool (*runs_alone)(const Graph& g, int32_t row) = nullptr;
    std::string_view idle_warning = {};
    // W0501 for each output of a component beyond the kind's fixed slots (a router's routes)
    // that drives nothing: `{}` standing for the output's name, then the component's.
    // Empty: such outputs are not warned about.
    std::string_view unused_output = {};
    // W0501 when this fixed output drives nothing (a connector's `out`), with
    // `idle_output_warning`, `{}` standing for the component's name. -1: none.
    int idle_output = -1;
    std::string_view idle_output_warning = {};
};

// A plugin kind's check (KindDesc::check) written over its component's PluginId.
template <bool (*Check)(const Graph&, PluginId, PluginProblem&)>
bool plugin_check(const Graph& g, int32_t row, PluginProblem& problem) {
    return Check(g, PluginId(row), problem);
}

// The table fields of a kind on the kind table, from its graph table's member name:
// `.table = ...` written `PLANT_KIND_TABLE(member)`.
#define PLANT_KIND_TABLE(member)                                                          \
    .table = #member, .rows = [](const ::plant::graph::Graph& g) { return g.member.size(); }, \
    .comp_of = [](const ::plant::graph::Graph& g, int32_t row) {                          \
        return g.member[std::remove_cvref_t<decltype(g.member)>::id_type(row)].comp;        \
    }

// The kinds on the kind table (kinds/list.h), in its order; a built-in kind's row (every
// built-in kind has one), nullptr for Plugin.
std::span<const KindDesc* const> builtin_kinds();
const KindDesc* builtin_kind(CompKind kind);
// The word plant files write for a kind: its row's (a body is written `physics`), else the
// graph's (`plugin`).
std::string_view kind_word(CompKind kind);

// Registers a kind (before any plant is compiled or loaded); false if its word is taken by
// a built-in kind or another plugin, or it declares a slot or parameter twice.
bool register_kind(const KindDesc& desc);
const KindDesc* find_plugin(std::string_view word);
std::span<const KindDesc* const> plugins();

// The descriptor of a plugin component, nullptr for a built-in kind or a broken graph.
const KindDesc* plugin_of(const Graph& g, CompId comp);
// The slot table of any component: the fixed slots of a built-in kind, the descriptor's
// slots of a plugin.
std::span<const SlotSpec> slots_of(const Graph& g, CompId comp);

const EntrySpec* find_entry(const KindDesc& desc, std::string_view word);

std::string_view word(ParamType);

}  // namespace plant::graph
