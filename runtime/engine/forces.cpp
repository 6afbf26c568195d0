// Forced slots: the fault forcing of a training plant (a stuck sensor, a cut wire, an
// inverted contact). A force is set between steps by Engine::force (from an event, the one
// way in) and takes effect in the next logic phase. Outputs: the component keeps writing
// its natural value, which is swapped for the forced one while the logic phase reads it
// and after the step (traces, the viewer). Inputs: forced after the logic phase, so the
// Petri phase and the actuators act on the forced signal. Costs nothing while nothing is
// forced: each hook returns on an empty list.
#include "engine/runtime.h"

#include <algorithm>

namespace plant::engine {

using namespace plant::graph;

namespace {

void unlist(std::vector<SlotId>& list, SlotId x) {
    auto it = std::find(list.begin(), list.end(), x);
    if (it != list.end()) list.erase(it);  // keeps the order the phases see
}

void deactivate(Runtime& r, SlotId x, bool out) {
    if (!r.st.act[x]) return;
    r.st.act[x] = 0;
    unlist(out ? r.st.out_list : r.st.in_list, x);
}

struct Ref {
    double* value;    // the slot's values now
    double* natural;  // the component's or the flows' own
    const double* forced;
    int width;
    SlotType type;
};

Ref ref(Runtime& r, SlotId x) {
    const Slot& s = r.g.slots[x];
    const int32_t adr = r.tab.value_adr[x].v;  // the slot's values' place in each per-value array
    const int w = slot_width(s.type);
    if (w == 0) return {nullptr, nullptr, nullptr, 0, s.type};
    return {r.val(x), &r.st.force_natural[adr], &r.st.force_value[adr], w, s.type};
}

// The value readers see: stuck at its value, open reads as off (none for references and
// strings), inverted is the natural bool negated.
void show(const Ref& v, ForceMode m) {
    for (int i = 0; i < v.width; ++i) {
        switch (m) {
        case ForceMode::Stuck: v.value[i] = v.forced[i]; break;
        case ForceMode::Open: v.value[i] = v.type == SlotType::Ref || v.type == SlotType::String ? -1 : 0; break;
        case ForceMode::Invert: v.value[i] = v.natural[i] != 0 ? 0 : 1; break;
        case ForceMode::None: v.value[i] = v.natural[i]; break;
        }
    }
}

void keep_natural(const Ref& v) { std::copy(v.value, v.value + v.width, v.natural); }
void restore_natural(const Ref& v) { std::copy(v.natural, v.natural + v.width, v.value); }

// A forced slot's activity in the logic phase (outputs) or the acting phases (inputs): a
// void slot stuck on is active every step, stuck off or open never; any other is active
// when its writer made it so and once when the force begins or ends, except open, which
// is never active, but once when it begins on a bool or number (the reader sees the signal
// drop to off); a string or reference cut open carries no message at all.
void activity(Runtime& r, SlotId x, bool out, ForceMode m, int width) {
    const bool edge = r.st.force_edge[x] != 0;
    const SlotType t = r.g.slots[x].type;
    const bool level = t == SlotType::Bool || t == SlotType::Int || t == SlotType::Real;  // has an "off"
    if (width == 0 && m == ForceMode::Stuck) {  // a void slot stuck off is kept as open (Engine::force)
        if (out) r.activate_out(x);
        else r.activate_in(x);
    } else if (m == ForceMode::Open && !(edge && level)) {
        deactivate(r, x, out);
    } else if (edge && width) {
        if (out) r.activate_out(x);
        else r.activate_in(x);
    }
}

// Applies the force on `x` now: the natural value kept (outputs always, inputs when the
// flows wrote them this step), the forced one shown, the activity set.
void apply(Runtime& r, SlotId x, bool out) {
    const ForceMode m = ForceMode(r.st.force_mode[x]);
    const Ref v = ref(r, x);
    if (v.width) {
        if (out || r.st.act[x]) keep_natural(v);
        show(v, m);
    }
    activity(r, x, out, m, v.width);
}

// Ends the logic phase's (or the acting phases') view of a list: edges are spent and
// released slots leave it.
void settle(Runtime& r, std::vector<SlotId>& list) {
    for (size_t i = 0; i < list.size();) {
        const SlotId x = list[i];
        r.st.force_edge[x] = 0;
        if (ForceMode(r.st.force_mode[x]) == ForceMode::None) list.erase(list.begin() + ptrdiff_t(i));
        else ++i;
    }
}

}  // namespace

void forces_step_begin(Runtime& r) {
    for (SlotId x : r.st.forced_out)
        if (r.tab.value_adr[x].valid()) restore_natural(ref(r, x));
}

void forces_logic_begin(Runtime& r) {
    for (SlotId x : r.st.forced_out) apply(r, x, true);
}

void force_again(Runtime& r, SlotId x) {
    if (ForceMode(r.st.force_mode[x]) != ForceMode::None) apply(r, x, true);
}

void forces_logic_end(Runtime& r) {
    for (SlotId x : r.st.forced_out)
        if (r.tab.value_adr[x].valid()) restore_natural(ref(r, x));
    settle(r, r.st.forced_out);
    for (SlotId x : r.st.forced_in) apply(r, x, false);
    settle(r, r.st.forced_in);
}

void forces_step_end(Runtime& r) {
    for (SlotId x : r.st.forced_out) {
        if (!r.tab.value_adr[x].valid()) continue;
        const Ref v = ref(r, x);
        keep_natural(v);
        show(v, ForceMode(r.st.force_mode[x]));
    }
}

}  // namespace plant::engine
