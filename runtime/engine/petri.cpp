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
#include <atomic>

namespace plant::engine {

using namespace plant::graph;

namespace {

// This step's outputs go inactive, and are flagged in seen[step % 2] for observers; the other
// array, the step before's, drops its list (it is this array's list two steps on, and nothing
// reads it now). And the active inputs, one lookup each: every place whose put input is active
// gets one token (an input is in the list once, and a place has one put input: no two write
// one place; a net's liveness may be set by two, to the same 1); those a component acts on
// are noted in the slice's own row, in order (`petri_acts`; a row that fills up says so, and
// then the calling thread looks at the whole list). On the physics threads in slices of the
// three lists: no two write one byte otherwise. Returns how many slices (rows) it used.
size_t clear_outputs(Runtime& r) {
    State& s = r.st;
    uint8_t* const now = s.seen[s.step & 1].data();
    uint8_t* const before = s.seen[(s.step & 1) ^ 1].data();
    const size_t n_out = s.out_list.size(), n_seen = n_out + s.seen_list.size(), n = n_seen + s.in_list.size();
    const size_t slices = slice_count(n, 256, kMaxSlices);
    auto clearing = [&r, &s, now, before, n, n_out, n_seen, slices](int i) {
        const auto [b, e] = slice_of(n, slices, i);
        State::PetriActs& acts = s.petri_acts[size_t(i)];
        acts.num = 0;
        acts.full = false;
        // The slice's part of each list, one loop each (positions b..e of the three in a row).
        for (size_t k = b, end = std::min(e, n_out); k < end; ++k) {
            const SlotId x = s.out_list[k];
            now[index(x)] = 1;
            s.act[x] = 0;
        }
        for (size_t k = std::max(b, n_out), end = std::min(e, n_seen); k < end; ++k)
            before[index(s.seen_list[k - n_out])] = 0;
        for (size_t k = std::max(b, n_seen); k < e; ++k) {
            const SlotId x = s.in_list[k - n_seen];
            const Tables::SlotIn in = r.tab.slot_in[x];
            if (in.acts.valid()) {
                if (acts.num < acts.slots.size()) acts.slots[acts.num++] = x;
                else acts.full = true;
            }
            if (!in.put.valid()) continue;
            const PlaceId p = in.put;
            s.tokens[p] = std::min(s.tokens[p] + 1, kMaxTokens);
            State::PlaceStep& ps = s.place_step[p];
            ps.put = 1;
            std::atomic_ref(s.net_live[ps.net]).store(1, std::memory_order_relaxed);
        }
    };
    run_slices(r.phys.workers(), slices, clearing);
    s.seen_list.swap(s.out_list);
    s.out_list.clear();
    return slices;
}

// The components phase 5 acts on (actuators.cpp), listed in the order of the active inputs,
// each once, its mark 1 while every active input of it is one it acts on alone
// (Tables::alone), 2 once another is.
void list_acting(Runtime& r, SlotId x) {
    State& s = r.st;
    const CompId c = r.tab.slot_in[x].acts;
    uint8_t& m = s.comp_mark[c];
    if (!m) s.comp_list.push_back(c);
    m = m == 2 || !r.tab.alone(x) ? 2 : 1;
}

// Net n's step, on the physics thread of its slice (it writes only its own places, transitions'
// outputs and liveness): every transition enabled in the marking fires, all together; then each
// place that got a put or is on a fired transition's arc takes its new count, and its outputs
// go into `made`, the slice's list. A net that has an enabled transition is examined again next
// step, a quiet one waits for a put.
void step_net(Runtime& r, size_t n, std::vector<SlotId>& made) {
    State& s = r.st;
    const Tables& t = r.tab;
    const Graph& g = r.g;
    if (!s.net_live[n] && !t.net_always_live[n]) return;
    auto activate = [&r, &made](SlotId x) {
        if (r.flag_active(x)) made.push_back(x);
    };
    bool any = false;
    const int32_t first = t.net_transitions.adr[n], end = first + t.net_transitions.num[n];
    for (int32_t k = first; k < end; ++k) {
        bool enabled = true;
        for (int32_t a = t.net_in_adr[k]; a < t.net_in_adr[k + 1] && enabled; ++a)
            enabled = s.tokens[t.net_in[a].place] >= t.net_in[a].weight;
        if (!enabled) continue;  // the marking is read before any count changes, below
        any = true;
        const Transition& tr = g.transitions[t.net_transitions.list[k]];
        for (const Arc& a : g.arcs.slice(tr.in_adr, tr.in_num)) s.place_step[a.place].consume += a.weight;
        for (const Arc& a : g.arcs.slice(tr.out_adr, tr.out_num)) s.place_step[a.place].produce += a.weight;
        if (tr.fired_slot.valid()) activate(tr.fired_slot);
    }
    s.net_live[n] = any;
    for (PlaceId p : t.net_places[int32_t(n)]) {
        State::PlaceStep& ps = s.place_step[p];
        if (!ps.put && ps.consume == 0 && ps.produce == 0) continue;  // untouched (an arc's weight is at least 1)
        const int64_t before = s.tokens[p] - (ps.put ? 1 : 0);
        // A full place stays full (graph.h): the count never wraps, nor loses exactness.
        const int64_t after = std::min(std::max<int64_t>(0, s.tokens[p] - ps.consume) + ps.produce, kMaxTokens);
        if ((ps.put || ps.produce > 0) && ps.entered.valid()) activate(ps.entered);
        if (after != before && ps.tokens_slot.valid()) {
            *r.val(ps.tokens_slot) = double(after);
            activate(ps.tokens_slot);
        }
        s.tokens[p] = after;
        ps.consume = ps.produce = 0;
        ps.put = 0;
    }
}

}  // namespace

size_t petri_slices(size_t nets) { return slice_count(nets, 64, kMaxSlices); }

void phase_petri(Runtime& r) {
    State& s = r.st;
    const Graph& g = r.g;
    // The puts of the active inputs too, noting those a component acts on. Nothing this phase
    // does activates an input.
    const size_t rows = clear_outputs(r);
    s.comp_list.clear();
    bool full = false;
    for (size_t i = 0; i < rows; ++i) full = full || s.petri_acts[i].full;
    if (full) {
        for (SlotId x : s.in_list)
            if (r.tab.slot_in[x].acts.valid()) list_acting(r, x);
    } else {
        for (size_t i = 0; i < rows; ++i)
            for (uint32_t k = 0; k < s.petri_acts[i].num; ++k) list_acting(r, s.petri_acts[i].slots[k]);
    }
    if (g.places.empty()) return;
    // The nets in slices; what each slice made active joins the step's list in slice order. On
    // one thread, or in one slice, that is the nets in order on this thread: straight onto the list.
    const size_t nets = r.tab.nets.size(), slices = petri_slices(nets);
    if (r.phys.workers().threads() == 1 || slices <= 1) {
        for (size_t n = 0; n < nets; ++n) step_net(r, n, s.out_list);
        return;
    }
    auto stepping = [&r, nets, slices](int k) {
        std::vector<SlotId>& made = r.st.petri_made[size_t(k)];
        made.clear();
        const auto [b, e] = slice_of(nets, slices, size_t(k));
        for (size_t n = b; n < e; ++n) step_net(r, n, made);
    };
    run_slices(r.phys.workers(), slices, stepping);
    for (size_t k = 0; k < slices; ++k) s.out_list.insert(s.out_list.end(), s.petri_made[k].begin(), s.petri_made[k].end());
}

}  // namespace plant::engine
