// Lowering a component of a plugin kind (graph/plugin.h). The generic part has checked its
// properties against the descriptor's parameters (type, dimension, required) and added
// the descriptor's slots; what is left is storing the parameters in the declared order,
// and later, with the flows of its scope, its entries.
#include "sema/kinds/lowering.h"

#include <fmt/format.h>

#include <algorithm>

namespace plant::sema {
namespace {

// A parameter's (or an entry option's) stored form: the checked value, or its default, in
// the field of its type (graph.h, PLANT_FIELDS_PARAM). A Vec3 not given is default_num in
// each coordinate, a StringList not given is empty, a Type not given is none; a CompRef is
// none here and resolved by link_plugin, once the object's components all exist.
graph::PluginParam stored(Elaborator& el, const graph::ParamSpec& ps, const Value* v) {
    using graph::ParamType;
    graph::PluginParam p;
    p.num = ps.default_num;
    switch (ps.type) {
    case ParamType::Vec3: p.vec = v ? vec(*v) : graph::Vec3{ps.default_num, ps.default_num, ps.default_num}; break;
    case ParamType::Type:
        if (v) p.type = el.do_type(v->str, v->span);
        break;
    case ParamType::StringList:
        p.list_adr = graph::next_adr(el.g_.plugin_strings);
        if (v)
            for (const Value& item : v->items) el.g_.plugin_strings.push_back({el.name(item.str)});
        p.list_num = graph::rows_since(el.g_.plugin_strings, p.list_adr);
        break;
    case ParamType::CompRef: break;
    default: {
        const bool text = ps.type == ParamType::String || (ps.type == ParamType::Value && v && v->kind == Value::Kind::Str);
        if (text) p.text = el.name(v ? std::string_view(v->str) : std::string_view());
        else if (v && v->kind == Value::Kind::Bool) p.num = v->boolean ? 1 : 0;
        else if (v) p.num = v->num;
        break;
    }
    }
    return p;
}

}  // namespace

bool refuse_placement(Lowering& lw, const graph::KindDesc& kind) {
    if (!lw.decl.placement || kind.placed) return false;
    const Span at = lw.decl.placement->at ? lw.decl.placement->at->span : lw.decl.name.span;
    auto& d = lw.el.sink_.report(DiagId::WrongComponentKind, at,
                                 fmt::format("'{}' takes no placement: a {} component is not drawn in the scene",
                                             lw.decl.name.text, kind.word));
    if (!kind.inside.empty())
        d.notes.push_back({{}, fmt::format("place its {} instead (`{} NAME at (X, Y, Z) {{ … }}`)", kind.inside,
                                           kind.inside)});
    return true;
}

void lower_plugin(Lowering& lw) {
    graph::Graph& g = lw.el.g_;
    const graph::KindDesc& kind = *lw.spec.plugin;
    graph::Plugin rec;
    rec.comp = lw.comp;
    rec.kind = lw.el.name(kind.word);
    rec.param_adr = graph::next_adr(g.plugin_params);
    rec.param_num = graph::count_of(kind.params);
    rec.entry_adr = graph::Adr<graph::PluginEntry>(0);  // set when it has entries
    // A placement: the world pose of a kind that is drawn in the scene (a panel); on any
    // other plugin kind it would be silently dropped, so it is refused.
    if (lw.decl.placement && !refuse_placement(lw, kind)) {
        rec.placed = true;
        rec.pose = lw.frame.pose();
    }
    for (const graph::ParamSpec& ps : kind.params)
        g.plugin_params.push_back(stored(lw.el, ps, lw.props.get(std::string(ps.name))));
    const graph::PluginId plugin = g.plugins.push_back(rec);
    lw.set_detail(plugin);
    // Where its kind's check reports (a panel's button too, which has no entries pass).
    lw.el.plugin_spans_.resize(g.plugins.size());
    lw.el.plugin_spans_[plugin] = lw.decl.name.span;
}

void link_plugin(Linking& lk) {
    graph::Graph& g = lk.el.g_;
    const graph::Plugin& rec = g.plugins[lk.row<graph::Plugin>()];
    const graph::KindDesc* kind = graph::find_plugin(g.str(rec.kind));
    if (!kind) return;
    for (size_t k = 0; k < kind->params.size(); ++k) {
        const graph::ParamSpec& ps = kind->params[k];
        if (ps.type != graph::ParamType::CompRef) continue;
        const ast::Property* p = lk.prop(std::string(ps.name).c_str());
        if (!p) continue;
        if (const std::string n = lk.ref_name(*p); !n.empty()) g.plugin_params[rec.param_adr + k].comp = lk.find_comp(n, p->value->span);
    }
}

}  // namespace plant::sema

namespace plant::sema {
namespace {

// "a 'coil'", "an 'invert'": an entry's word with its article.
std::string quoted_word(std::string_view w) {
    const bool vowel = !w.empty() && std::string_view("aeiou").find(w[0]) != std::string_view::npos;
    return fmt::format("{} '{}'", vowel ? "an" : "a", w);
}
std::string_view dir_text(graph::Dir d) { return d == graph::Dir::In ? "an input" : "an output"; }

std::string types_text(std::span<const graph::SlotType> types) {
    std::string s;
    for (size_t i = 0; i < types.size(); ++i)
        s += std::string(i == 0 ? "" : i + 1 == types.size() ? " or " : ", ") + std::string(graph::word(types[i]));
    return s;
}

}  // namespace

// The entries of a plugin component, once every slot of the plant can be named: the word
// one the kind takes, the key an integer in range, the target a slot or port of the entry's
// direction and types, the options known, set once and of their type and dimension.
void Elaborator::add_entries(graph::CompId comp, const ast::ComponentDecl& c, const Env& env, graph::DoId scope_do) {
    const graph::KindDesc* kind = graph::plugin_of(g_, comp);
    if (!kind) return;
    const graph::PluginId plugin = graph::detail_of<graph::Plugin>(g_.comps[comp]);
    if (!plugin_spans_.contains(plugin)) plugin_spans_.resize(g_.plugins.size());
    plugin_spans_[plugin] = c.name.span;
    if (c.entries.empty()) return;
    g_.plugins[plugin].entry_adr = graph::next_adr(g_.plugin_entries);
    for (const ast::EntryDecl& e : c.entries) {
        const graph::EntrySpec* es = graph::find_entry(*kind, e.word.text);
        if (!es) {
            std::vector<std::string> words;
            for (const auto& x : kind->entries) words.emplace_back(x.word);
            auto& d = sink_.report(DiagId::UnknownProperty, e.word.span,
                                   fmt::format("{} {} takes no entry '{}'",
                                               std::string_view("aeiou").find(kind->word.front()) != std::string_view::npos
                                                   ? "an"
                                                   : "a",
                                               kind->word, e.word.text));
            if (auto hint = closest_name(e.word.text, words); !hint.empty())
                d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
            else
                d.notes.push_back({{}, fmt::format("its entries: {}", fmt::join(words, ", "))});
            continue;
        }
        const Value key = ev_.eval(*e.key, env);
        if (es->key == graph::EntryKey::Time) {
            if (!ev_.expect_number(key, units::dims::time, fmt::format("the time of {} entry", quoted_word(es->word)))) continue;
            if (!(key.num >= 0)) {
                sink_.report(DiagId::OutOfRange, e.key->span,
                             fmt::format("the time of {} entry is 0 s or later, not {} s", quoted_word(es->word), key.num));
                continue;
            }
        } else if (!ev_.expect_int(key, fmt::format("the key of {} entry", quoted_word(es->word)))) {
            continue;
        } else if (key.num < 0 || key.num > es->max_key) {
            sink_.report(DiagId::OutOfRange, e.key->span,
                         fmt::format("the key of {} entry is between 0 and {}, not {}", quoted_word(es->word), es->max_key,
                                     static_cast<long long>(key.num)));
            continue;
        }
        const Endpoint end = resolve(scope_do, e.target, env);
        if (!end.ok) continue;
        if (end.ref_slot.valid()) {
            sink_.report(DiagId::NotARef, e.target.span,
                         fmt::format("an entry names a slot of a fixed object; '{}' belongs to whichever object the "
                                     "reference holds at run time", end.text));
            continue;
        }
        if (end.dir != es->target && !es->any_dir) {
            sink_.report(DiagId::DirectionMismatch, e.target.span,
                         fmt::format("{} entry names {}, but '{}' is {}", quoted_word(es->word), dir_text(es->target), end.text,
                                     dir_text(end.dir)));
            continue;
        }
        if (!es->types.empty() && std::find(es->types.begin(), es->types.end(), end.type) == es->types.end()) {
            sink_.report(DiagId::SlotTypeMismatch, e.target.span,
                         fmt::format("{} entry takes a {} slot, but '{}' is {}", quoted_word(es->word), types_text(es->types),
                                     end.text, graph::word(end.type)));
            continue;
        }
        std::vector<graph::PluginParam> options;
        if (!entry_options(e, *es, end.type, env, options)) continue;
        graph::PluginEntry rec;
        rec.word = name(es->word);
        rec.key = key.num;
        rec.slot_adr = graph::next_adr(g_.plugin_entry_slots);
        rec.slot_num = graph::count_of(end.slots);
        for (graph::SlotId s : end.slots) g_.plugin_entry_slots.push_back({s});
        rec.param_adr = graph::next_adr(g_.plugin_params);
        rec.param_num = graph::count_of(options);
        for (const graph::PluginParam& o : options) g_.plugin_params.push_back(o);
        rec.src = src(e.span);
        const graph::Id<graph::PluginEntry> entry = g_.plugin_entries.push_back(rec);
        entry_spans_.resize(g_.plugin_entries.size());
        entry_spans_[entry] = e.span;
    }
    g_.plugins[plugin].entry_num = graph::rows_since(g_.plugin_entries, g_.plugins[plugin].entry_adr);
}

// Checks a kind makes across entries or components (a Modbus link's overlapping
// addresses, two links on one port), reported at the entry or the component.
void Elaborator::check_plugins() {
    for (graph::PluginId p : ids_of(g_.plugins)) {
        const graph::KindDesc* kind = graph::plugin_of(g_, g_.plugins[p].comp);
        graph::PluginProblem problem;
        if (!kind || !kind->check || kind->check(g_, p.v, problem)) continue;
        const graph::Id<graph::PluginEntry> entry = g_.plugins[p].entry_adr + problem.entry;
        const Span at = problem.entry >= 0 && entry_spans_.contains(entry) ? entry_spans_[entry]
                        : plugin_spans_.contains(p)                        ? plugin_spans_[p]
                                                                           : Span{};
        sink_.report(DiagId::KindCheck, at, problem.message);
    }
}

// `(name = value, ...)` of an entry, in the order its spec declares them, defaults filled in.
// A Value option takes the type of the entry's slot (`target`).
bool Elaborator::entry_options(const ast::EntryDecl& e, const graph::EntrySpec& es, graph::SlotType target,
                               const Env& env, std::vector<graph::PluginParam>& out) {
    std::vector<uint8_t> given(es.options.size(), 0);
    std::vector<Value> values(es.options.size());
    bool ok = true;
    for (const ast::Arg& a : e.options) {
        if (!a.name) {
            sink_.report(DiagId::UnknownArgument, a.span,
                         fmt::format("an entry's options are named: `({} = ...)`",
                                     es.options.empty() ? std::string("name") : std::string(es.options[0].name)));
            ok = false;
            continue;
        }
        auto it = std::find_if(es.options.begin(), es.options.end(), [&](const auto& o) { return o.name == a.name->text; });
        if (it == es.options.end()) {
            std::vector<std::string> names;
            for (const auto& o : es.options) names.emplace_back(o.name);
            auto& d = sink_.report(DiagId::UnknownArgument, a.name->span,
                                   fmt::format("{} entry has no option '{}'", quoted_word(es.word), a.name->text));
            if (auto hint = closest_name(a.name->text, names); !hint.empty())
                d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
            ok = false;
            continue;
        }
        const auto k = it - es.options.begin();
        if (given[k]) {
            sink_.report(DiagId::DuplicateProperty, a.name->span, fmt::format("option '{}' is given twice", a.name->text));
            ok = false;
            continue;
        }
        values[k] = ev_.eval(*a.value, env);
        given[k] = 1;
        const std::string what = fmt::format("option '{}'", it->name);
        switch (it->type) {
        case graph::ParamType::Number: ok = ev_.expect_number(values[k], param_dim(*it), what) && ok; break;
        case graph::ParamType::Int: ok = ev_.expect_int(values[k], what) && ok; break;
        case graph::ParamType::Bool: ok = ev_.expect_bool(values[k], what) && ok; break;
        case graph::ParamType::String: ok = ev_.expect_string(values[k], what) && ok; break;
        case graph::ParamType::Value: ok = expect_slot_value(values[k], target, what) && ok; break;
        default: break;  // not an entry option's type (graph::register_kind refuses it)
        }
    }
    for (size_t k = 0; k < es.options.size(); ++k) {
        const graph::ParamSpec& ps = es.options[k];
        if (!given[k] && ps.required) {
            sink_.report(DiagId::MissingProperty, e.span,
                         fmt::format("{} entry needs the option '{}' ({})", quoted_word(es.word), ps.name, ps.doc));
            ok = false;
        }
        out.push_back(stored(*this, ps, given[k] ? &values[k] : nullptr));
    }
    return ok;
}

// A value for a slot of type `t`: void and bool take true or false (a void slot: on or
// off), int a whole number, real a number of any unit (stored in SI), string a text.
bool Elaborator::expect_slot_value(const Value& v, graph::SlotType t, const std::string& what) {
    switch (t) {
    case graph::SlotType::Void:
    case graph::SlotType::Bool: return ev_.expect_bool(v, what + " (of a " + std::string(graph::word(t)) + " slot)");
    case graph::SlotType::Int: return ev_.expect_int(v, what + " (of an int slot)");
    case graph::SlotType::String: return ev_.expect_string(v, what + " (of a string slot)");
    case graph::SlotType::Real:
        if (v.kind == Value::Kind::Num) return true;
        return ev_.expect_number(v, units::Dim{}, what + " (of a real slot)");
    default: break;  // the entry's types exclude the rest
    }
    sink_.report(DiagId::SlotTypeMismatch, v.span,
                 fmt::format("{}: a {} slot takes no value here", what, graph::word(t)));
    return false;
}

}  // namespace plant::sema
