// The series of a run for the page's plots (docs/viewer.md, "history"): the counters and
// the records sampled from t = 0, so that a page opened late, or a replay after a seek,
// plots the whole run. Bounded: when the samples would pass the bound, every other one is
// dropped and the interval doubles, so an hour-long run keeps its whole shape.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace plant::view {

// The counters every status carries, in the history's order.
inline constexpr const char* kCounterNames[] = {"issued", "taken", "on_line", "lost", "stalled", "removed"};
inline constexpr size_t kCounters = std::size(kCounterNames);

class History {
public:
    // `records`: the scene's records (one column each, after the counters). At most about
    // `numbers` values are kept (samples × columns), at least 200 samples.
    explicit History(size_t records = 0, size_t numbers = 400000);
    void clear();
    // Whether a sample is due at simulated time t (one every `every()` seconds).
    bool due(double t) const { return t + 1e-9 >= next_; }
    // `values`: the counters, then the records (kCounters + records numbers).
    void add(double t, std::span<const double> values);
    double every() const { return every_; }
    size_t samples() const { return time_.size(); }
    size_t capacity() const { return max_; }
    // {"type":"history","every":E,"time":[...],"counters":{"issued":[...],...},"records":[[...],...]}
    std::string json() const;

private:
    size_t cols_, max_;
    double every_ = 0.2, next_ = 0;
    std::vector<double> time_, values_;  // values_: samples × cols_, row by row
};

}  // namespace plant::view
