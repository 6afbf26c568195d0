#include "build.h"

#include "kinds.h"

#include <cassert>

namespace plant::graph {

int32_t add_do(Graph& g, std::string_view path, int32_t parent, int32_t type, const Pose& pose, Src src) {
    Do d;
    d.path = g.intern(path);
    d.parent = parent;
    d.type = type;
    d.ordinal = type >= 0 ? g.do_types[static_cast<size_t>(type)].instance_num++ : 0;
    d.comp_adr = static_cast<int32_t>(g.comps.size());
    d.comp_num = 0;
    d.pool = -1;
    d.pose = pose;
    d.src = src;
    g.dos.push_back(d);
    return static_cast<int32_t>(g.dos.size()) - 1;
}

int32_t add_comp(Graph& g, int32_t owner, CompKind kind, std::string_view name, Src src) {
    const auto id = static_cast<int32_t>(g.comps.size());
    Comp c;
    c.name = g.intern(name);
    c.kind = kind;
    c.owner = owner;
    c.slot_adr = static_cast<int32_t>(g.slots.size());
    c.slot_num = 0;
    c.detail = -1;
    c.src = src;
    g.comps.push_back(c);
    Do& d = g.dos[static_cast<size_t>(owner)];
    if (d.comp_num == 0) d.comp_adr = id;
    d.comp_num = id + 1 - d.comp_adr;
    for (const SlotSpec& s : fixed_slots(kind)) add_slot(g, id, s.name, s.type, s.dir, src);
    return id;
}

int32_t add_slot(Graph& g, int32_t comp, std::string_view name, SlotType type, Dir dir, Src src) {
    Comp& c = g.comps[static_cast<size_t>(comp)];
    assert(c.slot_adr + c.slot_num == static_cast<int32_t>(g.slots.size()) && "a component's slots are contiguous");
    Slot s;
    s.name = g.intern(name);
    s.type = type;
    s.dir = dir;
    s.comp = comp;
    s.value_adr = -1;
    if (const int w = slot_width(type); w > 0) {
        s.value_adr = static_cast<int32_t>(g.values.size());
        g.values.resize(g.values.size() + static_cast<size_t>(w), Value{0.0});
        if (type == SlotType::Ref || type == SlotType::String) g.values.back().v = -1;
        if (type == SlotType::Quat || type == SlotType::Pose) g.values.back().v = 1;
    }
    s.src = src;
    g.slots.push_back(s);
    ++c.slot_num;
    return static_cast<int32_t>(g.slots.size()) - 1;
}

int32_t add_flow(Graph& g, int32_t from, int32_t to, Cond cond, bool once, int32_t from_access, int32_t to_access,
                 Src src) {
    Flow f;
    f.from = from;
    f.to = to;
    f.from_access = from_access;
    f.to_access = to_access;
    f.cond = cond;
    f.once = once;
    f.src = src;
    g.flows.push_back(f);
    return static_cast<int32_t>(g.flows.size()) - 1;
}

double& slot_value(Graph& g, int32_t slot) {
    return g.values[static_cast<size_t>(g.slots[static_cast<size_t>(slot)].value_adr)].v;
}

}  // namespace plant::graph
