// Phase 5: components act on their active inputs, in component id order, each
// reading its inputs in a fixed order: what switches something off before what
// switches it on (so "on" wins when both are active), modes before poses and
// velocities. Then sources with a rate issue.
#include "engine/runtime.h"

#include "engine/plugin.h"

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
    s.comp_list.clear();
    for (SlotId x : s.in_list) {
        const CompId c = r.tab.slot_in[x].acts;
        if (!c.valid() || s.comp_mark[c]) continue;
        s.comp_mark[c] = 1;
        s.comp_list.push_back(c);
    }
    std::sort(s.comp_list.begin(), s.comp_list.end());
    for (CompId c : s.comp_list) {
        s.comp_mark[c] = 0;
        act_on(r, c);
    }
    act_kinds(r);  // the kind table's whole-table hooks: sources with a rate issue
}

}  // namespace plant::engine
