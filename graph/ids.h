// Typed ids: a row of one table of the graph (graph.h), so that a slot id cannot be
// stored or passed where a component id belongs.
//
//   SlotId s{3};          // explicit from a number; SlotId{} is -1, "none"
//   s.valid(), s.v        // the number, as the text form writes it
//   g[s]                  // the Slot (graph.h: checked in debug builds)
//
// Id<R> names a row of R's table; Adr<R> is the first row of a child list, the `adr` of
// an (adr, num) pair. Both ways between an id and its int32_t number are explicit: built
// from one with SlotId(n), read as one with `.v`; a table is indexed by its own id only
// (IdVector), and adr + k gives an Adr's k-th row.
// OptId<R> is an Id<R> field that may be -1; Detail a component's row in its kind's table.
// The loader checks every field of these types against its table (validate.cpp).
#pragma once

#include <cassert>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <type_traits>
#include <utility>
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
    // Read as a number only when asked (`.v`, or int32_t(id)): an id passed for an int, an
    // int initialised from an id, arithmetic on an id and a std::vector indexed by an id do
    // not compile (tests/compile_fail/id_as_int.cpp).
    constexpr explicit operator int32_t() const { return v; }
    constexpr TypedId& operator++() {
        ++v;
        return *this;
    }
    // An Adr's first row (adr + k is its k-th: operator+ below).
    constexpr TypedId<Record, IdRole::Row> first() const
        requires(Role == IdRole::Adr)
    {
        return TypedId<Record, IdRole::Row>(v);
    }

    friend constexpr bool operator==(TypedId, TypedId) = default;
    friend constexpr auto operator<=>(TypedId, TypedId) = default;  // row order (a sorted key)
    // Ids of two tables never compare (they would through int32_t).
    template <class R2, IdRole Role2>
    friend bool operator==(TypedId, TypedId<R2, Role2>) = delete;
};

template <class Record>
using Id = TypedId<Record, IdRole::Row>;
template <class Record>
using Adr = TypedId<Record, IdRole::Adr>;

// An id field that may be -1, "none" (`Do::parent`, `Field::body`): the loader accepts -1
// there and in no other id field, knowing which from the type (validate.cpp). It is an
// Id<R> (indexes R's table, compares, passes where an Id<R> is taken), and an Id<R> is
// stored into it as it is.
template <class Record>
struct OptId : Id<Record> {
    using Id<Record>::Id;
    constexpr OptId() = default;
    constexpr OptId(Id<Record> id) : Id<Record>(id) {}
};

// A component's row in the table of its kind (Comp::detail): which table depends on the
// component's kind, so it is no Id<R> of one table. Read it as the id of the kind's table,
// detail_of<Timer>(comp) (graph.h), and store it from one, Detail(timer_id); code over every
// kind (the loader, the kind table's hooks) reads the number, .v; -1: none (a state, a router), !valid().
struct Detail {
    int32_t v = -1;

    constexpr Detail() = default;
    template <class R>
    constexpr explicit Detail(Id<R> row) : v(row.v) {}
    constexpr bool valid() const { return v >= 0; }  // it has a row
    friend constexpr bool operator==(Detail, Detail) = default;
};

template <class T>
constexpr bool is_typed_id = false;
template <class R, IdRole Role>
constexpr bool is_typed_id<TypedId<R, Role>> = true;
template <class R>
constexpr bool is_typed_id<OptId<R>> = true;
template <class T>
constexpr bool is_optional_id = false;
template <class R>
constexpr bool is_optional_id<OptId<R>> = true;

// Adr<R> + k is the id of the k-th row of the child list it starts.
template <class R, class I>
    requires std::integral<I> || (std::is_enum_v<I> && std::is_convertible_v<I, int32_t>)
constexpr Id<R> operator+(Adr<R> adr, I k) {
    return Id<R>(adr.v + static_cast<int32_t>(k));
}

// A number of rows, as an id counts them: the count of a table or any vector.
template <class V>
constexpr int32_t count_of(const V& v) {
    return static_cast<int32_t>(v.size());
}

// A table's id as the number it indexes, where no typed table takes it (a key, a bit).
template <class R, IdRole Role>
constexpr size_t index(TypedId<R, Role> id) {
    return static_cast<size_t>(id.v);
}

// The ids [first, first + n) in order: for (BodyId b : ids_of(g.bodies)) ...,
// for (ShapeId s : children(body.shape_adr, body.shape_num)) ...
template <class IdT>
struct IdRange {
    struct It {
        int32_t i;
        constexpr IdT operator*() const { return IdT(i); }
        constexpr It& operator++() {
            ++i;
            return *this;
        }
        friend constexpr bool operator==(It, It) = default;
    };
    int32_t first, last;
    constexpr It begin() const { return {first}; }
    constexpr It end() const { return {last}; }
    constexpr int32_t size() const { return last - first; }
};
template <class R>
constexpr IdRange<Id<R>> children(Adr<R> adr, int32_t num) {
    return {adr.v, adr.v + num};
}

// A vector indexed by one id type (Carbon's ValueStore / IdVector): v[id] takes an IdT
// and nothing else, so an id of another table, an Adr or a plain integer does not index it
// (a number that is an id is made one first, SlotId(n)). The graph's
// tables and the runtime's per-id arrays are these. In release builds operator[] is the
// vector's; debug builds assert the id in range.
template <class IdT, class T>
class IdVector {
public:
    using value_type = T;
    using id_type = IdT;
    using iterator = typename std::vector<T>::iterator;
    using const_iterator = typename std::vector<T>::const_iterator;

    IdVector() = default;
    explicit IdVector(int32_t n, const T& fill = T{}) : v_(static_cast<size_t>(n), fill) {}
    IdVector(std::initializer_list<T> init) : v_(init) {}

    T& operator[](IdT i) {
        assert(static_cast<size_t>(i.v) < v_.size());
        return v_[static_cast<size_t>(i.v)];
    }
    const T& operator[](IdT i) const {
        assert(static_cast<size_t>(i.v) < v_.size());
        return v_[static_cast<size_t>(i.v)];
    }
    // Checked: throws std::out_of_range (a negative id too).
    const T& at(IdT i) const { return v_.at(static_cast<size_t>(i.v)); }
    T& at(IdT i) { return v_.at(static_cast<size_t>(i.v)); }
    bool contains(IdT i) const { return i.v >= 0 && static_cast<size_t>(i.v) < v_.size(); }

    // The rows of a child list (an adr, num pair) as one span.
    template <class R>
        requires std::same_as<IdT, Id<R>>
    std::span<const T> slice(Adr<R> adr, int32_t num) const {
        assert(adr.v >= 0 && num >= 0 && static_cast<size_t>(adr.v) + static_cast<size_t>(num) <= v_.size());
        return std::span<const T>(v_.data() + adr.v, static_cast<size_t>(num));
    }

    size_t size() const { return v_.size(); }
    int32_t count() const { return static_cast<int32_t>(v_.size()); }
    bool empty() const { return v_.empty(); }
    // The id the next row appended gets, and every id in order.
    IdT next_id() const { return IdT(count()); }
    IdRange<IdT> ids() const { return {0, count()}; }

    iterator begin() { return v_.begin(); }
    iterator end() { return v_.end(); }
    const_iterator begin() const { return v_.begin(); }
    const_iterator end() const { return v_.end(); }
    T& front() { return v_.front(); }
    const T& front() const { return v_.front(); }
    T& back() { return v_.back(); }
    const T& back() const { return v_.back(); }
    T* data() { return v_.data(); }
    const T* data() const { return v_.data(); }

    // Appends a row and returns its id.
    IdT push_back(const T& x) {
        v_.push_back(x);
        return IdT(count() - 1);
    }
    IdT push_back(T&& x) {
        v_.push_back(std::move(x));
        return IdT(count() - 1);
    }
    template <class... A>
    T& emplace_back(A&&... a) {
        return v_.emplace_back(std::forward<A>(a)...);
    }
    void pop_back() { v_.pop_back(); }
    void resize(size_t n) { v_.resize(n); }
    void resize(size_t n, const T& fill) { v_.resize(n, fill); }
    void assign(size_t n, const T& fill) { v_.assign(n, fill); }
    void reserve(size_t n) { v_.reserve(n); }
    void clear() { v_.clear(); }
    size_t capacity() const { return v_.capacity(); }

    // The rows as a plain vector (for code that is generic over containers).
    std::vector<T>& vec() { return v_; }
    const std::vector<T>& vec() const { return v_; }

    friend bool operator==(const IdVector&, const IdVector&) = default;

private:
    std::vector<T> v_;
};

// A table of the graph: its rows by their Id<R>.
template <class R>
using Table = IdVector<Id<R>, R>;

// The id the next row appended to a table gets (its size), and as a list's first row.
template <class R>
constexpr Id<R> next_id(const Table<R>& table) {
    return table.next_id();
}
template <class R>
constexpr Adr<R> next_adr(const Table<R>& table) {
    return Adr<R>(table.count());
}
// The rows appended to a table since its next_adr was `adr`: the `num` of an (adr, num) list.
template <class R>
constexpr int32_t rows_since(const Table<R>& table, Adr<R> adr) {
    return table.count() - adr.v;
}
template <class IdT, class T>
constexpr IdRange<IdT> ids_of(const IdVector<IdT, T>& v) {
    return v.ids();
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
struct Value;
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
struct PluginString;
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
template <>
struct fmt::formatter<plant::graph::Detail> : fmt::formatter<int32_t> {
    template <class Ctx>
    auto format(plant::graph::Detail d, Ctx& ctx) const {
        return fmt::formatter<int32_t>::format(d.v, ctx);
    }
};
template <class R>
struct fmt::formatter<plant::graph::OptId<R>> : fmt::formatter<plant::graph::Id<R>> {};
