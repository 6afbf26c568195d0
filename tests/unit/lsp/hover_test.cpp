// Hover on an object type shows its `///` block: the lines right above its declaration,
// blank lines between allowed (`plant fmt` removes them); a block above the imports or
// cut off by code documents the file, not the type. Every stdlib type has one.
#include "paths.h"
#include "../compiler/compile_helper.h"
#include "lsp/symbols.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

using namespace plant;

namespace {

// The markdown hover shows on the name of object type `type`, declared in the root file.
std::string hover_on_type(const Compilation& c, const std::string& type) {
    const sema::LoadedModule& m = c.program.modules[size_t(c.program.root)];
    for (const auto& o : m.ast->objects)
        if (o.name.text == type) {
            const nlohmann::json h = lsp::hover(c, m, o.name.span.begin + 1);
            return h.is_null() ? "" : h["contents"]["value"].get<std::string>();
        }
    FAIL("no type ", type);
    return "";
}

// What follows the signature's code block: the documentation.
std::string doc_of(const std::string& hover) {
    const size_t end = hover.find("\n```", 3);
    return end == std::string::npos ? "" : hover.substr(end + 4);
}

void compile_library(const std::string& path, Compilation& c) {
    CompileOptions opts;
    opts.stdlib_dir = PLANT_STDLIB_DIR;
    opts.require_plant = false;
    compile_file(path, opts, c);
    sema::survey_names(c.program, c.sources, c.names, sema::kMaxMembers);
}

}  // namespace

TEST_CASE("hover: the /// block above a type, with or without blank lines between") {
    Compilation c;
    compile_library(test::temp_plant("docs.plant", "/// The file: not a type's.\n"
                                                   "import std.belts\n\n"
                                                   "/// Right above.\nobject A {}\n\n"
                                                   "/// Two blank lines below,\n/// then the type.\n\n\nobject B {}\n\n"
                                                   "/// Cut off by a comment.\n// an ordinary comment\nobject C {}\n\n"
                                                   "object D {}\n"),
                    c);
    REQUIRE(c.ok());
    CHECK(doc_of(hover_on_type(c, "A")) == "\n\nRight above.\n");
    CHECK(doc_of(hover_on_type(c, "B")) == "\n\nTwo blank lines below,\nthen the type.\n");
    CHECK(doc_of(hover_on_type(c, "C")).empty());
    CHECK(doc_of(hover_on_type(c, "D")).empty());
}

TEST_CASE("hover: every object type of the stdlib shows its documentation") {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(PLANT_STDLIB_DIR))
        if (e.path().extension() == ".plant") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    REQUIRE(files.size() >= 9);
    int types = 0;
    for (const auto& f : files) {
        Compilation c;
        compile_library(f.string(), c);
        REQUIRE_MESSAGE(c.ok(), f);
        for (const auto& o : c.program.modules[size_t(c.program.root)].ast->objects) {
            ++types;
            CHECK_MESSAGE(doc_of(hover_on_type(c, o.name.text)).size() > 20, f.filename().string() << ": " << o.name.text);
        }
    }
    CHECK(types >= 20);
}
