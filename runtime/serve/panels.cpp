#include "serve/panels.h"

#include <nlohmann/json.hpp>

#include <array>
#include <string>
#include <string_view>

namespace plant::view {
namespace {

// An element kind, the output the page shows it by, and its parameters in the kind's order
// (runtime/panel/kind.cpp).
struct PanelElement {
    std::string_view kind, shown;
    std::array<std::string_view, 4> params;
};
constexpr std::array kPanelElements = {
    PanelElement{"button", "down", {"label", "color"}},
    PanelElement{"estop", "engaged", {"label"}},
    PanelElement{"selector", "position", {"label", "positions", "names", "initial"}},
    PanelElement{"lamp", "state", {"label", "color"}},
    PanelElement{"display", "value", {"label", "unit", "digits"}},
};

const PanelElement* panel_element(std::string_view kind) {
    for (const PanelElement& e : kPanelElements)
        if (e.kind == kind) return &e;
    return nullptr;
}

graph::SlotId panel_slot(const graph::Graph& g, const graph::Comp& c, std::string_view name) {
    for (graph::SlotId s : graph::children(c.slot_adr, c.slot_num))
        if (g.str(g.slots[s].name) == name) return s;
    return {};
}

// Calls f(plugin row, element or nullptr for the panel) over every panel and its elements.
template <class F>
void each_panel_row(const graph::Graph& g, F f) {
    for (graph::PluginId p : graph::ids_of(g.plugins)) {
        const std::string_view kind = g.str(g.plugins[p].kind);
        if (kind == "panel") f(p, nullptr);
        else if (const PanelElement* e = panel_element(kind)) f(p, e);
    }
}

}  // namespace

nlohmann::json panels_json(const graph::Graph& g) {
    nlohmann::json panels = nlohmann::json::array();
    each_panel_row(g, [&](graph::PluginId p, const PanelElement* e) {
        const graph::Plugin& pl = g.plugins[p];
        const graph::CompId comp = pl.comp;
        auto param = [&](int k) -> const graph::PluginParam& { return g.plugin_params[pl.param_adr + k]; };
        if (!e) {
            panels.push_back({{"path", g.comp_path(comp)},
                              {"title", pl.param_num > 0 ? std::string(g.str(param(0).text)) : std::string()},
                              {"elements", nlohmann::json::array()}});
            // Placed in the scene too (`panel ops at (…)`): its world pose, px py pz qx qy qz qw.
            if (pl.placed)
                panels.back()["pose"] = {pl.pose.p[0], pl.pose.p[1], pl.pose.p[2], pl.pose.q[0],
                                         pl.pose.q[1], pl.pose.q[2], pl.pose.q[3]};
            return;
        }
        if (panels.empty()) return;  // an element always follows its panel (the compiler, the loader's check)
        const std::string path = g.comp_path(comp);
        nlohmann::json el{{"kind", e->kind}, {"path", path}, {"name", path.substr(path.rfind('.') + 1)}};
        for (int k = 0; k < pl.param_num && k < int(e->params.size()) && !e->params[size_t(k)].empty(); ++k) {
            const std::string key(e->params[size_t(k)]);
            if (param(k).text.id >= 0) el[key] = std::string(g.str(param(k).text));
            else if (key == "label" || key == "color" || key == "names" || key == "unit") el[key] = "";
            else el[key] = param(k).num;
        }
        panels.back()["elements"].push_back(std::move(el));
    });
    return panels;
}

nlohmann::json panel_values(const engine::Engine& e) {
    const graph::Graph& g = e.graph();
    nlohmann::json values = nlohmann::json::array();
    each_panel_row(g, [&](graph::PluginId p, const PanelElement* el) {
        if (!el) return;
        const graph::SlotId s = panel_slot(g, g.comps[g.plugins[p].comp], el->shown);
        values.push_back(s.valid() ? e.value(s)[0] : 0.0);
    });
    return values;
}

}  // namespace plant::view
