#include "serve/history.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace plant::view {

namespace {
constexpr double kFirstEvery = 0.2;  // s of simulated time: the status's own period
}

History::History(size_t records, size_t numbers)
    : cols_(kCounters + records), max_(std::clamp<size_t>(numbers / (kCounters + records), 200, 4000)) {
    time_.reserve(max_);
    values_.reserve(max_ * cols_);
}

void History::clear() {
    time_.clear();
    values_.clear();
    every_ = kFirstEvery;
    next_ = 0;
}

void History::add(double t, std::span<const double> values) {
    if (!time_.empty() && t < time_.back()) clear();  // a restart or a seek back
    if (time_.size() == max_) {
        // Every other sample goes (the first and the newest stay), the interval doubles.
        size_t k = 0;
        for (size_t i = 0; i < time_.size(); i += 2, ++k) {
            time_[k] = time_[i];
            std::copy_n(values_.begin() + ptrdiff_t(i * cols_), cols_, values_.begin() + ptrdiff_t(k * cols_));
        }
        time_.resize(k);
        values_.resize(k * cols_);
        every_ *= 2;
    }
    time_.push_back(t);
    for (size_t c = 0; c < cols_; ++c) values_.push_back(c < values.size() ? values[c] : 0.0);
    next_ = (std::floor(t / every_ + 1e-9) + 1) * every_;
}

std::string History::json() const {
    using json = nlohmann::json;
    json j{{"type", "history"}, {"every", every_}, {"time", time_}};
    json counters = json::object(), records = json::array();
    for (size_t c = 0; c < cols_; ++c) {
        std::vector<double> col(time_.size());
        for (size_t i = 0; i < time_.size(); ++i) col[i] = values_[i * cols_ + c];
        if (c < kCounters) counters[kCounterNames[c]] = std::move(col);
        else records.push_back(std::move(col));
    }
    j["counters"] = std::move(counters);
    j["records"] = std::move(records);
    return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

}  // namespace plant::view
