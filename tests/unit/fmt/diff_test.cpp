// plant fmt --check's unified diff: the format `diff -u` prints, every difference with its
// context, and on random texts a diff that applies (the hunks turn the first text into the
// second) and is shortest (as many lines out and in as the longest common subsequence leaves).
#include "fmt/diff.h"

#include <doctest/doctest.h>

#include <random>
#include <sstream>
#include <string>
#include <vector>

using plant::formatter::unified_diff;

namespace {

std::vector<std::string> diff_lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l + "\n");
    if (!text.empty() && text.back() != '\n') out.back().pop_back();
    return out;
}

// Applies a unified diff to `text`, checking each hunk's header and context on the way.
std::string apply_diff(const std::string& text, const std::string& diff, int& removed, int& added) {
    const std::vector<std::string> a = diff_lines_of(text);
    std::istringstream in(diff);
    std::string l;
    std::getline(in, l);
    CHECK(l.rfind("--- ", 0) == 0);
    std::getline(in, l);
    CHECK(l.rfind("+++ ", 0) == 0);
    std::string out;
    size_t at = 0;  // next line of a not yet copied
    std::string* last = nullptr;
    while (std::getline(in, l)) {
        if (l.rfind("@@ -", 0) == 0) {
            long start = 0, count = 1;
            const std::string r = l.substr(4, l.find(' ', 4) - 4);
            start = std::stol(r);
            if (r.find(',') != std::string::npos) count = std::stol(r.substr(r.find(',') + 1));
            const size_t first = size_t(count == 0 ? start : start - 1);
            REQUIRE(first >= at);
            for (; at < first; ++at) out += a[at];
            continue;
        }
        if (l == "\\ No newline at end of file") {
            // After an added line: drop the line end written with it (else the text's own line had none).
            if (last && !last->empty() && last->back() == '\n') last->pop_back();
            continue;
        }
        REQUIRE(!l.empty());
        const std::string body = l.substr(1) + "\n";
        if (l[0] == '+') {
            out += body;
            ++added;
            last = &out;  // the newline just written is the one to drop
            continue;
        }
        REQUIRE(at < a.size());
        const std::string want = a[at].back() == '\n' ? a[at] : a[at] + "\n";
        CHECK(body == want);  // context and removed lines are the text's own
        if (l[0] == ' ') {
            out += a[at];
            last = nullptr;
        } else {
            REQUIRE(l[0] == '-');
            ++removed;
            last = nullptr;
        }
        ++at;
    }
    for (; at < a.size(); ++at) out += a[at];
    return out;
}

size_t lcs(const std::vector<std::string>& a, const std::vector<std::string>& b) {
    std::vector<std::vector<size_t>> t(a.size() + 1, std::vector<size_t>(b.size() + 1, 0));
    for (size_t i = a.size(); i-- > 0;)
        for (size_t j = b.size(); j-- > 0;)
            t[i][j] = a[i] == b[j] ? t[i + 1][j + 1] + 1 : std::max(t[i + 1][j], t[i][j + 1]);
    return t[0][0];
}

}  // namespace

TEST_CASE("fmt diff: every difference, each hunk with three lines of context, as diff -u") {
    std::string a, b;
    for (int i = 1; i <= 20; ++i) {
        a += "line " + std::to_string(i) + "\n";
        b += (i == 2 ? "LINE 2\n" : i == 15 ? "" : "line " + std::to_string(i) + "\n");
    }
    b += "line 21\n";
    // What GNU diff -u prints for these two texts (file names aside).
    CHECK(unified_diff(a, b, "x.plant") ==
          "--- x.plant\n+++ x.plant\n"
          "@@ -1,5 +1,5 @@\n line 1\n-line 2\n+LINE 2\n line 3\n line 4\n line 5\n"
          "@@ -12,9 +12,9 @@\n line 12\n line 13\n line 14\n-line 15\n line 16\n line 17\n line 18\n line 19\n line 20\n+line 21\n");
    CHECK(unified_diff(a, a, "x.plant").empty());
    // No line end after the last line, on either side.
    CHECK(unified_diff("a\nb", "a\nb\n", "y") == "--- y\n+++ y\n@@ -1,2 +1,2 @@\n a\n-b\n\\ No newline at end of file\n+b\n");
    CHECK(unified_diff("", "a\n", "y") == "--- y\n+++ y\n@@ -0,0 +1 @@\n+a\n");
}

TEST_CASE("fmt diff: on random texts the diff applies and is the shortest") {
    std::mt19937 rng(34);
    for (int round = 0; round < 300; ++round) {
        auto text = [&] {
            std::string t;
            const int n = int(rng() % 30);
            for (int i = 0; i < n; ++i) t += std::string(1, char('a' + rng() % 4)) + "\n";
            if (rng() % 5 == 0) t += "z";  // no line end at the end
            return t;
        };
        const std::string a = text(), b = text();
        const std::string d = unified_diff(a, b, "r.plant");
        if (a == b) {
            CHECK(d.empty());
            continue;
        }
        int removed = 0, added = 0;
        CHECK(apply_diff(a, d, removed, added) == b);
        const auto la = diff_lines_of(a), lb = diff_lines_of(b);
        const size_t common = lcs(la, lb);
        CHECK(size_t(removed) == la.size() - common);
        CHECK(size_t(added) == lb.size() - common);
    }
}
