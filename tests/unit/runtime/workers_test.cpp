// Workers (runtime/engine/workers.h): every item of every job runs exactly once, on whichever
// thread claims it, and run() returns only when all have finished, also when helpers wake late
// (more threads than cores: this machine has two) or never get to a job at all.
#include "engine/workers.h"

#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <utility>
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

namespace {

void spin_for(int us) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(us);
    while (std::chrono::steady_clock::now() < until) {
    }
}

// Two loops in two functions: a profile's rows are named by the loop's function.
void loop_a(Workers& w, std::vector<int>& hits) {
    auto a = [&](int i) { ++hits[size_t(i)], spin_for(100); };
    w.run(8, a);
}
void loop_b(Workers& w, std::vector<int>& hits) {
    auto b = [&](int i) { hits[size_t(i)] += 2, spin_for(100); };
    w.run(4, b);
}

}  // namespace

TEST_CASE("workers: a profile has a row per loop, its runs and items") {
    Workers w(2);
    w.profile().on = true;
    std::vector<int> hits(8, 0);
    for (int j = 0; j < 3; ++j) loop_a(w, hits);
    loop_b(w, hits);
    const plant::engine::StepJob* rows[2] = {};
    int named = 0;
    for (const plant::engine::StepJob& job : w.profile().jobs)
        if (job.name != nullptr && named < 2) rows[named++] = &job;
        else CHECK(job.name == nullptr);
    REQUIRE(named == 2);  // two loops, two rows, in the order they first ran
    CHECK(rows[0]->calls == 3);
    CHECK(rows[1]->calls == 1);
    CHECK(std::string(rows[0]->name).find("loop_a") != std::string::npos);
    CHECK(std::string(rows[1]->name).find("loop_b") != std::string::npos);
    CHECK(rows[0]->work_ns > 24 * 1e3);  // 24 items, each at least a microsecond of processor time
    CHECK(rows[0]->longest_ns > 0);
    CHECK(rows[0]->wall_ns >= rows[0]->longest_ns);
    CHECK(hits[0] == 5);
    w.profile().reset();
    CHECK(w.profile().jobs[0].name == nullptr);
}

// The profile's own clock reads (a system call each) are not counted as work: one read's cost
// comes off each item's time, and off each serial stretch once, and once more per job in it.
// A read's cost is measured when the profile begins; here it is then set far above anything
// timed, so that what is taken off shows exactly (each time comes out 0), however slow or busy
// the machine (measured times of code this small vary by more than a read under load).
TEST_CASE("workers: the profile takes its clock's reads off what it times") {
    using plant::engine::StepProfile;
    Workers w(2);
    StepProfile& p = w.profile();
    p.on = true;
    p.begin();
    CHECK(p.read_ns > 0);  // measured
    p.read_ns = 1e9;       // a second a read: larger than any stretch below
    std::vector<int> hits(100, 0);
    auto busy = [&](int i) { ++hits[size_t(i)], spin_for(20); };
    for (int j = 0; j < 5; ++j) w.run(100, busy);
    CHECK(p.jobs_count_ == 5);  // the jobs since the last lap, each one more read to take off
    CHECK(p.work_ns == 0);      // each item's read taken off (it measured about 20 µs)
    spin_for(20);
    p.lap(StepProfile::Logic);
    CHECK(p.jobs_count_ == 0);
    CHECK(p.serial_ns[StepProfile::Logic] == 0);  // the lap's stretch: its read, and the jobs'
    CHECK(hits[0] == 5);
}

namespace {

// Loop K of many, each its own lambda in its own function.
template <int K>
void loop_k(Workers& w) {
    auto f = [](int) { spin_for(5); };
    w.run(2, f);
}
template <int... K>
void loops(Workers& w, std::integer_sequence<int, K...>) {
    (loop_k<K>(w), ...);
}

}  // namespace

TEST_CASE("workers: a profile with more loops than rows keeps every loop's runs") {
    Workers w(1);
    w.profile().on = true;
    loops(w, std::make_integer_sequence<int, 30>{});
    int64_t runs = 0;
    for (const plant::engine::StepJob& job : w.profile().jobs) {
        CHECK(job.name != nullptr);
        runs += job.calls;
    }
    CHECK(runs == 30);  // 23 rows of their own, the last for the other 7
    CHECK(std::string(w.profile().jobs[plant::engine::StepProfile::kJobs - 1].name) == "(other loops)");
    CHECK(w.profile().jobs[plant::engine::StepProfile::kJobs - 1].calls == 7);
}
