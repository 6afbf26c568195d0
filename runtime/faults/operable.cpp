#include "faults/operable.h"

#include "engine/plugin.h"

#include <algorithm>
#include <array>
#include <cstdlib>

namespace plant::faults {
namespace {
// Named apart from kind.cpp's (the unity build compiles both in one file).

constexpr std::string_view kOperableWord = "operable";
enum OperableOption : int { label_option };
constexpr std::array kOperableOptions = {
    graph::ParamSpec{"label", graph::ParamType::String, "", false, 0,
                     "what the trainee's list of controls calls it; not given: its path"},
};
constexpr int32_t kOperableMaxKey = 9999;
constexpr std::array kOperableEntries = {
    graph::EntrySpec{"input", "an input a trainee's page may fire or set; the key: its place in the page's list",
                     graph::Dir::In, {}, kOperableOptions, kOperableMaxKey, graph::EntryKey::Index, false},
};
constexpr graph::KindDesc kOperableDesc{kOperableWord,
                                "the inputs a trainee may operate in `plant serve` (docs/viewer.md, \"Roles\")",
                                {},
                                {},
                                kOperableEntries};

}  // namespace

void register_operable_kind() {
    static constexpr engine::KindBehaviour kOperableBehaviour{};
    static const bool registered = engine::register_plugin(kOperableDesc, kOperableBehaviour);
    if (!registered) std::abort();  // only a second kind named `operable` could refuse it
}

std::vector<Operable> operable_inputs(const graph::Graph& g) {
    std::vector<Operable> out;
    for (const graph::Plugin& p : g.plugins) {
        if (g.str(p.kind) != kOperableWord) continue;
        for (int32_t k = 0; k < p.entry_num; ++k) {
            const graph::PluginEntry& e = g.plugin_entries[p.entry_adr + k];
            Operable o;
            o.key = e.key;
            for (const graph::PluginEntrySlot& s : g.plugin_entry_slots.slice(e.slot_adr, e.slot_num)) o.slots.push_back(s.v);
            if (label_option < e.param_num)
                if (const graph::Name t = g.plugin_params[e.param_adr + label_option].text; t.id >= 0)
                    o.label = std::string(g.str(t));
            out.push_back(std::move(o));
        }
    }
    std::stable_sort(out.begin(), out.end(), [](const Operable& a, const Operable& b) { return a.key < b.key; });
    return out;
}

}  // namespace plant::faults
