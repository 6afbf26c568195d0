// Myers' O(ND) difference algorithm (E. Myers, "An O(ND) Difference Algorithm and Its
// Variations", 1986) on lines, then hunks with context in the unified format.
#include "fmt/diff.h"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

namespace plant::formatter {
namespace {

// Lines with their line ends; a last line without one is its own kind of line.
std::vector<std::string_view> split(std::string_view text) {
    std::vector<std::string_view> lines;
    size_t at = 0;
    while (at < text.size()) {
        const size_t nl = text.find('\n', at);
        const size_t end = nl == std::string_view::npos ? text.size() : nl + 1;
        lines.push_back(text.substr(at, end - at));
        at = end;
    }
    return lines;
}

enum class Op : char { Same = ' ', Del = '-', Add = '+' };

// A formatter's diff has few edits; past this many the rest is one replacement (still a
// correct diff, only not the shortest), so memory stays bounded (about kMaxEdits² ints).
constexpr long kMaxEdits = 4000;

// The edit script turning a[lo_a, hi_a) into b[lo_b, hi_b).
void myers(const std::vector<std::string_view>& a, const std::vector<std::string_view>& b, std::vector<Op>& out) {
    const long n = long(a.size()), m = long(b.size()), max = std::min(n + m, kMaxEdits);
    std::vector<std::vector<long>> trace;  // V after each d, diagonals -d..d at [k + d]
    std::vector<long> v(2 * max + 3, 0);
    const long off = max + 1;
    long found = -1;
    for (long d = 0; d <= max && found < 0; ++d) {
        for (long k = -d; k <= d; k += 2) {
            long x = (k == -d || (k != d && v[off + k - 1] < v[off + k + 1])) ? v[off + k + 1]
                                                                                              : v[off + k - 1] + 1;
            long y = x - k;
            while (x < n && y < m && a[x] == b[y]) ++x, ++y;
            v[off + k] = x;
            if (x >= n && y >= m) found = d;
        }
        trace.emplace_back(v.begin() + off - d, v.begin() + off + d + 1);
    }
    if (found < 0) {  // too many edits: all of a out, all of b in
        out.assign(n, Op::Del);
        out.insert(out.end(), m, Op::Add);
        return;
    }
    std::vector<Op> rev;
    long x = n, y = m;
    for (long d = found; d > 0; --d) {
        const std::vector<long>& prev = trace[d - 1];  // diagonals -(d-1)..d-1
        const long k = x - y;
        auto at = [&](long kk) { return prev[kk + d - 1]; };
        const bool down = k == -d || (k != d && at(k - 1) < at(k + 1));
        const long pk = down ? k + 1 : k - 1;
        const long px = at(pk), py = px - pk;
        while (x > (down ? px : px + 1) && y > (down ? py + 1 : py)) rev.push_back(Op::Same), --x, --y;
        rev.push_back(down ? Op::Add : Op::Del);
        x = px, y = py;
    }
    while (x > 0 && y > 0) rev.push_back(Op::Same), --x, --y;
    out.assign(rev.rbegin(), rev.rend());
}

std::string range(long start, long count) {
    // GNU diff: an empty range names the line before it; a range of one, its line alone.
    if (count == 1) return std::to_string(start + 1);
    return fmt::format("{},{}", count == 0 ? start : start + 1, count);
}

void line(std::string& out, char op, std::string_view l) {
    out += op;
    out += l;
    if (l.empty() || l.back() != '\n') out += "\n\\ No newline at end of file\n";
}

}  // namespace

std::string unified_diff(std::string_view before, std::string_view after, std::string_view name, int context) {
    if (before == after) return {};
    const std::vector<std::string_view> a = split(before), b = split(after);
    // The common start and end need no search.
    size_t pre = 0;
    while (pre < a.size() && pre < b.size() && a[pre] == b[pre]) ++pre;
    size_t post = 0;
    while (post < a.size() - pre && post < b.size() - pre && a[a.size() - 1 - post] == b[b.size() - 1 - post]) ++post;
    std::vector<Op> mid;
    myers({a.begin() + long(pre), a.end() - long(post)}, {b.begin() + long(pre), b.end() - long(post)}, mid);
    std::vector<Op> ops(pre, Op::Same);
    ops.insert(ops.end(), mid.begin(), mid.end());
    ops.insert(ops.end(), post, Op::Same);

    std::string out = fmt::format("--- {}\n+++ {}\n", name, name);
    const long c = context, total = long(ops.size());
    long i = 0, ia = 0, ib = 0;  // position in ops, a and b
    while (i < total) {
        if (ops[i] == Op::Same) {
            ++i, ++ia, ++ib;
            continue;
        }
        // A hunk: from `c` lines before this change to `c` after the last change that is
        // at most 2c unchanged lines from the next.
        const long lead = std::min(c, ia < ib ? ia : ib);
        long end = i;
        for (long same = 0; end < total; ++end) {
            same = ops[end] == Op::Same ? same + 1 : 0;
            if (same > 2 * c) break;
        }
        // `end` is past the run of unchanged lines that ends the hunk; keep `c` of them.
        long last = end;
        while (last > i && ops[last - 1] == Op::Same) --last;
        const long stop = std::min(total, last + c);
        long na = lead, nb = lead;
        for (long k = i; k < stop; ++k) {
            na += ops[k] != Op::Add;
            nb += ops[k] != Op::Del;
        }
        out += fmt::format("@@ -{} +{} @@\n", range(ia - lead, na), range(ib - lead, nb));
        for (long k = lead; k > 0; --k) line(out, ' ', a[ia - k]);
        for (; i < stop; ++i) {
            const Op op = ops[i];
            if (op == Op::Same) line(out, ' ', a[ia]), ++ia, ++ib;
            else if (op == Op::Del) line(out, '-', a[ia++]);
            else line(out, '+', b[ib++]);
        }
    }
    return out;
}

}  // namespace plant::formatter
