// Lowering a component of a plugin kind (graph/plugin.h). make_component has checked its
// properties against the descriptor's parameters (type, dimension, required) as for any
// kind; what is left is storing them in the descriptor's order.
#include "sema/elaborator.h"

namespace plant::sema {

void Elaborator::lower_plugin(int32_t comp, const graph::KindDesc& kind,
                              const std::map<std::string, std::pair<const ast::Property*, Value>>& props) {
    graph::Plugin rec;
    rec.comp = comp;
    rec.kind = name(kind.word);
    rec.param_adr = static_cast<int32_t>(g_.plugin_params.size());
    rec.param_num = static_cast<int32_t>(kind.params.size());
    for (const graph::ParamSpec& ps : kind.params) {
        graph::PluginParam p{ps.default_num, graph::Name{}};
        auto it = props.find(std::string(ps.name));
        const Value* v = it == props.end() || it->second.second.kind == Value::Kind::None ? nullptr : &it->second.second;
        if (ps.type == graph::ParamType::String) p.text = name(v ? std::string_view(v->str) : std::string_view());
        else if (ps.type == graph::ParamType::Bool && v) p.num = v->boolean ? 1 : 0;
        else if (v) p.num = v->num;
        g_.plugin_params.push_back(p);
    }
    g_.plugins.push_back(rec);
    g_.comps[static_cast<size_t>(comp)].detail = static_cast<int32_t>(g_.plugins.size()) - 1;
}

}  // namespace plant::sema
