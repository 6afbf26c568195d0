// Bad input gets a clear error, never a crash or a hang: seeded random damage to bundled
// plant files (the compiler) and compiled graphs (the loader and the runtime). Run under
// AddressSanitizer + UBSan in CI, a memory error here fails the suite. Each case also
// checks that the damage produced both outcomes, so it cannot pass by testing nothing.
#include "paths.h"
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "graph/text.h"

#include <doctest/doctest.h>

#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

using namespace plant::test;

namespace {

std::string read_repo_file(const std::string& path) {
    std::ifstream in(std::string(PLANT_SOURCE_DIR) + "/" + path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// Tokens of plant source: blanks, comments, strings, numbers, words, two-character
// operators, single characters.
std::vector<std::string> tokens(const std::string& text) {
    static const std::regex tok(R"(\s+|//[^\n]*|"[^"\n]*"|\d+(\.\d+)?(e[-+]?\d+)?|[A-Za-z_]\w*|->|=>|\.\.|\S)");
    std::vector<std::string> out;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), tok); it != std::sregex_iterator(); ++it)
        out.push_back(it->str());
    return out;
}

}  // namespace

TEST_CASE("robustness: damaged plant files compile or fail with located errors") {
    const std::vector<std::string> files = {"plants/experiments/traction.plant", "plants/experiments/spacing.plant",
                                            "stdlib/switch.plant", "stdlib/separator.plant",
                                            "examples/arm.plant"};
    std::vector<std::vector<std::string>> sources;
    std::vector<std::string> pool = {"0", "-1", "1e308", "1e-308", "99999999999999999", "{", "}", "(", ")", ",",
                                     "..", "->", "=", "ms", "kg/s", "deg", "for", "if", "let", "plant", "\""};
    for (const std::string& f : files) {
        sources.push_back(tokens(read_repo_file(f)));
        for (const std::string& t : sources.back())
            if (!t.empty() && !std::isspace(static_cast<unsigned char>(t[0]))) pool.push_back(t);
    }
    std::mt19937 rnd(20261122);
    auto pick = [&](size_t n) { return size_t(std::uniform_int_distribution<size_t>(0, n - 1)(rnd)); };
    int ok = 0, failed = 0;
    for (int run = 0; run < 240; ++run) {
        std::vector<std::string> t = sources[pick(sources.size())];
        const int edits = 1 + int(pick(3));
        for (int e = 0; e < edits && !t.empty(); ++e) {
            const size_t i = pick(t.size());
            switch (pick(4)) {
            case 0: t.erase(t.begin() + long(i)); break;
            case 1: t.insert(t.begin() + long(i), pool[pick(pool.size())]); break;
            case 2: t[i] = pool[pick(pool.size())]; break;
            default: t.resize(i); break;  // cut short
            }
        }
        std::string text;
        for (const std::string& s : t) text += s;
        plant::Compilation c;
        compile_text(text, c, "damaged.plant");
        if (c.ok()) {
            ++ok;
            continue;
        }
        ++failed;
        for (const auto& d : c.sink.all())
            if (d.severity == plant::Severity::Error) CHECK_MESSAGE(d.span.valid(), d.message << "\n--- in:\n" << text);
    }
    MESSAGE(ok << " compiled, " << failed << " failed");
    CHECK(ok > 0);
    CHECK(failed > 0);
}

TEST_CASE("robustness: damaged graph files load and run, or are refused") {
    const std::vector<std::string> files = {"tests/golden/run/switch_toggle.graph",
                                            "tests/golden/run/belt_two_bottles.graph",
                                            "tests/golden/run/separator_cycle.graph"};
    std::vector<std::string> texts;
    for (const std::string& f : files) {
        texts.push_back(read_repo_file(f));
        REQUIRE_MESSAGE(!texts.back().empty(), f);
    }
    std::mt19937 rnd(11222026);
    auto pick = [&](size_t n) { return size_t(std::uniform_int_distribution<size_t>(0, n - 1)(rnd)); };
    static const std::regex number(R"((^|[=( |:])(-?\d+(\.\d+)?(e[-+]?\d+)?)(?=[ )|:]|$))");
    const std::vector<std::string> values = {"-1", "0", "1", "2", "3", "7", "14", "50", "1000", "-2", "0.5", "1e300", "1e-300"};
    int loaded = 0, refused = 0;
    for (int run = 0; run < 300; ++run) {
        std::istringstream in(texts[pick(texts.size())]);
        std::vector<std::string> lines;
        for (std::string l; std::getline(in, l);) lines.push_back(l);
        for (int e = 0; e < 1 + int(pick(2)); ++e) {
            std::string& l = lines[4 + pick(lines.size() - 5)];
            if (l.starts_with("count")) continue;
            std::vector<std::smatch> ms;
            for (auto it = std::sregex_iterator(l.begin(), l.end(), number); it != std::sregex_iterator(); ++it)
                ms.push_back(*it);
            if (ms.size() < 2) continue;
            const std::smatch& m = ms[1 + pick(ms.size() - 1)];  // not the record's id
            l = l.substr(0, size_t(m.position(2))) + values[pick(values.size())] +
                l.substr(size_t(m.position(2) + m.length(2)));
        }
        std::string text;
        for (const std::string& l : lines) text += l + "\n";
        std::istringstream damaged(text);
        plant::graph::Graph g;
        std::string error;
        if (!plant::graph::read_text(damaged, g, error)) {
            ++refused;
            CHECK_MESSAGE(error.starts_with("line "), error);
            continue;
        }
        ++loaded;
        plant::engine::Engine e(g);
        for (int s = 0; s < 90; ++s) e.step();
        CHECK(e.time() > 0);
    }
    MESSAGE(loaded << " loaded and ran, " << refused << " refused");
    CHECK(loaded > 0);
    CHECK(refused > 0);
}
