// Typed ids: a row of one table of the graph (graph.h), so that a slot id cannot be
// stored or passed where a component id belongs.
//
//   SlotId s{3};          // explicit from a number; SlotId{} is -1, "none"
//   s.valid(), s.v        // the number, as the text form writes it
//   g[s]                  // the Slot (graph.h: checked in debug builds)
//
// Id<R> names a row of R's table; Adr<R> is the first row of a child list, the `adr` of
// an (adr, num) pair. Both read as their int32_t number (indexing, arithmetic), so the
// step's code is the integer code it was; building one from a number is explicit.
// The loader checks every field of these types against its table (validate.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include <fmt/format.h>

namespace plant::graph {

enum class IdRole : uint8_t { Row, Adr };

template <class Record, IdRole Role>
struct TypedId {
    using record = Record;
    static constexpr IdRole role = Role;

    int32_t v = -1;

    constexpr TypedId() = default;
    constexpr explicit TypedId(int32_t value) : v(value) {}

    constexpr bool valid() const { return v >= 0; }
    constexpr int32_t value() const { return v; }
    constexpr operator int32_t() const { return v; }
    constexpr TypedId& operator++() {
        ++v;
        return *this;
    }

    friend constexpr bool operator==(TypedId, TypedId) = default;
    // Ids of two tables never compare (they would through int32_t).
    template <class R2, IdRole Role2>
    friend bool operator==(TypedId, TypedId<R2, Role2>) = delete;
};

template <class Record>
using Id = TypedId<Record, IdRole::Row>;
template <class Record>
using Adr = TypedId<Record, IdRole::Adr>;

template <class T>
constexpr bool is_typed_id = false;
template <class R, IdRole Role>
constexpr bool is_typed_id<TypedId<R, Role>> = true;

// The id the next row appended to a table gets (its size), and as a list's first row.
template <class R>
constexpr Id<R> next_id(const std::vector<R>& table) {
    return Id<R>(static_cast<int32_t>(table.size()));
}
template <class R>
constexpr Adr<R> next_adr(const std::vector<R>& table) {
    return Adr<R>(static_cast<int32_t>(table.size()));
}

// The ids of a table's rows in order: for (BodyId b : ids_of(g.bodies)) ...
template <class R>
struct IdRange {
    struct It {
        int32_t i;
        constexpr Id<R> operator*() const { return Id<R>(i); }
        constexpr It& operator++() {
            ++i;
            return *this;
        }
        friend constexpr bool operator==(It, It) = default;
    };
    int32_t n;
    constexpr It begin() const { return {0}; }
    constexpr It end() const { return {n}; }
};
template <class R>
constexpr IdRange<R> ids_of(const std::vector<R>& table) {
    return {static_cast<int32_t>(table.size())};
}

// JSON (nlohmann, found by ADL): its number.
template <class Json, class R, IdRole Role>
void to_json(Json& j, TypedId<R, Role> id) {
    j = id.v;
}

// The records (graph.h) that ids name.
struct DoType;
struct Do;
struct Comp;
struct Slot;
struct Flow;
struct Access;
struct AccessTarget;
struct Logic;
struct LogicIn;
struct Body;
struct Shape;
struct Point;
struct Field;
struct Joint;
struct Place;
struct Transition;
struct Arc;
struct Trigger;
struct Gripper;
struct Source;
struct IdEntry;
struct Exit;
struct Route;
struct Graphics;
struct Animation;
struct Key;
struct Variant;
struct Label;
struct Record;
struct Port;
struct PortTarget;
struct Plugin;
struct PluginParam;
struct PluginEntry;
struct PluginEntrySlot;

using DoTypeId = Id<DoType>;
using DoId = Id<Do>;
using CompId = Id<Comp>;
using SlotId = Id<Slot>;
using FlowId = Id<Flow>;
using AccessId = Id<Access>;
using LogicId = Id<Logic>;
using BodyId = Id<Body>;
using FieldId = Id<Field>;
using JointId = Id<Joint>;
using PlaceId = Id<Place>;
using TransitionId = Id<Transition>;
using TriggerId = Id<Trigger>;
using GripperId = Id<Gripper>;
using SourceId = Id<Source>;
using ExitId = Id<Exit>;
using GraphicsId = Id<Graphics>;
using AnimationId = Id<Animation>;
using VariantId = Id<Variant>;
using PortId = Id<Port>;
using PluginId = Id<Plugin>;

}  // namespace plant::graph

// Formatted as its number, as the text form and messages always wrote it.
template <class R, plant::graph::IdRole Role>
struct fmt::formatter<plant::graph::TypedId<R, Role>> : fmt::formatter<int32_t> {
    template <class Ctx>
    auto format(plant::graph::TypedId<R, Role> id, Ctx& ctx) const {
        return fmt::formatter<int32_t>::format(id.v, ctx);
    }
};
