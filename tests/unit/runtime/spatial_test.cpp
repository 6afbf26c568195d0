// The body index (engine/spatial.h): after every refresh, a box's lookup finds exactly the
// bodies a scan of all of them finds, while bottles on two belts running opposite ways pass
// each other in x all the time (so the slices' own sorts overlap and the whole list is sorted
// again; docs/runtime.md, "How the work is divided among the threads").
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/runtime.h"
#include "engine/workers.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace plant;
using namespace plant::test;

namespace {

// Bottles on two belts running opposite ways: they pass each other in x all the time.
constexpr const char* kTwoBelts = R"(
import std.belts, std.bottle
plant Passing {
    a: Belt(length = 3 m, speed = 50 cm/s)
    b: Belt(length = 3 m, speed = -50 cm/s) at (0 m, 40 cm, 0 m)
    for i in 0 .. 24 {
        pa[i]: Bottle at (10 cm + i * 12 cm, 0 m, 0 m)
        pb[i]: Bottle at (10 cm + i * 12 cm, 40 cm, 0 m)
    }
}
)";

// The dynamic bodies in the world, in id order.
std::vector<graph::BodyId> in_world(const engine::Runtime& r) {
    std::vector<graph::BodyId> in;
    for (graph::BodyId b : r.tab.dyn_bodies)
        if (r.phys.in_world(b)) in.push_back(b);
    return in;
}

// What a box's lookup finds, and what a scan of `in` finds (centres with x in [xlo, xhi], in a
// cell of 1 m in y that [ylo, yhi] touches), each sorted by id.
std::pair<std::vector<int32_t>, std::vector<int32_t>> lookup_and_scan(const engine::Runtime& r,
                                                                      const std::vector<graph::BodyId>& in, btScalar xlo,
                                                                      btScalar xhi, btScalar ylo, btScalar yhi) {
    auto cell = [](btScalar y) { return int(std::floor(y)); };
    std::vector<int32_t> found, scanned;
    r.index.for_each(xlo, xhi, ylo, yhi, [&](graph::BodyId b) { found.push_back(b.v); });
    for (graph::BodyId b : in) {
        const btVector3& p = r.index.com(b);
        if (p.x() >= xlo && p.x() <= xhi && cell(p.y()) >= cell(ylo) && cell(p.y()) <= cell(yhi)) scanned.push_back(b.v);
    }
    std::sort(found.begin(), found.end());
    std::sort(scanned.begin(), scanned.end());
    return {found, scanned};
}

}  // namespace

TEST_CASE("body index: a box finds what a scan of every body finds, as bottles pass each other") {
    const graph::Graph g = compiled_text(kTwoBelts, "spatial_passing.plant");
    engine::Engine e(g);
    engine::Runtime& r = e.internals();
    const std::vector<graph::BodyId>& dyn = r.tab.dyn_bodies;
    REQUIRE(dyn.size() >= 64);  // two slices of the index at least
    std::vector<btScalar> x0;  // each body's x at the start
    for (graph::BodyId b : dyn) x0.push_back(r.phys.com(b).x());
    int64_t checked = 0;
    for (int step = 0; step < 150 * 3; ++step) {
        e.step();
        r.index.refresh(r.phys, r.phys.workers());  // what the step's last refresh made, again
        const std::vector<graph::BodyId> in = in_world(r);
        for (size_t k = 0; k < in.size(); k += 3) {
            const btVector3 c0 = r.index.com(in[k]);
            const auto [found, scanned] = lookup_and_scan(r, in, c0.x() - 0.3f, c0.x() + 0.3f, c0.y() - 0.1f, c0.y() + 0.1f);
            CAPTURE(step);
            REQUIRE(found == scanned);
            ++checked;
        }
    }
    CHECK(checked > 150 * 3 * 10);
    // The bottles passed each other: pairs whose order in x is now the other way round.
    int64_t passed = 0;
    for (size_t i = 0; i < dyn.size(); ++i)
        for (size_t j = 0; j < dyn.size(); ++j)
            passed += x0[i] < x0[j] - 0.05f && r.phys.com(dyn[i]).x() > r.phys.com(dyn[j]).x() + 0.05f;
    CHECK(passed > 100);
}

// The lookup searches only the run of the list each cell covers (Spatial's table of where each
// cell's run begins): belts in cells far apart, with empty cells between them and beyond, and
// boxes that start and end in empty cells, below the lowest body's cell, above the highest, and
// across all of them.
TEST_CASE("body index: a box finds what a scan finds in cells far apart, empty and beyond the bodies") {
    const graph::Graph g = compiled_text(R"(
import std.belts, std.bottle
plant Cells {
    a: Belt(length = 2 m, speed = 50 cm/s) at (0 m, -3.5 m, 0 m)
    b: Belt(length = 2 m, speed = -50 cm/s) at (0 m, 0 m, 0 m)
    d: Belt(length = 2 m, speed = 50 cm/s) at (0 m, 2.5 m, 0 m)
    for i in 0 .. 12 {
        pa[i]: Bottle at (10 cm + i * 14 cm, -3.5 m, 0 m)
        pb[i]: Bottle at (10 cm + i * 14 cm, 0 m, 0 m)
        pd[i]: Bottle at (10 cm + i * 14 cm, 2.5 m, 0 m)
    }
}
)", "spatial_cells.plant");
    engine::Engine e(g);
    engine::Runtime& r = e.internals();
    // y ranges: around each belt, empty cells only, below and above every body, and all of them.
    const std::vector<std::pair<btScalar, btScalar>> ys = {{-3.6f, -3.4f}, {-0.1f, 0.1f}, {2.4f, 2.6f}, {-2.5f, -1.2f},
                                                           {0.5f, 1.9f},   {-9.f, -5.f},  {6.f, 9.f},  {-9.f, 9.f},
                                                           {-4.f, 0.05f},  {-0.05f, 3.f}};
    int64_t found_some = 0, checked = 0;
    for (int step = 0; step < 150; ++step) {
        e.step();
        r.index.refresh(r.phys, r.phys.workers());
        const std::vector<graph::BodyId> in = in_world(r);
        REQUIRE(in.size() >= 72);
        for (const auto& [ylo, yhi] : ys)
            for (btScalar x = -0.5f; x < 2.5f; x += 0.4f) {
                const auto [found, scanned] = lookup_and_scan(r, in, x, x + 0.5f, ylo, yhi);
                CAPTURE(step);
                CAPTURE(ylo);
                CAPTURE(x);
                REQUIRE(found == scanned);
                found_some += !found.empty();
                ++checked;
            }
    }
    CHECK(checked == 150 * 10 * 8);
    CHECK(found_some > 150 * 10);  // not only empty boxes
}

namespace {

// The whole list in its order (a y range of more cells than a lookup walks goes through it).
std::vector<int32_t> listed(const engine::Spatial& s) {
    std::vector<int32_t> all;
    s.for_each(-1e9f, 1e9f, -1e6f, 1e6f, [&](graph::BodyId b) { all.push_back(b.v); });
    return all;
}

}  // namespace

// Between two physics steps a refresh reads from Bullet only the bodies written since the last
// one (and those new to the world), and comes out bit for bit as an index that reads them all:
// bottles placed elsewhere, one made the fastest and then slow again (the largest speed is
// found again among the others), one taken out of the world and put back, its place changed.
TEST_CASE("body index: between steps only what was written is read again, and the index is as one that reads all") {
    const graph::Graph g = compiled_text(kTwoBelts, "spatial_written.plant");
    engine::Engine e(g);
    engine::Runtime& r = e.internals();
    const std::vector<graph::BodyId>& dyn = r.tab.dyn_bodies;
    REQUIRE(dyn.size() >= 64);
    auto same_as_reading_all = [&r](const char* what) {
        CAPTURE(what);
        engine::Spatial all(r.tab, graph::count_of(r.g.bodies));  // never refreshed: reads every body
        all.refresh(r.phys, r.phys.workers());
        REQUIRE(all.last_read() == in_world(r).size());
        CHECK(listed(r.index) == listed(all));
        // Lookups, through each cell's run of the list (the table of where each begins is
        // made again only when a body's cell changed).
        for (btScalar y = -1.5f; y < 2.f; y += 0.5f)
            for (btScalar x = -0.5f; x < 3.5f; x += 0.5f) {
                std::vector<int32_t> a, b;
                r.index.for_each(x, x + 0.6f, y, y + 0.3f, [&](graph::BodyId o) { a.push_back(o.v); });
                all.for_each(x, x + 0.6f, y, y + 0.3f, [&](graph::BodyId o) { b.push_back(o.v); });
                CAPTURE(x);
                CAPTURE(y);
                REQUIRE(a == b);
            }
        CHECK(r.index.reach() == all.reach());
        CHECK(r.index.vmax() == all.vmax());
        for (graph::BodyId b : in_world(r)) {
            CAPTURE(b.v);
            REQUIRE(r.index.com(b) == all.com(b));
            REQUIRE(r.index.lo(b) == all.lo(b));
            REQUIRE(r.index.hi(b) == all.hi(b));
        }
    };
    auto moving = [&r](graph::BodyId b, btVector3 by) {
        btTransform f = r.phys.frame(b);
        f.setOrigin(f.getOrigin() + by);
        r.phys.place(b, f);
    };
    const graph::BodyId fast = dyn[5], out = dyn[17], moved = dyn[30];
    for (int step = 0; step < 60; ++step) e.step();
    const size_t n = in_world(r).size();
    r.index.refresh(r.phys, r.phys.workers());
    CHECK(r.index.last_read() == n);  // the physics stepped since the last refresh (the step's, before it)
    r.index.refresh(r.phys, r.phys.workers());
    CHECK(r.index.last_read() == 0);  // nothing written since
    same_as_reading_all("nothing written");
    // A bottle is two bodies carried as one (welds.cpp): writing one writes both.

    moving(moved, btVector3(0.7f, -1.4f, 0));  // to another cell, past others in x
    r.phys.write(fast).setLinearVelocity(btVector3(9, 0, 0));
    r.index.refresh(r.phys, r.phys.workers());
    CHECK(r.index.last_read() >= 2);
    CHECK(r.index.last_read() <= 4);
    CHECK(r.index.vmax() == doctest::Approx(9));
    same_as_reading_all("placed, made fast");

    r.phys.write(fast).setLinearVelocity(btVector3(0, 0, 0));
    r.phys.take_out(out);
    r.index.refresh(r.phys, r.phys.workers());
    CHECK(r.index.last_read() >= 1);
    CHECK(r.index.last_read() <= 2);
    CHECK(in_world(r).size() == n - 1);
    CHECK(r.index.vmax() < 3);  // found again among the others (bottles falling off a belt's end are the fastest)
    same_as_reading_all("slow again, one out");

    moving(out, btVector3(-0.3f, 0, 0.05f));
    r.phys.insert(out);
    r.index.refresh(r.phys, r.phys.workers());
    CHECK(r.index.last_read() >= 1);
    CHECK(r.index.last_read() <= 2);
    CHECK(in_world(r).size() == n);
    same_as_reading_all("back in, elsewhere");

    e.step();  // a step: every body read again
    r.index.refresh(r.phys, r.phys.workers());
    CHECK(r.index.last_read() == n);
    same_as_reading_all("after a step");
}
