// Every usage example in a stdlib file's `///` comments compiles. The convention (as in
// Markdown, where an indented code block cannot interrupt a paragraph): an example is a run
// of `///` lines indented by three or more spaces that follows a blank `///` line. Its
// `import` lines are imports; the rest are members of a plant. The test wraps it as
//
//   import std.MODULE          (the file's own module)
//   import ...                 (the example's imports)
//   plant Example { ... }      (the example's other lines)
//
// so an example says which other modules it needs, as a user's file would.
#include "paths.h"
#include "../compiler/compile_helper.h"
#include "diag/diagnostic.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Example {
    int line = 0;  // of its first line, 1-based
    std::string imports, members;
};

std::vector<Example> examples(std::istream& in) {
    std::vector<Example> out;
    std::string line, before;
    bool open = false;
    for (int n = 1; std::getline(in, line); ++n) {
        const bool indented = line.rfind("///   ", 0) == 0;
        if (indented && (open || before == "///")) {
            if (!open) out.push_back({n, "", ""});
            open = true;
            const std::string code = line.substr(6);
            const size_t word = code.find("import ");
            const bool is_import = word != std::string::npos && word == code.find_first_not_of(' ');
            (is_import ? out.back().imports : out.back().members) += code + "\n";
        } else {
            open = false;
        }
        before = line.substr(0, line.find_last_not_of(" \t") + 1);
    }
    return out;
}

// The errors of compiling `text` as a file, one per line; empty when it compiles.
std::string errors_of(const std::string& text, const std::string& name) {
    plant::Compilation c;
    plant::test::compile_text(text, c, name);
    std::string errors;
    for (const auto& d : c.sink.sorted())
        if (d.severity == plant::Severity::Error)
            errors += "  " + std::string(plant::info(d.id).code) + ": " + d.message + "\n";
    return errors;
}

}  // namespace

TEST_CASE("docs: the usage examples in the stdlib's /// comments compile") {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(PLANT_STDLIB_DIR))
        if (e.path().extension() == ".plant") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    REQUIRE(files.size() >= 8);
    size_t compiled = 0;
    for (const fs::path& file : files) {
        std::ifstream in(file);
        const std::vector<Example> found = examples(in);
        const std::string shown = "stdlib/" + file.filename().string();
        CHECK_MESSAGE(!found.empty(), shown << " has no usage example");
        for (const Example& ex : found) {
            const std::string text = "import std." + file.stem().string() + "\n" + ex.imports +
                                     "plant Example {\n" + ex.members + "}\n";
            const std::string errors =
                errors_of(text, "examples/" + file.stem().string() + "_" + std::to_string(ex.line) + ".plant");
            CHECK_MESSAGE(errors.empty(), shown << ":" << ex.line << ": the example does not compile:\n"
                                                << errors << "as\n" << text);
            ++compiled;
        }
    }
    CHECK(compiled >= files.size());
}

TEST_CASE("docs: a stdlib example is an indented run after a blank /// line") {
    std::istringstream in("/// Prose:\n///\n///   a: A\n///   import std.x\n/// prose\n"
                          "/// - a list item\n///   its second line\n///\n///   b: B\n");
    const std::vector<Example> found = examples(in);
    REQUIRE(found.size() == 2);
    CHECK(found[0].line == 3);
    CHECK(found[0].members == "a: A\n");
    CHECK(found[0].imports == "import std.x\n");
    CHECK(found[1].line == 9);
    CHECK(found[1].members == "b: B\n");
    // A broken example is an error, named by the caller with its file:line.
    CHECK(errors_of("import std.belts\nplant Example {\n    b: Belt(lenght = 1 m)\n}\n", "broken.plant") != "");
}
