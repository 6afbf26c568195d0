// Plant parameters and `--set NAME=VALUE` (CompileOptions::overrides).
#include "compile_helper.h"

#include <doctest/doctest.h>

using namespace plant;
using plant::test::compile_text;
using plant::test::has_code;

namespace {

const char* kLine = R"(
object Band(speed: velocity = 50 cm/s, k: gain = 16 kg/s) {
    field drive at (0 m, 0 m, 5 cm) { extent = (1 m, 8 cm, 10 cm); speed = speed; gain = k }
}
plant Line(speed: velocity = 50 cm/s, k: gain = 16 kg/s, n: int = 1) {
    for i in 0 .. n { band[i]: Band(speed, k) at (i * 1 m, 0 m, 0 m) }
}
)";

// Line and column of the first diagnostic in a --set value.
std::pair<uint32_t, uint32_t> set_position(const Compilation& c) {
    for (const auto& d : c.sink.sorted())
        if (d.span.valid() && c.sources.name(d.span.file) == "--set") {
            auto lc = c.sources.line_col(d.span.file, d.span.begin);
            return {lc.line, lc.col};
        }
    return {0, 0};
}

}  // namespace

TEST_CASE("plant parameters: defaults without --set, values from --set in SI") {
    Compilation plain;
    compile_text(kLine, plain, "line.plant");
    REQUIRE(plain.ok());
    REQUIRE(plain.graph.fields.size() == 1);
    CHECK(plain.graph.fields[graph::FieldId(0)].gain == 16);
    CHECK(plain.graph.fields[graph::FieldId(0)].speed == doctest::Approx(0.5));

    Compilation set;
    compile_text(kLine, set, "line.plant", {"k=4 N*s/m", "speed = 1.5 m/s", "n=3"});
    REQUIRE(set.ok());
    REQUIRE(set.graph.fields.size() == 3);
    for (const auto& f : set.graph.fields) {
        CHECK(f.gain == 4);
        CHECK(f.speed == doctest::Approx(1.5));
    }
}

TEST_CASE("--set: an unknown name, a bad expression or a wrong dimension is an error at its column") {
    struct Case {
        const char* set;
        const char* code;
        uint32_t col;
    };
    for (const Case& k : {Case{"kk=4 kg/s", "E0303", 1}, Case{"k=4 g", "E0203", 3}, Case{"k=4", "E0203", 3},
                          Case{"k 4 kg/s", "E0001", 3}, Case{"speed=", "E0001", 7}, Case{"n=1.5", "E0204", 3},
                          Case{"speed=2 * k", "E0101", 11}}) {
        const std::string text = k.set;
        CAPTURE(text);
        Compilation c;
        compile_text(kLine, c, "line.plant", {k.set});
        CHECK_FALSE(c.ok());
        CHECK(has_code(c, k.code));
        CHECK(set_position(c) == std::pair<uint32_t, uint32_t>{1, k.col});
    }
}

TEST_CASE("--set: twice for one parameter, or for a file without a plant, is an error") {
    Compilation twice;
    compile_text(kLine, twice, "line.plant", {"k=1 kg/s", "k=2 kg/s"});
    CHECK(has_code(twice, "E0305"));

    Compilation library;
    compile_text("object Empty { }\n", library, "lib.plant", {"k=1 kg/s"});
    CHECK(has_code(library, "E0303"));
}

TEST_CASE("plant parameters: one without a default must be set") {
    const char* text = "plant P(length: length) { field f { extent = (length, 8 cm, 10 cm); gain = 1 kg/s } }\n";
    Compilation missing;
    compile_text(text, missing, "p.plant");
    CHECK(has_code(missing, "E0301"));

    Compilation given;
    compile_text(text, given, "p.plant", {"length=2 m"});
    REQUIRE(given.ok());
    CHECK(given.graph.fields[graph::FieldId(0)].extent[0] == 2);
}
