// Bullet's allocator (runtime/engine/bullet_alloc.cpp): every block Bullet asks for is
// 16-aligned and holds what was asked, a freed block serves the next request of its class
// without the heap, a request past the largest class or for a wider alignment is served from
// the heap and counted, and blocks freed on another thread come back. Sanitizer builds leave
// Bullet on the heap: there only what any allocator must do is checked.
#include "engine/engine.h"
#include "engine/physics.h"
#include "scene_builder.h"

#include <LinearMath/btAlignedAllocator.h>
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

using plant::engine::bullet_heap_requests;
using plant::engine::bullet_pool;

namespace {

bool aligned_to(const void* p, size_t a) { return reinterpret_cast<uintptr_t>(p) % a == 0; }

}  // namespace

TEST_CASE("bullet allocator: blocks are aligned, hold their size, and are recycled by class") {
    // Sizes across the classes: each 16-B step up to 128, the quarter steps above, the edges.
    std::vector<size_t> sizes;
    for (size_t n = 1; n <= 300; n += 7) sizes.push_back(n);
    for (size_t n : {size_t(744), size_t(768), size_t(769), size_t(880), size_t(4096), size_t(5000),
                     size_t(229376), size_t(1) << 20})
        sizes.push_back(n);
    std::vector<void*> blocks;
    for (size_t n : sizes) {
        void* p = btAlignedAlloc(n, 16);
        REQUIRE(p != nullptr);
        CHECK(aligned_to(p, 16));
        std::memset(p, 0xab, n);  // the whole request is usable (ASan would say otherwise)
        blocks.push_back(p);
    }
    // Freed blocks serve the same requests again without the heap, in the reverse order of
    // a class's list.
    for (void* p : blocks) btAlignedFree(p);
    const uint64_t before = bullet_heap_requests();
    std::vector<void*> again;
    for (size_t n : sizes) again.push_back(btAlignedAlloc(n, 16));
    if (bullet_pool()) {
        CHECK(bullet_heap_requests() == before);
        // The block of the largest size is the one freed: it is alone in its class here.
        CHECK(again.back() == blocks.back());
    }
    for (void* p : again) btAlignedFree(p);
}

TEST_CASE("bullet allocator: a wider alignment or a request past 1 MiB comes from the heap, counted") {
    const uint64_t before = bullet_heap_requests();
    void* wide = btAlignedAlloc(100, 64);
    void* huge = btAlignedAlloc((size_t(1) << 20) + 1, 16);
    REQUIRE(wide != nullptr);
    REQUIRE(huge != nullptr);
    CHECK(aligned_to(wide, 64));
    CHECK(aligned_to(huge, 16));
    std::memset(wide, 1, 100);
    std::memset(huge, 1, (size_t(1) << 20) + 1);
    if (bullet_pool()) CHECK(bullet_heap_requests() == before + 2);
    btAlignedFree(wide);
    btAlignedFree(huge);
}

TEST_CASE("bullet allocator: blocks freed on another thread are taken again, with no heap request") {
    // 496 B is a class each thread keeps a list of, 1,000 B one only the shared list holds.
    // 256 blocks are four of the batches a thread's list takes from the shared one: a fresh
    // thread that asks for 256 takes exactly the ones a thread that ended gave back.
    for (size_t size : {size_t(496), size_t(1000)}) {
        CAPTURE(size);
        constexpr int kBlocks = 256;
        std::vector<void*> blocks(kBlocks), again(kBlocks);
        for (void*& p : blocks) p = btAlignedAlloc(size, 16);
        std::thread([&] {
            for (void* p : blocks) btAlignedFree(p);
        }).join();
        const uint64_t before = bullet_heap_requests();
        std::thread([&] {
            for (void*& p : again) p = btAlignedAlloc(size, 16);
        }).join();
        if (bullet_pool()) {
            CHECK(bullet_heap_requests() == before);
            std::vector<void*> a = blocks, b = again;
            std::sort(a.begin(), a.end());
            std::sort(b.begin(), b.end());
            CHECK(a == b);  // the very blocks the other thread freed
        }
        for (void* p : again) btAlignedFree(p);
    }
}

// A pooled object's joints join Bullet's world only at its first issue, and Bullet then grows
// two arrays of each of its bodies (its constraints, the bodies it does not collide with) that
// stay with the body: the runtime grows them when it starts (Physics::reserve_joint_refs). Here
// 300 welded pairs (a bottle's body and its foot), issued one at a time and taken back at once,
// each for the first time: no issue may ask the pools for more (without the reservation the
// 1,200 blocks of 16 B outgrow their class several times).
TEST_CASE("bullet allocator: a pooled object's first issue asks the pools for nothing") {
    using namespace plant::test;
    using plant::graph::SlotId;
    SceneBuilder b;
    b.g.settings.gravity = {0, 0, 0};
    const int32_t bottle = b.type("Bottle");
    constexpr int kPool = 300;
    const int32_t pool = int32_t(b.g.dos.size());
    for (int i = 0; i < kPool; ++i) {
        const int32_t d = b.dobj("pool" + std::to_string(i), 0, bottle, at(0, 10 + i, 0));
        const int32_t main = b.body(d, "main", BodyMode::Dynamic, {sphere(0.03)}, 0.036, at(0, 10 + i, 0.04));
        const int32_t foot = b.body(d, "foot", BodyMode::Dynamic, {sphere(0.003)}, 0.004, at(0, 10 + i, 0.003));
        b.g.bodies[plant::graph::BodyId(foot)].collision = false;
        b.joint(d, "weld", JointKind::Fixed, main, foot, at(0, 0, -0.037), at(0, 0, 0));
    }
    const int32_t line = b.dobj("line");
    const int32_t src = b.source(line, "src", bottle, pool, kPool, 0, at(0, 0, 0), {});
    const int32_t sc = b.g.sources[plant::graph::SourceId(src)].comp.v;
    const int32_t t = b.trigger(line, "end", {1, 1, 1}, at(0, 0, 0), bottle);
    const int32_t ec = b.g.exits[plant::graph::ExitId(b.exit(line, "out", t))].comp.v;
    plant::engine::Engine e(b.g);
    auto cycle = [&] {  // one issued and taken
        e.input(SlotId(b.S(sc, "issue")));
        for (int k = 0; k < 3; ++k) e.step();
    };
    cycle();  // the first one makes what one object in the world needs (a joint, its solver rows)
    const uint64_t before = bullet_heap_requests();
    for (int i = 1; i < kPool; ++i) cycle();
    CHECK(e.value(SlotId(b.S(sc, "count")))[0] == kPool);
    CHECK(e.value(SlotId(b.S(ec, "count")))[0] == kPool);  // each taken before the next came
    if (bullet_pool()) CHECK(bullet_heap_requests() == before);
}
