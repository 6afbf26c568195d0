// Volume triggers. An object is inside while the bounding box of one of its bodies
// (declared dynamic, in the world, gripped or not) overlaps the trigger's box. The
// object reported is the body's DO or, with a filter, the nearest DO above it whose
// type is the filter. Each trigger keeps the sorted list of objects inside; comparing
// it with the previous step's list gives on_enter / on_leave, for any number of
// objects at once.
#include "engine/runtime.h"

#include "graph/kinds.h"

#include <cmath>

namespace plant::engine {

using namespace plant::graph;

namespace {

int32_t object_of(const Graph& g, int32_t d, int32_t filter) {
    if (filter < 0) return d;
    for (size_t guard = 0; d >= 0 && guard <= g.dos.size(); ++guard, d = g.dos[d].parent)
        if (g.dos[d].type == filter) return d;
    return -1;
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

}  // namespace

void sense_triggers(Runtime& r) {
    State& s = r.st;
    const Graph& g = r.g;
    if (g.triggers.empty()) return;
    r.index.refresh(r.phys, true);
    s.inside.swap(s.inside_prev);
    s.inside.clear();
    for (size_t t = 0; t < g.triggers.size(); ++t) {
        const Trigger& tg = g.triggers[t];
        TriggerState& ts = s.triggers[t];
        ts.prev_adr = ts.adr;
        ts.prev_num = ts.num;
        ts.pose = tg.body >= 0 ? r.phys.frame(tg.body) * r.tab.trigger_local[t] : to_bt(tg.pose);
        const btMatrix3x3& R = ts.pose.getBasis();
        const btVector3 h = to_bt(tg.extent) * btScalar(0.5);
        const btVector3& c = ts.pose.getOrigin();
        const btScalar rx = std::abs(R[0][0]) * h.x() + std::abs(R[0][1]) * h.y() + std::abs(R[0][2]) * h.z() +
                            r.index.reach();
        const btScalar ry = std::abs(R[1][0]) * h.x() + std::abs(R[1][1]) * h.y() + std::abs(R[1][2]) * h.z() +
                            r.index.reach();
        const size_t adr = s.inside.size();
        r.index.for_each(c.x() - rx, c.x() + rx, c.y() - ry, c.y() + ry, [&](int32_t b) {
            if (!overlaps(r.index.lo(b), r.index.hi(b), ts.pose, h)) return;
            const int32_t obj = object_of(g, r.tab.body_do[b], tg.filter);
            if (obj < 0) return;
            // Insert sorted, once per object (a bottle has two bodies).
            size_t k = s.inside.size();
            bool dup = false;
            for (size_t q = adr; q < k && !dup; ++q) dup = s.inside[q] == obj;
            if (dup) return;
            s.inside.push_back(obj);
            while (k > adr && s.inside[k - 1] > obj) {
                s.inside[k] = s.inside[k - 1];
                --k;
            }
            s.inside[k] = obj;
        });
        ts.adr = int32_t(adr);
        ts.num = int32_t(s.inside.size() - adr);

        // Merge the two sorted lists.
        int32_t entered = 0, left = 0, first_in = -1;
        const int32_t *a = s.inside.data() + ts.adr, *ae = a + ts.num;
        const int32_t *p = s.inside_prev.data() + ts.prev_adr, *pe = p + ts.prev_num;
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
        const int32_t s0 = r.comp_slot(tg.comp, triggerslot::on_enter);
        if (entered) {
            ts.enters += entered;
            r.activate(s0 + triggerslot::on_enter);
            r.emit(s0 + triggerslot::object, first_in);
        }
        if (left) r.activate(s0 + triggerslot::on_leave);
        if (ts.num) r.activate(s0 + triggerslot::on_stay);
        if (ts.num != ts.prev_num) r.emit(s0 + triggerslot::count_inside, ts.num);
    }
}

// The object a trigger last saw starts empty.
void start_triggers(Runtime& r) {
    for (const Trigger& t : r.g.triggers) *r.val(r.comp_slot(t.comp, triggerslot::object)) = -1;
}

}  // namespace plant::engine
