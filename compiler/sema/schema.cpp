#include "sema/schema.h"

#include <algorithm>
#include <deque>
#include <mutex>
#include <utility>

namespace plant::sema {
namespace {

using graph::CompKind;
using T = graph::ParamType;
using P = graph::ParamSpec;

// Parameters as the compiler checks them: each with the dimension of its unit.
std::vector<PropSpec> props_of(std::span<const graph::ParamSpec> params) {
    std::vector<PropSpec> out;
    for (const graph::ParamSpec& p : params) out.push_back({p.name, p.type, param_dim(p), p.required, p.doc});
    return out;
}

// A kind's row as the compiler's spec: its parameters become properties, so the generic
// checks of make_component apply to them.
KindSpec kind_spec(const graph::KindDesc& d) {
    KindSpec k{d.word, d.kind, {d.modes.begin(), d.modes.end()}, props_of(d.params)};
    k.doc = d.doc;
    k.shapes = d.blocks & graph::kShapes;
    k.animations = d.blocks & graph::kAnimations;
    k.variants = d.blocks & graph::kVariants;
    k.places = d.blocks & graph::kPlaces;
    k.routes = d.blocks & graph::kRoutes;
    k.children = !d.holds.empty() || (d.blocks & graph::kChildren);  // a panel's elements, child graphics
    k.on = d.on;
    if (d.kind == CompKind::Plugin) k.plugin = &d;
    return k;
}

// Every built-in kind is a row of the kind table; their specs in CompKind order. A kind
// declared by a form of its own (a connector, `logic go = ...`) is no component word.
std::vector<KindSpec> make_kinds() {
    std::vector<KindSpec> k;
    for (const graph::KindDesc* row : graph::builtin_kinds())
        if (!row->own_form) k.push_back(kind_spec(*row));
    std::stable_sort(k.begin(), k.end(), [](const KindSpec& a, const KindSpec& b) { return a.kind < b.kind; });
    return k;
}

const std::vector<KindSpec>& kinds() {
    static const std::vector<KindSpec> k = make_kinds();
    return k;
}

}  // namespace

const KindSpec* find_kind(std::string_view word) {
    for (const auto& k : kinds())
        if (k.word == word) return &k;
    // Plugins register before any compile; their specs are made once, on first use.
    static std::deque<KindSpec> plugin_specs;  // a deque: the specs handed out stay put
    static std::mutex m;                       // compiles may run on several threads (sweeps)
    std::lock_guard lock(m);
    for (const auto& k : plugin_specs)
        if (k.word == word) return &k;
    if (const graph::KindDesc* d = graph::find_plugin(word)) return &plugin_specs.emplace_back(kind_spec(*d));
    return nullptr;
}

std::vector<std::string> kind_words() {
    std::vector<std::string> out;
    for (const auto& k : kinds()) out.emplace_back(k.word);
    for (const graph::KindDesc* d : graph::plugins()) out.emplace_back(d->word);
    return out;
}

units::Dim param_dim(const graph::ParamSpec& p) {
    if ((p.type != graph::ParamType::Number && p.type != graph::ParamType::Vec3) || p.unit.empty()) return {};
    auto u = units::parse_unit(p.unit);
    return u ? u->dim : units::Dim{};
}

std::span<const graph::SlotSpec> kind_slots(const KindSpec& k) {
    return k.plugin ? k.plugin->slots : graph::fixed_slots(k.kind);
}

const PropSpec* find_prop(const KindSpec& k, std::string_view name) {
    for (const auto& p : k.props)
        if (p.name == name) return &p;
    return nullptr;
}

}  // namespace plant::sema
