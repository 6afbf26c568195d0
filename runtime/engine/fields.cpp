// Phase 1: kinematic motion, the conveyor law, the Bullet step.
//
// The law F = k·diag(d)·(v_tar − v) is taken in the field's local frame, with diag
// of |d| so that a field pointing along −x drives towards −x. It is linear in v, and
// stiff: explicit with k = 16 kg/s it diverges for a 20 g bottle at 150 Hz
// (k·dt/m = 5.3 > 2). Its exact one-step solution for a free body is
// e' = e·exp(−k·dt/m), and that is what we apply (see integrate_group). A field's
// max_force caps the force on each body (the band slips under a held bottle); a body in
// several fields has the largest of their limits.
//
// Bodies joined by enabled fixed joints form a rigid group and are integrated
// together, translation and rotation (6 dof): the light foot of a bottle pulls as
// hard as its main body (the force depends on velocity, not mass) and so tips the
// bottle, but the torque this creates is integrated implicitly too, so the
// bottle's rotation stays stable however light it is.
#include "engine/cells.h"
#include "engine/runtime.h"
#include "graph/kinds.h"
#include "engine/workers.h"

#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <LinearMath/btTransformUtil.h>

#include <algorithm>
#include <cmath>

namespace plant::engine {

using namespace plant::graph;

namespace {

BodyId root(State::PerBody<BodyId>& parent, BodyId x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

// Rigid groups and their member lists, rebuilt only when a joint, a dynamics mode or
// membership changed. All arrays are sized by the body count: no allocation. Only a body
// declared dynamic is ever simulated (dynamic_now): the others' entries keep their start
// (each its own group, of no mass and no members; init_state) and are not visited.
void rebuild_groups(Runtime& r) {
    State& s = r.st;
    const std::vector<BodyId>& dyn = r.tab.dyn_bodies;  // in id order
    for (BodyId b : dyn) s.group_of[b] = b;
    for (JointId j : ids_of(r.g.joints)) {
        const Joint& jt = r.g.joints[j];
        if (jt.kind != JointKind::Fixed || !r.phys.joint_on(j) || !jt.body_b.valid()) continue;
        if (!r.phys.dynamic_now(jt.body_a) || !r.phys.dynamic_now(jt.body_b)) continue;
        s.group_of[root(s.group_of, jt.body_a)] = root(s.group_of, jt.body_b);
    }
    for (BodyId b : dyn) {
        s.group_of[b] = root(s.group_of, b);
        s.group_mass[b] = 0;
        s.group_num[b] = 0;
    }
    for (BodyId b : dyn)
        if (r.phys.dynamic_now(b)) {
            s.group_mass[s.group_of[b]] += r.phys.mass(b);
            s.group_num[s.group_of[b]]++;
        }
    int32_t adr = 0;
    for (BodyId b : dyn) {
        s.group_adr[b] = adr;
        adr += s.group_num[b];
        s.group_num[b] = 0;
    }
    for (BodyId b : dyn)
        if (r.phys.dynamic_now(b)) {
            const BodyId g = s.group_of[b];
            s.group_list[s.group_adr[g] + s.group_num[g]++] = b;
        }
    s.groups_version = r.phys.version();
}

// The field's frame, recomputed only when its carrier has moved. Returns whether it changed.
bool field_frame(Runtime& r, FieldId f) {
    const Field& fd = r.g.fields[f];
    State::FieldFrame& ff = r.st.field_frame[f];
    const btTransform carrier = fd.body.valid() ? r.phys.rb(fd.body).getWorldTransform() : btTransform::getIdentity();
    if (ff.valid && carrier == ff.carrier) return false;
    ff.carrier = carrier;
    ff.pose = fd.body.valid() ? r.phys.frame(fd.body) * r.tab.field_local[f] : to_bt(fd.pose);
    const btMatrix3x3& R = ff.pose.getBasis();
    ff.K = R.scaled(r.tab.field_gain[f]) * R.transpose();  // R·diag(gain)·R^T
    const btVector3 h = to_bt(fd.extent) * btScalar(0.5);
    ff.half = h;
    State::FieldXY& xy = r.st.field_xy[f];
    xy.cx = ff.pose.getOrigin().x(), xy.cy = ff.pose.getOrigin().y();
    xy.rx = std::abs(R[0][0]) * h.x() + std::abs(R[0][1]) * h.y() + std::abs(R[0][2]) * h.z();
    xy.ry = std::abs(R[1][0]) * h.x() + std::abs(R[1][1]) * h.y() + std::abs(R[1][2]) * h.z();
    ff.valid = true;
    return true;
}

// ---- Which fields a body is in: the grid of cells.h.

// Files every field under the cells its bounding box grown by kNear covers (after any field
// frame changed): a point's cell then lists every field whose box is within kNear of it.
// Allocates only when the plant's fields cover more cells than ever before.
void build_field_cells(Runtime& r) {
    State& s = r.st;
    s.field_filed.clear();
    s.field_big.clear();
    for (FieldId f : ids_of(r.g.fields)) {
        if (r.g.fields[f].gain <= 0) continue;
        const State::FieldXY& xy = s.field_xy[f];
        file_box(xy.cx - xy.rx - kNear, xy.cy - xy.ry - kNear, xy.cx + xy.rx + kNear, xy.cy + xy.ry + kNear, f.v,
                 s.field_filed, s.field_big);
    }
    index_cells(s.field_filed, s.field_cells, s.field_cell_adr, s.field_cell_list);  // by cell, then field id
    s.field_cells_valid = true;
    ++s.field_builds;
}

constexpr btScalar kOutside = btScalar(1e-4);  // m: beyond a field's bounding box (rounding is far less)

// The law of every field body b's centre of mass is in, summed in field id order (so the sums
// do not depend on how bodies are split among threads). Returns whether any field acts on it.
bool gather_fields(Runtime& r, BodyId b) {
    State& s = r.st;
    const btVector3 p = r.phys.com(b);
    int64_t ix, iy;
    const int32_t *cell = nullptr, *cell_end = nullptr;
    if (cell_of(p.x(), p.y(), ix, iy)) {
        cell_ids(s.field_cells, s.field_cell_adr, s.field_cell_list, cell_key(ix, iy), cell, cell_end);
    } else if (!(std::abs(p.x()) < btScalar(1e30) && std::abs(p.y()) < btScalar(1e30))) {
        return false;  // NaN: in no field (the sensors take it out)
    }
    const int32_t *big = s.field_big.data(), *big_end = big + s.field_big.size();
    bool any = false;
    btVector3 v(0, 0, 0);
    bool have_v = false;
    while (cell != cell_end || big != big_end) {  // the two id-ordered lists, merged
        const FieldId f(big == big_end || (cell != cell_end && *cell < *big) ? *cell++ : *big++);  // filed as numbers
        if (!s.field_act[f]) continue;
        if (s.field_xy[f].beyond(p) > kOutside) continue;  // outside its bounding box (by more than rounding)
        const State::FieldFrame& ff = s.field_frame[f];
        const btMatrix3x3& R = ff.pose.getBasis();
        const btVector3& h = ff.half;
        const btVector3 local = (p - ff.pose.getOrigin()) * R;  // R^T (p - c): into the field frame
        if (std::abs(local.x()) > h.x() || std::abs(local.y()) > h.y() || std::abs(local.z()) > h.z()) continue;
        if (!have_v) {
            v = r.phys.velocity(b), have_v = true;
            s.ride_field[b] = f;  // the first acting field in id order: where it rides (Loss)
            s.ride_step[b] = s.step;
            s.ride_at[b] = p;
        }
        const Field& fd = r.g.fields[f];
        const btVector3& gain = r.tab.field_gain[f];
        s.field_run[b] = std::max(s.field_run[b], std::abs(double(s.field_speed[f])));
        s.body_k[b] += gain[gain.maxAxis()];
        s.body_cap[b] = std::max(s.body_cap[b], fd.max_force > 0 ? fd.max_force : HUGE_VAL);
        const btVector3 vl = v * R;
        const btVector3 target = r.tab.field_turns[f]  // the band's rigid rotation about the pivot's vertical
                                     ? turning_target(s.field_spin[f], r.tab.field_pivot[f], local, vl, btScalar(r.dt / 2))
                                     : s.field_target[f];
        s.force[b] += R * (gain * (target - vl));
        s.gain[b] += ff.K;
        any = true;
    }
    return any;
}

// The conveyor law for the dynamic bodies of one physics world (listed in world_list), from
// gathering the fields to the forces that integrate it. Touches only these bodies and their
// rigid groups (which share their world), so worlds can run on several threads at once.
void fields_of_world(Runtime& r, int32_t w) {
    State& s = r.st;
    const BodyId* list = s.world_list.data() + s.world_adr[w];
    BodyId* touched = s.touched.data() + s.world_adr[w];
    int32_t n = 0;
    for (int32_t i = 0; i < s.world_num[w]; ++i) {
        const BodyId b = list[i];
        if (gather_fields(r, b)) touched[n++] = b;
    }
    for (int32_t i = 0; i < n; ++i) {
        const BodyId b = touched[i];
        // Stalled: slower than a tenth of the running field it is in, as the last
        // physics step left it (a bottle held at a gate, a jam).
        if (s.field_run[b] > 0 && r.phys.velocity(b).length() < 0.1 * s.field_run[b]) {
            if (s.slow_step[b] + 1 < s.step) s.stall_since[b] = s.time;
            s.slow_step[b] = s.step;
        }
        s.field_run[b] = 0;
    }
    for (int32_t i = 0; i < n; ++i) {
        const BodyId b = touched[i];
        const BodyId grp = s.group_of[b];
        if (s.group_num[grp] <= 1) {
            integrate_single(r, b);
            r.phys.rb(b).activate();
        } else if (!s.group_mark[grp]) {
            s.group_mark[grp] = 1;
            integrate_group(r, grp);
        }
    }
    for (int32_t i = 0; i < n; ++i) {
        const BodyId b = touched[i];
        s.group_mark[s.group_of[b]] = 0;
        s.force[b].setZero();
        s.gain[b].setValue(0, 0, 0, 0, 0, 0, 0, 0, 0);
        s.body_k[b] = 0;
        s.body_cap[b] = 0;
    }
}

void move_kinematic(Runtime& r) {
    State& s = r.st;
    for (const BodyId b : s.commanded) {
        const Vec3 &v = s.cmd_lin[b], &w = s.cmd_ang[b];
        if (v == Vec3{0, 0, 0} && w == Vec3{0, 0, 0}) continue;
        if (!r.phys.in_world(b) || r.phys.dynamic_now(b) || s.held_by[b].valid()) continue;
        btRigidBody& rb = r.phys.write(b);
        btTransform next;
        btTransformUtil::integrateTransform(rb.getWorldTransform(), to_bt(v), to_bt(w), btScalar(r.dt), next);
        rb.setWorldTransform(next);  // Bullet derives the kinematic velocity from the move
    }
}

// Whether field f acts now (on, with a gain) and its target velocity.
void field_acts(Runtime& r, FieldId f) {
    State& s = r.st;
    const Field& fd = r.g.fields[f];
    const btVector3& gain = r.tab.field_gain[f];
    s.field_act[f] = fd.gain > 0 && s.field_on[f] && gain[gain.maxAxis()] > 0;
    if (!s.field_act[f]) return;
    if (r.tab.field_turns[f]) {
        s.field_target[f].setZero();
        s.field_spin[f] = btScalar(s.field_speed[f] / fd.radius);
    } else {
        s.field_target[f] = to_bt(fd.dir) * btScalar(s.field_speed[f]);
    }
}

}  // namespace

// Each body gathers the fields its centre of mass is in (a grid of the fields' bounding
// boxes), and each physics world's bodies are done in that world's job (fields_of_world),
// before Bullet steps it: the worlds of a plant in several regions run on the physics threads.
// The fields' frames and cells, on the calling thread. Whether any field can act.
bool prepare_fields(Runtime& r) {
    State& s = r.st;
    const Graph& g = r.g;
    // With no field there is no law, but bodies may rest where no field acts (transport.cpp):
    // the kinematic parts are looked at and the check made all the same.
    if (g.fields.empty() && !r.steady.on) return false;
    if (!g.fields.empty() && s.groups_version != r.phys.version()) rebuild_groups(r);
    // Each field's frame and whether it acts (every field, or the carried ones: State::
    // field_carried), and whether a kinematic part left its room (transport.cpp), in slices on
    // the physics threads: each writes its fields' own entries.
    const bool all = !s.field_cells_valid || s.field_statics != r.phys.statics_placed();
    const size_t nf = all ? g.fields.size() : s.field_carried.size(), nk = r.steady.on ? r.steady.kinematic.size() : 0;
    const size_t slices = slice_count(nf + nk, 32, s.slice_moved.size());
    auto frames = [&r, &s, nf, nk, all, slices](int i) {
        bool moved = false;
        const auto [fb, fe] = slice_of(nf, slices, i);
        for (size_t k = fb; k < fe; ++k) {
            const FieldId f = all ? FieldId(int32_t(k)) : s.field_carried[k];
            if (r.g.fields[f].gain > 0) moved |= field_frame(r, f);
            field_acts(r, f);
        }
        s.slice_moved[i] = moved;
        const auto [kb, ke] = slice_of(nk, slices, i);
        s.slice_left[i] = kb < ke && kinematic_left(r, kb, ke);
    };
    run_slices(r.phys.workers(), slices, frames);
    for (FieldId f : s.field_touched) {
        if (!all) field_acts(r, f);
        s.field_is_touched[f] = 0;
    }
    s.field_touched.clear();
    if (all) s.field_statics = r.phys.statics_placed();
    bool moved = !s.field_cells_valid, left = false;
    for (size_t i = 0; i < slices; ++i) moved |= s.slice_moved[i] != 0, left |= s.slice_left[i] != 0;
    if (moved) build_field_cells(r);
    check_steady(r, left);  // transport.cpp: who leaves or rejoins the solver this step
    return !g.fields.empty();
}

// The bodies the law can act on, by world (after the regions' worlds are assigned), each
// world's in id order: a counting sort in slices of the bodies on the physics threads (each
// slice counts its own bodies per world, then places them from where its part of each world's
// list starts), the counts added up on this thread in between.
void list_field_bodies(Runtime& r) {
    State& s = r.st;
    Workers& wk = r.phys.workers();
    const size_t nw = r.phys.worlds(), nb = r.tab.dyn_bodies.size(), most = kMaxSlices;
    const size_t slices = slice_count(nb, 512, most);
    int32_t* const per = s.slice_world.data();  // [slice * nw + world]
    auto counting = [&r, &s, per, nb, nw, slices](int i) {
        int32_t* const mine = per + i * nw;
        std::fill(mine, mine + nw, 0);
        const auto [b0, e0] = slice_of(nb, slices, i);
        for (size_t k = b0; k < e0; ++k) {
            const BodyId b = r.tab.dyn_bodies[k];
            // Not what a gripper or a hand holds: the band slides under it.
            const bool on = r.phys.dynamic_now(b) && !s.held_by[b].valid() && !s.in_hand[b] && !r.phys.coasting(b);
            s.law_on[b] = on;
            if (on) ++mine[r.phys.world_of(b)];
        }
    };
    run_slices(wk, slices, counting);
    // The slices' rows are read as they were written, a row at a time: each world's count,
    // where its list starts, then where each slice's part of it starts (after the parts of the
    // slices before).
    s.world_adr.assign(nw, 0);
    s.world_num.assign(nw, 0);
    s.worlds_busy.clear();
    for (size_t i = 0; i < slices; ++i)
        for (size_t w = 0; w < nw; ++w) s.world_num[w] += per[i * nw + w];
    int32_t at = 0;
    for (size_t w = 0; w < nw; ++w) {
        s.world_adr[w] = at;
        at += s.world_num[w];
        if (s.world_num[w]) s.worlds_busy.push_back(static_cast<int>(w));
    }
    s.world_next.assign(s.world_adr.begin(), s.world_adr.end());
    for (size_t i = 0; i < slices; ++i)
        for (size_t w = 0; w < nw; ++w) {
            int32_t& c = per[i * nw + w];
            const int32_t n = c;
            c = s.world_next[w];  // slice i's first body of world w goes here
            s.world_next[w] += n;
        }
    auto placing = [&r, &s, per, nb, nw, slices](int i) {
        int32_t* const next = per + i * nw;
        const auto [b0, e0] = slice_of(nb, slices, i);
        for (size_t k = b0; k < e0; ++k) {
            const BodyId b = r.tab.dyn_bodies[k];
            if (s.law_on[b]) s.world_list[next[r.phys.world_of(b)]++] = b;
        }
    };
    run_slices(wk, slices, placing);
}

void phase_physics(Runtime& r) {
    StepProfile& p = r.phys.workers().profile();
    r.phys.update_welds();  // before any force of this step
    move_kinematic(r);
    p.lap(StepProfile::Welds);
    const bool fields = prepare_fields(r);
    p.lap(StepProfile::FieldsPrep);
    if (!r.st.hands.empty()) {
        // A hand pulls after the law has acted (the forces add up in this order): the law's
        // jobs first, then the hands, then the worlds.
        if (fields) {
            list_field_bodies(r);
            auto job = [&r](int i) { fields_of_world(r, r.st.worlds_busy[i]); };
            r.phys.workers().run(int(r.st.worlds_busy.size()), job);
        }
        apply_hands(r);
        p.lap(StepProfile::FieldsPrep);
        r.phys.step(r.dt);
    } else {
        // Which world a body steps in does not change what the law does to it: the law runs
        // in each world's job, right before Bullet steps that world.
        Physics::StepHooks h;
        if (fields) {
            h.ready = [](void* c) { list_field_bodies(*static_cast<Runtime*>(c)); };
            h.before = [](void* c, int w) {
                Runtime& rt = *static_cast<Runtime*>(c);
                if (w >= 0 && w < count_of(rt.st.world_num) && rt.st.world_num[w]) fields_of_world(rt, w);
            };
            h.ctx = &r;
        }
        r.phys.step(r.dt, h);
    }
    advance_steady(r);  // what left the solver moves by the law's exact solution
    r.st.warn.missed_contacts = r.phys.missed_contacts();
    p.lap(StepProfile::Follow);
    r.st.step++;
    r.st.time = double(r.st.step) * r.dt;  // no accumulated rounding
}

}  // namespace plant::engine
