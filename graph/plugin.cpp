#include "plugin.h"

#include <array>
#include <string>

namespace plant::graph {
namespace {

// The rows of the kinds on the kind table, one per kind in kinds/list.h (kinds/NAME/kind.cpp).
#define PLANT_KIND_ROW(word, WORD) &kinds::word::desc,
const std::array kBuiltins = {PLANT_KINDS(PLANT_KIND_ROW)};
#undef PLANT_KIND_ROW

std::vector<const KindDesc*>& registry() {
    static std::vector<const KindDesc*> r;
    return r;
}

template <class T>
bool names_unique(std::span<const T> items) {
    for (size_t i = 0; i < items.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (items[i].name == items[j].name) return false;
    return true;
}

}  // namespace

std::span<const KindDesc* const> builtin_kinds() { return kBuiltins; }

const KindDesc* builtin_kind(CompKind kind) {
    static const auto by_kind = [] {
        std::array<const KindDesc*, size_t(CompKind::Plugin) + 1> a{};
        for (const KindDesc* d : kBuiltins) a[size_t(d->kind)] = d;
        return a;
    }();
    return kind == CompKind::Plugin ? nullptr : by_kind[size_t(kind)];
}

std::string_view kind_word(CompKind kind) {
    const KindDesc* d = builtin_kind(kind);
    return d ? d->word : word(kind);
}

bool register_kind(const KindDesc& desc) {
    CompKind builtin{};
    // The words plant files use for the built-in kinds (their rows'), and the graph's.
    for (const KindDesc* d : kBuiltins)
        if (d->word == desc.word) return false;
    if (desc.word.empty() || parse_word(desc.word, builtin) || find_plugin(desc.word) || !names_unique(desc.slots) ||
        !names_unique(desc.params))
        return false;
    if (desc.kind != CompKind::Plugin) return false;  // a kind on the kind table is in kinds/list.h
    if (desc.blocks != 0) return false;  // the built-in sub-blocks: its lowering would not read them
    if (desc.check_tables || !desc.unused_output.empty() || desc.own_form || desc.bare_slot >= 0 || !desc.noun.empty() ||
        desc.idle_output >= 0)
        return false;  // read for table kinds only
    for (const ParamSpec& p : desc.params)  // a component's parameter has no slot to take its type from
        if (p.type == ParamType::Value) return false;
    for (size_t i = 0; i < desc.entries.size(); ++i) {
        if (!names_unique(desc.entries[i].options) || desc.entries[i].max_key < 0) return false;
        for (const ParamSpec& o : desc.entries[i].options)
            if (o.type > ParamType::Value) return false;
        for (size_t j = 0; j < i; ++j)
            if (desc.entries[i].word == desc.entries[j].word) return false;
    }
    registry().push_back(&desc);
    return true;
}

const KindDesc* find_plugin(std::string_view word) {
    for (const KindDesc* d : registry())
        if (d->word == word) return d;
    return nullptr;
}

std::span<const KindDesc* const> plugins() { return registry(); }

const KindDesc* plugin_of(const Graph& g, CompId comp) {
    if (!g.comps.contains(comp)) return nullptr;
    const Comp& c = g.comps[comp];
    const PluginId plugin = detail_of<Plugin>(c);
    if (c.kind != CompKind::Plugin || !g.plugins.contains(plugin)) return nullptr;
    return find_plugin(g.str(g.plugins[plugin].kind));
}

std::span<const SlotSpec> slots_of(const Graph& g, CompId comp) {
    if (const KindDesc* d = plugin_of(g, comp)) return d->slots;
    if (g.comps.contains(comp)) return fixed_slots(g.comps[comp].kind);
    return {};
}

const EntrySpec* find_entry(const KindDesc& desc, std::string_view word) {
    for (const EntrySpec& e : desc.entries)
        if (e.word == word) return &e;
    return nullptr;
}

std::string_view word(ParamType t) {
    switch (t) {
    case ParamType::Number: return "number";
    case ParamType::Int: return "int";
    case ParamType::Bool: return "bool";
    case ParamType::String: return "string";
    case ParamType::Value: return "value";
    case ParamType::Vec3: return "vec3";
    case ParamType::StringList: return "string list";
    case ParamType::Type: return "type";
    case ParamType::CompRef: return "component reference";
    }
    return "?";
}

}  // namespace plant::graph
