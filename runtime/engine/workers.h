// A fixed set of threads that run the items of one job at a time (the physics phase steps its
// Bullet worlds on them; see regions.cpp). Results do not depend on the number of threads:
// items must be independent of each other.
#pragma once

#include "graph/ids.h"

#include <atomic>
#include <cstdint>
#include <thread>
#include <utility>
#include <vector>

namespace plant::engine {

// One loop's jobs in a profile (StepProfile::jobs). The loops of one function share a row where
// the compiler merges their lambdas' signatures, which read the same (GCC does).
struct StepJob {
    const char* name = nullptr;  // Workers::run's signature for the loop's lambda (a literal)
    int64_t calls = 0;
    double wall_ns = 0, work_ns = 0, longest_ns = 0;  // summed over the calls
};

// Where a step's time goes, for the benchmarks (Engine::profile): each segment of the step is
// timed on the calling thread (its processor time, so that a busy machine's waits do not count),
// less the time it spent in Workers::run (the parallel work, timed item by item in the
// processor time of the thread that ran it). Off by default: then it reads no clock.
// Allocates nothing.
struct StepProfile {
    enum Segment : int {
        Welds,       // welds formed and ended, kinematic moves, hands
        FieldsPrep,  // fields' frames and cells, the bodies listed by world
        Regions,     // free movers assigned to their regions' worlds
        Follow,      // welded passengers follow their carriers; missed contacts
        Bodies,      // bodies that left, body outputs
        Graphics,
        Triggers,    // the index of bodies and every trigger
        Others,      // timers, grippers, exits, plugins
        Logic,
        Petri,
        Actuators,   // actuators, sources, forced values
        kSegments
    };
    static const char* name(int segment);
    static constexpr int kProjected = 5;  // 1, 2, 4, 8, 16 threads
    static constexpr int threads_of(int i) { return 1 << i; }

    bool on = false;
    int64_t steps = 0;
    double step_ns = 0;                 // wall time of the steps
    double serial_ns[kSegments] = {};   // processor time of the calling thread outside Workers::run
    double jobs_ns = 0;                 // wall time in Workers::run
    double work_ns = 0;                 // the items' processor times, summed over the threads
    double projected_ns[kProjected] = {};  // Workers::run's time on n threads: max(work / n, longest item)
    // Each kind of job (a loop of Workers::run, named by its function), where its wall time goes:
    // how the threads present shared its items, against their processor time and the longest.
    using Job = StepJob;
    // The last row takes every loop that finds the others taken ("(other loops)"): a profile
    // with more loops than rows still counts all their time.
    static constexpr int kJobs = 24;
    Job jobs[kJobs];
    void add_job(const char* name, double wall, double work, double longest);

    void reset();
    void begin();                  // at the start of a step
    void lap(Segment s) {          // the time since the last lap (or begin) goes to s
        if (on) lap_on(s);
    }
    void lap_on(Segment s);
    void end();                    // at the end of a step
    double serial_total() const;
    // The serial share on threads_of(i) threads: serial / (serial + projected_ns[i]).
    double share(int i) const;
    // Amdahl: the step's time on n threads as the serial time plus projected_ns, relative to 1.
    double speedup(int i) const;

    // What one read of a thread's processor-time clock costs (a system call: no fast path for
    // it in Linux's vDSO; 0.66 µs on a 2-core VM, where a step at 1,000 bottles reads it several
    // hundred times). Measured when a profiled step first begins; each timed stretch holds
    // about one read's cost besides its own (the end of the read that starts it, the start of
    // the one that ends it), which is taken off: an item's time, and a segment's, which also
    // holds one per job in it (the job's own two reads, outside the job's window).
    double read_ns = 0;
    void calibrate();

    int64_t last_ = 0, start_ = 0;
    double jobs_since_ = 0;  // time in Workers::run since the last lap
    int jobs_count_ = 0;     // and how many jobs
};

// Which thread of its Workers the calling thread is: 0 for the thread that calls run(), 1 to
// threads() - 1 for the helpers (set once when each starts). Per-thread scratch is indexed by it.
int worker_slot();

class Workers {
public:
    // `threads` counts the calling thread: 1 runs every item on the caller.
    explicit Workers(int threads);
    ~Workers();
    Workers(const Workers&) = delete;
    Workers& operator=(const Workers&) = delete;

    int threads() const { return int(helpers_.size()) + 1; }

    // Calls f(i) for every i in [0, n), spread over the threads, and returns when all are done.
    // Allocates nothing.
    template <class F>
    void run(int n, F& f) {
        run(n, f, __PRETTY_FUNCTION__);
    }
    // The same, named `name` (a literal) in the profile's jobs.
    template <class F>
    void run(int n, F& f, const char* name) {
        run(n, [](void* ctx, int i) { (*static_cast<F*>(ctx))(i); }, &f, name);
    }
    // `name` (a literal) tells the profile's jobs apart.
    void run(int n, void (*fn)(void*, int), void* ctx, const char* name = nullptr);

    StepProfile& profile() { return prof_; }

private:
    void helper();
    int work(uint32_t job);
    void item(void (*fn)(void*, int), void* ctx, int i, int64_t& sum, int64_t& longest);
    void add_times(int64_t sum, int64_t longest);

    std::vector<std::thread> helpers_;
    // The job: written by the calling thread only while it is closed and no helper is inside.
    std::atomic<void (*)(void*, int)> fn_{nullptr};
    std::atomic<void*> ctx_{nullptr};
    std::atomic<int> n_{0};
    // The job's number (high 32 bits) and its next item to claim (low 32 bits; kClosed while the
    // next job is written). A helper claims an item by advancing it, only for the job it woke for.
    std::atomic<uint64_t> ticket_{0};
    std::atomic<int> done_{0};        // items of the current job finished
    std::atomic<int> inside_{0};      // helpers between waking for a job and leaving it
    std::atomic<uint64_t> job_{0};    // bumped for each job; helpers wait for it to change
    std::atomic<bool> stop_{false};
    StepProfile prof_;
    std::atomic<int64_t> item_sum_{0}, item_max_{0};  // while profiling: this job's items
};

// A loop over ids [0, n) cut into slices, a few per thread, each slice an item of one job
// (regions.cpp, fields.cpp, transport.cpp, spatial.cpp, bodies.cpp, kinds/graphics/run.cpp,
// kinds/trigger/run.cpp): an item writes only its own ids' entries (or its slice's), and
// what touches shared state runs after the job on the calling thread, in id order.
//
// How many slices: at least `least` ids in each, kMaxSlices at most (four per thread on 16
// threads), and at most `most` (the size of a caller's per-slice scratch); at least one. The
// count does not depend on how many threads run them: a job is cut the same way on 1 thread as
// on 16, so the items a profile times on 2 threads are those 16 would share (its projection,
// StepProfile::speedup, holds), and an item's size does not change with the machine.
inline constexpr size_t kMaxSlices = 64;
inline size_t slice_count(size_t n, size_t least, size_t most) {
    const size_t by_size = (n + least - 1) / least;
    const size_t c = by_size < kMaxSlices ? by_size : kMaxSlices;
    return c < 1 ? 1 : c < most ? c : most;
}
// Slice i of `count` over [0, n): its first id and the one after its last.
inline std::pair<size_t, size_t> slice_of(size_t n, size_t count, size_t i) {
    const size_t per = (n + count - 1) / count, b = i * per < n ? i * per : n;
    return {b, b + per < n ? b + per : n};
}
// Slice i of `count` over a table of n rows, as their ids.
template <class IdT>
graph::IdRange<IdT> slice_ids(size_t n, size_t count, size_t i) {
    const auto [b, e] = slice_of(n, count, i);
    return {static_cast<int32_t>(b), static_cast<int32_t>(e)};
}
// Calls f(i) for every slice i in [0, count): on the threads, or here when there is one.
// `name` (a literal) tells the loop apart in the profile's jobs from the function's other loops;
// without one, the loop is named by its function.
template <class F>
void run_slices(Workers& w, size_t count, F& f, const char* name = nullptr) {
    if (count <= 1) f(0);
    else if (name) w.run(int(count), f, name);
    else w.run(int(count), f);
}

}  // namespace plant::engine
