// The processor time the benchmarks measure: this process's, all its threads, user and system
// (steadier than the wall clock on a busy machine).
#pragma once

#include <ctime>

namespace plant::bench {

inline double process_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace plant::bench
