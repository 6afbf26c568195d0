#include "graph.h"

#include <fmt/format.h>

#include <cmath>
#include <iterator>

namespace plant::graph {

Name Graph::intern(std::string_view s) {
    // A loader may fill `names` directly. Duplicates in such a table keep the sizes
    // apart, so the index is then rebuilt on every call: correct, only slower.
    if (index_.size() != names.size()) {
        index_.clear();
        for (int32_t i = 0; i < count_of(names); ++i) index_.emplace(names[i], i);
    }
    // Looking up first: almost every name is already there, and emplace would build a
    // string and a node for nothing.
    thread_local std::string key;
    key.assign(s);
    if (auto it = index_.find(key); it != index_.end()) return Name{it->second};
    const Name added{count_of(names)};
    index_.emplace(key, added.id);
    names.emplace_back(s);
    return added;
}

namespace {

std::string join(std::string_view a, std::string_view b) {
    if (a.empty()) return std::string(b);  // the root DO has an empty path
    return fmt::format("{}.{}", a, b);
}

bool in_range(const std::vector<std::string>& v, int32_t i) {
    return i >= 0 && i < count_of(v);
}

}  // namespace

std::string Graph::comp_path(CompId comp) const {
    if (!comps.contains(comp)) return fmt::format("<comp {}>", comp);
    const Comp& c = comps[comp];
    std::string owner = dos.contains(c.owner) ? std::string(str(dos[c.owner].path))
                                               : fmt::format("<do {}>", c.owner);
    return join(owner, str(c.name));
}

std::string Graph::slot_path(SlotId slot) const {
    if (!slots.contains(slot)) return fmt::format("<slot {}>", slot);
    const Slot& s = slots[slot];
    return join(comp_path(s.comp), str(s.name));
}

std::string Graph::port_path(PortId port) const {
    if (!ports.contains(port)) return fmt::format("<port {}>", port);
    const Port& p = ports[port];
    std::string owner = dos.contains(p.owner) ? std::string(str(dos[p.owner].path))
                                               : fmt::format("<do {}>", p.owner);
    return join(owner, str(p.name));
}

std::string Graph::src_text(Src s) const {
    if (s.file < 0) return "-";
    if (!in_range(files, s.file)) return fmt::format("<file {}>:{}:{}", s.file, s.line, s.col);
    return fmt::format("{}:{}:{}", files[s.file], s.line, s.col);
}

// ---- comparison ----

namespace {

// Equal as the text form sees them: -0 differs from 0, and any NaN equals any NaN.
bool same_double(double x, double y) {
    if (std::isnan(x) || std::isnan(y)) return std::isnan(x) && std::isnan(y);
    return x == y && std::signbit(x) == std::signbit(y);
}

struct Same {
    const Graph& a;
    const Graph& b;

    bool operator()(double x, double y) const { return same_double(x, y); }
    template <size_t N>
    bool operator()(const std::array<double, N>& x, const std::array<double, N>& y) const {
        for (size_t i = 0; i < N; ++i)
            if (!same_double(x[i], y[i])) return false;
        return true;
    }
    bool operator()(const Pose& x, const Pose& y) const { return (*this)(x.p, y.p) && (*this)(x.q, y.q); }
    bool operator()(Name x, Name y) const {
        bool vx = in_range(a.names, x.id), vy = in_range(b.names, y.id);
        if (vx != vy) return false;
        return vx ? a.names[x.id] == b.names[y.id] : x.id == y.id;
    }
    template <class T>
    bool operator()(const T& x, const T& y) const { return x == y; }  // ints, bools, enums, Src

    template <class R, class F>
    bool table(const Table<R>& x, const Table<R>& y, F&& fields) const {
        if (x.size() != y.size()) return false;
        for (Id<R> i : x.ids())
            if (!fields(x[i], y[i])) return false;
        return true;
    }
};

}  // namespace

bool Graph::same_as(const Graph& other) const {
    Same same{*this, other};
    if (!same(plant, other.plant) || !same(settings.rate, other.settings.rate) ||
        !same(settings.gravity, other.settings.gravity) ||
        settings.steady_transport != other.settings.steady_transport || files != other.files)
        return false;
#define PLANT_SAME_FIELD(T_, f_) &&same(x.f_, y.f_)
#define PLANT_SAME_TABLE(member, Record, elem, FIELDS)                                   \
    if (!same.table(member, other.member,                                                \
                    [&](const Record& x, const Record& y) { return true FIELDS(PLANT_SAME_FIELD); })) \
        return false;
    PLANT_GRAPH_TABLES(PLANT_SAME_TABLE)
#undef PLANT_SAME_TABLE
#undef PLANT_SAME_FIELD
    return true;
}

// ---- enum words ----

namespace {

template <class E, size_t N>
std::string_view word_of(E e, const std::string_view (&words)[N]) {
    auto i = static_cast<size_t>(e);
    return i < N ? words[i] : std::string_view("?");
}

template <class E, size_t N>
bool parse_of(std::string_view s, E& e, const std::string_view (&words)[N]) {
    for (size_t i = 0; i < N; ++i)
        if (words[i] == s) {
            e = static_cast<E>(i);
            return true;
        }
    return false;
}

constexpr std::string_view kSlotType[] = {"void", "bool", "int", "real", "vec3",
                                          "quat", "pose", "string", "ref"};
constexpr std::string_view kDir[] = {"in", "out"};
constexpr std::string_view kCompKind[] = {"graphics", "body",    "field",  "constraint", "state",
                                          "trigger",  "timer",   "gripper", "source",    "exit",
                                          "router",   "logic",   "label",   "plugin"};
constexpr std::string_view kBodyMode[] = {"dynamic", "static", "kinematic"};
constexpr std::string_view kShapeKind[] = {"box", "sphere", "cylinder", "capsule", "hull"};
constexpr std::string_view kJointKind[] = {"fixed", "hinge", "slider"};
constexpr std::string_view kCond[] = {"source", "target", "both", "either"};
constexpr std::string_view kLogicOp[] = {"and", "or"};

}  // namespace

// The static_assert catches an enumerator added without a word.
#define PLANT_ENUM_WORDS(E, words, last)                                                 \
    static_assert(std::size(words) == static_cast<size_t>(E::last) + 1);               \
    std::string_view word(E e) { return word_of(e, words); }                            \
    bool parse_word(std::string_view s, E& e) { return parse_of(s, e, words); }

PLANT_ENUM_WORDS(SlotType, kSlotType, Ref)
PLANT_ENUM_WORDS(Dir, kDir, Out)
PLANT_ENUM_WORDS(CompKind, kCompKind, Plugin)
PLANT_ENUM_WORDS(BodyMode, kBodyMode, Kinematic)
PLANT_ENUM_WORDS(ShapeKind, kShapeKind, Hull)
PLANT_ENUM_WORDS(JointKind, kJointKind, Slider)
PLANT_ENUM_WORDS(Cond, kCond, Either)
PLANT_ENUM_WORDS(LogicOp, kLogicOp, Or)
#undef PLANT_ENUM_WORDS

template <> std::span<const std::string_view> words<SlotType>() { return kSlotType; }
template <> std::span<const std::string_view> words<Cond>() { return kCond; }

}  // namespace plant::graph
