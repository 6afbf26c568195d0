#include "engine/times.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace plant::engine {

int time_decimals(double dt) {
    if (!(dt > 0)) return 3;
    // 1e-9: an exact power of ten (50 Hz: 2 / dt = 100) needs no extra decimal.
    return std::clamp(int(std::ceil(std::log10(2 / dt) - 1e-9)), 1, 9);
}

int trace_time_decimals(double dt) { return time_decimals(dt) + 3; }

std::string time_text(double t, double dt) { return fmt::format("{:.{}f}", t, time_decimals(dt)); }

double time_slack(double dt) { return 0.5 * std::pow(10.0, -time_decimals(dt)); }

}  // namespace plant::engine
