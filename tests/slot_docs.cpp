// docs/language.md's slot tables are generated from the slot declarations in
// graph/kinds.h (and the plugin kinds with slots: the panel's elements). In each `### ... `WORD`` section of a component kind, the first
// table headed `| slot | type | dir | |` starts with one row per fixed slot, in index
// order; rows for content-dependent slots (`A.play`, `NAME`) follow, written by hand.
//
//   plant_slot_docs FILE.md            exit 1 (with the differences) unless FILE's tables match
//   plant_slot_docs --update FILE.md   rewrite the fixed rows (scripts/update-goldens.sh)
#include "graph/kinds.h"
#include "panel/kind.h"
#include "sema/schema.h"

#include <algorithm>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

using namespace plant;

namespace {

std::string row(const graph::SlotSpec& s) {
    std::ostringstream o;
    o << "| `" << s.name << "` | " << graph::word(s.type) << " | " << graph::word(s.dir) << " | " << s.doc << " |";
    return o.str();
}

bool fixed_row(const std::string& line) {
    static const std::regex kFixed(R"(^\| `[a-z_][a-z_0-9]*` \|.*)");
    return std::regex_match(line, kFixed);
}

// The lines with each kind's fixed rows replaced; every difference in `problems`.
std::vector<std::string> regenerate(const std::vector<std::string>& in, std::vector<std::string>& problems) {
    static const std::regex kHeading(R"(^###+ .*?`([a-z_]+)`.*)");
    std::vector<std::string> out;
    std::vector<std::string> seen;
    const sema::KindSpec* kind = nullptr;  // the section's kind, until its table is done
    for (size_t i = 0; i < in.size(); ++i) {
        std::smatch m;
        if (std::regex_match(in[i], m, kHeading)) kind = sema::find_kind(m[1].str());
        else if (in[i].rfind("## ", 0) == 0) kind = nullptr;
        out.push_back(in[i]);
        if (!kind || in[i] != "| slot | type | dir | |") continue;
        seen.emplace_back(kind->word);
        if (i + 1 < in.size()) out.push_back(in[++i]);  // |---|...
        size_t n = 0;
        auto specs = sema::kind_slots(*kind);
        while (i + 1 < in.size() && fixed_row(in[i + 1])) {
            ++i;
            if (n >= specs.size() || in[i] != row(specs[n]))
                problems.push_back("line " + std::to_string(i + 1) + ": " + in[i] + "\n  expected: " +
                                   (n < specs.size() ? row(specs[n]) : std::string("no such fixed slot")));
            ++n;
        }
        if (n < specs.size())
            problems.push_back(std::string(kind->word) + ": the table lacks " + std::to_string(specs.size() - n) +
                               " fixed slot(s), first '" + std::string(specs[n].name) + "'");
        for (const auto& s : specs) out.push_back(row(s));
        kind = nullptr;
    }
    for (const std::string& w : sema::kind_words()) {
        const auto* k = sema::find_kind(w);
        if (k && !sema::kind_slots(*k).empty() && std::find(seen.begin(), seen.end(), w) == seen.end())
            problems.push_back("no slot table for the kind '" + w + "'");
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    panel::register_panel_kinds();
    bool update = argc == 3 && std::string(argv[1]) == "--update";
    if (argc != 2 && !update) {
        std::cerr << "usage: plant_slot_docs [--update] FILE.md\n";
        return 2;
    }
    const std::string path = argv[argc - 1];
    std::ifstream f(path);
    if (!f) {
        std::cerr << path << ": cannot read\n";
        return 2;
    }
    std::vector<std::string> lines;
    for (std::string l; std::getline(f, l);) lines.push_back(l);
    std::vector<std::string> problems;
    std::vector<std::string> out = regenerate(lines, problems);
    if (update) {
        std::ofstream w(path);
        for (const auto& l : out) w << l << "\n";
        return w ? 0 : 2;
    }
    for (const auto& p : problems) std::cerr << path << ": " << p << "\n";
    if (!problems.empty())
        std::cerr << "the slot tables are generated from graph/kinds.h: run scripts/update-goldens.sh\n";
    return problems.empty() ? 0 : 1;
}
