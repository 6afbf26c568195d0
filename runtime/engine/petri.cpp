// Phase 4: outputs of this step have been seen by the logic phase and are cleared
// (kept as seen for observers); then the Petri nets step:
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
#include "engine/workers.h"
#include "graph/kinds.h"

#include <algorithm>

namespace plant::engine {

using namespace plant::graph;

namespace {

// This step's outputs go inactive, and are flagged in seen[step % 2] for observers; the other
// array, the step before's, drops its list (it is this array's list two steps on, and nothing
// reads it now). On the physics threads in slices of the two lists: no two write one byte.
void clear_outputs(Runtime& r) {
    State& s = r.st;
    uint8_t* const now = s.seen[s.step & 1].data();
    uint8_t* const before = s.seen[(s.step & 1) ^ 1].data();
    const size_t n_out = s.out_list.size(), n = n_out + s.seen_list.size();
    const size_t slices = slice_count(n, 256, kMaxSlices);
    auto clearing = [&s, now, before, n, n_out, slices](int i) {
        const auto [b, e] = slice_of(n, slices, i);
        for (size_t k = b; k < e; ++k) {
            if (k >= n_out) {
                before[index(s.seen_list[k - n_out])] = 0;
                continue;
            }
            const SlotId x = s.out_list[k];
            now[index(x)] = 1;
            s.act[x] = 0;
        }
    };
    run_slices(r.phys.workers(), slices, clearing);
    s.seen_list.swap(s.out_list);
    s.out_list.clear();
}

// The transitions of net n enabled in the marking, in order, each given to `out`; a net that
// has one is examined again next step, a quiet one waits for a put.
template <class Out>
void check_net(Runtime& r, size_t n, Out&& out) {
    State& s = r.st;
    const Tables& t = r.tab;
    if (!s.net_live[n] && !t.net_always_live[n]) return;
    bool any = false;
    const int32_t first = t.net_transitions.adr[n], end = first + t.net_transitions.num[n];
    for (int32_t k = first; k < end; ++k) {
        bool enabled = true;
        for (int32_t a = t.net_in_adr[k]; a < t.net_in_adr[k + 1] && enabled; ++a)
            enabled = s.tokens[t.net_in[a].place] >= t.net_in[a].weight;
        if (enabled) {
            out(t.net_transitions.list[k]);
            any = true;
        }
    }
    s.net_live[n] = any;
}

// Every net's enabled transitions into s.fired, net by net in order. With more than one
// thread the nets go in slices, each writing its own part of fired_at (from its first net's
// position) and its count; the parts are then joined in the slices' order: the same list.
void find_enabled(Runtime& r) {
    State& s = r.st;
    const size_t nets = r.tab.nets.size();
    Workers& w = r.phys.workers();
    const size_t slices = slice_count(nets, 64, s.slice_fired.size());
    s.fired.clear();
    if (w.threads() == 1 || slices <= 1) {
        for (size_t n = 0; n < nets; ++n) check_net(r, n, [&s](TransitionId t) { s.fired.push_back(t); });
        return;
    }
    auto slice = [&r, &s, nets, slices](int k) {
        const auto [b, e] = slice_of(nets, slices, k);
        int32_t num = 0;
        if (b < e) {
            TransitionId* out = s.fired_at.data() + r.tab.net_transitions.adr[b];
            for (size_t n = b; n < e; ++n) check_net(r, n, [out, &num](TransitionId t) { out[num++] = t; });
        }
        s.slice_fired[k] = num;
    };
    w.run(int(slices), slice);
    for (size_t k = 0; k < slices; ++k) {
        const auto [b, e] = slice_of(nets, slices, k);
        if (b == e) continue;
        const TransitionId* from = s.fired_at.data() + r.tab.net_transitions.adr[b];
        s.fired.insert(s.fired.end(), from, from + s.slice_fired[k]);
    }
}

void touch(State& s, PlaceId p, State::PlaceStep& ps) {
    if (ps.touched) return;
    ps.touched = 1;
    s.places_touched.push_back(p);
}

}  // namespace

void phase_petri(Runtime& r) {
    State& s = r.st;
    const Graph& g = r.g;
    clear_outputs(r);
    if (g.places.empty()) return;

    for (SlotId x : s.in_list) {
        const PlaceId p = r.tab.slot_in[x].put;
        if (!p.valid()) continue;
        s.tokens[p] = std::min(s.tokens[p] + 1, kMaxTokens);
        State::PlaceStep& ps = s.place_step[p];
        touch(s, p, ps);
        s.net_live[ps.net] = 1;
    }
    // Places touched by puts so far all received a token.
    const size_t puts = s.places_touched.size();

    find_enabled(r);
    for (TransitionId t : s.fired) {
        const Transition& tr = g.transitions[t];
        for (const Arc& a : g.arcs.slice(tr.in_adr, tr.in_num)) {
            State::PlaceStep& ps = s.place_step[a.place];
            ps.consume += a.weight;
            touch(s, a.place, ps);
        }
        for (const Arc& a : g.arcs.slice(tr.out_adr, tr.out_num)) {
            State::PlaceStep& ps = s.place_step[a.place];
            ps.produce += a.weight;
            touch(s, a.place, ps);
        }
        if (tr.fired_slot.valid()) r.activate_out(tr.fired_slot);
    }
    for (size_t i = 0; i < s.places_touched.size(); ++i) {
        const PlaceId p = s.places_touched[i];
        State::PlaceStep& ps = s.place_step[p];
        const int64_t before = s.tokens[p] - (i < puts ? 1 : 0);
        // A full place stays full (graph.h): the count never wraps, nor loses exactness.
        const int64_t after = std::min(std::max<int64_t>(0, s.tokens[p] - ps.consume) + ps.produce, kMaxTokens);
        if ((i < puts || ps.produce > 0) && ps.entered.valid()) r.activate_out(ps.entered);
        if (after != before && ps.tokens_slot.valid()) r.emit(ps.tokens_slot, double(after));
        s.tokens[p] = after;
        ps.consume = ps.produce = 0;
        ps.touched = 0;
    }
    s.places_touched.clear();
}

}  // namespace plant::engine
