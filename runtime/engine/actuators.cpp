// Phase 5: components act on their active inputs, in component id order (the result of that
// order: kinematic moves, which touch only their own body, go to the physics threads a
// stretch at a time, below), each reading its inputs in a fixed order: what switches
// something off before what switches it on (so "on" wins when both are active), modes
// before poses and velocities. Then sources with a rate issue.
#include "engine/runtime.h"

#include "engine/plugin.h"
#include "engine/workers.h"

#include "graph/kinds.h"

#include <algorithm>

namespace plant::engine {

using namespace plant::graph;

namespace {

// Each kind's acting lives with the rest of its behaviour (a kind on the kind table: its
// kinds/NAME/run.cpp, a plugin's its act hook); a state's places are read in phase 4,
// routers, connectors and labels in phase 3 (tables.cpp: slot_in's `acts` only where a kind acts).
void act_on(Runtime& r, CompId comp) {
    const Comp& c = r.g.comps[comp];
    if (c.kind == CompKind::Plugin) return act_plugin(r, detail_of<Plugin>(c));
    if (const KindBehaviour* b = builtin_behaviour(c.kind)) b->act_one(r, c);
}

}  // namespace

void phase_actuators(Runtime& r) {
    State& s = r.st;
    // The components with an active input, listed and marked by phase 4 (petri.cpp).
    std::sort(s.comp_list.begin(), s.comp_list.end());
    // In id order, a stretch at a time: a stretch ends at a component that neither acts alone
    // nor leaves the physics alone. Within it, those that act alone (each touching only its own
    // row and body) are the items of a job, in slices of the stretch; then the others (no body,
    // no physics: they commute with the first) in order; then the one that ended it. The same
    // result as one pass in id order, on any number of threads.
    Workers& w = r.phys.workers();
    const size_t n = s.comp_list.size();
    for (size_t i = 0; i < n;) {
        size_t j = i, alone = 0;
        for (; j < n; ++j) {
            const CompId c = s.comp_list[j];
            if (s.comp_mark[c] == 1) {
                ++alone;
                continue;
            }
            const CompKind k = r.g.comps[c].kind;
            const KindBehaviour* b = k == CompKind::Plugin ? nullptr : builtin_behaviour(k);
            if (!b || !b->acts_off_physics) break;
        }
        const size_t first = i, len = j - i, slices = alone > 4 ? slice_count(len, 4, kMaxSlices) : 1;
        auto acting = [&r, &s, first, len, slices](int k) {
            const auto [b, e] = slice_of(len, slices, size_t(k));
            for (size_t q = first + b; q < first + e; ++q)
                if (s.comp_mark[s.comp_list[q]] == 1) act_on(r, s.comp_list[q]);
        };
        run_slices(w, slices, acting);
        for (size_t q = first; q < j; ++q)
            if (s.comp_mark[s.comp_list[q]] != 1) act_on(r, s.comp_list[q]);
        if (j < n) act_on(r, s.comp_list[j++]);
        i = j;
    }
    for (CompId c : s.comp_list) s.comp_mark[c] = 0;
    act_kinds(r);  // the kind table's whole-table hooks: sources with a rate issue
}

}  // namespace plant::engine
