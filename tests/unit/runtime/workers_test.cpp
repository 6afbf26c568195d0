// Workers (runtime/engine/workers.h): every item of every job runs exactly once, on whichever
// thread claims it, and run() returns only when all have finished, also when helpers wake late
// (more threads than cores: this machine has two) or never get to a job at all.
#include "engine/workers.h"

#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

using plant::engine::Workers;

namespace {

// Runs `jobs` jobs of varying sizes and checks each item ran once, its effect visible after run().
void check_jobs(Workers& w, int jobs, bool slow_items) {
    std::vector<int> hits(64, 0);
    std::atomic<int> on_helpers{0};
    for (int j = 0; j < jobs; ++j) {
        const int n = 1 + (j * 7) % 64;
        std::fill(hits.begin(), hits.end(), 0);
        auto f = [&](int i) {
            ++hits[size_t(i)];  // each item its own entry: no two threads write one
            if (plant::engine::worker_slot() != 0) on_helpers.fetch_add(1, std::memory_order_relaxed);
            if (slow_items && i % 5 == 0) std::this_thread::sleep_for(std::chrono::microseconds(50));
        };
        w.run(n, f);
        for (int i = 0; i < 64; ++i) {
            CAPTURE(j);
            CAPTURE(i);
            REQUIRE(hits[size_t(i)] == (i < n ? 1 : 0));
        }
    }
    if (w.threads() > 1 && slow_items) CHECK(on_helpers.load() > 0);  // the helpers took part
}

}  // namespace

TEST_CASE("workers: every item of every job runs once, on 1 to 8 threads") {
    for (int threads : {1, 2, 3, 8}) {
        CAPTURE(threads);
        Workers w(threads);
        CHECK(w.threads() == threads);
        check_jobs(w, 2000, false);  // short jobs: helpers often wake after the caller ran them all
        check_jobs(w, 40, true);     // items that sleep: the helpers take some
    }
}

TEST_CASE("workers: the profile's item times add up while profiling") {
    Workers w(3);
    w.profile().on = true;
    std::vector<int> hits(16, 0);
    auto f = [&](int i) {
        ++hits[size_t(i)];
        const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(200);
        while (std::chrono::steady_clock::now() < until) {
        }
    };
    for (int j = 0; j < 10; ++j) w.run(16, f);
    for (int h : hits) CHECK(h == 10);
    // 160 items of 200 µs of wall time each: each at least a microsecond of processor time
    // however busy the machine.
    CHECK(w.profile().work_ns > 160 * 1e3);
    CHECK(w.profile().projected_ns[0] >= w.profile().projected_ns[4]);
}
