// Components, the generic part: the kind word, its mode, its properties known, set once
// and typed, its sub-blocks allowed; the component appended with its fixed slots; then its
// kind's lowering and, once the object's components all exist, its late linking
// (kinds/NAME/lower.cpp; a plugin's sema/kinds/plugin.cpp). A connector (`logic`) is
// declared by its own form and made by its own lowering (kinds/logic/lower.cpp).
#include "sema/elaborator.h"
#include "sema/kinds/lowering.h"

#include "graph/build.h"
#include "graph/kinds.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <fmt/format.h>

namespace plant::sema {

using graph::CompKind;
using graph::Dir;
using graph::SlotType;

// The compiler's part of each kind on the kind table (kinds/NAME/lower.cpp), beside its row.
const KindLowering* builtin_lowering(CompKind kind) {
#define PLANT_KIND_LOWERING(word, WORD) std::pair{&kinds::word::desc, &kinds::word::lowering},
    static const std::array rows = {PLANT_KINDS(PLANT_KIND_LOWERING)};
#undef PLANT_KIND_LOWERING
    for (const auto& [desc, lowering] : rows)
        if (desc->kind == kind) return lowering;
    return nullptr;
}

namespace {

// The kind's lowering; the one place a kind joins the compiler: a kind on the kind table
// (every built-in kind) through its row, a plugin kind through its descriptor. A connector
// is a `logic` declaration, not a component written with a kind word (make_logic).
void lower(Lowering& lw) {
    if (const KindLowering* k = builtin_lowering(lw.spec.kind)) {
        refuse_placement(lw, *graph::builtin_kind(lw.spec.kind));
        return k->lower(lw);
    }
    if (lw.spec.kind == CompKind::Plugin) lower_plugin(lw);
}

// The kind's late linking, for the kinds that name other components.
void link(Linking& lk) {
    if (const KindLowering* k = builtin_lowering(lk.rec.kind)) {
        if (k->link) k->link(lk);
        return;
    }
    if (lk.rec.kind == CompKind::Plugin) link_plugin(lk);
}

}  // namespace

double Lowering::num(const char* n, double def) const {
    const Value* v = props.get(n);
    return v ? v->num : def;
}

bool Lowering::boolean(const char* n, bool def) const {
    const Value* v = props.get(n);
    return v ? v->boolean : def;
}

void Lowering::positive(const char* n) const {
    const Value* v = props.get(n);
    if (v && v->num <= 0) el.sink_.report(DiagId::NonPositive, v->span, fmt::format("'{}' must be positive", n));
}

void Lowering::positive_vec(const char* n) const {
    const Value* v = props.get(n);
    if (v && std::any_of(v->items.begin(), v->items.end(), [](const Value& x) { return x.num <= 0; }))
        el.sink_.report(DiagId::NonPositive, v->span, fmt::format("every extent in '{}' must be positive", n));
}

graph::CompId Linking::find_comp(const std::string& n, Span span) const {
    auto it = scope.comps.find(n);
    if (it == scope.comps.end()) {
        std::vector<std::string> names;
        for (const auto& [k, v] : scope.comps) names.push_back(k);
        auto& d = el.sink_.report(DiagId::UnknownName, span, fmt::format("no component '{}' in this object", n));
        if (auto hint = closest_name(n, names); !hint.empty())
            d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
        return {};
    }
    return it->second;
}

const graph::Comp* Linking::find_of_table(const std::string& n, Span span, std::string_view table,
                                          const char* what) const {
    CompKind want = CompKind::Plugin;  // the kind on the kind table whose table it is
    for (const graph::KindDesc* k : graph::builtin_kinds())
        if (k->table == table) want = k->kind;
    assert(want != CompKind::Plugin);  // find<R> is asked for the table of a kind on the kind table
    const graph::CompId id = find_comp(n, span);
    if (!id.valid()) return nullptr;
    const auto& target = el.g_.comps[id];
    if (target.kind != want) {
        el.sink_.report(DiagId::WrongComponentKind, span,
                        fmt::format("'{}' is a {} component, but {} must be a {} component", n,
                                    graph::kind_word(target.kind), what, graph::kind_word(want)));
        return nullptr;
    }
    return &target;
}

const ast::Property* Linking::prop(const char* n) const {
    for (const auto& p : decl.properties)
        if (p.name.text == n) return &p;
    return nullptr;
}

std::string Linking::ref_name(const ast::Property& p) const {
    Value v = el.ev_.eval(*p.value, env);
    return v.kind == Value::Kind::Name ? v.str : std::string();
}

graph::SlotId Elaborator::add_slot(graph::CompId comp, std::string_view n, SlotType t, Dir dir, Span span) {
    return graph::add_slot(g_, comp, n, t, dir, src(span));
}

// The mode word, e.g. `physics b: kinematic`; the kind's default when absent or unknown.
std::string Elaborator::check_mode(const ast::ComponentDecl& c, const KindSpec& spec) {
    std::string mode = spec.modes.empty() ? "" : std::string(spec.modes.front());
    if (c.mode) {
        auto it = std::find(spec.modes.begin(), spec.modes.end(), c.mode->text);
        if (it == spec.modes.end()) {
            std::vector<std::string> words(spec.modes.begin(), spec.modes.end());
            auto& d = sink_.report(DiagId::UnknownName, c.mode->span,
                                   fmt::format("'{}' is not a mode of {}", c.mode->text, spec.word));
            d.notes.push_back({{}, words.empty() ? std::string("this kind takes no mode")
                                                 : fmt::format("modes: {}", fmt::join(words, ", "))});
        } else {
            mode = c.mode->text;
        }
    }
    return mode;
}

// Properties: known to the kind, set once, of the right type and dimension; a required one
// present. A wrong one is kept as None, so that the kind's lowering sees it as unset.
Props Elaborator::check_properties(const Scope& sc, const ast::ComponentDecl& c, const KindSpec& spec, const Env& env) {
    Props props;
    std::set<std::string> suggested;  // a misspelt property is not also reported missing
    for (const auto& p : c.properties) {
        const PropSpec* ps = find_prop(spec, p.name.text);
        if (!ps) {
            std::vector<std::string> names;
            for (const auto& q : spec.props) names.emplace_back(q.name);
            auto& d = sink_.report(DiagId::UnknownProperty, p.name.span,
                                   fmt::format("{} has no property '{}'", spec.word, p.name.text));
            if (auto hint = closest_name(p.name.text, names); !hint.empty()) {
                d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
                suggested.insert(hint);
            } else if (!names.empty()) {
                d.notes.push_back({{}, fmt::format("its properties: {}", fmt::join(names, ", "))});
            }
            continue;
        }
        if (props.has(p.name.text)) {
            auto& d = sink_.report(DiagId::DuplicateProperty, p.name.span,
                                   fmt::format("property '{}' is set twice", p.name.text));
            d.notes.push_back({props.values[p.name.text].first->name.span, "first set here"});
            continue;
        }
        Value v = ev_.eval(*p.value, env);
        std::string what = fmt::format("'{}'", p.name.text);
        bool ok = v.kind != Value::Kind::None;
        switch (ps->type) {
        case graph::ParamType::Number:
            // Limits take the dimension of the joint: checked when the kind is known.
            if (ps->name == "lower" || ps->name == "upper") ok = ok && ev_.expect_number(v, v.dim, what);
            else ok = ok && ev_.expect_number(v, ps->dim, what);
            break;
        case graph::ParamType::Vec3: ok = ok && ev_.expect_vec3(v, ps->dim, what); break;
        case graph::ParamType::Int: ok = ok && ev_.expect_int(v, what); break;
        case graph::ParamType::Bool: ok = ok && ev_.expect_bool(v, what); break;
        case graph::ParamType::String: ok = ok && ev_.expect_string(v, what); break;
        case graph::ParamType::StringList:
            if (ok && v.kind != Value::Kind::List) {
                sink_.report(DiagId::ValueTypeMismatch, v.span, fmt::format("{} must be a list of strings", what));
                ok = false;
            }
            for (const auto& it : v.items) ok = ok && ev_.expect_string(it, "an entry of " + what);
            break;
        case graph::ParamType::Type:
            if (ok && v.kind == Value::Kind::Name && v.str.find('.') == std::string::npos) {
                std::vector<std::string> known;
                for (const auto& [n, t] : types_) known.push_back(n);
                auto& d = sink_.report(DiagId::UnknownType, v.span, fmt::format("unknown object type '{}'", v.str));
                if (auto hint = closest_name(v.str, known); !hint.empty())
                    d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
                ok = false;
            } else if (ok && v.kind == Value::Kind::Type) {
                ok = find_type(v.str, sc.module, v.span, nullptr) != nullptr;  // declared in a module this one sees
            } else if (ok && v.kind != Value::Kind::Type) {
                sink_.report(DiagId::ValueTypeMismatch, v.span,
                             fmt::format("{} must name an object type, not {}", what, with_article(describe(v))));
                ok = false;
            }
            break;
        case graph::ParamType::CompRef:
            if (ok && v.kind != Value::Kind::Name) {
                sink_.report(DiagId::ValueTypeMismatch, v.span,
                             fmt::format("{} must name a component of this object, not {}", what, with_article(describe(v))));
                ok = false;
            }
            break;
        case graph::ParamType::Value: break;  // an entry's option only (graph::register_kind)
        }
        props.values[p.name.text] = {&p, ok ? v : Value{}};
    }
    for (const auto& ps : spec.props)
        if (ps.required && !props.has(std::string(ps.name)) && !suggested.count(std::string(ps.name)))
            sink_.report(DiagId::MissingProperty, c.name.span,
                         fmt::format("{} '{}' needs the property '{}' ({})", spec.word, c.name.text, ps.name, ps.doc));

    return props;
}

// Sub-blocks (shapes, animations, ...) and `on` only where the kind holds them.
void Elaborator::check_sub_blocks(const ast::ComponentDecl& c, const KindSpec& spec) {
    auto misplaced = [&](bool allowed, const auto& list, std::string_view what) {
        if (!allowed && !list.empty())
            sink_.report(DiagId::WrongComponentKind, list.front().span,
                         fmt::format("a {} component cannot hold {}", spec.word, what));
    };
    misplaced(spec.shapes, c.shapes, "shapes");
    misplaced(spec.animations, c.animations, "animations");
    misplaced(spec.variants, c.variants, "variants");
    misplaced(spec.places, c.places, "places");
    misplaced(spec.places, c.transitions, "transitions");
    misplaced(spec.routes, c.routes, "routes");
    misplaced(spec.children, c.children, "child components");
    misplaced(spec.plugin && !spec.plugin->entries.empty(), c.entries, "entries");
    if (c.on && !spec.on)
        sink_.report(DiagId::WrongComponentKind, c.on->span,
                     fmt::format("a {} component cannot be attached with 'on'", spec.word));
}

graph::CompId Elaborator::make_component(Scope& sc, const ast::ComponentDecl& c, const Env& env, graph::CompId parent,
                                         const std::string& prefix) {
    const KindSpec* spec = find_kind(c.kind.text);
    if (!spec) {
        auto& d = sink_.report(DiagId::UnknownComponentKind, c.kind.span,
                               fmt::format("unknown component kind '{}'", c.kind.text));
        if (auto hint = closest_name(c.kind.text, kind_words()); !hint.empty())
            d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
        return {};
    }
    std::string cname = prefix.empty() ? c.name.text : prefix + "." + c.name.text;
    if (spec->plugin && !spec->plugin->inside.empty() && !inside_plugin(sc, prefix, spec->plugin->inside)) {
        sink_.report(DiagId::WrongComponentKind, c.kind.span,
                     fmt::format("a {} is written inside a {} component", spec->word, spec->plugin->inside));
        return {};
    }
    if (!declare(sc, cname, c.name.span)) return {};

    const std::string mode = check_mode(c, *spec);
    const Props props = check_properties(sc, c, *spec, env);

    check_sub_blocks(c, *spec);

    const graph::CompId comp = graph::add_comp(g_, sc.do_id, spec->kind, cname, src(c.name.span));
    if (spec->plugin)  // a plugin's slots are its descriptor's, not a fixed table's
        for (const graph::SlotSpec& s : spec->plugin->slots) graph::add_slot(g_, comp, s.name, s.type, s.dir, src(c.name.span));
    sc.comps[cname] = comp;
    comp_spans_[comp] = c.name.span;
    if (names_ && !c.name.text.empty()) {
        // Its name, and the places, transitions, animations and variants it declares: each
        // a slot of the top component (child graphics are its slots "child", "child.anim").
        const std::string top = cname.substr(0, cname.find('.'));
        const Span owner = comp_spans_[sc.comps[top]];
        const std::string base = top == cname ? "" : cname.substr(top.size() + 1);
        auto slot = [&](const std::string& n) { return base.empty() ? n : base + "." + n; };
        if (base.empty()) names_->declare(c.name.span);
        else names_->declare(c.name.span, owner, base);
        for (const auto& p : c.places) names_->declare(p.name.span, owner, slot(p.name.text));
        for (const auto& t : c.transitions) names_->declare(t.name.span, owner, slot(t.name.text));
        for (const auto& a : c.animations) names_->declare(a.name.span, owner, slot(a.name.text));
        for (const auto& v : c.variants) names_->declare(v.name.span, owner, slot(v.name.text));
    }

    const Frame frame = sc.frame * placement(c.placement ? &*c.placement : nullptr, env);
    Lowering lw{*this, sc, c, env, *spec, props, mode, comp, g_.comps[comp].slot_adr, frame, parent};
    lower(lw);

    // A plugin kind's own components (a panel's buttons): named parent.child, each of a
    // kind the holder takes.
    if (spec->plugin && !spec->plugin->holds.empty()) {
        for (const auto& child : c.children) {
            const auto& holds = spec->plugin->holds;
            if (std::find(holds.begin(), holds.end(), child.kind.text) == holds.end()) {
                std::vector<std::string> words(holds.begin(), holds.end());
                auto& d = sink_.report(DiagId::WrongComponentKind, child.kind.span,
                                       fmt::format("a {} holds no '{}'", spec->word, child.kind.text));
                if (auto hint = closest_name(child.kind.text, words); !hint.empty())
                    d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
                else
                    d.notes.push_back({{}, fmt::format("it holds: {}", fmt::join(words, ", "))});
                continue;
            }
            make_component(sc, child, env, {}, cname);
        }
        return comp;
    }
    // Children of its own kind (graph::kChildren: child graphics): their own components, named
    // parent.child, posed relative to it.
    for (const auto& child : c.children) {
        if (!spec->children) break;  // reported above: this kind holds no children
        if (child.kind.text != spec->word) {
            sink_.report(DiagId::WrongComponentKind, child.kind.span,
                         fmt::format("only {0} can hold child {0}", spec->word));
            continue;
        }
        Frame saved = sc.frame;
        sc.frame = frame;
        make_component(sc, child, env, comp, cname);
        sc.frame = saved;
    }
    return comp;
}

// Whether `holder` (a component of this object, "" for none) is of the plugin kind `word`.
bool Elaborator::inside_plugin(const Scope& sc, const std::string& holder, std::string_view word) const {
    auto it = sc.comps.find(holder);
    if (holder.empty() || it == sc.comps.end()) return false;
    const graph::KindDesc* d = graph::plugin_of(g_, it->second);
    return d && d->word == word;
}

// References between components of one DO, resolved once they all exist.
void Elaborator::link_component(Scope& sc, graph::CompId comp, const ast::ComponentDecl& c, const Env& env) {
    std::string on;
    if (c.on) {
        for (const auto& seg : c.on->segs) on += (on.empty() ? "" : ".") + seg.name.text;
        name_component(sc, c.on->segs, 0, c.on->segs.size());
    }
    Linking lk{*this, sc, c, env, comp, g_.comps[comp], on};
    link(lk);
}

}  // namespace plant::sema
