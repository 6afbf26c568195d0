// Objects that come and go, what the kinds that move them share: an object's bar code (a
// source hands it out, an exit reports it) and what an exit (kinds/exit/run.cpp) or a
// trainee's hand does to take an object out of the world: back into its source's pool
// (kinds/source/).
#include "engine/runtime.h"

#include "graph/kinds.h"

namespace plant::engine {

using namespace plant::graph;

// The bar code of an object: its label's text, else its path.
double object_id(Runtime& r, DoId d) {
    const Id<Label> l = r.tab.do_label[d];
    if (l.valid()) return *r.val(r.comp_slot(r.g.labels[l].comp, labelslot::value));
    return r.g.dos[d].path.id;
}

// The object out of the world, back into its source's pool when it is a pooled one (the
// whole pooled object, also when `obj` is a part of it); its root, or -1 when it was not in
// the world.
DoId take_object(Runtime& r, DoId obj) {
    DoId root = obj;
    for (DoId d = obj; d.valid(); d = r.g.dos[d].parent)
        if (r.tab.do_source[d].valid()) {
            root = d;
            break;
        }
    bool any = false;
    for (BodyId b : r.tab.do_bodies[root])
        if (r.phys.in_world(b)) {
            take_body_out(r, b);
            any = true;
        }
    if (!any) return DoId{};
    if (const SourceId src = r.tab.do_source[root]; src.valid()) {
        SourceState& ss = r.st.sources[src];
        const int32_t num = r.g.sources[src].pool_num;
        r.st.pool_ring[ss.ring_adr + (ss.head + ss.free) % num] = root;
        ss.free++;
    }
    return root;
}

}  // namespace plant::engine
