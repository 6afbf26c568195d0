// Component kinds as plugins: a kind the core does not know, declared by one descriptor
// that the compiler and the runtime share. The descriptor says what the kind is called in
// plant files, its slots (the same SlotSpec table the built-in kinds have, graph/kinds.h),
// its parameters and their documentation; the runtime adds the kind's behaviour
// (engine/plugin.h). A new kind is therefore new files plus one registration line per side
// (docs/architecture.md, "Adding a component kind").
//
// In the graph a plugin component is a Comp of kind CompKind::Plugin whose detail is a row
// of `plugins` (its kind word and its parameters in `plugin_params`). Its slots are the
// descriptor's, in order, at comp.slot_adr. The loader refuses a plugin component whose
// kind this program has not registered, or whose slots or parameters differ from the
// descriptor's.
#pragma once

#include "graph.h"
#include "kinds.h"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace plant::graph {

// Value: an entry option whose type is the entry's slot's (void and bool: true or false;
// int; real: a number in SI units; string), stored as a number or a text accordingly.
enum class ParamType : uint8_t { Number, Int, Bool, String, Value };

struct ParamSpec {
    std::string_view name;
    ParamType type;
    // Number: the SI unit its values are in ("m/s", "Hz"; "" for a plain number); the
    // compiler checks a written value's dimension against it.
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
    bool (*check)(const Graph& g, int32_t plugin, PluginProblem& problem) = nullptr;
    // Components of other plugin kinds written inside this one's block (a panel's buttons
    // and lamps): each becomes a component of its own, named `parent.child` like a child
    // graphics, so its slots are `parent.child.slot`. Empty: the kind holds none.
    std::span<const std::string_view> holds = {};
    // Non-empty: a component of this kind is written only inside a component of the kind
    // of that word (a button inside a panel), never on its own.
    std::string_view inside = {};
};

// Registers a kind (before any plant is compiled or loaded); false if its word is taken by
// a built-in kind or another plugin, or it declares a slot or parameter twice.
bool register_kind(const KindDesc& desc);
const KindDesc* find_plugin(std::string_view word);
std::span<const KindDesc* const> plugins();

// The descriptor of a plugin component, nullptr for a built-in kind or a broken graph.
const KindDesc* plugin_of(const Graph& g, int32_t comp);
// The slot table of any component: the fixed slots of a built-in kind, the descriptor's
// slots of a plugin.
std::span<const SlotSpec> slots_of(const Graph& g, int32_t comp);

const EntrySpec* find_entry(const KindDesc& desc, std::string_view word);

std::string_view word(ParamType);

}  // namespace plant::graph
