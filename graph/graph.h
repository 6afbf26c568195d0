// The compiled plant graph: the one contract between compiler/ and runtime/.
//
// A constant, flat model in the spirit of MuJoCo's mjModel: one table per kind of
// element, each a std::vector of small records indexed by a 32-bit id, references as
// typed ids (ids.h: SlotId, CompId, ...) with -1 for none, child lists as an (adr, num)
// pair into another table (adr an Adr<Record> of the table it indexes), every
// name interned once in `names`. All quantities are SI (m, kg, s, rad, N).
//
// The field list of every record is an X-macro (PLANT_GRAPH_TABLES below). It drives
// the struct definitions, the text writer, the loader and the comparison, so a field
// added here is saved, loaded and compared without further code.
#pragma once

#include "ids.h"
#include "kinds/list.h"  // the kinds on the kind table: their records' fields (PLANT_FIELDS_...)

#include <array>
#include <cassert>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace plant::graph {

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>;  // x, y, z, w (Bullet's order)

struct Pose {
    Vec3 p{0, 0, 0};
    Quat q{0, 0, 0, 1};
    friend bool operator==(const Pose&, const Pose&) = default;
};

// An interned string: index into Graph::names. -1 is "no name".
struct Name {
    int32_t id = -1;
    friend bool operator==(const Name&, const Name&) = default;
};

// A source position: file index into Graph::files, 1-based line and column.
struct Src {
    int32_t file = -1;
    int32_t line = 0;
    int32_t col = 0;
    friend bool operator==(const Src&, const Src&) = default;
};

// ---- enumerations (each has a stable lower-case word in the text form) ----

enum class SlotType : uint8_t { Void, Bool, Int, Real, Vec3, Quat, Pose, String, Ref };
enum class Dir : uint8_t { In, Out };
enum class CompKind : uint8_t {
    Graphics, Body, Field, Constraint, State, Trigger, Timer, Gripper, Source, Exit, Router,
    Logic, Label, Plugin
};
enum class BodyMode : uint8_t { Dynamic, Static, Kinematic };
enum class ShapeKind : uint8_t { Box, Sphere, Cylinder, Capsule, Hull };
enum class JointKind : uint8_t { Fixed, Hinge, Slider };
// When a flow runs, judged on the activity of its two ends in the current step.
enum class Cond : uint8_t { Source, Target, Both, Either };
enum class LogicOp : uint8_t { And, Or };

// Number of doubles a slot of this type occupies in the value table.
constexpr int slot_width(SlotType t) {
    switch (t) {
    case SlotType::Void: return 0;
    case SlotType::Vec3: return 3;
    case SlotType::Quat: return 4;
    case SlotType::Pose: return 7;
    default: return 1;  // bool, int, real, string (a name id), ref (a DO id, -1 none)
    }
}

// ---- the tables ----
// X(table, Record, element-word) and per record F(type, field).

#define PLANT_FIELDS_DOTYPE(F) \
    F(Name, name)              \
    F(int32_t, instance_num)   \
    F(Src, src)

#define PLANT_FIELDS_DO(F)                                                            \
    F(Name, path)          /* dotted path from the plant root, e.g. "s1.blade" */     \
    F(OptId<Do>, parent)     /* DO id, -1 for the root */                               \
    F(OptId<DoType>, type)       /* DoType id, -1 for the plant itself */                   \
    F(int32_t, ordinal)    /* index among the DOs of the same type */                 \
    F(Adr<Comp>, comp_adr)                                                              \
    F(int32_t, comp_num)                                                              \
    F(OptId<Comp>, pool)       /* Source component that owns this DO, -1 if not pooled */ \
    F(Pose, pose)          /* world pose at start */                                  \
    F(Src, src)

#define PLANT_FIELDS_COMP(F)                                                  \
    F(Name, name)       /* local name inside its DO */                        \
    F(CompKind, kind)                                                         \
    F(DoId, owner)   /* DO id */                                           \
    F(Adr<Slot>, slot_adr)                                                      \
    F(int32_t, slot_num)                                                      \
    F(Detail, detail)  /* its row in the table of its kind (detail_of), -1 for none */ \
    F(Src, src)

#define PLANT_FIELDS_SLOT(F)                                                        \
    F(Name, name)       /* local name inside its component, e.g. "swing_out.play" */ \
    F(SlotType, type)                                                               \
    F(Dir, dir)                                                                     \
    F(CompId, comp)                                                                \
    F(Adr<Value>, value_adr) /* first double in Graph::values, -1 for void */       \
    F(Src, src)

// A dynamic end (an Access) keeps its reference slot in from/to, so both always name a
// slot; the slots the end may be are the access's targets (graph/network.h).
#define PLANT_FIELDS_FLOW(F)                                                              \
    F(SlotId, from)        /* output slot; the access's ref_slot when from_access >= 0 */ \
    F(SlotId, to)          /* input slot; the access's ref_slot when to_access >= 0 */  \
    F(OptId<Access>, from_access) /* Access id for a dynamically addressed source, -1 none */   \
    F(OptId<Access>, to_access)   /* Access id for a dynamically addressed target, -1 none */   \
    F(Cond, cond)                                                                         \
    F(bool, once)           /* singular: runs once, re-armed by a step where its condition fails */  \
    F(Src, src)

// A slot of an object known only at run time: the object held in `ref_slot`
// (a DO id), which the compiler proved is of type `do_type`; the slot to use is
// targets[target_adr + ordinal of that DO among its type].
#define PLANT_FIELDS_ACCESS(F) \
    F(SlotId, ref_slot)       \
    F(DoTypeId, do_type)        \
    F(Adr<AccessTarget>, target_adr)     \
    F(int32_t, target_num)     \
    F(Name, member)            \
    F(Src, src)

#define PLANT_FIELDS_RECORD(F)                                  \
    F(SlotId, slot)     /* slot whose value/activity is traced */ \
    F(Name, column)

// A port an object type declares (`in to_working: void => net.MoveToWorkingPos.put`):
// no run-time existence, but addressable by its dotted path in events, the viewer and
// `plant info --slots`. Inputs forward to every target, outputs name the one output.
#define PLANT_FIELDS_PORT(F)                                                  \
    F(DoId, owner)      /* DO id */                                        \
    F(Name, name)                                                             \
    F(SlotType, type)                                                         \
    F(Dir, dir)                                                               \
    F(Adr<PortTarget>, target_adr) /* into port_targets: slot ids */                  \
    F(int32_t, target_num)                                                    \
    F(Src, src)

// A component of a plugin kind (graph/plugin.h): a kind registered by its descriptor,
// not known to this header. Its parameters are stored in the order the descriptor
// declares them: a number (SI) or a text, whichever the parameter's type is.
#define PLANT_FIELDS_PLUGIN(F)                                                     \
    F(CompId, comp)                                                               \
    F(Name, kind)          /* the kind's word, e.g. "counter" */                   \
    F(Adr<PluginParam>, param_adr)  /* into plugin_params */                                \
    F(int32_t, param_num)                                                          \
    F(Adr<PluginEntry>, entry_adr)  /* into plugin_entries */                               \
    F(int32_t, entry_num)                                                          \
    F(bool, placed)        /* given a placement (KindDesc::placed: a panel drawn in the scene) */ \
    F(Pose, pose)          /* its world pose when placed */

// An entry of a plugin component's table (`coil 3 => s1.to_working(pulse = 1)`): its
// word, its key (an index, or a time in s: graph/plugin.h, EntryKey), the slots its target names (an input port: every input it forwards to),
// its options in the order the entry's spec declares them.
#define PLANT_FIELDS_PLUGINENTRY(F)                                                \
    F(Name, word)                                                                  \
    F(double, key)                                                                 \
    F(Adr<PluginEntrySlot>, slot_adr)   /* into plugin_entry_slots */                           \
    F(int32_t, slot_num)                                                           \
    F(Adr<PluginParam>, param_adr)  /* into plugin_params */                                \
    F(int32_t, param_num)                                                          \
    F(Src, src)

// A parameter of a plugin component (or an option of an entry), in the order its spec
// declares them, in the field its type (graph/plugin.h: ParamType) is stored in: a Number,
// Int or Bool in `num`, a String in `text` (a Value option: either), a Vec3 in `vec`, a Type
// in `type` (the object type it names), a CompRef in `comp` (a component of the same object),
// a StringList as the run `list_adr`, `list_num` of plugin_strings. The other fields keep
// their defaults (0, none, -1).
#define PLANT_FIELDS_PARAM(F)            \
    F(double, num)                       \
    F(Name, text)                        \
    F(Vec3, vec)                         \
    F(OptId<DoType>, type)               \
    F(OptId<Comp>, comp)                 \
    F(Adr<PluginString>, list_adr)       \
    F(int32_t, list_num)

#define PLANT_FIELDS_POINT(F) F(Vec3, p)
#define PLANT_FIELDS_VALUE(F) F(double, v)
#define PLANT_FIELDS_INT(F) F(int32_t, v)
#define PLANT_FIELDS_SLOTREF(F) F(SlotId, v)
#define PLANT_FIELDS_NAMEREF(F) F(Name, v)

// X(member, Record, word, FIELDS)
#define PLANT_GRAPH_TABLES(X)                                         \
    X(do_types, DoType, dotype, PLANT_FIELDS_DOTYPE)                  \
    X(dos, Do, do, PLANT_FIELDS_DO)                                   \
    X(comps, Comp, comp, PLANT_FIELDS_COMP)                           \
    X(slots, Slot, slot, PLANT_FIELDS_SLOT)                           \
    X(values, Value, value, PLANT_FIELDS_VALUE)                       \
    X(flows, Flow, flow, PLANT_FIELDS_FLOW)                           \
    X(accesses, Access, access, PLANT_FIELDS_ACCESS)                  \
    X(access_targets, AccessTarget, access_target, PLANT_FIELDS_SLOTREF)  \
    X(logics, Logic, logic, PLANT_FIELDS_LOGIC)                       \
    X(logic_inputs, LogicIn, logic_input, PLANT_FIELDS_LOGICIN)       \
    X(bodies, Body, body, PLANT_FIELDS_BODY)                          \
    X(shapes, Shape, shape, PLANT_FIELDS_SHAPE)                       \
    X(points, Point, point, PLANT_FIELDS_POINT)                       \
    X(fields, Field, field, PLANT_FIELDS_FIELD)                       \
    X(joints, Joint, joint, PLANT_FIELDS_CONSTRAINT)                  \
    X(places, Place, place, PLANT_FIELDS_PLACE)                       \
    X(transitions, Transition, transition, PLANT_FIELDS_TRANSITION)   \
    X(arcs, Arc, arc, PLANT_FIELDS_ARC)                               \
    X(triggers, Trigger, trigger, PLANT_FIELDS_TRIGGER)               \
    X(timers, Timer, timer, PLANT_FIELDS_TIMER)                       \
    X(grippers, Gripper, gripper, PLANT_FIELDS_GRIPPER)               \
    X(sources, Source, source, PLANT_FIELDS_SOURCE)                   \
    X(ids, IdEntry, id, PLANT_FIELDS_NAMEREF)                         \
    X(exits, Exit, exit, PLANT_FIELDS_EXIT)                           \
    X(routes, Route, route, PLANT_FIELDS_ROUTE)                       \
    X(graphics, Graphics, graphics, PLANT_FIELDS_GRAPHICS)            \
    X(animations, Animation, animation, PLANT_FIELDS_ANIMATION)       \
    X(keys, Key, key, PLANT_FIELDS_KEY)                               \
    X(variants, Variant, variant, PLANT_FIELDS_VARIANT)               \
    X(labels, Label, label, PLANT_FIELDS_LABEL)                       \
    X(records, Record, record, PLANT_FIELDS_RECORD)                   \
    X(ports, Port, port, PLANT_FIELDS_PORT)                           \
    X(port_targets, PortTarget, port_target, PLANT_FIELDS_SLOTREF)       \
    X(plugins, Plugin, plugin, PLANT_FIELDS_PLUGIN)                  \
    X(plugin_params, PluginParam, plugin_param, PLANT_FIELDS_PARAM)  \
    X(plugin_strings, PluginString, plugin_string, PLANT_FIELDS_NAMEREF) \
    X(plugin_entries, PluginEntry, plugin_entry, PLANT_FIELDS_PLUGINENTRY) \
    X(plugin_entry_slots, PluginEntrySlot, plugin_entry_slot, PLANT_FIELDS_SLOTREF)

// Tables the text form leaves out when they are empty (the loader then reads them as
// empty): a graph without plugin components reads and writes as before plugins existed.
constexpr bool optional_table(std::string_view member) {
    return member.starts_with("plugin");
}

#define PLANT_DECLARE_FIELD(type, field) type field{};
#define PLANT_DECLARE_RECORD(member, Record, word, FIELDS) \
    struct Record {                                        \
        FIELDS(PLANT_DECLARE_FIELD)                        \
        friend bool operator==(const Record&, const Record&) = default; \
    };
PLANT_GRAPH_TABLES(PLANT_DECLARE_RECORD)
#undef PLANT_DECLARE_RECORD

// The physics rates a plant may have: 1 Hz to 1 MHz (the compiler, `plant run --rate`
// and the graph loader all hold to it).
constexpr double kMinRate = 1.0, kMaxRate = 1e6;
// Petri nets: a place starts with at most kMaxInitialTokens, an arc weighs at most
// kMaxArcWeight (compiler and loader check both); while running, a place holds at most
// kMaxTokens, the largest count a slot's number (a double) holds exactly, and stays there.
constexpr int32_t kMaxInitialTokens = 1'000'000, kMaxArcWeight = 1'000'000;
constexpr int64_t kMaxTokens = int64_t(1) << 53;

struct Settings {
    double rate = 150.0;      // physics steps per second, kMinRate .. kMaxRate
    Vec3 gravity{0, 0, -9.81};
    bool steady_transport = true;  // bottles in steady transport may leave the solver (docs/runtime.md)
    friend bool operator==(const Settings&, const Settings&) = default;
};

struct Graph {
    Name plant;                      // the plant's name
    Settings settings;
    std::vector<std::string> files;  // source files, relative, in first-use order
    std::vector<std::string> names;  // interned strings

#define PLANT_DECLARE_TABLE(member, Record, word, FIELDS) Table<Record> member;
    PLANT_GRAPH_TABLES(PLANT_DECLARE_TABLE)
#undef PLANT_DECLARE_TABLE

    // A row by its typed id: g[SlotId{3}] is g.slots[3], asserted in range in debug
    // builds (the step's accessor); at() throws std::out_of_range.
#define PLANT_DECLARE_ACCESS(member, Record, word, FIELDS)                                        \
    const Record& operator[](Id<Record> i) const {                                               \
        return member[i];                                                                        \
    }                                                                                            \
    Record& operator[](Id<Record> i) { return member[i]; }                                       \
    const Record& at(Id<Record> i) const { return member.at(i); }
    PLANT_GRAPH_TABLES(PLANT_DECLARE_ACCESS)
#undef PLANT_DECLARE_ACCESS
    // The table of a record type: g.rows<Slot>() is g.slots.
    template <class R>
    const Table<R>& rows() const;

    // Interning: returns the existing id for an equal string.
    Name intern(std::string_view s);
    std::string_view str(Name n) const { return n.id < 0 ? std::string_view{} : names[n.id]; }

    // The dotted path of a slot: "<do path>.<comp>.<slot>".
    std::string slot_path(SlotId slot) const;
    std::string comp_path(CompId comp) const;
    std::string port_path(PortId port) const;  // "<do path>.<port>"
    std::string src_text(Src s) const;  // "file:line:col" or "-"

    // Compares every table field by field (names by text, not by id).
    bool same_as(const Graph& other) const;

private:
    std::unordered_map<std::string, int32_t> index_;  // rebuilt when names grew elsewhere
};

// The table of a record type and its name in the text form ("slots").
template <class R>
constexpr std::string_view table_name();
#define PLANT_DEFINE_ROWS(member, Record, word, FIELDS)                                  \
    template <>                                                                         \
    inline const Table<Record>& Graph::rows<Record>() const { return member; }    \
    template <>                                                                         \
    constexpr std::string_view table_name<Record>() { return #member; }
PLANT_GRAPH_TABLES(PLANT_DEFINE_ROWS)
#undef PLANT_DEFINE_ROWS

// A component's row in its kind's table, as that table's id: detail_of<Timer>(comp). The
// kind's row says which table (KindDesc::table), and the loader checks that the row it
// names is the component's own (validate.cpp), so the id is right for a component of the
// kind whose table is R's.
template <class R>
constexpr Id<R> detail_of(const Comp& c) {
    return Id<R>(c.detail.v);
}

// Word of an enum value in the text form, and the reverse (false if unknown).
std::string_view word(SlotType);
std::string_view word(Dir);
std::string_view word(CompKind);
std::string_view word(BodyMode);
std::string_view word(ShapeKind);
std::string_view word(JointKind);
std::string_view word(Cond);
std::string_view word(LogicOp);
// Every word of an enum, in enumerator order (for "did you mean" and the lists in messages).
template <class E>
std::span<const std::string_view> words();
template <> std::span<const std::string_view> words<SlotType>();
template <> std::span<const std::string_view> words<Cond>();
bool parse_word(std::string_view, SlotType&);
bool parse_word(std::string_view, Dir&);
bool parse_word(std::string_view, CompKind&);
bool parse_word(std::string_view, BodyMode&);
bool parse_word(std::string_view, ShapeKind&);
bool parse_word(std::string_view, JointKind&);
bool parse_word(std::string_view, Cond&);
bool parse_word(std::string_view, LogicOp&);

}  // namespace plant::graph
