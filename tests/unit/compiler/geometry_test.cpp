// W0601 on the shipped bottling plant: clean as shipped (one line and four), and each
// mistake a user made to it warns once, at the one conveyor's declaration with a note at the
// other's: a lane belt moved 10 cm away from its switch, 10 cm aside, 1 cm up.
#include "compile_helper.h"

#include <doctest/doctest.h>

#include <algorithm>

using namespace plant;

namespace {

// The W0601 warnings of a compilation.
std::vector<Diagnostic> conveyor_warnings(const Compilation& c) {
    std::vector<Diagnostic> out;
    for (const Diagnostic& d : c.sink.sorted())
        if (d.id == DiagId::ConveyorEndsMiss) out.push_back(d);
    return out;
}

// bottling.plant with lane A's placement replaced.
std::string bottling_with_lane_a(const std::string& at) {
    std::string text = test::slurp(std::string(PLANT_SOURCE_DIR) + "/plants/bottling.plant");
    const std::string was = "lane_a: Belt(length = 70 cm, speed = v) at (x0 + 80 cm + ba, -bl, 0 m)";
    const size_t p = text.find(was);
    REQUIRE(p != std::string::npos);
    return text.replace(p, was.size(), "lane_a: Belt(length = 70 cm, speed = v) at " + at);
}

// 1-based line of the declaration that starts with `head` in `text`.
uint32_t line_of(const std::string& text, const std::string& head) {
    const size_t p = text.find(head);
    REQUIRE(p != std::string::npos);
    return uint32_t(std::count(text.begin(), text.begin() + std::ptrdiff_t(p), '\n') + 1);
}

// `extra`: declarations added to the plant's own block (before its closing brace).
void check_moved(const std::string& at, const std::string& says, const std::string& extra = "") {
    std::string text = bottling_with_lane_a(at);
    if (!extra.empty()) text.insert(text.rfind('}'), extra);
    Compilation c;
    test::compile_text(text, c, "bottling_moved.plant", {"lines=2"});
    REQUIRE(c.ok());
    const auto ws = conveyor_warnings(c);
    REQUIRE(ws.size() == 1);  // once for both lines: one pair of declarations
    const Diagnostic& w = ws[0];
    INFO(w.message);
    CHECK(w.message.find("line[0].s1.") != std::string::npos);
    CHECK(w.message.find("line[0].lane_a.drive") != std::string::npos);
    CHECK(w.message.find(says) != std::string::npos);
    CHECK(c.sources.line_col(w.span.file, w.span.begin).line == line_of(text, "s1:  RoutedSwitch("));
    REQUIRE(!w.notes.empty());
    CHECK(c.sources.line_col(w.notes[0].span.file, w.notes[0].span.begin).line == line_of(text, "lane_a: Belt("));
}

}  // namespace

TEST_CASE("geometry: the shipped bottling plant has no conveyor ends that nearly meet") {
    for (const char* lines : {"lines=1", "lines=4"}) {
        Compilation c;
        test::compile_text(test::slurp(std::string(PLANT_SOURCE_DIR) + "/plants/bottling.plant"), c, "bottling.plant",
                           {lines});
        REQUIRE(c.ok());
        CHECK(conveyor_warnings(c).empty());
    }
}

TEST_CASE("geometry: a lane belt moved 10 cm from its switch warns at both declarations") {
    check_moved("(x0 + 80 cm + ba, -bl - 10 cm, 0 m)", "10.0 cm ahead");
}

TEST_CASE("geometry: a lane belt beside its switch's branch exit warns") {
    check_moved("(x0 + 90 cm + ba, -bl, 0 m)", "10.0 cm aside");
}

TEST_CASE("geometry: a lane belt 1 cm above its switch's branch exit warns") {
    check_moved("(x0 + 80 cm + ba, -bl, 1 cm)", "a step of 1.0 cm");
}

TEST_CASE("geometry: a lane belt 2 cm aside meets its switch off its centre line") {
    check_moved("(x0 + 82 cm + ba, -bl, 0 m)", "2.0 cm off its centre line");
}

// The search for the conveyor an outlet meets looks only at the boxes near it (a grid over the
// ground); a box too large for the grid's cells (a 300 m floor's field) is looked at for every
// outlet: the warning is the same with one far below the line.
TEST_CASE("geometry: a field as large as a floor changes nothing the search finds") {
    const std::string floor = "    field floor at (0 m, 0 m, -5 m) { extent = (300 m, 300 m, 1 cm); gain = 1 kg/s }\n";
    check_moved("(x0 + 80 cm + ba, -bl - 10 cm, 0 m)", "10.0 cm ahead", floor);
    check_moved("(x0 + 80 cm + ba, -bl, 1 cm)", "a step of 1.0 cm", floor);
}
