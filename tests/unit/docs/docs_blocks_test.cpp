// Every ```plant block in README.md and docs/*.md is compiled: the docs cannot drift from
// the language. The fence's info string says what the block is (docs/README.md):
//
//   ```plant                a whole file: it compiles without errors (a library is checked
//                           type by type)
//   ```plant fail=E0201     it must fail with that code (fail=E0203,E0101: with each)
//   ```plant fragment       members of a plant: compiled inside `plant Fragment { ... }`
//   ```plant at=examples    a file of that folder (its relative imports resolve there)
//
// And no project file cites a document that a checkout does not have.
#include "paths.h"
#include "../compiler/compile_helper.h"
#include "diag/diagnostic.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

struct Block {
    std::string file;
    int line = 0;
    std::string text, fail, at;
    bool fragment = false;
};

std::vector<Block> plant_blocks(const fs::path& md, const std::string& shown) {
    std::vector<Block> out;
    std::ifstream in(md);
    std::string line;
    Block* open = nullptr;
    for (int n = 1; std::getline(in, line); ++n) {
        if (open) {
            if (line.rfind("```", 0) == 0) open = nullptr;
            else open->text += line + "\n";
            continue;
        }
        if (line.rfind("```", 0) != 0) continue;
        std::istringstream info(line.substr(3));
        std::string lang, word;
        info >> lang;
        if (lang != "plant") {
            // Skip the other fence's body.
            while (std::getline(in, line) && line.rfind("```", 0) != 0) ++n;
            ++n;
            continue;
        }
        Block b;
        b.file = shown;
        b.line = n;
        while (info >> word) {
            if (word.rfind("fail=", 0) == 0) b.fail = word.substr(5);
            else if (word.rfind("at=", 0) == 0) b.at = word.substr(3);
            else if (word == "fragment") b.fragment = true;
            else FAIL_CHECK(shown << ":" << n << ": unknown word '" << word << "' after ```plant");
        }
        out.push_back(std::move(b));
        open = &out.back();
    }
    return out;
}

// The folder a block is compiled in: a fresh one, or one that mirrors `at` (symlinks to
// its entries) so that relative imports resolve as in that folder.
fs::path block_dir(const Block& b, int index) {
    const fs::path dir = plant::test::scratch_dir() / "docs" / std::to_string(index);
    fs::create_directories(dir);
    if (!b.at.empty())
        for (const auto& e : fs::directory_iterator(fs::path(PLANT_SOURCE_DIR) / b.at))
            fs::create_symlink(e.path(), dir / e.path().filename());
    return dir;
}

}  // namespace

TEST_CASE("docs: every plant block in the README and docs/ compiles, or fails as it says") {
    std::vector<std::pair<fs::path, std::string>> files{{fs::path(PLANT_SOURCE_DIR) / "README.md", "README.md"}};
    std::vector<fs::path> docs;
    for (const auto& e : fs::directory_iterator(fs::path(PLANT_SOURCE_DIR) / "docs"))
        if (e.path().extension() == ".md") docs.push_back(e.path());
    std::sort(docs.begin(), docs.end());
    for (const auto& d : docs) files.emplace_back(d, "docs/" + d.filename().string());

    int index = 0, compiled = 0, failing = 0;
    for (const auto& [path, shown] : files)
        for (const Block& b : plant_blocks(path, shown)) {
            const fs::path dir = block_dir(b, ++index);
            const fs::path file = dir / "block.plant";
            std::ofstream(file) << (b.fragment ? "plant Fragment {\n" + b.text + "}\n" : b.text);
            plant::Compilation c;
            plant::CompileOptions opts;
            opts.stdlib_dir = PLANT_STDLIB_DIR;
            opts.require_plant = false;
            plant::compile_file(file.string(), opts, c);
            std::string codes;
            for (const auto& d : c.sink.sorted())
                if (d.severity == plant::Severity::Error) codes += std::string(plant::info(d.id).code) + " ";
            INFO(b.file << ":" << b.line << ": errors: " << codes);
            if (b.fail.empty()) {
                CHECK(c.ok());
                ++compiled;
            } else {
                std::istringstream want(b.fail);
                for (std::string code; std::getline(want, code, ',');)
                    CHECK_MESSAGE(codes.find(code + " ") != std::string::npos, "expected " << code);
                ++failing;
            }
        }
    CHECK(compiled > 30);
    CHECK(failing > 30);
}

TEST_CASE("docs: no project file cites a document a checkout does not have") {
    // MISSION.md and PLATFORM.md live outside the repository.
    int files = 0;
    for (const char* dir : {"README.md", "docs", "compiler", "runtime", "stdlib", "plants", "examples", "tools",
                            "bench", "scripts", "viewer", "tests/unit"}) {
        const fs::path root = fs::path(PLANT_SOURCE_DIR) / dir;
        std::vector<fs::path> paths;
        if (fs::is_regular_file(root)) paths.push_back(root);
        else if (fs::is_directory(root))
            for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
                if (it->is_directory() && it->path().filename() == "node_modules") {
                    it.disable_recursion_pending();
                    continue;
                }
                if (it->is_regular_file()) paths.push_back(it->path());
            }
        for (const auto& p : paths) {
            if (p.filename() == "docs_blocks_test.cpp") continue;
            std::ifstream in(p);
            std::stringstream s;
            s << in.rdbuf();
            const std::string text = s.str();
            ++files;
            for (const char* cited : {"MISSION.md", "PLATFORM.md", "STYLE.md"})
                CHECK_MESSAGE(text.find(cited) == std::string::npos, p.string() << " cites " << std::string(cited));
        }
    }
    CHECK(files > 100);
}

// Both the section and the row of the table of codes: the table was once missing codes
// that had sections (E0312, E0313).
TEST_CASE("docs: diagnostics.md has a section and a table row for every registered code") {
    std::ifstream in(std::string(PLANT_SOURCE_DIR) + "/docs/diagnostics.md");
    std::stringstream s;
    s << in.rdbuf();
    const std::string text = s.str();
    std::ifstream codes(std::string(PLANT_SOURCE_DIR) + "/compiler/diag/codes.def");
    int n = 0;
    for (std::string line; std::getline(codes, line);) {
        const size_t at = line.find("\"");
        if (line.rfind("PLANT_DIAG(", 0) != 0 || at == std::string::npos) continue;
        const std::string code = line.substr(at + 1, 5);
        ++n;
        CHECK_MESSAGE(text.find("### " + code) != std::string::npos, "docs/diagnostics.md lacks " << code);
        // PLANT_DIAG(Id, "E0123", Error, "summary") -> | [E0123](#e0123) | error | summary |
        const size_t sev = line.find(", ", at + 7) + 2, sum = line.find('"', sev) + 1;
        std::string lower = code, severity = line.substr(sev, line.find(',', sev) - sev);
        for (char& ch : lower) ch = char(std::tolower(static_cast<unsigned char>(ch)));
        for (char& ch : severity) ch = char(std::tolower(static_cast<unsigned char>(ch)));
        const std::string row = "| [" + code + "](#" + lower + ") | " + severity + " | " +
                                line.substr(sum, line.rfind('"') - sum) + " |";
        CHECK_MESSAGE(text.find(row) != std::string::npos, "docs/diagnostics.md's table lacks: " << row);
    }
    CHECK(n > 40);
}
