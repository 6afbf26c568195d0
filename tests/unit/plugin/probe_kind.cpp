#include "probe_kind.h"

#include "engine/plugin.h"

#include <array>

namespace plant::test {
namespace {

using graph::Dir;
using graph::ParamType;
using graph::SlotSpec;
using graph::SlotType;

enum Slot : int { z, names, chars, watches_timer, typed };
constexpr std::array kSlots = {
    SlotSpec{"z", SlotType::Real, Dir::Out, "the offset's z, m"},
    SlotSpec{"names", SlotType::Int, Dir::Out, "how many names it was given"},
    SlotSpec{"chars", SlotType::Int, Dir::Out, "the characters of its names and label"},
    SlotSpec{"watches_timer", SlotType::Bool, Dir::Out, "whether `watch` names a timer"},
    SlotSpec{"typed", SlotType::Bool, Dir::Out, "whether `object` names the type Bottle"},
};
enum Param : int { offset, names_p, object, watch, label };
constexpr std::array kParams = {
    graph::ParamSpec{"offset", ParamType::Vec3, "m", false, 0, "a displacement; (0, 0, 0) when not given"},
    graph::ParamSpec{"names", ParamType::StringList, "", false, 0, "names; none when not given"},
    graph::ParamSpec{"object", ParamType::Type, "", false, 0, "an object type"},
    graph::ParamSpec{"watch", ParamType::CompRef, "", true, 0, "a component of the same object"},
    graph::ParamSpec{"label", ParamType::String, "", false, 0, "a text"},
};
constexpr graph::KindDesc kDesc{"probe", "reports its parameters (a kind of the tests)", kSlots, kParams};

void start_probe(engine::PluginCtx& c) {
    const graph::Graph& g = c.graph();
    c.emit(z, c.param_vec3(offset)[2]);
    c.emit(names, c.param_list_size(names_p));
    size_t n = c.param_text(label).size();
    for (int k = 0; k < c.param_list_size(names_p); ++k) n += c.param_list(names_p, k).size();
    c.emit(chars, double(n));
    const graph::CompId w = c.param_comp(watch);
    c.emit(watches_timer, w.valid() && g.comps[w].kind == graph::CompKind::Timer ? 1 : 0);
    const graph::DoTypeId t = c.param_type(object);
    c.emit(typed, t.valid() && g.str(g.do_types[t].name) == "Bottle" ? 1 : 0);
}
constexpr engine::KindBehaviour kBehaviour{0, start_probe};

}  // namespace

void register_probe_kind() {
    static const bool registered = engine::register_plugin(kDesc, kBehaviour);
    (void)registered;
}

}  // namespace plant::test
