// plant fmt: every shipped plant file keeps its compiled graph when formatted (in memory:
// the files need not be formatted already; byte for byte but for the source positions
// the graph records, see fmt_compare.h), formatting is idempotent, and syntax errors
// are refused. One case per layout rule: tests/golden/fmt.
#include "paths.h"
#include "../../fmt_compare.h"
#include "fmt/formatter.h"
#include "sema/modules.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

using namespace plant;
namespace fs = std::filesystem;

namespace {

std::string read(const fs::path& p) {
    std::string text, why;
    REQUIRE(sema::read_file(p, text, why));
    return text;
}

std::optional<std::string> tidy(const std::string& text, Sink& sink) {
    SourceMap sources;
    return formatter::format_text("t.plant", text, sources, sink);
}

std::optional<std::string> tidy(const std::string& text) {
    Sink sink;
    return tidy(text, sink);
}

// stdlib/, plants/ and examples/, with their subfolders.
std::vector<fs::path> shipped_files() {
    std::vector<fs::path> files;
    for (const char* dir : {"stdlib", "plants", "examples"})
        for (const auto& e : fs::recursive_directory_iterator(fs::path(PLANT_SOURCE_DIR) / dir))
            if (e.is_regular_file() && e.path().extension() == ".plant") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace

TEST_CASE("fmt: every shipped plant file compiles to the same graph after formatting") {
    const auto files = shipped_files();
    REQUIRE(files.size() >= 20);
    // All of them formatted at once: a plant then also imports the formatted stdlib.
    sema::Overlay formatted;
    for (const auto& f : files) {
        const std::string text = read(f);
        Sink sink;
        const auto out = tidy(text, sink);
        INFO(f.string());
        REQUIRE(out.has_value());
        CHECK(testing::without_blanks(*out) == testing::without_blanks(text));
        CHECK(tidy(*out) == out);  // idempotent
        formatted[fs::weakly_canonical(f).string()] = *out;
    }
    int plants = 0;
    for (const auto& f : files) {
        INFO(f.string());
        const std::string before = testing::compiled_form(f.string(), nullptr);
        const std::string after = testing::compiled_form(f.string(), &formatted);
        CHECK(before.find("diagnostic E") == std::string::npos);
        CHECK(after == before);
        plants += before.find("plant-graph") != std::string::npos;
    }
    CHECK(plants >= 10);  // the comparison covers graphs, not only ASTs
}

TEST_CASE("fmt: a file with a syntax error is refused with the diagnostic") {
    Sink sink;
    CHECK_FALSE(tidy("object A {\n    let a = = 1\n}\n", sink).has_value());
    REQUIRE(sink.has_errors());
    CHECK(info(sink.all()[0].id).code == std::string("E0001"));
}

TEST_CASE("fmt: a unit stays glued to itself, a binary operator gets its spaces") {
    // `2 mm/length` would read `length` as a unit: the formatter must not create it.
    CHECK(tidy("object A(l: length = 1 m) {\n    let a = 2 mm /l\n    let v = 5 cm/s\n}\n") ==
          "object A(l: length = 1 m) {\n    let a = 2 mm / l\n    let v = 5 cm/s\n}\n");
}

TEST_CASE("fmt: comments are kept, and the text ends in one line end") {
    const std::string in = "// a\nobject A { // b\n  let a = 1 /* c */ // d\n}  // e\n// f";
    const auto out = tidy(in);
    REQUIRE(out.has_value());
    CHECK(*out == "// a\nobject A {  // b\n    let a = 1 /* c */  // d\n}  // e\n// f\n");
}
