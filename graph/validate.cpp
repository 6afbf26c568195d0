#include "validate.h"

#include "kinds.h"
#include "network.h"
#include "plugin.h"
#include "range.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string_view>
#include <type_traits>
#include <utility>

namespace plant::graph {

namespace {

bool finite(double v) { return std::isfinite(v); }
template <size_t N>
bool finite(const std::array<double, N>& v) {
    for (double x : v)
        if (!std::isfinite(x)) return false;
    return true;
}
bool finite(const Pose& p) { return finite(p.p) && finite(p.q); }
template <class T>
bool finite(const T&) {
    return true;
}

// A rotation: |q| = 1 up to the rounding of a written quaternion.
bool unit(const Quat& q) {
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    return std::abs(n - 1) < 1e-6;
}
bool unit_quats(const Pose& p) { return unit(p.q); }
template <class T>
bool unit_quats(const T&) {
    return true;
}

class Checker {
public:
    Checker(const Graph& g, GraphProblem& p) : g_(g), p_(p) {}

    bool run() {
        if (!(finite(g_.settings.rate) && g_.settings.rate >= kMinRate && g_.settings.rate <= kMaxRate))
            return fail_at("", -1, fmt::format("settings: rate {} is not between 1 Hz and 1 MHz", g_.settings.rate));
        if (!finite(g_.settings.gravity)) return fail_at("", -1, "settings: gravity is not finite");
        if (!gravity_in_range(g_.settings.gravity.data()))
            return fail_at("", -1, "settings: gravity is beyond 1 km/s² along an axis");
        return every_field() && ranges() && dos() && comps() && slots() && flows() && table_kinds() &&
               animations() && variants() && ports() && plugin_records();
    }

private:
    bool fail_at(std::string_view table, int32_t row, std::string message) {
        p_.table = std::string(table);
        p_.row = row;
        p_.message = std::move(message);
        return false;
    }
    bool fail(std::string message) { return fail_at(table_, row_, std::move(message)); }
    void at(std::string_view table, int32_t row) {
        table_ = table;
        row_ = row;
    }
    // check(record, id) for every record of a table, stopping at the first that fails.
    template <class R, class F>
    bool each(std::string_view table, const Table<R>& rows, F&& check) {
        for (Id<R> i : rows.ids()) {
            at(table, i.v);
            if (!check(rows[i], i)) return false;
        }
        return true;
    }

    // `value` is a row of a table with n rows, or -1 when `none` allows it.
    bool id(std::string_view field, int32_t value, size_t n, std::string_view target, bool none = false) {
        if (none && value == -1) return true;
        if (value >= 0 && std::cmp_less(value, n)) return true;
        return fail(fmt::format("field '{}' = {} is not {}a row of {} ({} rows)", field, value,
                                none ? "-1 or " : "", target, n));
    }
    // [adr, adr + num) inside a table of n rows (num = 0: any adr).
    bool range(std::string_view adr_field, int32_t adr, int32_t num, size_t n, std::string_view target) {
        if (num == 0 && adr >= -1) return true;
        if (num > 0 && adr >= 0 && std::cmp_less_equal(int64_t{adr} + num, n)) return true;
        return fail(fmt::format("fields '{}' + num ({} + {}) are not a range of {} ({} rows)", adr_field, adr, num,
                                target, n));
    }
    // A slot of the given type and direction (every_field() checked it is one, or -1).
    bool slot(std::string_view field, SlotId s, SlotType type, Dir dir) {
        std::string flaw = slot_flaw(g_, field, s, type, dir);
        return flaw.empty() || fail(std::move(flaw));
    }
    bool check(bool ok, std::string_view what) { return ok || fail(std::string(what)); }
    // The component `c` is of `kind` and its detail is this record.
    bool owner(CompId c, CompKind kind, int32_t self) {
        const Comp& cp = g_.comps[c];
        if (cp.kind != kind || cp.detail.v != self)
            return fail(fmt::format("field 'comp' = {}: that component is a {} whose detail is {}, not this {}", c,
                                    word(cp.kind), cp.detail, word(kind)));
        return true;
    }

    // Every double finite, every written rotation a unit quaternion, every source
    // position in a known file; every Id<R> field a row of R's table (or -1 where
    // its type is an OptId<R>), every Adr<R> field and the `_num` after it a range of R's table.
    bool every_field() {
#define PLANT_CHECK_FIELD(T_, f_)                                                         \
    if (!finite(r.f_)) return fail(fmt::format("field '{}' is not a finite number", #f_)); \
    if (!unit_quats(r.f_)) return fail(fmt::format("field '{}' has a rotation that is not a unit quaternion", #f_)); \
    if (!src_ok(r.f_)) return fail(fmt::format("field '{}' names file {}, not one of the {} files", #f_, src_file(r.f_), g_.files.size())); \
    if (!reference(#f_, r.f_)) return false;
#define PLANT_CHECK_TABLE(member, Record, elem, FIELDS)     \
    for (Id<Record> i : g_.member.ids()) {                  \
        constexpr std::string_view table = #member;         \
        at(table, i.v);                                     \
        const Record& r = g_.member[i];                     \
        FIELDS(PLANT_CHECK_FIELD)                           \
    }
        PLANT_GRAPH_TABLES(PLANT_CHECK_TABLE)
#undef PLANT_CHECK_TABLE
#undef PLANT_CHECK_FIELD
        return true;
    }
    // Whether the field may be -1 is its type's (OptId<R>), decided at compile time.
    template <class T>
    bool reference(std::string_view field, const T& v) {
        if constexpr (is_typed_id<T>) {
            using R = typename T::record;
            if constexpr (T::role == IdRole::Row)
                return id(field, v.v, g_.rows<R>().size(), table_name<R>(), is_optional_id<T>);
            // A slot's values: as many as its type's width, -1 for none (slots() checks it).
            if constexpr (std::is_same_v<R, Value>) return true;
            adr_ = {field, v.v, g_.rows<R>().size(), table_name<R>()};
        } else if constexpr (std::is_same_v<T, int32_t>) {
            if (!adr_.table.empty() && field.ends_with("_num")) {
                const Pending a = std::exchange(adr_, {});
                return range(a.field, a.adr, v, a.rows, a.table);
            }
        }
        return true;
    }
    template <class T>
    bool src_ok(const T& s) {
        if constexpr (std::is_same_v<T, Src>) return s.file >= -1 && s.file < count_of(g_.files);
        return true;
    }
    template <class T>
    int32_t src_file(const T& s) {
        if constexpr (std::is_same_v<T, Src>) return s.file;
        return 0;
    }

    // Places, sizes and masses within range.h's bounds (the first out of range).
    bool ranges() {
        const std::vector<RangeFlaw> flaws = range_flaws(g_);
        if (flaws.empty()) return true;
        const RangeFlaw& f = flaws.front();
        return fail_at(f.table, f.row, fmt::format("field '{}' {}", f.field, f.text));
    }

    bool dos() {
        if (!each("do_types", g_.do_types, [&](const auto& r, DoTypeId) {
            return check(r.instance_num >= 0, "field 'instance_num' is negative");
        }))
            return false;
        return each("dos", g_.dos, [&](const Do& d, DoId i) {
            if (!check(d.parent.v < i.v, "field 'parent' must name an earlier DO (or be -1)")) return false;
            if (d.type.valid() && !(d.ordinal >= 0 && d.ordinal < g_.do_types[d.type].instance_num))
                return fail(fmt::format("field 'ordinal' = {} is not below its type's instance_num {}", d.ordinal,
                                        g_.do_types[d.type].instance_num));
            if (d.pool.valid() && !check(g_.comps[d.pool].kind == CompKind::Source,
                                      "field 'pool' does not name a source component"))
                return false;
            return true;
        });
    }

    // The table a component kind's `detail` indexes, with its size; none for a kind on the
    // kind table without one (its row's `table` empty).
    bool detail_table(CompKind k, size_t& n, std::string_view& name) const {
        if (const KindDesc* d = builtin_kind(k)) {
            if (d->table.empty()) return false;
            n = d->rows(g_), name = d->table;
            return true;
        }
        if (k != CompKind::Plugin) return false;
        n = g_.plugins.size(), name = "plugins";
        return true;
    }

    bool comps() {
        return each("comps", g_.comps, [&](const Comp& cp, CompId c) {
            size_t n = 0;
            std::string_view table;
            if (detail_table(cp.kind, n, table)) {
                if (!id("detail", cp.detail.v, n, table)) return false;
            } else if (!check(cp.detail.v == -1, "field 'detail' must be -1 for this kind")) {
                return false;
            }
            // A plugin's detail is a row of `plugins` by now; plugin_records() checks the rest.
            const KindDesc* plugin = cp.kind == CompKind::Plugin ? plugin_of(g_, c) : nullptr;
            if (cp.kind == CompKind::Plugin && !plugin)
                return fail(fmt::format("a component of kind '{}', which this program does not have (a plugin it "
                                        "was not built with)", g_.str(g_.plugins[detail_of<Plugin>(cp)].kind)));
            const auto fixed = slots_of(g_, c);
            if (plugin && cp.slot_num != count_of(fixed))
                return fail(fmt::format("a {} has {} slots, field 'slot_num' is {}", plugin->word, fixed.size(),
                                        cp.slot_num));
            if (cp.slot_num < count_of(fixed))
                return fail(fmt::format("a {} has {} fixed slots, field 'slot_num' is {}", word(cp.kind), fixed.size(),
                                        cp.slot_num));
            for (int32_t k = 0; k < cp.slot_num; ++k) {
                const Slot& s = g_.slots[cp.slot_adr + k];
                if (s.comp != c)
                    return fail(fmt::format("slot {} in its slot range belongs to component {}", cp.slot_adr + k, s.comp));
                if (k >= count_of(fixed)) continue;
                const SlotSpec& spec = fixed[k];
                if (s.type != spec.type || s.dir != spec.dir)
                    return fail(fmt::format("slot {} ('{}' of a {}) is {} {}, expected {} {}", cp.slot_adr + k, spec.name,
                                            word(cp.kind), word(s.type), word(s.dir), word(spec.type), word(spec.dir)));
            }
            return true;
        });
    }

    // Plugin components: a kind this program registered, its parameters as its descriptor
    // declares them.
    bool plugin_records() {
        return each("plugins", g_.plugins, [&](const Plugin& p, PluginId i) {
            if (!owner(p.comp, CompKind::Plugin, i.v)) return false;
            const KindDesc* d = find_plugin(g_.str(p.kind));  // comps() found it
            if (p.param_num != count_of(d->params))
                return fail(fmt::format("a {} has {} parameters, field 'param_num' is {}", d->word, d->params.size(),
                                        p.param_num));
            if (!params_valid(d->params, p.param_adr, fmt::format("of a {}", d->word), g_.comps[p.comp].owner)) return false;
            if (p.placed && !d->placed) return fail(fmt::format("a {} takes no placement, field 'placed' is true", d->word));
            for (Id<PluginEntry> e : children(p.entry_adr, p.entry_num))
                if (!plugin_entry(*d, g_.plugin_entries[e], e.v)) return false;
            return true;
        }) && each("plugins", g_.plugins, [&](const Plugin& p, PluginId i) {
            // The kind's own check, once every component's records are sound.
            const KindDesc* d = find_plugin(g_.str(p.kind));
            PluginProblem problem;
            if (!d->check || d->check(g_, i.v, problem)) return true;
            return fail(problem.entry < 0 ? fmt::format("a {}: {}", d->word, problem.message)
                                          : fmt::format("plugin entry {}: {}", p.entry_adr + problem.entry, problem.message));
        });
    }

    // Parameters (or an entry's options) as their specs declare them.
    // A component reference names a component of the same object (`owner`: the plugin
    // component's DO; an entry's options have none); one not required may be none, and so
    // may a type.
    bool params_valid(std::span<const ParamSpec> specs, Adr<PluginParam> adr, const std::string& of, DoId owner = {}) {
        for (size_t k = 0; k < specs.size(); ++k) {
            const ParamSpec& ps = specs[k];
            const PluginParam& v = g_.plugin_params[adr + k];
            bool ok = true;  // Number, Value (the kind checks), Vec3: every_field() checked them finite
            switch (ps.type) {
            case ParamType::String: ok = v.text.id >= 0; break;
            case ParamType::Int: ok = v.num == std::floor(v.num); break;
            case ParamType::Bool: ok = v.num == 0 || v.num == 1; break;
            case ParamType::Type: ok = v.type.valid() || !ps.required; break;
            case ParamType::CompRef:
                ok = v.comp.valid() ? owner.valid() && g_.comps[v.comp].owner == owner : !ps.required;
                break;
            default: ok = std::isfinite(v.num); break;
            }
            if (!ok) return fail(fmt::format("parameter '{}' {} is not a valid {}", ps.name, of, word(ps.type)));
        }
        return true;
    }

    // An entry: a word of the kind, a key in range, its target slots of the entry's direction
    // and types, its options.
    bool plugin_entry(const KindDesc& d, const PluginEntry& e, int32_t row) {
        const std::string where = fmt::format("plugin entry {}", row);
        const EntrySpec* es = find_entry(d, g_.str(e.word));
        if (!es) return fail(fmt::format("{}: a {} takes no entry '{}'", where, d.word, g_.str(e.word)));
        if (es->key == EntryKey::Time ? !(e.key >= 0 && std::isfinite(e.key))
                                      : !(e.key >= 0 && e.key <= es->max_key && e.key == std::floor(e.key)))
            return fail(es->key == EntryKey::Time
                            ? fmt::format("{}: key {} is not a time of 0 s or more", where, e.key)
                            : fmt::format("{}: key {} is not a whole number between 0 and {}", where, e.key, es->max_key));
        const bool one = es->target == Dir::Out && !es->any_dir;
        if (e.slot_num < 1 || (one && e.slot_num != 1))
            return fail(fmt::format("{}: a '{}' entry names {} slot{}, {}", where, es->word, one ? "one" : "at least one",
                                    one ? "" : "s", fmt::format("field 'slot_num' is {}", e.slot_num)));
        for (const PluginEntrySlot& es_slot : g_.plugin_entry_slots.slice(e.slot_adr, e.slot_num)) {
            const SlotId s = es_slot.v;
            const Slot& sl = g_.slots[s];
            const bool type_ok = es->types.empty() || std::find(es->types.begin(), es->types.end(), sl.type) != es->types.end();
            if ((sl.dir != es->target && !es->any_dir) || !type_ok)
                return fail(fmt::format("{}: slot {} is {} {}, which a '{}' entry cannot name", where, s, word(sl.type),
                                        word(sl.dir), es->word));
        }
        if (e.param_num != count_of(es->options))
            return fail(fmt::format("{}: a '{}' entry has {} options, field 'param_num' is {}", where, es->word,
                                    es->options.size(), e.param_num));
        return params_valid(es->options, e.param_adr, fmt::format("of a '{}' entry", es->word));
    }

    bool slots() {
        return each("slots", g_.slots, [&](const Slot& sl, SlotId) {
            const int w = slot_width(sl.type);
            if (w == 0) return true;
            if (!sl.value_adr.valid() || std::cmp_greater(int64_t{sl.value_adr.v} + w, g_.values.size()))
                return fail(fmt::format("field 'value_adr' = {}: a {} slot needs {} values there, the graph has {}",
                                        sl.value_adr, word(sl.type), w, g_.values.size()));
            return true;
        });
    }

    // Accesses and their targets, then the flows whose ends go through them.
    bool flows() {
        if (!each("accesses", g_.accesses, [&](const Access& a, AccessId) {
            if (!slot("ref_slot", a.ref_slot, SlotType::Ref, Dir::Out)) return false;
            if (a.target_num != g_.do_types[a.do_type].instance_num)
                return fail(fmt::format("field 'target_num' = {}: its type has {} instances", a.target_num,
                                        g_.do_types[a.do_type].instance_num));
            return true;
        }))
            return false;
        return each("flows", g_.flows, [&](const Flow& f, FlowId) {
            // A dynamic end holds its access's reference slot: the one place the runtime reads it from.
            if (f.from_access.valid() && f.from != g_.accesses[f.from_access].ref_slot)
                return fail(fmt::format("field 'from' = {}: a dynamic source holds its access's ref_slot {}", f.from,
                                        g_.accesses[f.from_access].ref_slot));
            if (f.to_access.valid() && f.to != g_.accesses[f.to_access].ref_slot)
                return fail(fmt::format("field 'to' = {}: a dynamic target holds its access's ref_slot {}", f.to,
                                        g_.accesses[f.to_access].ref_slot));
            // A flow drives inputs: written into an output, the value would be lost or clobbered.
            if (!each_end_slot(g_, f.to, f.to_access, [&](SlotId s) { return g_.slots[s].dir == Dir::In; }))
                return fail("its target is not an input slot");
            // The runtime copies the target's width of values from the source.
            int width = -1;
            bool same = each_end_slot(g_, f.to, f.to_access, [&](SlotId s) {
                const int w = slot_width(g_.slots[s].type);
                if (width >= 0 && w != width) return false;
                width = w;
                return true;
            });
            if (!same) return fail("the slots its target may be differ in width");
            if (width <= 0) return true;
            const bool fits = each_end_slot(g_, f.from, f.from_access,
                                       [&](SlotId s) { return slot_width(g_.slots[s].type) == width; });
            if (!fits) return fail(fmt::format("its source is not {} values wide, as its target is", width));
            return true;
        });
    }

    // The kinds on the kind table: each row's component of the kind with the row as its
    // detail, then the kind's own check of the row; then each kind's check of the other
    // tables its components own rows of.
    bool table_kinds() {
        for (const KindDesc* d : builtin_kinds())
            for (int32_t i = 0; d->rows && std::cmp_less(i, d->rows(g_)); ++i) {
                at(d->table, i);
                if (!owner(d->comp_of(g_, i), d->kind, i)) return false;
                PluginProblem problem;
                if (d->check && !d->check(g_, i, problem)) return fail(problem.message);
            }
        for (const KindDesc* d : builtin_kinds())
            if (d->check_tables && !d->check_tables(g_, p_)) return false;
        return true;
    }

    bool animations() {
        return each("animations", g_.animations, [&](const Animation& a, AnimationId i) {
            if (!check(a.duration >= 0, "field 'duration' is negative") ||
                !check(a.key_num > 0, "an animation needs keys") ||
                !slot("play_slot", a.play_slot, SlotType::Void, Dir::In) ||
                !slot("finished_slot", a.finished_slot, SlotType::Void, Dir::Out))
                return false;
            // A bad key is reported at the key.
            for (int32_t k = 0; k < a.key_num; ++k) {
                const Id<Key> key = a.key_adr + k;
                const double t = g_.keys[key].t;
                at("keys", key.v);
                if (k == 0 && t < 0) return fail(fmt::format("the first key of animation {} is at a negative time", i));
                if (k > 0 && !(t > g_.keys[a.key_adr + (k - 1)].t))
                    return fail(fmt::format("its time is not later than the key before it (animation {})", i));
            }
            return true;
        });
    }

    bool variants() {
        return each("variants", g_.variants, [&](const Variant& v, VariantId) {
            return slot("select_slot", v.select_slot, SlotType::Void, Dir::In);
        });
    }

    bool ports() {
        return each("ports", g_.ports, [&](const Port& p, PortId) {
            if (p.target_num < 1 || (p.dir == Dir::Out && p.target_num != 1))
                return fail(fmt::format("a port forwards to {} slots ({} port)", p.target_num, word(p.dir)));
            for (const PortTarget& t : g_.port_targets.slice(p.target_adr, p.target_num))
                if (!slot("port_targets", t.v, p.type, p.dir)) return false;
            return true;
        });
    }

    // An Adr field waiting for its num.
    struct Pending {
        std::string_view field;
        int32_t adr = -1;
        size_t rows = 0;
        std::string_view table;
    };

    const Graph& g_;
    GraphProblem& p_;
    Pending adr_;
    std::string_view table_;
    int32_t row_ = -1;
};

}  // namespace

std::string slot_flaw(const Graph& g, std::string_view field, OptId<Slot> s, SlotType type, Dir dir) {
    if (!s.valid()) return {};
    const Slot& sl = g.slots[SlotId(s)];
    if (sl.type == type && sl.dir == dir) return {};
    return fmt::format("field '{}' = {}: slot {} is {} {}, expected {} {}", field, s, s, word(sl.type), word(sl.dir),
                       word(type), word(dir));
}

bool validate(const Graph& g, GraphProblem& problem) {
    problem = GraphProblem{};
    return Checker(g, problem).run();
}

}  // namespace plant::graph
