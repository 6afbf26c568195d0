#include "engine/workers.h"

#include <LinearMath/btQuickprof.h>

#include <algorithm>
#include <chrono>
#include <ctime>

namespace plant::engine {

namespace {

// A step has one job (the worlds, each with its conveyor law: physics.cpp), and the rest of the
// step runs on the calling thread in between. A helper that finds no job spins only briefly
// before it sleeps: spinning through the step's serial part would burn a core per helper (on 16
// threads that was a third more processor time per step) and, on cores shared by two hardware
// threads, slow the calling thread down. The calling thread, waiting for the helpers to finish
// their last items, spins longer: that wait is short and it has nothing else to do.
constexpr int kSpinsIdle = 256;
constexpr int kSpinsJoin = 4000;

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

void StepProfile::begin() {
    start_ = now_ns();
    last_ = cpu_ns(), jobs_since_ = 0;
}

void StepProfile::lap_on(Segment s) {
    const int64_t t = cpu_ns();
    serial_ns[s] += std::max(0.0, double(t - last_) - jobs_since_);
    last_ = t, jobs_since_ = 0;
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

void Workers::work() {
    if (prof_.on) {  // each item timed: the work the threads share, and the longest item
        int64_t sum = 0, longest = 0;
        for (int i = next_.fetch_add(1, std::memory_order_relaxed); i < n_; i = next_.fetch_add(1, std::memory_order_relaxed)) {
            const int64_t t0 = cpu_ns();
            fn_(ctx_, i);
            const int64_t d = cpu_ns() - t0;
            sum += d, longest = std::max(longest, d);
        }
        item_sum_.fetch_add(sum, std::memory_order_relaxed);
        for (int64_t m = item_max_.load(std::memory_order_relaxed);
             longest > m && !item_max_.compare_exchange_weak(m, longest, std::memory_order_relaxed);) {
        }
        return;
    }
    for (int i = next_.fetch_add(1, std::memory_order_relaxed); i < n_; i = next_.fetch_add(1, std::memory_order_relaxed))
        fn_(ctx_, i);
}

void Workers::helper() {
    uint64_t seen = 0;
    for (;;) {
        await(job_, kSpinsIdle, [seen](uint64_t j) { return j != seen; });
        seen = job_.load(std::memory_order_acquire);
        if (stop_.load(std::memory_order_acquire)) return;
        work();
        if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) busy_.notify_one();
    }
}

void Workers::run(int n, void (*fn)(void*, int), void* ctx) {
    const int64_t t0 = prof_.on ? now_ns() : 0, c0 = prof_.on ? cpu_ns() : 0;
    fn_ = fn, ctx_ = ctx, n_ = n;
    next_.store(0, std::memory_order_relaxed);
    item_sum_.store(0, std::memory_order_relaxed);
    item_max_.store(0, std::memory_order_relaxed);
    if (helpers_.empty() || n <= 1) {
        work();
    } else {
        busy_.store(int(helpers_.size()), std::memory_order_relaxed);
        job_.fetch_add(1, std::memory_order_acq_rel);  // publishes the job
        job_.notify_all();
        work();
        await(busy_, kSpinsJoin, [](int b) { return b == 0; });
    }
    if (prof_.on) {
        const double wall = double(now_ns() - t0), sum = double(item_sum_.load(std::memory_order_relaxed)),
                     longest = double(item_max_.load(std::memory_order_relaxed));
        prof_.jobs_ns += wall, prof_.jobs_since_ += double(cpu_ns() - c0), prof_.work_ns += sum;
        for (int i = 0; i < StepProfile::kProjected; ++i)
            prof_.projected_ns[i] += std::max(sum / StepProfile::threads_of(i), longest);
    }
}

}  // namespace plant::engine
