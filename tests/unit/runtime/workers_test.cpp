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

// The profile's own clock reads (a system call each) are not counted as work: a job of items
// that do nothing measures about nothing, where each item used to measure one read.
TEST_CASE("workers: the profile takes its clock's reads off what it times") {
    Workers w(1);
    w.profile().on = true;
    w.profile().begin();  // measures what a read costs
    const double read = w.profile().read_ns;
    REQUIRE(read > 0);
    auto nothing = [](int) {};
    for (int j = 0; j < 20; ++j) w.run(100, nothing);
    const double per_item = w.profile().work_ns / 2000;
    CAPTURE(read);
    CAPTURE(per_item);
    CHECK(per_item < 0.75 * read);  // each read was about 1.0 of it
    // Laps with nothing between them, and laps around an empty job: about nothing serial (a
    // lap holds one read, and a job one more outside its window).
    plant::engine::StepProfile& p = w.profile();
    for (int j = 0; j < 200; ++j) p.lap(plant::engine::StepProfile::Logic);
    for (int j = 0; j < 200; ++j) {
        w.run(2, nothing);
        p.lap(plant::engine::StepProfile::Petri);
    }
    CHECK(p.serial_ns[plant::engine::StepProfile::Logic] / 200 < 0.75 * read);
    CHECK(p.serial_ns[plant::engine::StepProfile::Petri] / 200 < 1.5 * read);  // was about 2.0
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
