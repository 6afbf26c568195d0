// The language server's definition and references read the names sema resolved
// (sema::survey_names): a name stands for what the compiler takes it to be. Where the two
// differed before, the compiler's reading wins: a default sees only the parameters before
// it, and a type the file does not import is no reference to it. A loop that runs no time
// and the branch an `if` does not take are still read.
#include "paths.h"
#include "../compiler/compile_helper.h"
#include "lsp/symbols.h"

#include <doctest/doctest.h>

#include <string>

using namespace plant;

namespace {

struct Read {
    Compilation c;
    const sema::LoadedModule* root = nullptr;
    std::string text;
};

// `text` as the file `name`, compiled as the language server does (a library may hold no plant).
void read(const std::string& name, const std::string& text, Read& r) {
    CompileOptions opts;
    opts.stdlib_dir = PLANT_STDLIB_DIR;
    opts.require_plant = false;
    compile_file(test::temp_plant(name, text), opts, r.c);
    sema::survey_names(r.c.program, r.c.sources, r.c.names, sema::kMaxMembers);
    r.root = &r.c.program.modules[static_cast<size_t>(r.c.program.root)];
    r.text = text;
}

// The offset of the `n`th `word` (0: the first) in the text, inside the word.
size_t at(const Read& r, const std::string& word, int n = 0) {
    size_t pos = r.text.find(word);
    for (int i = 0; i < n && pos != std::string::npos; ++i) pos = r.text.find(word, pos + 1);
    REQUIRE(pos != std::string::npos);
    return pos + 1;
}

// How many places the references of the name at `offset` list (its declaration included).
size_t references(const Read& r, size_t offset) {
    const auto t = lsp::target_at(r.c, *r.root, offset);
    if (!t) return 0;
    nlohmann::json locations = nlohmann::json::array();
    lsp::add_references(r.c, *t, true, locations);
    return locations.size();
}

}  // namespace

TEST_CASE("references: a default sees only the parameters before it, as the compiler reads it") {
    Read r;
    read("later_param.plant", "object A(x: length = y, y: length = 1 m, z: length = y) {}\n", r);
    CHECK_FALSE(r.c.ok());  // `y` in x's default is unknown there
    CHECK_FALSE(lsp::target_at(r.c, *r.root, at(r, "y")));  // x's default: not the parameter
    const auto y = lsp::target_at(r.c, *r.root, at(r, "y", 1));
    REQUIRE(y);
    CHECK(lsp::target_at(r.c, *r.root, at(r, "y", 2)) == y);  // z's default: the parameter
    CHECK(references(r, at(r, "y", 1)) == 2);                  // its declaration and z's default
}

TEST_CASE("references: a type the file does not import is no reference to it") {
    test::temp_plant("vis/far.plant", "object Far {}\n");
    test::temp_plant("vis/near.plant", "import far\nobject Near {\n    f: Far\n}\n");
    Read r;
    read("vis/top.plant", "import near\nobject Top {\n    n: Near\n    f: Far\n}\n", r);
    CHECK_FALSE(r.c.ok());  // Far is declared in a module top.plant does not import
    CHECK(lsp::target_at(r.c, *r.root, at(r, "Near")));
    CHECK_FALSE(lsp::target_at(r.c, *r.root, at(r, "Far")));
}

TEST_CASE("references: a loop that runs no time and the branch not taken are read too") {
    Read r;
    read("branches.plant",
         "object A(n: int = 0, big: bool = false) {\n"
         "    let w = 2 cm\n"
         "    for i in 0 .. n {\n"
         "        s[i]: Pad(size = w + i * w)\n"
         "    }\n"
         "    if big {\n"
         "        p: Pad(size = w)\n"
         "        flow p.done -> p.go\n"
         "    } else {\n"
         "        q: Pad(size = 2 * w)\n"
         "        q: Pad(size = 3 * w) at (w, 0 m, 0 m)  // a second q: its names are read too\n"
         "    }\n"
         "}\n"
         "object Pad(size: length = 1 cm) {\n"
         "    in go: void => t.start\n"
         "    out done: void => t.tick\n"
         "    timer t: oneshot { period = 1 s }\n"
         "}\n",
         r);
    CHECK_FALSE(r.c.ok());                     // q is declared twice
    CHECK(references(r, at(r, "w")) == 7);     // the let and its six uses
    CHECK(references(r, at(r, "size")) == 1 + 4);  // a named argument in every branch
    CHECK(references(r, at(r, "i]")) == 3);    // the loop variable, in the index and the value
    // A path through the instance of the branch not taken: p, and Pad's port.
    const auto p = lsp::target_at(r.c, *r.root, at(r, "p.done"));
    REQUIRE(p);
    CHECK(p->at == at(r, "p: Pad") - 1);
    CHECK(references(r, at(r, "done:")) == 2);
}

TEST_CASE("references: a logic connector's `out` is its slot, as a flow reads it") {
    Read r;
    read("logic.plant",
         "object A {\n"
         "    out both: void => go.out\n"
         "    timer t: periodic { period = 1 s }\n"
         "    timer u: periodic { period = 2 s }\n"
         "    logic go = t.tick and u.tick\n"
         "}\n",
         r);
    CHECK(r.c.ok());
    const auto out = lsp::target_at(r.c, *r.root, at(r, "out\n"));
    REQUIRE(out);  // before: no name
    CHECK(out->slot == "out");
    CHECK(out->at == at(r, "go =") - 1);  // the connector's
    CHECK(references(r, at(r, "go =")) == 2);  // the connector's name and its use in the path
}
