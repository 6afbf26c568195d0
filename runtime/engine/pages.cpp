#include "engine/pages.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>

#ifndef MADV_COLLAPSE
#define MADV_COLLAPSE 25  // Linux 6.1 (asm-generic/mman-common.h)
#endif

namespace plant::engine {

#if defined(__linux__) && !defined(__SANITIZE_ADDRESS__)
namespace {

constexpr uintptr_t kHuge = uintptr_t(2) << 20;

// One line of /proc/self/maps: whether it is the heap or a private anonymous mapping that may
// be written, and its range.
bool anonymous(const char* line, uintptr_t& lo, uintptr_t& hi) {
    unsigned long a = 0, b = 0, offset = 0, inode = 0;
    char perms[5] = {}, dev[16] = {};
    int name = 0;
    if (std::sscanf(line, "%lx-%lx %4s %lx %15s %lu %n", &a, &b, perms, &offset, dev, &inode, &name) < 6) return false;
    if (std::strcmp(perms, "rw-p") != 0) return false;
    const char* path = line + name;
    if (std::strncmp(path, "[heap]", 6) != 0 && !(inode == 0 && *path == '\0')) return false;
    lo = uintptr_t(a), hi = uintptr_t(b);
    return true;
}

// Backs each 2 MiB range of [lo, hi) whose pages are all resident with a huge page.
void collapse(uintptr_t lo, uintptr_t hi, const std::atomic<bool>* quit, HugePages& out) {
    unsigned char resident[kHuge / 4096];  // huge_pages checks that a page is 4 KiB
    for (uintptr_t a = (lo + kHuge - 1) & ~(kHuge - 1); a + kHuge <= hi; a += kHuge) {
        if (quit && quit->load(std::memory_order_relaxed)) return;
        if (mincore(reinterpret_cast<void*>(a), kHuge, resident) != 0) continue;
        bool all = true;
        for (size_t i = 0; i < sizeof resident && all; ++i) all = (resident[i] & 1) != 0;
        if (!all) continue;
        ++out.asked;
        if (madvise(reinterpret_cast<void*>(a), kHuge, MADV_COLLAPSE) == 0) ++out.backed;
    }
}

}  // namespace
#endif

HugePages huge_pages(const std::atomic<bool>* quit) {
    HugePages out;
#if defined(__linux__) && !defined(__SANITIZE_ADDRESS__)
    const long page = sysconf(_SC_PAGESIZE);
    if (page != 4096) return out;  // resident[] holds a 2 MiB range's 4 KiB pages
    const int fd = ::open("/proc/self/maps", O_RDONLY | O_CLOEXEC);
    if (fd < 0) return out;
    // Line by line through a fixed buffer (a line is about 100 bytes; a longer one, a path,
    // is not an anonymous mapping and is skipped).
    char buf[8192];
    size_t have = 0;
    bool skipping = false;
    for (;;) {
        const ssize_t n = ::read(fd, buf + have, sizeof buf - 1 - have);
        if (n <= 0) break;
        have += size_t(n);
        size_t start = 0;
        for (size_t i = 0; i < have; ++i) {
            if (buf[i] != '\n') continue;
            buf[i] = '\0';
            uintptr_t lo = 0, hi = 0;
            if (!skipping && anonymous(buf + start, lo, hi)) collapse(lo, hi, quit, out);
            skipping = false;
            start = i + 1;
        }
        if (start == 0 && have == sizeof buf - 1) {  // a line longer than the buffer
            skipping = true;
            have = 0;
            continue;
        }
        std::memmove(buf, buf + start, have - start);
        have -= start;
    }
    ::close(fd);
#else
    (void)quit;  // sanitized builds: Bullet's blocks are the sanitizer's, left as they are
#endif
    return out;
}

Pager::Pager() : thread_([this] { run(); }) {}

Pager::~Pager() {
    {
        std::lock_guard<std::mutex> lock(m_);
        quit_.store(true, std::memory_order_relaxed);
    }
    cv_.notify_all();
    thread_.join();
}

int Pager::calls() const {
    std::lock_guard<std::mutex> lock(m_);
    return calls_;
}

void Pager::wake() {
    ++next_;
    {
        std::lock_guard<std::mutex> lock(m_);
        ++due_;
    }
    cv_.notify_all();
}

void Pager::run() {
    std::unique_lock<std::mutex> lock(m_);
    for (;;) {
        cv_.wait(lock, [this] { return quit_.load(std::memory_order_relaxed) || served_ < due_; });
        if (quit_.load(std::memory_order_relaxed)) return;
        served_ = due_;  // one call serves all asked for so far
        lock.unlock();
        huge_pages(&quit_);
        lock.lock();
        ++calls_;
    }
}

}  // namespace plant::engine
