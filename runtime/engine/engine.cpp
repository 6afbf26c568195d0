#include "engine/engine.h"

#include "engine/runtime.h"
#include "engine/workers.h"
#include "graph/kinds.h"
#include "graph/network.h"

#include <algorithm>
#include <utility>

namespace plant::engine {

using namespace plant::graph;

namespace {

double rate_of(const Graph& g, const Options& opt) {
    if (opt.dt > 0) return 1.0 / opt.dt;
    if (opt.rate > 0) return opt.rate;
    return g.settings.rate > 0 ? g.settings.rate : 150.0;
}
double step_of(const Graph& g, const Options& opt) { return opt.dt > 0 ? opt.dt : 1.0 / rate_of(g, opt); }

// Bodies from which a plant's memory is backed by huge pages (Options::huge_pages): Bullet's
// bodies alone then take about 1.5 MiB, the reach of the TLB's 4 KiB pages on the processors
// we measure on (1,536 entries, 6 MiB, shared with everything else the step reads).
constexpr size_t kHugePagesFrom = 2000;

}  // namespace

Runtime::Runtime(const Graph& graph, const Options& opt)
    : g(graph),
      dt(step_of(graph, opt)),
      rate(rate_of(graph, opt)),
      tab(graph),
      sched(build_schedule(graph, tab)),
      phys(graph, tab, opt.broadphase, opt.threads),
      index(tab, graph.bodies.size()),
      logic_every_node(opt.logic_every_node) {
    init_state(st, g, tab);
    st.logic_due.assign(sched.always.size(), 0);
    if (phys.threads() > 1 && sched.lanes() > 1) {  // the logic phase in lanes (logic.cpp)
        st.lane_due.assign(sched.lane_always.size(), 0);
        st.lane_made.assign(sched.always.size(), 0);
        st.join_at.assign((kMaxSlices + 1) * sched.lanes() * 2, 0);
        st.lane_runs.resize(sched.lanes());
        for (size_t k = 0; k < sched.lanes(); ++k) {
            st.lane_runs[k].out.reserve(sched.lane_writes[k]);
            st.lane_runs[k].in.reserve(sched.lane_writes[k]);
        }
    }
    const size_t slices = kMaxSlices, worlds = phys.worlds();  // slice_count's most, per world
    st.slice_world.assign(slices * worlds, 0);
    start_steady(*this, opt.steady_transport && graph.settings.steady_transport);
    // Outputs that flows (or traces) read are refreshed every step; others only on demand.
    for (const Flow& f : g.flows) each_read_slot(g, f, [&](SlotId s) { st.watched[s] = 1; });
    for (const Record& rec : g.records) st.watched[rec.slot] = 1;
    for (const PluginEntry& e : g.plugin_entries)  // outputs a plugin component reads
        for (const PluginEntrySlot& es : g.plugin_entry_slots.slice(e.slot_adr, e.slot_num))
            if (g.slots[es.v].dir == Dir::Out) st.watched[es.v] = 1;
    refresh_observers();

    // Each kind's start (runtime.h): references start empty; state outputs are published,
    // so they are active in the first logic phase and flows conditioned on their source
    // see the start values once.
    start_kinds(*this);   // the kind table's, in its order (kinds/kinds.cmake)
    start_plugins(*this);  // what they emit is published the same way
    if (opt.huge_pages && g.bodies.size() >= kHugePagesFrom) pager = std::make_unique<Pager>();
}

std::string_view Runtime::str(int32_t name) const {
    if (name < 0) return {};
    if (name < count_of(g.names)) return g.names[name];
    const int32_t extra = name - count_of(g.names);
    return extra < count_of(extra_names) ? std::string_view(extra_names[extra]) : std::string_view{};
}

void Runtime::write_pose(SlotId slot, const Pose& p) {
    double* v = val(slot);
    for (int i = 0; i < 3; ++i) v[i] = p.p[i];
    for (int i = 0; i < 4; ++i) v[3 + i] = p.q[i];
}

void Runtime::emit_pose(SlotId slot, const Pose& p) {
    write_pose(slot, p);
    activate(slot);
}

void Runtime::refresh_observers() {
    ++st.watches;  // what a kind keeps of `watched` is out of date (kinds/graphics/run.cpp)
    st.observed_bodies.clear();
    for (BodyId b : ids_of(g.bodies)) {
        uint8_t bits = 0;
        for (int i = 0; i < 5; ++i)
            if (st.watched[comp_slot(g.bodies[b].comp, bodyslot::pose + i)]) bits |= uint8_t(1u << i);
        st.body_outputs[b] = bits;
        if (bits) st.observed_bodies.push_back(b);
    }
}

// ---- Engine ----

Engine::Engine(const Graph& g, Options opt) : rt_(std::make_unique<Runtime>(g, opt)) {}
Engine::~Engine() = default;

void Engine::step() {
    Runtime& r = *rt_;
    StepProfile& p = r.phys.workers().profile();
    if (p.on) p.begin();
    forces_step_begin(r);
    phase_physics(r);
    phase_sensors(r);
    phase_logic(r);
    p.lap(StepProfile::Logic);
    phase_petri(r);
    p.lap(StepProfile::Petri);
    phase_actuators(r);
    forces_step_end(r);
    p.lap(StepProfile::Actuators);
    if (r.pager) r.pager->tick(r.st.time);
    if (p.on) p.end();
}

StepProfile& Engine::profile() { return rt_->phys.workers().profile(); }

double Engine::time() const { return rt_->st.time; }
int64_t Engine::steps() const { return rt_->st.step; }
double Engine::dt() const { return rt_->dt; }
double Engine::rate() const { return rt_->rate; }
const Graph& Engine::graph() const { return rt_->g; }

void Engine::input(graph::SlotId slot, std::span<const double> value) {
    Runtime& r = *rt_;
    const Slot& s = r.g.slots[slot];
    int w = slot_width(s.type);
    for (size_t i = 0; std::cmp_less(i, w) && i < value.size(); ++i) r.val(slot)[i] = value[i];
    r.st.pending.push_back(slot);
}

void Engine::force(graph::SlotId slot, ForceMode mode, std::span<const double> value) {
    Runtime& r = *rt_;
    State& s = r.st;
    if (s.force_mode.empty()) {  // the first force: sized here, not in the step
        s.force_mode.assign(r.g.slots.size(), uint8_t(ForceMode::None));
        s.force_edge.assign(r.g.slots.size(), 0);
        s.force_value.assign(s.values.size(), 0);
        s.force_natural.assign(s.values.size(), 0);
        s.forced_in.reserve(r.g.slots.size());
        s.forced_out.reserve(r.g.slots.size());
    }
    const Slot& sl = r.g.slots[slot];
    const int w = slot_width(sl.type);
    if (w == 0 && mode == ForceMode::Stuck && !value.empty() && value[0] == 0) mode = ForceMode::Open;  // stuck off
    const bool out = r.tab.slot_out[slot] != 0;
    std::vector<SlotId>& list = out ? s.forced_out : s.forced_in;
    const bool listed = std::find(list.begin(), list.end(), slot) != list.end();
    if (!listed) {
        if (mode == ForceMode::None) return;  // not forced: nothing to release
        list.push_back(slot);
        if (w) std::copy(r.val(slot), r.val(slot) + w, s.force_natural.begin() + r.tab.value_adr[slot].v);
    }
    s.force_mode[slot] = uint8_t(mode);
    s.force_edge[slot] = 1;
    if (mode == ForceMode::Stuck)
        for (size_t i = 0; std::cmp_less(i, w) && i < value.size(); ++i) s.force_value[r.tab.value_adr[slot].v + i] = value[i];
}

ForceMode Engine::forced(graph::SlotId slot) const {
    const State& s = rt_->st;
    return s.force_mode.empty() ? ForceMode::None : ForceMode(s.force_mode[slot]);
}

int32_t Engine::intern(std::string_view s) {
    Runtime& r = *rt_;
    const int32_t graph_names = count_of(r.g.names);
    for (int32_t i = 0; i < graph_names; ++i)
        if (r.g.names[i] == s) return i;
    for (int32_t i = 0; i < count_of(r.extra_names); ++i)
        if (r.extra_names[i] == s) return graph_names + i;
    r.extra_names.emplace_back(s);
    return graph_names + count_of(r.extra_names) - 1;
}

std::string_view Engine::str(int32_t name) const { return rt_->str(name); }

void Engine::watch(graph::SlotId slot) {
    rt_->st.watched[slot] = 1;
    rt_->refresh_observers();
}

std::span<const double> Engine::value(graph::SlotId slot) const {
    const Slot& s = rt_->g.slots[slot];
    if (!s.value_adr.valid()) return {};
    const double* v = rt_->val(slot);
    return {v, v + slot_width(s.type)};
}

bool Engine::active(graph::SlotId slot) const {
    return (rt_->tab.slot_out[slot] ? rt_->st.seen[rt_->st.step & 1] : rt_->st.act)[slot] != 0;
}

bool Engine::emitted(graph::SlotId slot) const { return rt_->tab.slot_out[slot] && rt_->st.act[slot]; }

Pose Engine::body_pose(graph::BodyId b) const { return rt_->phys.pose(b); }
Vec3 Engine::body_com(graph::BodyId b) const { return from_bt(rt_->phys.com(b)); }
Vec3 Engine::body_velocity(graph::BodyId b) const { return from_bt(rt_->phys.velocity(b)); }
Vec3 Engine::body_angular_velocity(graph::BodyId b) const { return from_bt(rt_->phys.angular_velocity(b)); }
bool Engine::body_in_world(graph::BodyId b) const { return rt_->phys.in_world(b); }
bool Engine::body_collision(graph::BodyId b) const { return rt_->phys.collision_on(b); }
int32_t Engine::graphics_variant(graph::GraphicsId gr) const {
    const int32_t v = rt_->st.variant[gr];
    return v < 0 ? -1 : v - rt_->g.graphics[gr].variant_adr.v;
}
bool Engine::trigger_occupied(graph::TriggerId t) const { return rt_->st.triggers[t].num > 0; }
bool Engine::field_on(graph::FieldId f) const { return rt_->st.field_on[f] != 0; }
double Engine::field_speed(graph::FieldId f) const { return rt_->st.field_speed[f]; }
int64_t Engine::tokens(graph::PlaceId place) const { return rt_->st.tokens[place]; }
Pose Engine::graphics_pose(graph::GraphicsId gr) const {
    const GraphicsState& gs = rt_->st.graphics[gr];
    if (!gs.stale) return gs.pose;
    // Not kept up (GraphicsState::stale): what a visit would have computed (kinds/graphics/
    // run.cpp, advance_one), from its body's frame then and its place on the body.
    return pmul(gs.base_from_frame(on_body(rt_->g, gr)), gs.offset);
}
int64_t Engine::trigger_enters(graph::TriggerId t) const { return rt_->st.triggers[t].enters; }
int64_t Engine::issued(graph::SourceId src) const { return rt_->st.sources[src].issued; }
int64_t Engine::taken(graph::ExitId exit) const { return rt_->st.exit_count[exit]; }
double Engine::lost_at(graph::DoId object) const { return rt_->st.lost_at[object]; }
const Loss& Engine::loss(graph::DoId object) const { return rt_->st.loss[object]; }
std::span<const graph::DoId> Engine::lost() const { return rt_->st.lost; }
double Engine::stalled_for(graph::BodyId b) const {
    const State& s = rt_->st;
    return s.slow_step[b] + 1 >= s.step ? s.time - s.stall_since[b] : 0.0;
}
const Warnings& Engine::warnings() const { return rt_->st.warn; }
int Engine::regions() const { return std::max(1, rt_->phys.worlds() - 1); }
int Engine::threads() const { return rt_->phys.threads(); }

}  // namespace plant::engine
