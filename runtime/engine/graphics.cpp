// Graphics are tracked headless: the runtime keeps every pose a viewer would draw.
// A graphics' pose is its base (the attached body, its parent graphics, or its own
// start pose / set_pose) times an animation offset. An animation's keys are poses
// relative to that base at times t (s from the animation's start), interpolated
// linearly (slerp for orientation); the last key holds after the animation ends.
#include "engine/runtime.h"
#include "engine/workers.h"

#include "graph/kinds.h"

namespace plant::engine {

using namespace plant::graph;

namespace {

Pose sample(const Graph& g, const Animation& a, double t) {
    if (a.key_num <= 0) return Pose{};
    const std::span<const Key> k = g.keys.slice(a.key_adr, a.key_num);
    if (t <= k[0].t) return k[0].pose;
    for (int32_t i = 0; i + 1 < a.key_num; ++i) {
        if (t > k[i + 1].t) continue;
        double span = k[i + 1].t - k[i].t;
        return span > 0 ? pinterp(k[i].pose, k[i + 1].pose, (t - k[i].t) / span) : k[i + 1].pose;
    }
    return k[a.key_num - 1].pose;
}

bool same(const Pose& a, const Pose& b) { return a.p == b.p && a.q == b.q; }

}  // namespace

namespace {

enum : uint8_t { kPoseChanged = 1, kFinished = 2 };

// Graphics i's pose this step; what it must publish is returned as flags (kPoseChanged,
// kFinished), published by the caller. Reads its body's or its parent's pose, writes only
// its own state: the graphics with no parent can run on any thread.
uint8_t advance_one(Runtime& r, int32_t i) {
    State& s = r.st;
    const Graph& g = r.g;
    const Graphics& gr = g.graphics[i];
    GraphicsState& gs = s.graphics[i];
    uint8_t flags = 0;
    if (gr.body >= 0) {
        // A parked body's graphics keep their pose: nothing to do unless animated.
        if (!r.phys.in_world(gr.body) && gs.anim < 0) return 0;
        if (r.phys.in_world(gr.body)) {
            // Most bodies stand still (bands, rails): their pose is taken again only when
            // their Bullet transform changed.
            const btTransform& tr = r.phys.rb(gr.body).getWorldTransform();
            if (gs.base_fresh && tr == gs.body_tr) {
                if (gs.anim < 0) {
                    gs.prev = gs.pose;
                    return 0;  // base, offset and so the pose are as they were
                }
            } else {
                gs.body_tr = tr;
                gs.base_fresh = true;
                gs.base = pmul(r.phys.pose(gr.body), r.tab.graphics_local[i]);
            }
        }
    } else if (gr.parent >= 0) {
        gs.base = pmul(s.graphics[gr.parent].pose, r.tab.graphics_local[i]);
    }
    if (gs.anim >= 0) {
        const Animation& a = g.animations[gs.anim];
        gs.t += r.dt;
        gs.offset = sample(g, a, gs.t);
        if (gs.t + 1e-9 >= a.duration) {
            flags |= kFinished;
            gs.finished = gs.anim;
            gs.anim = -1;
        }
    }
    gs.prev = gs.pose;
    Pose pose = pmul(gs.base, gs.offset);
    if (same(pose, gs.pose)) return flags;
    gs.pose = pose;
    return flags | kPoseChanged;
}

void publish(Runtime& r, int32_t i, uint8_t flags) {
    GraphicsState& gs = r.st.graphics[i];
    if (flags & kFinished) r.activate(r.g.animations[gs.finished].finished_slot);
    if (flags & kPoseChanged) {
        const int32_t out = r.comp_slot(r.g.graphics[i].comp, graphicsslot::pose);
        if (r.st.watched[out]) r.emit_pose(out, gs.pose);
    }
}

}  // namespace

// The graphics with no parent (the first of graphics_order) in slices on the physics threads;
// then, in graphics_order on this thread, what they publish and the children (parents first).
void advance_graphics(Runtime& r) {
    const std::vector<int32_t>& order = r.tab.graphics_order;
    const size_t roots = r.tab.graphics_roots;
    std::vector<uint8_t>& flags = r.st.graphics_flags;
    const size_t slices = slice_count(r.phys.workers(), roots, 256, roots + 1);
    auto poses = [&r, &order, &flags, roots, slices](int i) {
        const auto [b, e] = slice_of(roots, slices, i);
        for (size_t k = b; k < e; ++k) flags[k] = advance_one(r, order[k]);
    };
    run_slices(r.phys.workers(), slices, poses);
    for (size_t k = 0; k < roots; ++k)
        if (flags[k]) publish(r, order[k], flags[k]);
    for (size_t k = roots; k < order.size(); ++k) {
        const uint8_t f = advance_one(r, order[k]);
        if (f) publish(r, order[k], f);
    }
}

void play_animation(Runtime& r, int32_t anim) {
    GraphicsState& gs = r.st.graphics[r.g.animations[anim].graphics];
    gs.anim = anim;  // replaces one playing: a graphics plays one animation at a time
    gs.t = 0;
}

void select_variant(Runtime& r, int32_t v) {
    const Variant& var = r.g.variants[v];
    r.st.variant[var.graphics] = v;
    r.emit(r.comp_slot(r.g.graphics[var.graphics].comp, graphicsslot::shown), var.name.id);
}

// What each graphics shows (its variant's name, or its model) is published once at the start.
void start_graphics(Runtime& r) {
    for (size_t i = 0; i < r.g.graphics.size(); ++i) {
        const int32_t v = r.st.variant[i];
        r.emit(r.comp_slot(r.g.graphics[i].comp, graphicsslot::shown),
               v >= 0 ? r.g.variants[v].name.id : r.g.graphics[i].model.id);
    }
}

void act_graphics(Runtime& r, const Comp& c, int32_t i) {
    const uint8_t* a = r.st.act.data() + c.slot_adr;
    if (a[graphicsslot::set_pose] && input_in_range(r, c.slot_adr + graphicsslot::set_pose)) {
        const double* v = r.val(c.slot_adr + graphicsslot::set_pose);
        r.st.graphics[i].base = Pose{{v[0], v[1], v[2]}, qnormalized({v[3], v[4], v[5], v[6]})};
        r.st.graphics[i].base_fresh = false;
    }
    for (int32_t x = c.slot_adr + graphicsslot::count; x < c.slot_adr + c.slot_num; ++x) {
        const int32_t aux = r.tab.slot_aux[x];
        if (!r.st.act[x] || aux < 0) continue;
        if (const AnimationId a(aux); r.g.animations.contains(a) && r.g.animations[a].play_slot == x) play_animation(r, aux);
        else if (const VariantId v(aux); r.g.variants.contains(v) && r.g.variants[v].select_slot == x) select_variant(r, aux);
    }
}

}  // namespace plant::engine
