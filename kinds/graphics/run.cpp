// The graphics' behaviour. Graphics are tracked headless: the runtime keeps every pose a
// viewer would draw. A graphics' pose is its base (the attached body, its parent graphics,
// or its own start pose / set_pose) times an animation offset. An animation's keys are poses
// relative to that base at times t (s from the animation's start), interpolated linearly
// (slerp for orientation); the last key holds after the animation ends. What each graphics
// shows is published at the start; in phase 2 the poses and the animations advance; in
// phase 5 it is moved, plays an animation or selects a variant. Its poses (State::graphics,
// variant) are shared with what follows or moves a graphics (the gripper, the source).
#include "engine/plugin.h"
#include "engine/runtime.h"
#include "engine/workers.h"

#include "graph/kinds.h"

#include <algorithm>
#include <memory>
#include <tuple>
#include <vector>

namespace plant::kinds::graphics {

using namespace plant::engine;
using graph::AnimationId, graph::GraphicsId, graph::VariantId, graph::CompKind;
namespace slot = plant::graph::graphicsslot;

namespace {

// What only the graphics' own hooks read: the order in which they are posed, their frames
// relative to what they ride on, and what each root publishes this step.
struct GraphicsData : KindData {
    std::vector<GraphicsId> order;  // parents before children
    size_t roots = 0;               // its first ones, with no parent (on a body or alone)
    // The depths in `order` (the roots, their children, theirs, ...), as [first, end).
    std::vector<std::pair<size_t, size_t>> depths;
    graph::IdVector<GraphicsId, graph::Pose> local;  // relative to the parent or attached body
    // What each slice of a depth's job published (the outputs it made active: an animation's
    // `finished`, then the pose, graphics by graphics in `order`), listed from twice its first
    // position on, and how many: per depth, kMaxSlices counts.
    std::vector<graph::SlotId> listed;
    std::vector<int32_t> counts;
    // A root on a body whose last visit changed nothing and would change nothing again (see
    // advance_one) while the body stays out of the world (kParked: no animation playing), or,
    // for a static body, stays in it and unmoved (kStanding: no animation, its base taken, its
    // last pose its pose) is not visited. A static body moves only when placed (a velocity is
    // refused: graph/range.h; Physics::statics_placed when last visited: `statics`); an input
    // that moves or animates the graphics clears its mark. A root on no body whose last visit
    // left its pose as it was, with no animation playing (kFixed: a switch's blade, a pin at
    // rest), is not visited until its base is set (set_pose clears its mark; a source issuing
    // its object sets State::graphics_placed) or an animation plays.
    // Per graphics, Graphics::body and whether it is static, in arrays of their own: the skip
    // reads them for every root each step, and a Graphics row is large.
    // advance_one and to_publish read them too, for every graphics posed: a root on a body then
    // reads nothing of its Graphics row.
    graph::IdVector<GraphicsId, graph::BodyId> body;  // per graphics: the body it is on
    graph::IdVector<GraphicsId, uint8_t> fixed;       // ... and whether that body is static
    graph::IdVector<GraphicsId, uint8_t> still;       // kMoving, kParked, kStanding
    // Per graphics, whether its pose output is watched (State::watched, read again when
    // State::watches says it changed: `watches`).
    graph::IdVector<GraphicsId, uint8_t> pose_watched;
    // Per graphics, whether only its pose output reads its pose: on a body that is not static,
    // no child graphics and no gripper following it. Such a graphics on a body in the world,
    // its output not watched and no animation playing, is passed over (GraphicsState::stale).
    graph::IdVector<GraphicsId, uint8_t> lone;
    uint64_t statics = UINT64_MAX, watches = UINT64_MAX;
};

enum : uint8_t { kMoving = 0, kParked, kStanding, kFixed };

std::unique_ptr<KindData> make_state(const graph::Graph& g) {
    auto s = std::make_unique<GraphicsData>();
    // Parents first (depth order; equal depths by id, which is deterministic).
    graph::IdVector<GraphicsId, int32_t> depth(g.graphics.count(), 0);
    for (GraphicsId i : ids_of(g.graphics)) {
        GraphicsId p = g.graphics[i].parent;
        for (size_t guard = 0; p.valid() && guard <= g.graphics.size(); ++guard) {
            depth[i]++;
            p = g.graphics[p].parent;
        }
        s->order.push_back(i);
    }
    std::stable_sort(s->order.begin(), s->order.end(), [&](GraphicsId a, GraphicsId b) { return depth[a] < depth[b]; });
    while (s->roots < s->order.size() && depth[s->order[s->roots]] == 0) ++s->roots;
    s->depths.push_back({0, s->roots});
    for (size_t k = s->roots; k < s->order.size(); ++k)
        if (k + 1 == s->order.size() || depth[s->order[k + 1]] != depth[s->order[k]])
            s->depths.push_back({s->depths.back().second, k + 1});
    s->listed.assign(2 * s->order.size(), graph::SlotId{});
    s->counts.assign(s->depths.size() * kMaxSlices, 0);
    s->local.resize(g.graphics.size());
    for (GraphicsId i : ids_of(g.graphics)) {
        const graph::Graphics& gr = g.graphics[i];
        if (gr.body.valid()) s->local[i] = on_body(g, i);
        else if (gr.parent.valid()) s->local[i] = pmul(pinv(g.graphics[gr.parent].pose), gr.pose);
    }
    s->body.assign(g.graphics.size(), graph::BodyId{});
    s->fixed.assign(g.graphics.size(), 0);
    for (GraphicsId i : ids_of(g.graphics)) {
        s->body[i] = g.graphics[i].body;
        s->fixed[i] = s->body[i].valid() && g.bodies[s->body[i]].mode == graph::BodyMode::Static;
    }
    s->still.assign(g.graphics.size(), kMoving);
    s->pose_watched.assign(g.graphics.size(), 0);
    s->lone.assign(g.graphics.size(), 0);
    for (GraphicsId i : ids_of(g.graphics)) s->lone[i] = s->body[i].valid() && !s->fixed[i];
    for (GraphicsId i : ids_of(g.graphics))
        if (g.graphics[i].parent.valid()) s->lone[g.graphics[i].parent] = 0;
    for (const graph::Gripper& gr : g.grippers)
        if (gr.graphics.valid()) s->lone[gr.graphics] = 0;
    return s;
}

GraphicsData& own(Runtime& r) { return kind_data<GraphicsData>(r.st, CompKind::Graphics); }

graph::Pose sample(const graph::Graph& g, const graph::Animation& a, double t) {
    if (a.key_num <= 0) return graph::Pose{};
    const std::span<const graph::Key> k = g.keys.slice(a.key_adr, a.key_num);
    if (t <= k[0].t) return k[0].pose;
    for (int32_t i = 0; i + 1 < a.key_num; ++i) {
        if (t > k[i + 1].t) continue;
        double span = k[i + 1].t - k[i].t;
        return span > 0 ? pinterp(k[i].pose, k[i + 1].pose, (t - k[i].t) / span) : k[i + 1].pose;
    }
    return k[a.key_num - 1].pose;
}

bool same(const graph::Pose& a, const graph::Pose& b) { return a.p == b.p && a.q == b.q; }

enum : uint8_t { kPoseChanged = 1, kFinished = 2 };

// Graphics i's pose this step; what it must publish is returned as flags (kPoseChanged,
// kFinished), published by the caller. Reads its body's or its parent's pose, writes only
// its own state: the graphics with no parent can run on any thread.
uint8_t advance_one(Runtime& r, const GraphicsData& data, GraphicsId i) {
    State& s = r.st;
    const graph::Graph& g = r.g;
    GraphicsState& gs = s.graphics[i];
    uint8_t flags = 0;
    if (const graph::BodyId body = data.body[i]; body.valid()) {  // Graphics::body
        // A parked body's graphics keep their pose: nothing to do unless animated.
        if (!r.phys.in_world(body) && gs.anim < 0) return 0;
        if (r.phys.in_world(body)) {
            // Most bodies stand still (bands, rails): their pose is taken again only when
            // their Bullet transform changed.
            const btTransform& tr = r.phys.rb(body).getWorldTransform();
            if (gs.base_fresh && tr == gs.body_tr) {
                if (gs.anim < 0) {
                    gs.prev = gs.pose;
                    return 0;  // base, offset and so the pose are as they were
                }
            } else {
                gs.body_tr = tr;
                gs.base_fresh = true;
                gs.base = pmul(r.phys.pose(body), data.local[i]);
            }
        }
    } else if (const auto parent = g.graphics[i].parent; parent.valid()) {
        gs.base = pmul(s.graphics[parent].pose, data.local[i]);
    }
    if (gs.anim >= 0) {
        const graph::Animation& a = g.animations[AnimationId(gs.anim)];
        gs.t += r.dt;
        gs.offset = sample(g, a, gs.t);
        if (gs.t + 1e-9 >= a.duration) {
            flags |= kFinished;
            gs.finished = gs.anim;
            gs.anim = -1;
        }
    }
    gs.prev = gs.pose;
    graph::Pose pose = pmul(gs.base, gs.offset);
    if (same(pose, gs.pose)) return flags;
    gs.pose = pose;
    return flags | kPoseChanged;
}

// What graphics i publishes of `flags`: a changed pose only where its output is watched.
uint8_t to_publish(const GraphicsData& data, GraphicsId i, uint8_t flags) {
    if ((flags & kPoseChanged) && !data.pose_watched[i]) flags &= ~kPoseChanged;
    return flags;
}

// What graphics i publishes, on the physics thread of its slice (its own outputs): their values
// written and their flags set, each output made active listed at `list[m++]`.
void publish(Runtime& r, GraphicsId i, uint8_t flags, graph::SlotId* list, int32_t& m) {
    const GraphicsState& gs = r.st.graphics[i];
    if (flags & kFinished) {
        const graph::SlotId x = r.g.animations[AnimationId(gs.finished)].finished_slot;
        if (r.flag_active(x)) list[m++] = x;
    }
    if (flags & kPoseChanged) {
        const graph::SlotId x = r.comp_slot(r.g.graphics[i].comp, slot::pose);
        r.write_pose(x, gs.pose);
        if (r.flag_active(x)) list[m++] = x;
    }
}

// Phase 2: the graphics with no parent (the first of `order`) in slices on the physics
// threads, then their children the same way, a depth at a time (each reads its parent's
// pose, of the depth before); each slice publishes its own and lists the outputs it made
// active. Then, on this thread, those lists join the step's: depth by depth, slice by slice,
// so in `order`.
void sense_all(Runtime& r) {
    GraphicsData& data = own(r);
    const std::vector<GraphicsId>& order = data.order;
    const bool all = data.statics != r.phys.statics_placed();
    data.statics = r.phys.statics_placed();
    if (data.watches != r.st.watches) {  // an output watched since (or the first step)
        for (GraphicsId g : ids_of(r.g.graphics))
            data.pose_watched[g] = r.st.watched[r.comp_slot(r.g.graphics[g].comp, slot::pose)];
        data.watches = r.st.watches;
    }
    // A root on a body: passed over while nothing can have changed (GraphicsData::still).
    auto root = [&r, &data, all](GraphicsId g) -> uint8_t {
        const graph::BodyId body = data.body[g];
        const uint8_t still = data.still[g];
        if ((still == kParked && !r.phys.in_world(body)) || (still == kStanding && !all && r.phys.in_world(body)) ||
            (still == kFixed && !r.st.graphics_placed[g]))
            return 0;  // what advance_one would find: nothing to do, nothing changed
        GraphicsState& gs = r.st.graphics[g];
        if (data.lone[g] && !data.pose_watched[g] && gs.anim < 0 && (gs.stale || r.phys.in_world(body))) {
            // Nothing reads its pose but its output, which is not watched: only its body's frame
            // is kept (in body_tr, while the body is in the world: a parked body's graphics keep
            // their last pose), and Engine::graphics_pose computes its pose from it as a visit
            // would. base_fresh false: body_tr is not Bullet's transform.
            if (r.phys.in_world(body)) gs.body_tr = r.phys.frame(body);
            gs.stale = true;
            gs.base_fresh = false;
            data.still[g] = kMoving;
            return 0;
        }
        if (gs.stale) {
            // Kept up again (its output watched, an animation started): base and pose as the
            // visits would have left them at the last step, so this visit publishes as one would.
            gs.stale = false;
            gs.base = gs.base_from_frame(data.local[g]);
            gs.pose = gs.prev = pmul(gs.base, gs.offset);
        }
        const uint8_t f = to_publish(data, g, advance_one(r, data, g));
        if (!body.valid()) r.st.graphics_placed[g] = 0;
        // On no body, its pose as before: pose and prev the same bits (advance_one copied one
        // into the other and computed the same pose again), so a visit would write nothing.
        data.still[g] = gs.anim >= 0              ? kMoving
                        : !body.valid()           ? (same(gs.prev, gs.pose) ? kFixed : kMoving)
                        : !r.phys.in_world(body)  ? kParked
                        : data.fixed[g] && gs.base_fresh && same(gs.prev, gs.pose) ? kStanding
                                                                                    : kMoving;
        return f;
    };
    // Depth d's graphics, their first position in `order`, and how many slices its job cuts
    // them into: the same for the job and for the publishing after it.
    auto depth = [&data](size_t d) {
        const auto [first, end] = data.depths[d];
        const size_t n = end - first;
        return std::tuple{first, n, slice_count(n, 32, n + 1)};
    };
    for (size_t d = 0; d < data.depths.size(); ++d) {
        const auto [first, n, parts] = depth(d);
        int32_t* const counts = data.counts.data() + d * kMaxSlices;
        auto poses = [&r, &data, &order, &root, d, first, n, parts, counts](int i) {
            const auto [b, e] = slice_of(n, parts, i);
            graph::SlotId* const list = data.listed.data() + 2 * (first + b);  // two a graphics at most
            int32_t m = 0;
            for (size_t k = first + b; k < first + e; ++k) {
                const uint8_t f = d == 0 ? root(order[k]) : to_publish(data, order[k], advance_one(r, data, order[k]));
                if (f) publish(r, order[k], f, list, m);
            }
            counts[i] = m;
        };
        run_slices(r.phys.workers(), parts, poses);
    }
    for (size_t d = 0; d < data.depths.size(); ++d) {
        const auto [first, n, parts] = depth(d);
        for (size_t i = 0; i < parts; ++i) {
            const graph::SlotId* const list = data.listed.data() + 2 * (first + slice_of(n, parts, i).first);
            r.st.out_list.insert(r.st.out_list.end(), list, list + data.counts[d * kMaxSlices + i]);
        }
    }
}

void play_animation(Runtime& r, AnimationId anim) {
    own(r).still[r.g.animations[anim].graphics] = kMoving;
    GraphicsState& gs = r.st.graphics[r.g.animations[anim].graphics];
    gs.anim = anim.v;  // replaces one playing: a graphics plays one animation at a time
    gs.t = 0;
}

void select_variant(Runtime& r, VariantId v) {
    const graph::Variant& var = r.g.variants[v];
    r.st.variant[var.graphics] = v.v;
    r.emit(r.comp_slot(r.g.graphics[var.graphics].comp, slot::shown), var.name.id);
}

// What each graphics shows (its variant's name, or its model) is published once at the start.
void start_all(Runtime& r) {
    for (GraphicsId i : ids_of(r.g.graphics)) {
        const int32_t v = r.st.variant[i];
        r.emit(r.comp_slot(r.g.graphics[i].comp, slot::shown),
               v >= 0 ? r.g.variants[VariantId(v)].name.id : r.g.graphics[i].model.id);
    }
}

void act_one(Runtime& r, const graph::Comp& c) {
    const GraphicsId i = graph::detail_of<graph::Graphics>(c);
    const uint8_t* a = r.st.act.slice(c.slot_adr, c.slot_num).data();
    if (a[slot::set_pose] && input_in_range(r, c, c.slot_adr + slot::set_pose)) {
        const double* v = r.val(c.slot_adr + slot::set_pose);
        r.st.graphics[i].base = graph::Pose{{v[0], v[1], v[2]}, qnormalized({v[3], v[4], v[5], v[6]})};
        r.st.graphics[i].base_fresh = false;
        own(r).still[i] = kMoving;
    }
    // Its slots after the fixed ones: an animation's play, a variant's select.
    for (graph::SlotId x : graph::IdRange<graph::SlotId>{(c.slot_adr + slot::count).v, (c.slot_adr + c.slot_num).v}) {
        const int32_t aux = r.tab.slot_aux[x];
        if (!r.st.act[x] || aux < 0) continue;
        if (const AnimationId an(aux); r.g.animations.contains(an) && r.g.animations[an].play_slot == x) play_animation(r, an);
        else if (const VariantId v(aux); r.g.variants.contains(v) && r.g.variants[v].select_slot == x) select_variant(r, v);
    }
}

}  // namespace

constexpr KindBehaviour behaviour{.make_state = make_state,
                                  .start_all = start_all,
                                  .sense_all = sense_all,
                                  .sense_segment = StepProfile::Graphics,
                                  .act_one = act_one,
                                  .acts_off_physics = true};  // its state, its animations' and variants'

}  // namespace plant::kinds::graphics
