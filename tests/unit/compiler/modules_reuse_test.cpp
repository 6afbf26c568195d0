// sema::Reuse: a load shares the parsed modules of an earlier one whose text did not
// change, parses the changed ones again, and reports exactly what a fresh load reports.
#include "paths.h"
#include "compile_helper.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

using namespace plant;

namespace {

std::vector<std::string> rendered(const Compilation& c) {
    std::vector<std::string> out;
    for (const Diagnostic& d : c.sink.sorted())
        out.push_back(std::string(info(d.id).code) + " " + std::to_string(d.span.file) + ":" + std::to_string(d.span.begin) +
                      " " + d.message);
    return out;
}

const sema::LoadedModule* module(const Compilation& c, const std::string& key_end) {
    for (const auto& m : c.program.modules)
        if (m.key.size() >= key_end.size() && m.key.compare(m.key.size() - key_end.size(), key_end.size(), key_end) == 0)
            return &m;
    return nullptr;
}

}  // namespace

TEST_CASE("modules: a load with Reuse shares the unchanged modules and reports the same diagnostics") {
    const std::string path = std::filesystem::weakly_canonical(std::string(PLANT_SOURCE_DIR) + "/plants/bottling.plant").string();
    CompileOptions opts;
    opts.stdlib_dir = PLANT_STDLIB_DIR;
    sema::Overlay overlay;
    std::string text;
    {
        std::ifstream in(path);
        text.assign(std::istreambuf_iterator<char>(in), {});
    }
    overlay[path] = text;
    opts.overlay = &overlay;
    Compilation first;
    compile_file(path, opts, first);
    REQUIRE(first.ok());

    // The plant misspells a slot: its module is parsed again, every stdlib module is shared.
    const size_t at = text.find("record s1.to_working");
    REQUIRE(at != std::string::npos);
    overlay[path] = text.substr(0, at) + "record s1.to_workin" + text.substr(at + 20);
    Compilation fresh, reused;
    compile_file(path, opts, fresh);
    opts.reuse = {&first.program, &first.sources};
    compile_file(path, opts, reused);
    CHECK(rendered(reused) == rendered(fresh));
    CHECK(plant::test::has_code(reused, "E0101"));
    REQUIRE(reused.program.modules.size() == first.program.modules.size());
    int shared = 0;
    for (size_t i = 0; i < first.program.modules.size(); ++i)
        shared += reused.program.modules[i].ast == first.program.modules[i].ast;
    CHECK(shared == int(first.program.modules.size()) - 1);
    CHECK(module(reused, "plants/bottling.plant")->ast != module(first, "plants/bottling.plant")->ast);
    CHECK(module(reused, "stdlib/switch.plant")->ast == module(first, "stdlib/switch.plant")->ast);
    CHECK(reused.graph.comps.size() == fresh.graph.comps.size());
}

TEST_CASE("modules: Reuse parses again a module that changed or did not parse") {
    const std::string path = std::filesystem::weakly_canonical(plant::test::temp_plant("reuse/a.plant", "")).string();
    const std::string part = std::filesystem::weakly_canonical(plant::test::temp_plant("reuse/part.plant", "")).string();
    sema::Overlay overlay;
    overlay[path] = "import part\nplant P {\n    x: Thing\n}\n";
    overlay[part] = "object Thing {\n    timer t: periodic { period = 1 s\n}\n";  // a syntax error
    CompileOptions opts;
    opts.overlay = &overlay;
    Compilation first;
    compile_file(path, opts, first);
    REQUIRE(plant::test::has_code(first, "E0001"));
    Compilation again;
    opts.reuse = {&first.program, &first.sources};
    compile_file(path, opts, again);
    CHECK(rendered(again) == rendered(first));  // the broken module is parsed again, and reported again
    CHECK(module(again, "reuse/part.plant")->ast != module(first, "reuse/part.plant")->ast);
    CHECK(module(again, "reuse/a.plant")->ast == module(first, "reuse/a.plant")->ast);

    overlay[part] = "object Thing {\n    timer t: periodic { period = 1 s }\n}\n";
    Compilation fixed;
    opts.reuse = {&again.program, &again.sources};
    compile_file(path, opts, fixed);
    CHECK(fixed.ok());
    CHECK(module(fixed, "reuse/part.plant")->ast != module(again, "reuse/part.plant")->ast);
}
