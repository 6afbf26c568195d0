// Phase 4: outputs of this step have been seen by the logic phase and are cleared
// (remembered as `seen` for observers); then the Petri nets step:
//   1. every place whose put input is active gets one token (once per step, however
//      many flows activated it);
//   2. every transition enabled in that marking (M[p] >= w for each input arc) fires,
//      all together, even when they compete for tokens (forward conflict);
//   3. M'[p] = max(0, M[p] − consumed[p]) + produced[p].
// Places that received a token (put or produced) activate `entered`; a changed
// marking activates `tokens`; a fired transition activates `fired`. These outputs
// are active in the next step's logic phase. (A state's start, its places publishing
// their tokens, is the kind table's: kinds/state/run.cpp.)
#include "engine/runtime.h"
#include "graph/kinds.h"

#include <algorithm>

namespace plant::engine {

using namespace plant::graph;

namespace {

void clear_outputs(State& s) {
    for (SlotId x : s.seen_list) s.seen[x] = 0;
    s.seen_list.swap(s.out_list);
    s.out_list.clear();
    for (SlotId x : s.seen_list) {
        s.seen[x] = 1;
        s.act[x] = 0;
    }
}

void touch(State& s, PlaceId p) {
    if (s.place_mark[p]) return;
    s.place_mark[p] = 1;
    s.places_touched.push_back(p);
}

}  // namespace

void phase_petri(Runtime& r) {
    State& s = r.st;
    const Graph& g = r.g;
    clear_outputs(s);
    if (g.places.empty()) return;

    for (SlotId x : s.in_list) {
        const PlaceId p = r.tab.put_place[x];
        if (!p.valid()) continue;
        s.tokens[p] = std::min(s.tokens[p] + 1, kMaxTokens);
        touch(s, p);
        s.net_live[r.tab.place_net[p]] = 1;
    }
    // Places touched by puts so far all received a token.
    const size_t puts = s.places_touched.size();

    s.fired.clear();
    for (int32_t net = 0; net < count_of(r.tab.nets); ++net) {
        if (!s.net_live[net] && !r.tab.net_always_live[net]) continue;
        const size_t before = s.fired.size();
        for (TransitionId id : r.tab.net_transitions[net]) {
            const Transition& tr = g.transitions[id];
            bool enabled = true;
            for (const Arc& a : g.arcs.slice(tr.in_adr, tr.in_num)) {
                enabled = s.tokens[a.place] >= a.weight;
                if (!enabled) break;
            }
            if (enabled) s.fired.push_back(id);
        }
        // A net that fired is examined again next step; a quiet one waits for a put.
        s.net_live[net] = s.fired.size() > before;
    }
    for (TransitionId t : s.fired) {
        const Transition& tr = g.transitions[t];
        for (const Arc& a : g.arcs.slice(tr.in_adr, tr.in_num)) {
            s.consume[a.place] += a.weight;
            touch(s, a.place);
        }
        for (const Arc& a : g.arcs.slice(tr.out_adr, tr.out_num)) {
            s.produce[a.place] += a.weight;
            touch(s, a.place);
        }
        if (tr.fired_slot.valid()) r.activate_out(tr.fired_slot);
    }
    for (size_t i = 0; i < s.places_touched.size(); ++i) {
        const PlaceId p = s.places_touched[i];
        const int64_t before = s.tokens[p] - (i < puts ? 1 : 0);
        // A full place stays full (graph.h): the count never wraps, nor loses exactness.
        const int64_t after = std::min(std::max<int64_t>(0, s.tokens[p] - s.consume[p]) + s.produce[p], kMaxTokens);
        const SlotId entered = r.tab.place_entered[p], tokens = r.tab.place_tokens[p];
        if ((i < puts || s.produce[p] > 0) && entered.valid()) r.activate_out(entered);
        if (after != before && tokens.valid()) r.emit(tokens, double(after));
        s.tokens[p] = after;
        s.consume[p] = s.produce[p] = 0;
        s.place_mark[p] = 0;
    }
    s.places_touched.clear();
}

}  // namespace plant::engine
