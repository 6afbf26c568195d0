// Huge pages for what the step reads (docs/runtime.md, "Performance notes").
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

namespace plant::engine {

// What one huge_pages call did: 2 MiB ranges asked for, and backed by huge pages.
struct HugePages {
    int64_t asked = 0, backed = 0;
};

// Asks the kernel to back with 2 MiB pages each 2 MiB range of the process's heap and of its
// other private anonymous mappings whose 4 KiB pages are all resident already, so that the
// process takes no more memory (Linux's MADV_COLLAPSE, 6.1 and later; where the kernel
// refuses, or in a sanitized build, nothing changes). A range already backed so costs a look.
// Changes no result: only how the bytes are mapped. Allocates nothing. Stops early once *quit
// is set.
HugePages huge_pages(const std::atomic<bool>* quit = nullptr);

// Bullet's bodies, shapes and trees, our per-body arrays and the pools' and contacts' blocks lie
// spread over the heap, and a step of a large plant visits thousands of bodies: with 4 KiB
// pages most visits miss the processor's cache of page translations (its TLB) as well. A Pager
// calls huge_pages on a thread of its own, so that the step never waits for it: once when it
// is made (the plant as built), and again when the plant's simulated time (tick, from the
// stepping thread) reaches 1, 10 and 40 s (the blocks the first steps asked for: contacts,
// the pools in circulation). Backing 2 MiB takes the kernel about 6 ms on a 2-core VM.
class Pager {
public:
    Pager();
    ~Pager();
    Pager(const Pager&) = delete;
    Pager& operator=(const Pager&) = delete;
    // After each step, with the simulated time; allocates nothing (a lock at the three times).
    void tick(double time) {
        if (next_ < kTimes && time >= kAt[next_]) wake();
    }
    int calls() const;  // the calls finished so far

private:
    static constexpr int kTimes = 3;
    static constexpr double kAt[kTimes] = {1, 10, 40};  // s of simulated time
    void wake();
    void run();
    int next_ = 0;  // the stepping thread's: the next of kAt
    mutable std::mutex m_;
    std::condition_variable cv_;
    // Set (under m_) by the destructor; read between ranges too, so it waits for no call.
    std::atomic<bool> quit_{false};
    int due_ = 1, served_ = 0;  // calls asked for, and made
    int calls_ = 0;
    std::thread thread_;  // last: started once the rest is made
};

}  // namespace plant::engine
