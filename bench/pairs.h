// What a client costs a run, measured in pairs in turns (the viewer page, the Modbus and the
// OPC UA client: plant_bench_serve, _plc, _opcua).
//
// Pair i runs the case without the client and the case with it one after the other: without
// first when i is even, with first when it is odd, so a drift of the machine's speed within
// a pair falls on both cases alike over the pairs. Each pair gives a ratio (with / without);
// the row quotes their median and their range. On this 2-core VM single runs of a second or
// two spread by ±15 % (its speed drifts from minute to minute), so a ratio of the two cases'
// medians over 3 runs read anywhere from x0.9 to x1.17 for the same binary; the median of the
// pairs' own ratios keeps only what the client changes in the same minute.
#pragma once

#include "median.h"

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace plant::bench {

struct Pairs {
    std::vector<double> without, with;

    // Runs pair `i`: measure(false) and measure(true) in its order; keeps both figures.
    template <class F>
    void run(int i, F&& measure) {
        if (i % 2 == 0) {
            without.push_back(measure(false));
            with.push_back(measure(true));
        } else {
            with.push_back(measure(true));
            without.push_back(measure(false));
        }
    }
    // Keeps a pair measured by the caller (a second figure of the same runs).
    void add(double w, double wo) {
        with.push_back(w);
        without.push_back(wo);
    }
    std::vector<double> ratios() const {
        std::vector<double> r;
        for (size_t i = 0; i < with.size() && i < without.size(); ++i) r.push_back(without[i] > 0 ? with[i] / without[i] : 0);
        return r;
    }
    double ratio() const { return median(ratios()); }
    // The lowest and the highest of the pairs' ratios.
    std::pair<double, double> range() const {
        const std::vector<double> r = ratios();
        if (r.empty()) return {0, 0};
        const auto [lo, hi] = std::minmax_element(r.begin(), r.end());
        return {*lo, *hi};
    }
};

}  // namespace plant::bench
