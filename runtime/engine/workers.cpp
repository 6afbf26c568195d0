#include "engine/workers.h"

#include <LinearMath/btQuickprof.h>

#include <algorithm>
#include <chrono>
#include <ctime>

namespace plant::engine {

namespace {

// A step has a few jobs (the worlds, each with its conveyor law: physics.cpp; the slices of the
// loops listed in workers.h), and the rest of the step runs on the calling thread in between.
// A helper that finds no job spins only briefly before it sleeps: spinning through the step's
// serial part would burn a core per helper (on 16 threads that was a third more processor time
// per step) and, on cores shared by two hardware threads, slow the calling thread down. The
// calling thread, waiting for the last items that helpers took, spins longer: that wait is
// short and it has nothing else to do. It never waits for a helper that took no item: on a
// busy machine a helper may get a core only after the calling thread has run every item, and
// the job is then done without it (the items are claimed one by one from `ticket_`).
constexpr int kSpinsIdle = 256;
constexpr int kSpinsJoin = 4000;
// The ticket's item field while the calling thread writes the next job: no item can be claimed.
constexpr uint32_t kClosed = 0xffffffffu;
// A 64-bit number's low half: a ticket's item, a job's number as a ticket holds it.
constexpr uint32_t low_half(uint64_t v) { return static_cast<uint32_t>(v); }
constexpr uint32_t job_of(uint64_t ticket) { return low_half(ticket >> 32); }

inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

template <class T, class Pred>
void await(const std::atomic<T>& a, int spins, Pred done) {
    for (int i = 0; i < spins; ++i) {
        if (done(a.load(std::memory_order_acquire))) return;
        relax();
    }
    for (T v = a.load(std::memory_order_acquire); !done(v); v = a.load(std::memory_order_acquire)) a.wait(v);
}

int64_t now_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

// The calling thread's processor time: what a segment or an item costs, without the time the
// thread waited for a core on a busy machine.
int64_t cpu_ns() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

}  // namespace

const char* StepProfile::name(int segment) {
    static const char* const names[kSegments] = {
        "welds, kinematic moves, hands", "conveyor law: fields, bodies by world", "regions: movers to worlds",
        "welds: passengers follow",      "bodies: left, outputs",                "graphics",
        "triggers (and the body index)", "timers, grippers, exits, plugins",     "logic",
        "Petri nets",                    "actuators, sources, forces"};
    return segment >= 0 && segment < kSegments ? names[segment] : "?";
}

void StepProfile::reset() {
    const bool was = on;
    *this = StepProfile{};
    on = was;
}

void StepProfile::calibrate() {
    // The cheapest of 5 rounds of 40 reads, timed by the wall clock (no system call).
    double best = 1e9;
    for (int round = 0; round < 5; ++round) {
        const int64_t a = now_ns();
        for (int i = 0; i < 40; ++i) (void)cpu_ns();
        best = std::min(best, double(now_ns() - a) / 40);
    }
    read_ns = best;
}

void StepProfile::begin() {
    if (read_ns <= 0) calibrate();
    start_ = now_ns();
    last_ = cpu_ns(), jobs_since_ = 0, jobs_count_ = 0;
}

void StepProfile::lap_on(Segment s) {
    const int64_t t = cpu_ns();
    serial_ns[s] += std::max(0.0, double(t - last_) - jobs_since_ - read_ns * (1 + jobs_count_));
    last_ = t, jobs_since_ = 0, jobs_count_ = 0;
}

void StepProfile::add_job(const char* name, double wall, double work, double longest) {
    if (name == nullptr) name = "(unnamed)";
    Job* row = &jobs[kJobs - 1];
    for (int i = 0; i < kJobs - 1; ++i)
        if (jobs[i].name == nullptr || jobs[i].name == name) {  // a literal: one address per loop
            row = &jobs[i];
            break;
        }
    if (row == &jobs[kJobs - 1] && row->name != nullptr && row->name != name) name = "(other loops)";
    row->name = name, ++row->calls, row->wall_ns += wall, row->work_ns += work, row->longest_ns += longest;
}

void StepProfile::end() {
    step_ns += double(now_ns() - start_);
    ++steps;
}

double StepProfile::serial_total() const {
    double t = 0;
    for (double x : serial_ns) t += x;
    return t;
}

double StepProfile::share(int i) const {
    const double all = serial_total() + projected_ns[i];
    return all > 0 ? serial_total() / all : 0;
}

double StepProfile::speedup(int i) const {
    const double one = serial_total() + projected_ns[0], n = serial_total() + projected_ns[i];
    return n > 0 ? one / n : 0;
}

namespace {
thread_local int t_slot = 0;
}

int worker_slot() { return t_slot; }

Workers::Workers(int threads) {
    // Bullet's profiler numbers the threads that call it with a counter that is not atomic:
    // every thread takes its number here, one after the other.
    btQuickprofGetCurrentThreadIndex2();
    for (int t = 1; t < threads; ++t) {
        std::atomic<bool> ready{false};
        helpers_.emplace_back([this, &ready, t] {
            t_slot = t;
            btQuickprofGetCurrentThreadIndex2();
            ready.store(true, std::memory_order_release);
            ready.notify_one();
            helper();
        });
        await(ready, kSpinsJoin, [](bool r) { return r; });
    }
}

Workers::~Workers() {
    stop_.store(true, std::memory_order_release);
    job_.fetch_add(1, std::memory_order_acq_rel);
    job_.notify_all();
    for (std::thread& t : helpers_) t.join();
}

// Item i of the job, timed when profiling.
inline void Workers::item(void (*fn)(void*, int), void* ctx, int i, int64_t& sum, int64_t& longest) {
    if (!prof_.on) return fn(ctx, i);
    const int64_t t0 = cpu_ns();
    fn(ctx, i);
    const int64_t d = std::max<int64_t>(0, cpu_ns() - t0 - static_cast<int64_t>(prof_.read_ns));
    sum += d, longest = std::max(longest, d);
}

void Workers::add_times(int64_t sum, int64_t longest) {
    if (!prof_.on) return;
    item_sum_.fetch_add(sum, std::memory_order_relaxed);
    for (int64_t m = item_max_.load(std::memory_order_relaxed);
         longest > m && !item_max_.compare_exchange_weak(m, longest, std::memory_order_relaxed);) {
    }
}

// Claims and runs items of job `job` until none is left; how many it ran. Only while the job's
// data cannot change: on the calling thread, or in a helper inside (`inside_`) that saw the job
// open.
int Workers::work(uint32_t job) {
    const int n = n_.load(std::memory_order_relaxed);
    void (*const fn)(void*, int) = fn_.load(std::memory_order_relaxed);
    void* const ctx = ctx_.load(std::memory_order_relaxed);
    int ran = 0;
    int64_t sum = 0, longest = 0;
    for (uint64_t t = ticket_.load(std::memory_order_acquire); job_of(t) == job && int64_t{low_half(t)} < n;) {
        if (!ticket_.compare_exchange_weak(t, t + 1, std::memory_order_acq_rel, std::memory_order_acquire)) continue;
        item(fn, ctx, static_cast<int>(low_half(t)), sum, longest);
        ++ran;
        t = ticket_.load(std::memory_order_acquire);
    }
    add_times(sum, longest);
    return ran;
}

void Workers::helper() {
    uint64_t seen = 0;
    for (;;) {
        await(job_, kSpinsIdle, [seen](uint64_t j) { return j != seen; });
        seen = job_.load(std::memory_order_acquire);
        if (stop_.load(std::memory_order_acquire)) return;
        // Inside, the calling thread does not write a next job; a job already closed (the
        // calling thread ran every item, or is writing the next one) is left alone.
        inside_.fetch_add(1, std::memory_order_seq_cst);
        if (job_of(ticket_.load(std::memory_order_seq_cst)) == low_half(seen)) {
            const int n = n_.load(std::memory_order_relaxed);
            if (const int ran = work(low_half(seen)); ran > 0 && done_.fetch_add(ran, std::memory_order_acq_rel) + ran == n)
                done_.notify_one();
        }
        if (inside_.fetch_sub(1, std::memory_order_acq_rel) == 1) inside_.notify_one();
    }
}

void Workers::run(int n, void (*fn)(void*, int), void* ctx, const char* name) {
    const int64_t t0 = prof_.on ? now_ns() : 0, c0 = prof_.on ? cpu_ns() : 0;
    item_sum_.store(0, std::memory_order_relaxed);
    item_max_.store(0, std::memory_order_relaxed);
    if (helpers_.empty() || n <= 1) {
        int64_t sum = 0, longest = 0;
        for (int i = 0; i < n; ++i) item(fn, ctx, i, sum, longest);
        add_times(sum, longest);
    } else {
        const uint64_t job = job_.load(std::memory_order_relaxed) + 1;  // only this thread bumps it
        // Closed first, then no helper inside: a helper that comes in later sees it closed. The
        // store and the first look are sequentially consistent, as the helper's entry and its
        // look at the ticket are: one of the two sees the other.
        ticket_.store(job << 32 | kClosed, std::memory_order_seq_cst);
        if (inside_.load(std::memory_order_seq_cst) != 0) await(inside_, kSpinsJoin, [](int k) { return k == 0; });
        fn_.store(fn, std::memory_order_relaxed);
        ctx_.store(ctx, std::memory_order_relaxed);
        n_.store(n, std::memory_order_relaxed);
        done_.store(0, std::memory_order_relaxed);
        ticket_.store(job << 32, std::memory_order_release);  // open
        job_.store(job, std::memory_order_release);           // wakes the helpers
        job_.notify_all();
        if (const int ran = work(low_half(job)); ran > 0) done_.fetch_add(ran, std::memory_order_acq_rel);
        await(done_, kSpinsJoin, [n](int d) { return d == n; });
    }
    if (prof_.on) {
        const double wall = double(now_ns() - t0), sum = double(item_sum_.load(std::memory_order_relaxed)),
                     longest = double(item_max_.load(std::memory_order_relaxed));
        prof_.jobs_ns += wall, prof_.jobs_since_ += double(cpu_ns() - c0), prof_.work_ns += sum;
        ++prof_.jobs_count_;
        for (int i = 0; i < StepProfile::kProjected; ++i)
            prof_.projected_ns[i] += std::max(sum / StepProfile::threads_of(i), longest);
        prof_.add_job(name, wall, sum, longest);
    }
}

}  // namespace plant::engine
