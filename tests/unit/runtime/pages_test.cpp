// Huge pages (runtime/engine/pages.cpp): a 2 MiB range is backed by a huge page only where all
// of it is resident, so the process takes no more memory, and its bytes stay what they were;
// where the kernel backs ranges (Linux 6.1 and later, transparent huge pages not switched off)
// a buffer that spans several ranges is backed; the Pager calls huge_pages once when made and
// once for each simulated time it is told of. A sanitized build leaves the pages alone.
#include "engine/pages.h"

#include <doctest/doctest.h>
#include <sys/mman.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>

using plant::engine::huge_pages;
using plant::engine::HugePages;
using plant::engine::Pager;

namespace {

constexpr size_t kMiB = size_t(1) << 20;

// Whether this kernel backs ranges on request: 6.1 or later, and huge pages not "never".
[[maybe_unused]] bool kernel_backs() {
    utsname u{};
    if (uname(&u) != 0) return false;
    int major = 0, minor = 0;
    if (std::sscanf(u.release, "%d.%d", &major, &minor) != 2 || major < 6 || (major == 6 && minor < 1)) return false;
    std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string mode;
    std::getline(f, mode);
    return !mode.empty() && mode.find("[never]") == std::string::npos;
}

// The kB of huge pages backing the mapping that holds p (/proc/self/smaps).
[[maybe_unused]] long huge_kb_at(const void* p) {
    std::ifstream f("/proc/self/smaps");
    std::string line;
    bool in = false;
    const auto a = reinterpret_cast<uintptr_t>(p);
    while (std::getline(f, line)) {
        unsigned long lo = 0, hi = 0;
        if (std::sscanf(line.c_str(), "%lx-%lx ", &lo, &hi) == 2 && line.find(':') > line.find(' ')) {
            in = a >= lo && a < hi;
            continue;
        }
        long kb = 0;
        if (in && std::sscanf(line.c_str(), "AnonHugePages: %ld kB", &kb) == 1) return kb;
    }
    return -1;
}

// How many of [p, p + n)'s pages are resident.
size_t resident_pages(void* p, size_t n) {
    const size_t page = size_t(sysconf(_SC_PAGESIZE));
    std::string v(n / page, '\0');
    if (mincore(p, n, reinterpret_cast<unsigned char*>(v.data())) != 0) return 0;
    size_t k = 0;
    for (char c : v) k += size_t(c & 1);
    return k;
}

long rss_pages() {
    std::ifstream f("/proc/self/statm");
    long size = 0, rss = 0;
    f >> size >> rss;
    return rss;
}

}  // namespace

TEST_CASE("huge pages: only ranges resident in full are backed, their bytes kept, no memory added") {
    const size_t n = 12 * kMiB, page = size_t(sysconf(_SC_PAGESIZE));
    auto* full = static_cast<unsigned char*>(mmap(nullptr, n, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
    auto* half = static_cast<unsigned char*>(mmap(nullptr, n, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
    REQUIRE(full != MAP_FAILED);
    REQUIRE(half != MAP_FAILED);
    for (size_t i = 0; i < n; ++i) full[i] = static_cast<unsigned char>(i * 131 + 7);
    for (size_t i = 0; i < n; i += 2 * page) half[i] = 1;  // every other page
    // Half resident, unless the system backs every fault with a huge page ("always").
    const size_t half_resident = resident_pages(half, n);
    const long before = rss_pages();

    const HugePages h = huge_pages();

    // The half-touched buffer is left alone: backing it would have made all of it resident.
    if (half_resident == n / page / 2) CHECK(resident_pages(half, n) == half_resident);
    CHECK(rss_pages() <= before + long(kMiB / page));
    bool same = true;
    for (size_t i = 0; i < n && same; ++i) same = full[i] == static_cast<unsigned char>(i * 131 + 7);
    CHECK(same);
#if defined(__SANITIZE_ADDRESS__)
    CHECK(h.asked == 0);
    CHECK(h.backed == 0);
#else
    CHECK(h.asked >= 5);  // the full buffer alone spans 5 aligned 2 MiB ranges
    CHECK(h.backed <= h.asked);
    if (kernel_backs()) {
        CHECK(h.backed == h.asked);
        CHECK(huge_kb_at(full + n / 2) >= 5 * 2048);
    }
#endif
    munmap(full, n);
    munmap(half, n);
}

TEST_CASE("huge pages: the pager calls once when made and once for each time it is told of") {
    Pager p;
    // Waits (10 s at most) until p has made `calls` calls.
    auto reaches = [&p](int calls) {
        for (int i = 0; i < 1000 && p.calls() < calls; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        return p.calls() == calls;
    };
    CHECK(reaches(1));  // when made
    p.tick(0.5);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(p.calls() == 1);
    p.tick(1.0);
    CHECK(reaches(2));
    p.tick(5);
    p.tick(10);
    CHECK(reaches(3));
    p.tick(40);
    CHECK(reaches(4));
    p.tick(1000);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(p.calls() == 4);  // no times left
}
