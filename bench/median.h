// The median the benchmarks quote (one slow or one lucky run must not move a row).
#pragma once

#include <algorithm>
#include <vector>

namespace plant::bench {

inline double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace plant::bench
