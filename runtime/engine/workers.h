// A fixed set of threads that run the items of one job at a time (the physics phase steps its
// Bullet worlds on them; see regions.cpp). Results do not depend on the number of threads:
// items must be independent of each other.
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace plant::engine {

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
        run(n, [](void* ctx, int i) { (*static_cast<F*>(ctx))(i); }, &f);
    }
    void run(int n, void (*fn)(void*, int), void* ctx);

private:
    void helper();
    void work();

    std::vector<std::thread> helpers_;
    void (*fn_)(void*, int) = nullptr;
    void* ctx_ = nullptr;
    int n_ = 0;
    std::atomic<int> next_{0};
    std::atomic<int> busy_{0};        // helpers still working on the current job
    std::atomic<uint64_t> job_{0};    // bumped for each job; helpers wait for it to change
    std::atomic<bool> stop_{false};
};

}  // namespace plant::engine
