// Same graph, same settings: bit-identical traces. And no heap allocation in step().
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/runtime.h"
#include "engine/trace.h"
#include "bottling_scene.h"
#include "trace_of.h"

#include <doctest/doctest.h>

#include <LinearMath/btAlignedAllocator.h>

#include <atomic>
#include <cstdlib>
#include <new>

using namespace plant::test;
using namespace plant::engine;

// ---- counting allocations (only while `g_counting` is set) ----
// The replacements pair malloc with free; GCC cannot see that through inlining.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_news{0}, g_bullet{0};

void* bullet_alloc(size_t n) {
    if (g_counting) ++g_bullet;
    return std::malloc(n);
}
void bullet_free(void* p) { std::free(p); }
}  // namespace

void* operator new(size_t n) {
    if (g_counting) ++g_news;
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void* operator new[](size_t n) { return operator new(n); }
void* operator new(size_t n, const std::nothrow_t&) noexcept {
    if (g_counting) ++g_news;
    return std::malloc(n ? n : 1);
}
void* operator new[](size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t) noexcept { std::free(p); }

namespace {

uint64_t fnv1a(const std::string& s) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    return h;
}

}  // namespace

TEST_CASE("runtime: two runs of the same graph give bit-identical traces") {
    const Graph g = bottling_scene();
    const std::string a = trace_of(g, 900), b = trace_of(g, 900);
    CHECK(a.size() > 10000);
    CHECK(fnv1a(a) == fnv1a(b));
    CHECK(a == b);
    // The scene is alive: bottles were issued, routed and taken.
    CHECK(a.find(",1,") != std::string::npos);
}

// The solver is handed an island's contacts and joints in an order of the plant's own, not in
// the order the broadphase found the pairs (physics.cpp, IslandSolver::in_order). The two
// broadphases find them in different orders, so a plant of one world gives the same trace with
// either. Both examples queue bottles against each other and against rails and guides; before
// the order was the plant's own, sap and dbvt gave different traces for each.
TEST_CASE("runtime: a plant of one world gives the same trace with either broadphase") {
    for (const char* example : {"examples/sorting.plant", "examples/separator.plant"}) {
        CAPTURE(example);
        Compilation c;
        compile_repo_file(example, c);
        REQUIRE(c.ok());
        Options dbvt, sap;
        dbvt.threads = sap.threads = 1;
        sap.broadphase = Broadphase::Sap;
        {
            Engine e(c.graph, dbvt);
            REQUIRE(e.internals().phys.worlds() == 1);  // as with sap: one world
        }
        const int steps = int(20 * c.graph.settings.rate);
        const TraceSelect all{true, true, true};
        const std::string a = trace_of(c.graph, steps, dbvt, all), b = trace_of(c.graph, steps, sap, all);
        CHECK(a.size() > 100000);
        CHECK(fnv1a(a) == fnv1a(b));
        CHECK(a == b);
    }
}

TEST_CASE("runtime: step() does not allocate") {
    btAlignedAllocSetCustom(bullet_alloc, bullet_free);
    for (int lines : {1, 3}) {  // one Bullet world; three regions on two threads
        const Graph g = bottling_scene(6, 0.5, lines);
        Options o;
        o.threads = 2;
        Engine e(g, o);
        for (int i = 0; i < 1500; ++i) e.step();  // warm up: bottles issued, carried, taken, reissued
        // A trainee's hand holds a bottle through the measured steps (the grab is between steps).
        for (size_t b = 0; b < g.bodies.size(); ++b)
            if (g.bodies[plant::graph::BodyId(b)].mode == plant::graph::BodyMode::Dynamic && e.body_in_world(plant::graph::BodyId(int32_t(b)))) {
                const plant::graph::Vec3 c = e.body_com(plant::graph::BodyId(int32_t(b)));
                e.hand_grab(plant::graph::BodyId(int32_t(b)), plant::graph::Vec3{c[0], c[1], c[2] + 0.05});
                break;
            }
        g_news = 0;
        g_bullet = 0;
        g_counting = true;
        for (int i = 0; i < 1500; ++i) e.step();
        g_counting = false;
        CAPTURE(lines);
        CHECK(g_news == 0);
        CHECK(e.warnings().hand_refused == 0);
        // Bullet allocates through its own allocator: the AABB-tree broadphase recycles
        // tree nodes through it as bodies move; its arrays otherwise only grow.
        MESSAGE("Bullet allocations in 1500 steps after warm-up, ", lines, " line(s): ", long(g_bullet));
    }
}
