// The source's behaviour: its `object` starts empty; in phase 5 it issues an object from
// its pool on `issue`, and, once every component acted, a source with a rate issues when
// its next issue is due. Its pools (State::sources, pool_ring) are shared with what takes
// objects out of the world (engine/objects.cpp: take_object).
#include "engine/plugin.h"
#include "engine/runtime.h"

#include "graph/kinds.h"

#include <memory>
#include <vector>

namespace plant::kinds::source {

using namespace plant::engine;
using graph::CompKind;
namespace slot = plant::graph::sourceslot;

namespace {

struct Sources : KindData {
    std::vector<graph::SourceId> rated;  // the rows of `sources` with a rate, in order
};

std::unique_ptr<KindData> make_state(const graph::Graph& g) {
    auto s = std::make_unique<Sources>();
    for (graph::SourceId i : ids_of(g.sources))
        if (g.sources[i].rate > 0) s->rated.push_back(i);
    return s;
}

// The next free object of the pool to the source's pose, as it was built (every part moves
// as the DO moves), its bar code handed out; counted in Warnings::pool_empty when none is.
void issue(Runtime& r, graph::SourceId src) {
    SourceState& ss = r.st.sources[src];
    const graph::Source& S = r.g.sources[src];
    if (ss.free == 0) {
        r.st.warn.pool_empty++;
        return;
    }
    const graph::DoId d = r.st.pool_ring[ss.ring_adr + ss.head];
    ss.head = (ss.head + 1) % S.pool_num;
    ss.free--;
    // Pooled objects keep their shape: every part moves as the DO moves to the source.
    const graph::Pose to = pmul(S.pose, pinv(r.g.dos[d].pose));
    for (graph::BodyId b : r.tab.do_bodies[d]) {
        const graph::Body& body = r.g.bodies[b];
        r.phys.set_dynamics(b, body.dynamics);
        r.phys.set_collision(b, body.collision);
        r.phys.place(b, to_bt(pmul(to, body.pose)));
        btRigidBody& rb = r.phys.write(b);
        rb.setLinearVelocity(btVector3(0, 0, 0));
        rb.setAngularVelocity(btVector3(0, 0, 0));
        rb.clearForces();
        r.st.gone[b] = 0;
        r.st.ride_field[b] = graph::FieldId{};  // a new life: where it rides starts again (Loss)
        r.st.ride_step[b] = -1;
        r.phys.insert(b);
    }
    for (graph::GraphicsId i : r.tab.do_graphics[d]) {
        r.st.graphics[i].base = pmul(to, r.g.graphics[i].pose);
        r.st.graphics[i].base_fresh = false;
        r.st.graphics_placed[i] = 1;
    }
    const double code = S.id_num > 0 ? r.g.ids[S.id_adr + ss.issued % S.id_num].v.id : r.g.dos[d].path.id;
    if (const graph::Id<graph::Label> l = r.tab.do_label[d]; l.valid())
        r.emit(r.comp_slot(r.g.labels[l].comp, graph::labelslot::value), code);
    ss.issued++;
    const graph::Adr<graph::Slot> s0 = r.g.comps[S.comp].slot_adr;
    r.activate(s0 + slot::issued);
    r.emit(s0 + slot::object, d.v);
    r.emit(s0 + slot::id, code);
    r.emit(s0 + slot::issued_count, double(ss.issued));
}

void start_all(Runtime& r) {
    for (const graph::Source& s : r.g.sources) *r.val(r.comp_slot(s.comp, slot::object)) = -1;
}

void act_one(Runtime& r, const graph::Comp& c) {
    if (r.st.act[c.slot_adr + slot::issue]) issue(r, graph::detail_of<graph::Source>(c));
}

void act_all(Runtime& r) {
    for (graph::SourceId src : kind_data<Sources>(r.st, CompKind::Source).rated) {
        SourceState& ss = r.st.sources[src];
        if (r.st.time + 1e-9 < ss.next_issue) continue;
        ss.next_issue += 1.0 / r.g.sources[src].rate;
        issue(r, src);
    }
}

}  // namespace

constexpr KindBehaviour behaviour{
    .make_state = make_state, .start_all = start_all, .act_one = act_one, .act_all = act_all};

}  // namespace plant::kinds::source
