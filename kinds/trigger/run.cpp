// The trigger's behaviour. An object is inside while the bounding box of one of its bodies
// (declared dynamic, in the world, gripped or not) overlaps the trigger's box. The object
// reported is the body's DO or, with a filter, the nearest DO above it whose type is the
// filter. Each trigger keeps the sorted list of objects inside; comparing it with the
// previous step's list gives on_enter / on_leave, for any number of objects at once. What
// it finds (State::triggers, inside) is read by the gripper and the exit, and by
// Engine::trigger_occupied; its `object` starts empty.
#include "engine/plugin.h"
#include "engine/runtime.h"
#include "engine/workers.h"

#include "graph/kinds.h"

#include <algorithm>
#include <cmath>
#include <span>

namespace plant::kinds::trigger {

using namespace plant::engine;
using graph::DoId, graph::DoTypeId, graph::TriggerId;
namespace slot = plant::graph::triggerslot;

namespace {

DoId object_of(const graph::Graph& g, DoId d, DoTypeId filter) {
    if (!filter.valid()) return d;
    for (size_t guard = 0; d.valid() && guard <= g.dos.size(); ++guard, d = g.dos[d].parent)
        if (g.dos[d].type == filter) return d;
    return DoId{};
}

// Separating axes of an axis-aligned box and an oriented one: the three world axes
// and the box's three. Conservative (edge-edge axes skipped), exact for aligned boxes.
bool overlaps(const btVector3& lo, const btVector3& hi, const btTransform& box, const btVector3& h) {
    const btMatrix3x3& R = box.getBasis();
    const btVector3 a = (lo + hi) * btScalar(0.5), e = (hi - lo) * btScalar(0.5);
    const btVector3 d = box.getOrigin() - a;
    for (int i = 0; i < 3; ++i) {
        btScalar rb = std::abs(R[i][0]) * h.x() + std::abs(R[i][1]) * h.y() + std::abs(R[i][2]) * h.z();
        if (std::abs(d[i]) > e[i] + rb) return false;
    }
    for (int j = 0; j < 3; ++j) {
        btScalar ra = std::abs(R[0][j]) * e.x() + std::abs(R[1][j]) * e.y() + std::abs(R[2][j]) * e.z();
        btScalar dj = R[0][j] * d.x() + R[1][j] * d.y() + R[2][j] * d.z();
        if (std::abs(dj) > h[j] + ra) return false;
    }
    return true;
}

// A trigger's objects now (`now`, sorted, `num` of them) against those of the step before
// (`before`, sorted, ts.num of them): how many came in, the first of them, and how many left.
void compare(TriggerState& ts, const DoId* now, int32_t num, const DoId* before) {
    int32_t entered = 0, left = 0;
    DoId first_in;
    const DoId *a = now, *ae = a + num;
    const DoId *p = before, *pe = p + ts.num;
    while (a != ae || p != pe) {
        if (p == pe || (a != ae && *a < *p)) {
            if (entered++ == 0) first_in = *a;
            ++a;
        } else if (a == ae || *p < *a) {
            ++left;
            ++p;
        } else {
            ++a;
            ++p;
        }
    }
    ts.entered = entered, ts.left = left, ts.first_in = first_in;
}

// A trigger's events this step (its list found and compared): its values written and its
// outputs flagged active here, on the physics thread of its slice (they are its own slots),
// and listed in `made` in the order the step's list of active outputs takes them.
void events(Runtime& r, TriggerState& ts, std::vector<graph::SlotId>& made) {
    const graph::Adr<graph::Slot> s0 = ts.slots;  // not the component's row: one cache miss less per trigger
    auto activate = [&r, &made](graph::SlotId x) {
        if (r.flag_active(x)) made.push_back(x);
    };
    if (ts.entered) {
        ts.enters += ts.entered;
        activate(s0 + slot::on_enter);
        *r.val(s0 + slot::object) = ts.first_in.v;
        activate(s0 + slot::object);
    }
    if (ts.left) activate(s0 + slot::on_leave);
    if (ts.num) activate(s0 + slot::on_stay);
    if (ts.num != ts.before) {
        *r.val(s0 + slot::count_inside) = ts.num;
        activate(s0 + slot::count_inside);
    }
}

// Which objects are inside the triggers of slice `slice` (`ids`), found on one of the physics
// threads: each trigger's pose, and its objects, sorted, appended to the slice's list of this
// step and compared with its list of the step before; the events of those with an object now
// or then, their outputs in the slice's list of outputs made active, in order.
void find_inside(Runtime& r, int32_t slice, graph::IdRange<TriggerId> ids) {
    State& s = r.st;
    const graph::Graph& g = r.g;
    std::vector<DoId>& out = s.trigger_lists[s.trigger_side][slice];
    const std::vector<DoId>& then = s.trigger_lists[s.trigger_side ^ 1][slice];
    std::vector<graph::SlotId>& made = s.trigger_made[slice];
    out.clear();
    made.clear();
    for (TriggerId t : ids) {
        TriggerState& ts = s.triggers[t];
        // On a body, its box moves with it; on none, its pose is as start_all set it.
        const graph::BodyId on = r.tab.trigger_body[t];
        if (on.valid()) ts.pose = r.phys.frame(on) * r.tab.trigger_local[t];
        const btVector3& h = r.tab.trigger_half[t];
        const btVector3& c = ts.pose.getOrigin();
        const btVector3 reach = on.valid() ? trigger_box_reach(ts.pose.getBasis(), h) : r.tab.trigger_reach[t];
        const btScalar rx = reach.x() + r.index.reach(), ry = reach.y() + r.index.reach();
        const size_t adr = out.size();
        r.index.for_each(c.x() - rx, c.x() + rx, c.y() - ry, c.y() + ry, [&](graph::BodyId b) {
            if (!overlaps(r.index.lo(b), r.index.hi(b), ts.pose, h)) return;
            const DoId obj = object_of(g, r.tab.body_do[b], g.triggers[t].filter);
            if (!obj.valid()) return;
            // Insert sorted, once per object (a bottle has two bodies).
            size_t k = out.size();
            bool dup = false;
            for (size_t q = adr; q < k && !dup; ++q) dup = out[q] == obj;
            if (dup) return;
            out.push_back(obj);
            while (k > adr && out[k - 1] > obj) {
                out[k] = out[k - 1];
                --k;
            }
            out[k] = obj;
        });
        const int32_t found = graph::count_of(std::span(out).subspan(adr));
        compare(ts, out.data() + adr, found, then.data() + ts.adr);
        ts.before = ts.num;
        ts.slice = slice, ts.adr = int32_t(adr), ts.num = found;
        s.trigger_occupied[t] = found > 0;
        if (ts.num || ts.before) events(r, ts, made);
    }
}

// Phase 2: the triggers' contents and events, a slice of the triggers per item (at least 32
// triggers in one, four per thread at most); then, on this thread, the outputs they made
// active into the step's list, in trigger order.
void sense_all(Runtime& r) {
    State& s = r.st;
    const graph::Graph& g = r.g;
    if (g.triggers.empty()) return;
    r.index.refresh(r.phys, r.phys.workers());
    s.trigger_side ^= 1;  // the step before's lists are kept for the comparison
    const size_t nt = g.triggers.size();
    const size_t slices = slice_count(nt, 32, s.trigger_made.size());
    auto finding = [&r, nt, slices](int i) { find_inside(r, i, slice_ids<TriggerId>(nt, slices, i)); };
    run_slices(r.phys.workers(), slices, finding);
    for (size_t i = 0; i < slices; ++i)
        s.out_list.insert(s.out_list.end(), s.trigger_made[i].begin(), s.trigger_made[i].end());
}

// The object a trigger last saw starts empty. The lists of the slices in use are sized: trigger/
// object pairs have no small bound, and this covers every object being in a few triggers at
// once (beyond it a list grows, amortised, once).
void start_all(Runtime& r) {
    for (TriggerId t : graph::ids_of(r.g.triggers)) {
        r.st.triggers[t].slots = r.g.comps[r.g.triggers[t].comp].slot_adr;
        r.st.triggers[t].pose = r.tab.trigger_local[t];  // in the world for one on no body (on a body: each step)
        *r.val(r.comp_slot(r.g.triggers[t].comp, slot::object)) = -1;
    }
    const size_t nt = r.g.triggers.size();
    if (nt == 0) return;
    const size_t slices = slice_count(nt, 32, r.st.trigger_made.size());
    const size_t pairs = std::max<size_t>(256, 4 * (r.tab.dyn_bodies.size() + nt));
    for (size_t i = 0; i < slices; ++i) {
        for (auto& lists : r.st.trigger_lists) lists[i].reserve(pairs / slices + 64);
        const auto [b, e] = slice_of(nt, slices, i);
        r.st.trigger_made[i].reserve(5 * (e - b));  // five outputs a trigger
    }
}

}  // namespace

constexpr KindBehaviour behaviour{
    .start_all = start_all, .sense_all = sense_all, .sense_segment = StepProfile::Triggers};

}  // namespace plant::kinds::trigger
