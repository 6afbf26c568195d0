// Regions: a Bullet world per group of static bodies that lie far enough from every other.
//
// Why: a plant of many lines side by side (the 1,000-bottle benchmark is 83 lines) in one Bullet
// world pays, in every step, for one broadphase tree holding every band and rail of every line,
// for Bullet's loops over all its bodies, and for a working set far larger than the caches. The
// lines do not touch: each line's statics and the bodies moving near them make a world of their
// own, stepped on as many threads as there are cores.
//
// The rule that keeps this exact. s is the largest size of a mover group (the bodies that are not
// static, joined by joints), measured as the sum of its bodies' bounding-sphere diameters.
//  - Static bodies (and the movers joined to them: anchored groups) whose bounding boxes, each
//    grown by h = s + 10 cm, overlap belong to one region; regions whose grown boxes overlap merge.
//    A region's box is its bodies' boxes plus 5 cm, so two regions' boxes are more than 2s apart.
//  - Before each step, a free mover group goes to the world of the region whose box one of its
//    bodies' bounding box (plus 5 cm) meets, in body order: a body can meet one region's box at
//    most, and two groups that meet different regions' boxes cannot touch. A group that meets no
//    box is in the void; it touches no static body. A void group that meets a mover of a region's
//    world (one that reaches out of its box) joins that world, and void groups that meet such a
//    group join it too.
//  - Anchored groups stay in their region. If one reaches out of its region's box and meets a
//    mover of another world, their contact is not simulated: counted (missed_contacts) and shown
//    in the run's summary. A static body placed by hand outside its region's box merges every
//    world into one.
// Results do not depend on the number of threads. They differ from a single world's in the last
// digits: Bullet's order of pairs and islands is per world.
#include "engine/physics.h"

#include "engine/pose.h"
#include "engine/workers.h"

#include <BulletCollision/BroadphaseCollision/btBroadphaseInterface.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletDynamics/ConstraintSolver/btTypedConstraint.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace plant::engine {

using namespace plant::graph;

namespace {

constexpr btScalar kGrow = btScalar(0.10);  // h = s + kGrow
constexpr btScalar kBox = btScalar(0.05);   // a region's box around its bodies' boxes
constexpr btScalar kNear = btScalar(0.05);  // a mover's box, grown: Bullet pairs bodies a little apart

struct Box {
    btVector3 lo, hi;
};

bool overlap(const btVector3& alo, const btVector3& ahi, const btVector3& blo, const btVector3& bhi) {
    return alo.x() <= bhi.x() && blo.x() <= ahi.x() && alo.y() <= bhi.y() && blo.y() <= ahi.y() &&
           alo.z() <= bhi.z() && blo.z() <= ahi.z();
}

bool inside(const btVector3& lo, const btVector3& hi, const btVector3& blo, const btVector3& bhi) {
    return lo.x() >= blo.x() && lo.y() >= blo.y() && lo.z() >= blo.z() && hi.x() <= bhi.x() &&
           hi.y() <= bhi.y() && hi.z() <= bhi.z();
}

struct UnionFind {
    std::vector<int32_t> up;
    explicit UnionFind(size_t n) : up(n) { std::iota(up.begin(), up.end(), 0); }
    int32_t find(int32_t a) {
        while (up[a] != a) a = up[a] = up[up[a]];
        return a;
    }
    bool unite(int32_t a, int32_t b) {
        a = find(a), b = find(b);
        if (a == b) return false;
        if (b < a) std::swap(a, b);
        up[b] = a;  // the lower index is the root
        return true;
    }
};

// Unites the boxes (grown by h) that overlap, through a grid of cells: each box is filed under
// the cells it covers, and only boxes sharing a cell are compared. Boxes covering very many
// cells are compared with every box.
bool unite_overlapping(const std::vector<Box>& boxes, const std::vector<int32_t>& ids, btScalar h, UnionFind& uf) {
    const btScalar cell = std::max(btScalar(1), 4 * h);
    std::vector<std::pair<uint64_t, int32_t>> filed;
    std::vector<int32_t> big;
    // The loader keeps places within 100 km (graph/range.h), but a run can take a body anywhere
    // finite (1e19 m, say): cell indices are clamped so that they stay far inside int64_t, and a
    // box that far out covers more cells than any other.
    auto idx = [cell](btScalar v) {
        return int64_t(std::clamp(std::floor(v / cell), btScalar(-1e12), btScalar(1e12)));
    };
    for (int32_t i : ids) {
        const Box& b = boxes[i];
        // A box Bullet computed as infinite or NaN (a centre of mass 1e308 m off its body, beyond
        // float's range, say) has no cells: it is compared with every box (and a NaN box
        // overlaps none). Only finite numbers reach idx.
        if (!std::isfinite(b.lo.x() + b.lo.y() + b.lo.z() + b.hi.x() + b.hi.y() + b.hi.z())) {
            big.push_back(i);
            continue;
        }
        const int64_t x0 = idx(b.lo.x() - h), x1 = idx(b.hi.x() + h), y0 = idx(b.lo.y() - h), y1 = idx(b.hi.y() + h),
                      z0 = idx(b.lo.z() - h), z1 = idx(b.hi.z() + h);
        if (double(x1 - x0 + 1) * double(y1 - y0 + 1) * double(z1 - z0 + 1) > 4096) {
            big.push_back(i);
            continue;
        }
        for (int64_t x = x0; x <= x1; ++x)
            for (int64_t y = y0; y <= y1; ++y)
                for (int64_t z = z0; z <= z1; ++z)
                    filed.emplace_back((uint64_t(x & 0x1fffff) << 42) | (uint64_t(y & 0x1fffff) << 21) | uint64_t(z & 0x1fffff), i);
    }
    std::sort(filed.begin(), filed.end());
    const btVector3 g(h, h, h);
    bool merged = false;
    auto test = [&](int32_t a, int32_t b) {
        const Box &p = boxes[a], &q = boxes[b];
        if (overlap(p.lo - g, p.hi + g, q.lo - g, q.hi + g)) merged |= uf.unite(a, b);
    };
    for (size_t i = 0; i < filed.size();) {
        size_t j = i;
        while (j < filed.size() && filed[j].first == filed[i].first) ++j;
        for (size_t a = i; a < j; ++a)
            for (size_t b = a + 1; b < j; ++b) test(filed[a].second, filed[b].second);
        i = j;
    }
    for (int32_t a : big)
        for (int32_t b : ids)
            if (a != b) test(a, b);
    return merged;
}

}  // namespace

void Physics::find_regions(bool split) {
    const int32_t nb = g_.bodies.count();

    // Groups: bodies joined by joints, numbered in order of their first body. The union-find
    // works on the bodies' numbers.
    UnionFind joined(nb);
    for (const Joint& j : g_.joints)
        if (j.body_b.valid()) joined.unite(j.body_a.v, j.body_b.v);
    group_of_.assign(nb, -1);
    std::vector<int32_t> first_of(nb, -1);
    int32_t groups = 0;
    for (BodyId b : ids_of(g_.bodies)) {
        int32_t r = joined.find(b.v);
        if (first_of[r] < 0) first_of[r] = groups++;
        group_of_[b] = first_of[r];
    }
    group_bodies_.adr.assign(groups, 0);
    group_bodies_.num.assign(groups, 0);
    for (BodyId b : ids_of(g_.bodies)) ++group_bodies_.num[group_of_[b]];
    for (int32_t gi = 1; gi < groups; ++gi) group_bodies_.adr[gi] = group_bodies_.adr[gi - 1] + group_bodies_.num[gi - 1];
    group_bodies_.list.assign(nb, BodyId{});
    {
        std::vector<int32_t> fill(groups, 0);
        for (BodyId b : ids_of(g_.bodies)) {
            const int32_t gi = group_of_[b];
            group_bodies_.list[group_bodies_.adr[gi] + fill[gi]++] = b;
        }
    }
    anchored_.assign(groups, 0);
    movers_.clear();
    for (BodyId b : ids_of(g_.bodies)) {
        if (declared_static(b)) anchored_[group_of_[b]] = 1;
        else movers_.push_back(b);
    }
    anchored_movers_.clear();
    for (BodyId b : movers_)
        if (anchored_[group_of_[b]]) anchored_movers_.push_back(b);
    void_mark_.assign(groups, 0);
    free_to_.clear();
    free_groups_.clear();
    for (int32_t gi = 0; gi < groups; ++gi)
        if (!anchored_[gi]) free_groups_.push_back(gi);
    free_to_.assign(free_groups_.size(), {0, 0});
    free_moves_.assign(kMaxSlices, 0);
    free_at_.assign(groups, -1);
    for (size_t k = 0; k < free_groups_.size(); ++k) free_at_[free_groups_[k]] = int32_t(k);
    // Every group looked at once; no bit past the last group.
    free_live_.assign((free_groups_.size() + 63) / 64, ~uint64_t(0));
    if (free_groups_.size() % 64) free_live_.back() = (uint64_t(1) << (free_groups_.size() % 64)) - 1;
    // assign_worlds' scratch, at most every free group and every mover: the step allocates nothing.
    void_groups_.reserve(free_groups_.size());
    void_home_.reserve(free_groups_.size());
    near_.reserve(movers_.size());

    // s: the largest free group.
    btScalar s = 0;
    for (int32_t gi : free_groups_) {
        btScalar size = 0;
        for (BodyId b : group_bodies_[gi]) {
            btVector3 c;
            btScalar r = 0;
            bodies_[b]->getCollisionShape()->getBoundingSphere(c, r);
            size += 2 * r;
        }
        s = std::max(s, size);
    }
    // A body whose centre of mass lies absurdly far off (1e32 m) has an infinite bounding
    // sphere: then every region is one (a margin that covers the plant), and no box is grown
    // by infinity (inf - inf is NaN).
    const btScalar h = std::isfinite(s) ? s + kGrow : btScalar(1e30);

    // Regions: the anchored groups' bodies, clustered (by their numbers, as the boxes are).
    std::vector<Box> boxes(nb);
    std::vector<int32_t> items;
    for (BodyId b : ids_of(g_.bodies)) {
        Box& box = boxes[index(b)];
        aabb(b, 0, box.lo, box.hi);
        if (!(box.lo.x() <= box.hi.x()))  // a shape without extent: its origin
            box.lo = box.hi = bodies_[b]->getWorldTransform().getOrigin();
        if (anchored_[group_of_[b]]) items.push_back(b.v);
    }
    UnionFind cluster(nb);
    for (int32_t b : items) cluster.unite(b, group_bodies_[group_of_[BodyId(b)]].front().v);
    unite_overlapping(boxes, items, h, cluster);
    std::vector<Box> cbox(nb);
    std::vector<int32_t> roots;
    do {  // clusters' boxes, kept at their roots (their lowest bodies), until none overlap
        roots.clear();
        for (int32_t b : items)
            if (cluster.find(b) == b) roots.push_back(b), cbox[b] = boxes[b];
        for (int32_t b : items) {
            const int32_t r = cluster.find(b);
            cbox[r].lo.setMin(boxes[b].lo);
            cbox[r].hi.setMax(boxes[b].hi);
        }
    } while (unite_overlapping(cbox, roots, h, cluster));

    const int32_t regions = count_of(roots);
    world_of_.assign(nb, 0);
    // Sweep-and-prune has a fixed number of handles per world, and bodies move between worlds:
    // with it, one world.
    if (regions <= 1 || !split) {
        worlds_.resize(1);
        slice_movers_.assign(kMaxSlices, 0);
        void_ = -1;
        return;
    }
    worlds_.resize(regions + 1);
    slice_movers_.assign(kMaxSlices * worlds_.size(), 0);
    by_movers_.resize(worlds_.size());
    std::iota(by_movers_.begin(), by_movers_.end(), 0);
    to_step_.reserve(worlds_.size());
    void_ = regions;
    std::vector<int32_t> region_of_root(nb, -1);
    for (int32_t i = 0; i < regions; ++i) {  // roots are in body order
        region_of_root[roots[i]] = i;
        const btVector3 m(kBox, kBox, kBox);
        worlds_[i].lo = cbox[roots[i]].lo - m;
        worlds_[i].hi = cbox[roots[i]].hi + m;
    }
    for (int32_t b : items) world_of_[BodyId(b)] = region_of_root[cluster.find(b)];
    for (int32_t gi : free_groups_) {
        int to = void_;
        for (BodyId b : group_bodies_[gi]) {
            if (to != void_) break;
            world_of_[b] = void_;
            to = home(b);
        }
        for (BodyId b : group_bodies_[gi]) world_of_[b] = to;
    }
}

void Physics::aabb(BodyId b, btScalar grow, btVector3& lo, btVector3& hi) const {
    bodies_[b]->getCollisionShape()->getAabb(bodies_[b]->getWorldTransform(), lo, hi);
    const btVector3 m(grow, grow, grow);
    lo -= m, hi += m;
}

int Physics::home(BodyId b) const {
    const int cur = world_of_[b];
    const btVector3& o = bodies_[b]->getWorldTransform().getOrigin();
    if (cur != void_ && inside(o, o, worlds_[cur].lo, worlds_[cur].hi)) return cur;  // most
    btVector3 lo, hi;
    aabb(b, kNear, lo, hi);
    if (cur != void_ && overlap(lo, hi, worlds_[cur].lo, worlds_[cur].hi)) return cur;
    for (int w = 0; w < void_; ++w)
        if (overlap(lo, hi, worlds_[w].lo, worlds_[w].hi)) return w;
    return void_;
}

void Physics::assign_worlds() {
    auto present = [this](BodyId b) { return in_world_[b] && !carried(b); };  // and in Bullet's
    auto box = [this](BodyId b, btVector3& lo, btVector3& hi) { aabb(b, kNear, lo, hi); };
    // Free groups: to the region whose box they meet. Where each goes, on the physics threads
    // in slices of the groups (a group's decision reads its own bodies' worlds, which only its
    // own move changes), and whether that is where it is already; the moves on this thread in
    // group order.
    constexpr int kStay = -3, kParked = -2, kVoid = -1;
    auto where = [this, &present](int32_t gi) {
        bool any = false;
        for (BodyId b : group_bodies_[gi]) {
            if (!present(b)) continue;
            any = true;
            const int h = home(b);
            if (h != void_) return h;
        }
        return any ? kVoid : kParked;  // parked: waits in the void's world, which is not stepped for it
    };
    // Only the groups whose bit in free_live_ is set (a pool's bottles wait parked: at 1,000
    // bottles in circulation, 3,320 groups, 800 of them in the world), in slices of the bits'
    // words; a group found parked in the void's world has its bit cleared by its slice.
    const size_t words = free_live_.size();
    const size_t slices = slice_count(words, 1, kMaxSlices);
    auto decide = [this, &where, words, slices](int i) {
        const auto [w0, w1] = slice_of(words, slices, i);
        const size_t b = w0 * 64;  // the slice's first group's position: its moves are listed from there
        // The live positions in order, one iterator kAhead ahead of the other to ask for the
        // group's first body (a body's pose is a miss each; a hint: no result changes).
        constexpr int kAhead = 8;
        size_t aw = w0;
        uint64_t abits = aw < w1 ? free_live_[aw] : 0;
        auto ask_ahead = [&] {  // for the next live position's group, if any
            while (abits == 0) {
                if (++aw >= w1) return;
                abits = free_live_[aw];
            }
            ask_origin(group_bodies_[free_groups_[aw * 64 + size_t(__builtin_ctzll(abits))]].front());
            abits &= abits - 1;
        };
        for (int a = 0; a < kAhead; ++a) ask_ahead();
        int32_t moves = 0;
        for (size_t w = w0; w < w1; ++w) {
            for (uint64_t bits = free_live_[w]; bits != 0; bits &= bits - 1) {
                const size_t k = w * 64 + size_t(__builtin_ctzll(bits));
                ask_ahead();
                const int32_t gi = free_groups_[k];
                const int to = where(gi), at = world_of_[group_bodies_[gi].front()];
                // A parked group waits in the void's world; a void group is placed below.
                const int go = to == kParked ? (at != void_ ? void_ : kStay) : (to == kVoid || at != to ? to : kStay);
                if (go != kStay) free_to_[b + size_t(moves++)] = {int32_t(k), go};
                if (to == kParked) free_live_[w] &= ~(uint64_t(1) << (k % 64));  // in the void's world after the moves
            }
        }
        free_moves_[i] = moves;
    };
    run_slices(*workers_, slices, decide);
    void_groups_.clear();
    for (size_t i = 0; i < slices; ++i) {
        const size_t first = slice_of(words, slices, i).first * 64;
        for (size_t j = first; j < first + size_t(free_moves_[i]); ++j) {
            const auto [k, to] = free_to_[j];
            if (to == kVoid) void_groups_.push_back(free_groups_[k]);
            else move_group(free_groups_[k], to);
        }
    }
    // Void groups join the world of a mover they meet (of a region's world, or a void group
    // that joined one before), in turn until none joins.
    void_home_.assign(void_groups_.size(), void_);
    if (!void_groups_.empty()) {
        for (int32_t gi : void_groups_) void_mark_[gi] = 1;
        near_.clear();
        for (BodyId m : movers_) {
            if (!present(m) || void_mark_[group_of_[m]]) continue;
            Near n;
            box(m, n.lo, n.hi);
            n.world = world_of_[m];
            near_.push_back(n);
        }
        for (bool changed = true; changed;) {
            changed = false;
            for (size_t i = 0; i < void_groups_.size(); ++i) {
                if (void_home_[i] != void_) continue;
                const int32_t gi = void_groups_[i];
                const size_t known = near_.size();
                for (BodyId b : group_bodies_[gi]) {
                    if (!present(b)) continue;
                    btVector3 lo, hi;
                    box(b, lo, hi);
                    for (size_t k = 0; k < known; ++k) {
                        if (!overlap(lo, hi, near_[k].lo, near_[k].hi)) continue;
                        if (void_home_[i] == void_) void_home_[i] = near_[k].world, changed = true;
                        else if (void_home_[i] != near_[k].world) ++missed_;
                    }
                }
                if (void_home_[i] == void_) continue;
                for (BodyId b : group_bodies_[gi]) {
                    if (!present(b)) continue;
                    Near n;
                    box(b, n.lo, n.hi);
                    n.world = void_home_[i];
                    near_.push_back(n);
                }
            }
        }
        for (int32_t gi : void_groups_) void_mark_[gi] = 0;
    }
    for (size_t i = 0; i < void_groups_.size(); ++i)
        if (world_of_[group_bodies_[void_groups_[i]].front()] != void_home_[i])
            move_group(void_groups_[i], void_home_[i]);
    // Anchored movers reaching out of their region's box: contacts with other worlds' movers.
    for (BodyId b : anchored_movers_) {
        if (!present(b)) continue;
        btVector3 lo, hi;
        box(b, lo, hi);
        const World& own = worlds_[world_of_[b]];
        if (inside(lo, hi, own.lo, own.hi)) continue;
        for (BodyId m : movers_) {
            if (!present(m) || world_of_[m] == world_of_[b]) continue;
            btVector3 mlo, mhi;
            box(m, mlo, mhi);
            if (overlap(lo, hi, mlo, mhi)) ++missed_;
        }
    }
    // Each world's movers (coasting ones are moved by us: transport.cpp), counted in slices of
    // movers_ on the physics threads, each slice into its own row; then the rows summed.
    const size_t nw = worlds_.size(), nm = movers_.size();
    const size_t mslices = slice_count(nm, 1024, kMaxSlices);  // slice_movers_ holds as many rows
    auto count = [this, nw, nm, mslices](int i) {
        int32_t* row = slice_movers_.data() + i * nw;
        std::fill(row, row + nw, 0);
        const auto [b, e] = slice_of(nm, mslices, i);
        for (size_t k = b; k < e; ++k)
            if (in_world_[movers_[k]] && !coasting(movers_[k])) ++row[world_of_[movers_[k]]];
    };
    run_slices(*workers_, mslices, count, "engine::Physics::assign_worlds: movers counted by world");
    for (size_t w = 0; w < nw; ++w) worlds_[w].movers = 0;
    for (size_t i = 0; i < mslices; ++i)  // the rows as they were written, a row at a time
        for (size_t w = 0; w < nw; ++w) worlds_[w].movers += slice_movers_[i * nw + w];
    for (size_t w = 0; w < nw; ++w) worlds_[w].active = worlds_[w].movers > 0;
}

// One world for everything from now on: the regions' boxes no longer hold (a static body was
// placed outside its region's box).
void Physics::merge_worlds() {
    if (void_ < 0) return;
    const int32_t groups = count_of(group_bodies_.adr);
    for (int32_t gi = 0; gi < groups; ++gi)
        if (world_of_[group_bodies_[gi].front()] != 0) move_group(gi, 0);
    worlds_.resize(1);  // the others are empty now
    void_ = -1;
}

void Physics::placed_static(BodyId b) {
    btVector3 lo, hi;
    aabb(b, 0, lo, hi);
    const World& w = world_at(b);
    if (!inside(lo, hi, w.lo, w.hi)) merge_worlds();
}

// Takes a group's bodies and joints out of their Bullet world and puts them into another, as
// they were: filters, parked or not, joints in or out.
void Physics::move_group(int32_t gi, int to) {
    std::vector<JointId>& joints = moved_joints_;
    joints.clear();
    for (BodyId b : group_bodies_[gi]) {
        if (body_joints_.num.empty()) break;
        for (JointId j : body_joints_[b]) {
            if (!joint_in_[j] || std::find(joints.begin(), joints.end(), j) != joints.end()) continue;
            world_at(g_.joints[j].body_a).world->removeConstraint(joints_[j].get());
            joints.push_back(j);
        }
    }
    for (BodyId b : group_bodies_[gi]) {
        if (!carried(b)) world_at(b).world->removeRigidBody(bodies_[b].get());
        world_of_[b] = to;
        if (carried(b)) continue;
        // Bullet files a body as static or not when it joins: a parked one joins as if it were
        // in the world, and one off the solver (steady transport) as if it were on it, so that
        // it is simulated once it is inserted again, or lands (set_mode_flags counts the write).
        const int state = bodies_[b]->getActivationState();
        const bool parked = !in_world_[b];
        const uint8_t off = coast_[b];
        in_world_[b] = 1;
        coast_[b] = 0;
        set_mode_flags(b);
        add_to_world(b, !parked && off != kCoasting);  // a resting body keeps its pairs
        in_world_[b] = !parked;
        coast_[b] = off;
        set_mode_flags(b);
        bodies_[b]->forceActivationState(state);
        if (parked || off == kCoasting) park(b);
    }
    for (JointId j : joints) world_at(g_.joints[j].body_a).world->addConstraint(joints_[j].get(), true);
}

}  // namespace plant::engine
