// What a running sweep says about itself: runs done of the total, how many were not ok,
// how many are running, and the time left at the pace so far. On a terminal one line that
// is rewritten in place; in a log (stderr not a terminal) plain lines, at most one every
// kLogEvery seconds and always the last, so a long sweep's log stays readable.
#include "sweep.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <ostream>

namespace plant::sweep {

namespace {

constexpr double kLogEvery = 10;  // seconds between two progress lines in a log

double seconds_now() {
    using namespace std::chrono;
    return duration<double>(steady_clock::now().time_since_epoch()).count();
}

}  // namespace

std::string format_duration(double s) {
    if (!(s >= 0) || s > 1e8) return "?";
    const long t = std::lround(s);
    if (t < 60) return fmt::format("{} s", t);
    if (t < 3600) return fmt::format("{} min {:02} s", t / 60, t % 60);
    return fmt::format("{} h {:02} min", t / 3600, (t % 3600) / 60);
}

Progress::Progress(std::ostream& err, bool terminal, size_t total, size_t done_before, size_t failed_before)
    : err_(err), terminal_(terminal), total_(total), done_(done_before), failed_(failed_before),
      done_before_(done_before), started_(seconds_now()) {}

std::string Progress::line(size_t running) const {
    std::string s = fmt::format("{}/{} runs done, {} not ok", done_, total_, failed_);
    if (running > 0) s += fmt::format(", {} running", running);
    const size_t ran = done_ - done_before_;
    if (done_ < total_) {
        // The pace of this session's runs (those kept by --resume took no time now).
        if (ran > 0) s += ", about " + format_duration((seconds_now() - started_) / double(ran) * double(total_ - done_)) + " left";
        else s += ", time left not known before the first run ends";
    } else {
        s += ", in " + format_duration(seconds_now() - started_);
    }
    return s;
}

void Progress::finished(bool ok, size_t running) {
    ++done_;
    if (!ok) ++failed_;
    show(running, done_ == total_);
}

void Progress::tick(size_t running) {
    if (terminal_ && seconds_now() - last_ >= 1) show(running, false);
}

void Progress::show(size_t running, bool force) {
    const double now = seconds_now();
    if (terminal_) {
        err_ << "\r\033[K" << "plant sweep: " << line(running) << std::flush;
        shown_ = true;
    } else if (force || now - last_ >= kLogEvery) {
        err_ << "plant sweep: " << line(running) << "\n" << std::flush;
    } else {
        return;
    }
    last_ = now;
}

void Progress::clear() {
    if (terminal_ && shown_) err_ << "\r\033[K" << std::flush;
    shown_ = false;
}

void Progress::end() {
    if (terminal_ && shown_) err_ << "\n" << std::flush;
    shown_ = false;
}

}  // namespace plant::sweep
