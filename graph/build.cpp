#include "build.h"

#include "kinds.h"

#include <cassert>

namespace plant::graph {

DoId add_do(Graph& g, std::string_view path, DoId parent, DoTypeId type, const Pose& pose, Src src) {
    const auto id = next_id(g.dos);
    Do d;
    d.path = g.intern(path);
    d.parent = parent;
    d.type = type;
    d.ordinal = d.type.valid() ? g[d.type].instance_num++ : 0;
    d.comp_adr = next_adr(g.comps);
    d.comp_num = 0;
    d.pool = CompId{};
    d.pose = pose;
    d.src = src;
    g.dos.push_back(d);
    return id;
}

CompId add_comp(Graph& g, DoId owner, CompKind kind, std::string_view name, Src src) {
    const auto id = next_id(g.comps);
    Comp c;
    c.name = g.intern(name);
    c.kind = kind;
    c.owner = owner;
    c.slot_adr = next_adr(g.slots);
    c.slot_num = 0;
    c.src = src;
    g.comps.push_back(c);
    Do& d = g[c.owner];
    if (d.comp_num == 0) d.comp_adr = Adr<Comp>(id.v);
    d.comp_num = id.v + 1 - d.comp_adr.v;
    for (const SlotSpec& s : fixed_slots(kind)) add_slot(g, id, s.name, s.type, s.dir, src);
    return id;
}

SlotId add_slot(Graph& g, CompId comp, std::string_view name, SlotType type, Dir dir, Src src) {
    const auto id = next_id(g.slots);
    Comp& c = g[comp];
    assert(c.slot_adr + c.slot_num == id && "a component's slots are contiguous");
    Slot s;
    s.name = g.intern(name);
    s.type = type;
    s.dir = dir;
    s.comp = comp;
    if (const int w = slot_width(type); w > 0) {
        s.value_adr = next_adr(g.values);
        g.values.resize(g.values.size() + w, Value{0.0});
        if (type == SlotType::Ref || type == SlotType::String) g.values.back().v = -1;
        if (type == SlotType::Quat || type == SlotType::Pose) g.values.back().v = 1;
    }
    s.src = src;
    g.slots.push_back(s);
    ++c.slot_num;
    return id;
}

FlowId add_flow(Graph& g, SlotId from, SlotId to, Cond cond, bool once, AccessId from_access, AccessId to_access,
                Src src) {
    const auto id = next_id(g.flows);
    Flow f;
    f.from = from;
    f.to = to;
    f.from_access = from_access;
    f.to_access = to_access;
    f.cond = cond;
    f.once = once;
    f.src = src;
    g.flows.push_back(f);
    return id;
}

double& slot_value(Graph& g, SlotId slot) {
    return g.values[g[slot].value_adr.first()].v;
}

}  // namespace plant::graph
