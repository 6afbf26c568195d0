#include "engine/workers.h"

#include <LinearMath/btQuickprof.h>

namespace plant::engine {

namespace {

// A job of the physics phase lasts tens of microseconds to milliseconds, and the next one comes
// within a step: a thread spins a little before it sleeps, so that waking it costs no system call
// in a busy run, and an idle one costs no processor time.
constexpr int kSpins = 4000;

inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

template <class T, class Pred>
void await(const std::atomic<T>& a, Pred done) {
    for (int i = 0; i < kSpins; ++i) {
        if (done(a.load(std::memory_order_acquire))) return;
        relax();
    }
    for (T v = a.load(std::memory_order_acquire); !done(v); v = a.load(std::memory_order_acquire)) a.wait(v);
}

}  // namespace

Workers::Workers(int threads) {
    // Bullet's profiler numbers the threads that call it with a counter that is not atomic:
    // every thread takes its number here, one after the other.
    btQuickprofGetCurrentThreadIndex2();
    for (int t = 1; t < threads; ++t) {
        std::atomic<bool> ready{false};
        helpers_.emplace_back([this, &ready] {
            btQuickprofGetCurrentThreadIndex2();
            ready.store(true, std::memory_order_release);
            ready.notify_one();
            helper();
        });
        await(ready, [](bool r) { return r; });
    }
}

Workers::~Workers() {
    stop_.store(true, std::memory_order_release);
    job_.fetch_add(1, std::memory_order_acq_rel);
    job_.notify_all();
    for (std::thread& t : helpers_) t.join();
}

void Workers::work() {
    for (int i = next_.fetch_add(1, std::memory_order_relaxed); i < n_; i = next_.fetch_add(1, std::memory_order_relaxed))
        fn_(ctx_, i);
}

void Workers::helper() {
    uint64_t seen = 0;
    for (;;) {
        await(job_, [seen](uint64_t j) { return j != seen; });
        seen = job_.load(std::memory_order_acquire);
        if (stop_.load(std::memory_order_acquire)) return;
        work();
        if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) busy_.notify_one();
    }
}

void Workers::run(int n, void (*fn)(void*, int), void* ctx) {
    if (helpers_.empty() || n <= 1) {
        for (int i = 0; i < n; ++i) fn(ctx, i);
        return;
    }
    fn_ = fn, ctx_ = ctx, n_ = n;
    next_.store(0, std::memory_order_relaxed);
    busy_.store(int(helpers_.size()), std::memory_order_relaxed);
    job_.fetch_add(1, std::memory_order_acq_rel);  // publishes the job
    job_.notify_all();
    work();
    await(busy_, [](int b) { return b == 0; });
}

}  // namespace plant::engine
