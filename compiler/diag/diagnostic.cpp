// The registry of diagnostic codes, the Sink that collects diagnostics, and the
// "did you mean" helper. Rendering is in render.cpp, SourceMap in source_map.cpp.
#include "diag/diagnostic.h"

#include <algorithm>
#include <cctype>
#include <tuple>

namespace plant {

namespace {

constexpr DiagInfo kInfos[] = {
#define PLANT_DIAG(Id, Code, Sev, Summary) {DiagId::Id, Code, Severity::Sev, Summary},
#include "diag/codes.def"
#undef PLANT_DIAG
};

}  // namespace

const DiagInfo& info(DiagId id) { return kInfos[static_cast<std::size_t>(id)]; }

std::vector<DiagInfo> all_diagnostics() { return {std::begin(kInfos), std::end(kInfos)}; }

// The returned reference stays valid only until the next call to report(): the
// diagnostics live in a vector that may reallocate. Add notes right away:
//   sink.report(DiagId::DuplicateName, span, "...").notes.push_back({first, "first here"});
Diagnostic& Sink::report(DiagId id, Span span, std::string message) {
    diags_.push_back({id, info(id).severity, span, std::move(message), {}});
    return diags_.back();
}

bool Sink::has_errors() const { return count(Severity::Error) > 0; }

int Sink::count(Severity s) const {
    return static_cast<int>(
        std::count_if(diags_.begin(), diags_.end(), [s](const Diagnostic& d) { return d.severity == s; }));
}

namespace {

// Sort key: diagnostics without a position come first, in report order.
auto sort_key(const Diagnostic& d) {
    bool valid = d.span.valid();
    return std::tuple(valid ? d.span.file : -1, valid ? d.span.begin : 0u, info(d.id).code);
}

bool same_span(const Span& a, const Span& b) {
    if (a.valid() != b.valid()) return false;
    return !a.valid() || (a.file == b.file && a.begin == b.begin && a.end == b.end);
}

bool is_duplicate(const Diagnostic& a, const Diagnostic& b) {
    return a.id == b.id && same_span(a.span, b.span) && a.message == b.message;
}

}  // namespace

// Duplicates (same code, span and message; notes are not compared) keep the first
// one reported. Duplicates have the same sort key, so after the stable sort they sit
// in the same run of equal keys: only that run needs to be searched.
std::vector<Diagnostic> Sink::sorted() const {
    std::vector<const Diagnostic*> order;
    order.reserve(diags_.size());
    for (const Diagnostic& d : diags_) order.push_back(&d);
    std::stable_sort(order.begin(), order.end(),
                     [](const Diagnostic* a, const Diagnostic* b) { return sort_key(*a) < sort_key(*b); });

    std::vector<Diagnostic> out;
    std::size_t run_start = 0;  // first element of `out` with the current key
    for (const Diagnostic* d : order) {
        if (!out.empty() && sort_key(out.back()) != sort_key(*d)) run_start = out.size();
        bool dup = std::any_of(out.begin() + static_cast<std::ptrdiff_t>(run_start), out.end(),
                               [d](const Diagnostic& kept) { return is_duplicate(kept, *d); });
        if (!dup) out.push_back(*d);
    }
    return out;
}

namespace {

// Optimal string alignment distance (Damerau-Levenshtein where a transposition of
// two adjacent characters counts as one edit), optionally ignoring ASCII case.
std::size_t edit_distance(std::string_view a, std::string_view b, bool fold_case) {
    auto eq = [fold_case](char x, char y) {
        if (!fold_case) return x == y;
        auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; };  // ASCII case
        return lower(x) == lower(y);
    };
    const std::size_t n = a.size(), m = b.size();
    std::vector<std::size_t> d((n + 1) * (m + 1));
    auto at = [&](std::size_t i, std::size_t j) -> std::size_t& { return d[i * (m + 1) + j]; };
    for (std::size_t i = 0; i <= n; ++i) at(i, 0) = i;
    for (std::size_t j = 0; j <= m; ++j) at(0, j) = j;
    for (std::size_t i = 1; i <= n; ++i) {
        for (std::size_t j = 1; j <= m; ++j) {
            std::size_t cost = eq(a[i - 1], b[j - 1]) ? 0 : 1;
            at(i, j) = std::min({at(i - 1, j) + 1, at(i, j - 1) + 1, at(i - 1, j - 1) + cost});
            if (i > 1 && j > 1 && eq(a[i - 1], b[j - 2]) && eq(a[i - 2], b[j - 1]))
                at(i, j) = std::min(at(i, j), at(i - 2, j - 2) + 1);
        }
    }
    return at(n, m);
}

}  // namespace

// Ranked by edit distance, then by case-insensitive edit distance, then by position
// in `candidates`. Accepted only within max(1, wanted.size() / 3) edits.
ClosestName::ClosestName(std::string_view wanted)
    : wanted_(wanted), limit_(std::max<std::size_t>(1, wanted.size() / 3)) {}

void ClosestName::offer(const std::string& c) {
    if (c == wanted_) return;
    // A distance is at least the difference in length: a candidate that differs by more than
    // the limit is not near, and its distances need not be found.
    const std::size_t n = wanted_.size(), m = c.size();
    if ((n > m ? n - m : m - n) > limit_) return;
    const std::size_t first = edit_distance(wanted_, c, false);
    if (first > limit_) return;
    const std::pair rank{first, edit_distance(wanted_, c, true)};
    if (!best_ || rank < best_rank_) {
        best_ = &c;
        best_rank_ = rank;
    }
}

std::string closest_name(std::string_view wanted, const std::vector<std::string>& candidates) {
    ClosestName closest(wanted);
    for (const std::string& c : candidates) closest.offer(c);
    return closest.best();
}

}  // namespace plant
