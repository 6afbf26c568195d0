// Lowering a component of a plugin kind (graph/plugin.h). The generic part has checked its
// properties against the descriptor's parameters (type, dimension, required) and added
// the descriptor's slots; what is left is storing the parameters in the declared order.
#include "sema/kinds/lowering.h"

namespace plant::sema {

void lower_plugin(Lowering& lw) {
    graph::Graph& g = lw.el.g_;
    const graph::KindDesc& kind = *lw.spec.plugin;
    graph::Plugin rec;
    rec.comp = lw.comp;
    rec.kind = lw.el.name(kind.word);
    rec.param_adr = static_cast<int32_t>(g.plugin_params.size());
    rec.param_num = static_cast<int32_t>(kind.params.size());
    for (const graph::ParamSpec& ps : kind.params) {
        graph::PluginParam p{ps.default_num, graph::Name{}};
        const Value* v = lw.props.get(std::string(ps.name));
        if (ps.type == graph::ParamType::String) p.text = lw.el.name(v ? std::string_view(v->str) : std::string_view());
        else if (ps.type == graph::ParamType::Bool && v) p.num = v->boolean ? 1 : 0;
        else if (v) p.num = v->num;
        g.plugin_params.push_back(p);
    }
    g.plugins.push_back(rec);
    lw.set_detail(g.plugins.size());
}

}  // namespace plant::sema
