#include "engine/plugin.h"

#include "engine/runtime.h"
#include "engine/workers.h"

#include <array>
#include <utility>
#include <vector>

namespace plant::engine {
namespace {

// The runtime's part of each kind on the kind table (kinds/NAME/run.cpp), beside its row.
#define PLANT_KIND_RUN(word, WORD) &kinds::word::behaviour,
const std::array kBuiltinRuns = {PLANT_KINDS(PLANT_KIND_RUN)};
#undef PLANT_KIND_RUN
#define PLANT_KIND_RUN_KIND(word, WORD) &kinds::word::desc,
const std::array kBuiltinRows = {PLANT_KINDS(PLANT_KIND_RUN_KIND)};
#undef PLANT_KIND_RUN_KIND

std::vector<std::pair<std::string_view, const KindBehaviour*>>& behaviours() {
    static std::vector<std::pair<std::string_view, const KindBehaviour*>> b;
    return b;
}

}  // namespace

const KindBehaviour* builtin_behaviour(graph::CompKind kind) {
    static const auto by_kind = [] {
        std::array<const KindBehaviour*, size_t(graph::CompKind::Plugin) + 1> a{};
        for (size_t i = 0; i < kBuiltinRows.size(); ++i) a[size_t(kBuiltinRows[i]->kind)] = kBuiltinRuns[i];
        return a;
    }();
    return by_kind[size_t(kind)];
}

std::span<const KindBehaviour* const> builtin_behaviours() { return kBuiltinRuns; }

void start_kinds(Runtime& r) {
    for (const KindBehaviour* b : kBuiltinRuns)
        if (b->start_all) b->start_all(r);
}

void sense_kinds(Runtime& r) {
    StepProfile& p = r.phys.workers().profile();
    for (const KindBehaviour* b : kBuiltinRuns) {
        if (!b->sense_all) continue;
        b->sense_all(r);
        if (b->sense_segment >= 0) p.lap(StepProfile::Segment(b->sense_segment));
    }
}

void act_kinds(Runtime& r) {
    for (const KindBehaviour* b : kBuiltinRuns)
        if (b->act_all) b->act_all(r);
}

bool register_plugin(const graph::KindDesc& desc, const KindBehaviour& behaviour) {
    if ((desc.senses == graph::PluginPhase::Sensors) != (behaviour.sense != nullptr) ||
        (desc.acts == graph::PluginPhase::Actuators) != (behaviour.act != nullptr) || behaviour.state_size < 0)
        return false;
    if (!graph::register_kind(desc)) return false;
    behaviours().emplace_back(desc.word, &behaviour);
    return true;
}

const KindBehaviour* find_behaviour(std::string_view word) {
    for (const auto& [w, b] : behaviours())
        if (w == word) return b;
    return nullptr;
}

PluginCtx::PluginCtx(Runtime& r, graph::PluginId plugin)
    : r_(r), plugin_(plugin), slot_adr_(r.tab.plugin_run[plugin].slot_adr) {}

bool PluginCtx::active(int slot) const { return r_.st.act[slot_adr_ + slot] != 0; }
void PluginCtx::emit(int slot, double v) {
    const graph::SlotId s = slot_adr_ + slot;
    if (r_.tab.value_adr[s].valid()) *r_.val(s) = v;
    r_.activate_out(s);
}
double PluginCtx::value(int slot) const {
    const graph::SlotId s = slot_adr_ + slot;
    return r_.tab.value_adr[s].valid() ? *r_.val(s) : 0;
}
const graph::PluginParam& PluginCtx::param_row(int i) const { return r_.g.plugin_params[r_.g.plugins[plugin_].param_adr + i]; }
double PluginCtx::param(int i) const { return param_row(i).num; }
std::string_view PluginCtx::param_text(int i) const { return r_.g.str(param_row(i).text); }
graph::Vec3 PluginCtx::param_vec3(int i) const { return param_row(i).vec; }
int PluginCtx::param_list_size(int i) const { return param_row(i).list_num; }
std::string_view PluginCtx::param_list(int i, int k) const { return r_.g.str(r_.g.plugin_strings[param_row(i).list_adr + k].v); }
graph::DoTypeId PluginCtx::param_type(int i) const { return param_row(i).type; }
graph::CompId PluginCtx::param_comp(int i) const { return param_row(i).comp; }
const graph::Graph& PluginCtx::graph() const { return r_.g; }
std::span<double> PluginCtx::state() const {
    const PluginRun& p = r_.tab.plugin_run[plugin_];
    double* state = r_.st.plugin_state.data() + p.state_adr;
    return {state, state + p.behaviour->state_size};
}
int PluginCtx::entry_count() const { return r_.g.plugins[plugin_].entry_num; }
const graph::PluginEntry& PluginCtx::entry(int e) const {
    return r_.g.plugin_entries[r_.g.plugins[plugin_].entry_adr + e];
}
std::string_view PluginCtx::entry_word(int e) const { return r_.g.str(entry(e).word); }
bool PluginCtx::entry_active(int e) const { return r_.st.act[r_.g.plugin_entry_slots[entry(e).slot_adr.first()].v] != 0; }
double PluginCtx::entry_option(int e, int k) const { return r_.g.plugin_params[entry(e).param_adr + k].num; }
double PluginCtx::time() const { return r_.st.time; }

void start_plugins(Runtime& r) {
    for (graph::PluginId i : graph::ids_of(r.g.plugins))
        if (const auto* b = r.tab.plugin_run[i].behaviour; b->start) {
            PluginCtx ctx(r, i);
            b->start(ctx);
        }
}

void sense_plugins(Runtime& r) {
    for (graph::PluginId i : r.tab.sensing_plugins) {
        PluginCtx ctx(r, i);
        r.tab.plugin_run[i].behaviour->sense(ctx);
    }
}

void act_plugin(Runtime& r, graph::PluginId plugin) {
    if (const auto* b = r.tab.plugin_run[plugin].behaviour; b->act) {
        PluginCtx ctx(r, plugin);
        b->act(ctx);
    }
}

}  // namespace plant::engine
