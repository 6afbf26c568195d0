#include "diag/diagnostic.h"

#include <doctest/doctest.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <set>

using namespace plant;

namespace {

// A span over the first occurrence of `needle` in the file's text.
Span span_of(const SourceMap& sm, int32_t file, std::string_view needle) {
    auto pos = sm.text(file).find(needle);
    REQUIRE(pos != std::string::npos);
    return {file, static_cast<uint32_t>(pos), static_cast<uint32_t>(pos + needle.size())};
}

Diagnostic make(DiagId id, Span span, std::string message) {
    return {id, info(id).severity, span, std::move(message), {}};
}

}  // namespace

TEST_CASE("every registered code is unique, well-formed and matches its severity") {
    auto all = all_diagnostics();
    REQUIRE(!all.empty());
    const std::regex shape("^[EW][0-9]{4}$");
    std::set<std::string_view> codes;
    for (std::size_t i = 0; i < all.size(); ++i) {
        const DiagInfo& d = all[i];
        CAPTURE(d.code);
        CHECK(std::regex_match(std::string(d.code), shape));
        CHECK(codes.insert(d.code).second);
        CHECK(d.severity == (d.code[0] == 'E' ? Severity::Error : Severity::Warning));
        CHECK(!d.summary.empty());
        CHECK(static_cast<std::size_t>(d.id) == i);
        CHECK(info(d.id).code == d.code);
    }
    CHECK(info(DiagId::SlotTypeMismatch).code == "E0201");
    CHECK(info(DiagId::LogicCycle).severity == Severity::Warning);
}

TEST_CASE("SourceMap: line and column of an offset") {
    SourceMap sm;
    int32_t f = sm.add("a.plant", "ab\ncd\n\nefg");
    CHECK(sm.size() == 1);
    CHECK(sm.name(f) == "a.plant");
    auto lc = [&](uint32_t off) {
        auto r = sm.line_col(f, off);
        return std::pair(r.line, r.col);
    };
    CHECK(lc(0) == std::pair(1u, 1u));
    CHECK(lc(2) == std::pair(1u, 3u));  // the '\n' itself
    CHECK(lc(3) == std::pair(2u, 1u));
    CHECK(lc(6) == std::pair(3u, 1u));  // empty line
    CHECK(lc(7) == std::pair(4u, 1u));
    CHECK(lc(10) == std::pair(4u, 4u));  // offset == size
    CHECK(lc(99) == std::pair(4u, 4u));  // past the end: clamped
    CHECK(sm.line_text(f, 1) == "ab");
    CHECK(sm.line_text(f, 3) == "");
    CHECK(sm.line_text(f, 4) == "efg");  // last line without newline
    CHECK(sm.line_text(f, 0) == "");
    CHECK(sm.line_text(f, 5) == "");
}

TEST_CASE("SourceMap: CRLF, trailing newline, empty file, several files") {
    SourceMap sm;
    int32_t crlf = sm.add("crlf.plant", "ab\r\ncd\r\n");
    int32_t empty = sm.add("empty.plant", "");
    CHECK(crlf == 0);
    CHECK(empty == 1);

    CHECK(sm.line_text(crlf, 1) == "ab");
    CHECK(sm.line_text(crlf, 2) == "cd");
    CHECK(sm.line_text(crlf, 3) == "");
    CHECK(sm.line_col(crlf, 4).line == 2);
    CHECK(sm.line_col(crlf, 4).col == 1);
    CHECK(sm.line_col(crlf, 8).line == 3);  // offset == size, after the final newline
    CHECK(sm.line_col(crlf, 8).col == 1);

    CHECK(sm.line_col(empty, 0).line == 1);
    CHECK(sm.line_col(empty, 0).col == 1);
    CHECK(sm.line_text(empty, 1) == "");
}

TEST_CASE("render_text: a span on one line") {
    SourceMap sm;
    int32_t f = sm.add("examples/bad.plant", "plant demo {\n    flow r1.id -> s1.to_working\n}\n");
    Diagnostic d = make(DiagId::SlotTypeMismatch, span_of(sm, f, "s1.to_working"),
                        "slot types differ: 'string' output 'r1.id' cannot drive 'void' input 's1.to_working'");
    CHECK(render_text(d, sm) ==
          "examples/bad.plant:2:19: error[E0201]: slot types differ: 'string' output 'r1.id' cannot drive "
          "'void' input 's1.to_working'\n"
          "    2 |     flow r1.id -> s1.to_working\n"
          "      |                   ^~~~~~~~~~~~~\n");
}

TEST_CASE("render_text: an empty span, a span at the end of the file, no position") {
    SourceMap sm;
    int32_t f = sm.add("x.plant", "plant p {");
    CHECK(render_text(make(DiagId::Syntax, {f, 6, 6}, "expected name"), sm) ==
          "x.plant:1:7: error[E0001]: expected name\n"
          "    1 | plant p {\n"
          "      |       ^\n");
    CHECK(render_text(make(DiagId::Syntax, {f, 9, 9}, "expected '}'"), sm) ==
          "x.plant:1:10: error[E0001]: expected '}'\n"
          "    1 | plant p {\n"
          "      |          ^\n");
    CHECK(render_text(make(DiagId::NoPlant, {}, "no plant declared"), sm) ==
          "plant: error[E0005]: no plant declared\n");
    // A file index the map does not know is treated as "no position".
    CHECK(render_text(make(DiagId::NoPlant, {7, 0, 1}, "no plant declared"), sm) ==
          "plant: error[E0005]: no plant declared\n");
}

TEST_CASE("render_text: a span over several lines is marked to the end of its first line") {
    SourceMap sm;
    int32_t f = sm.add("m.plant", "object Belt {\n  speed 1 m/s\n}\n");
    Span s = span_of(sm, f, "Belt {\n  speed");
    CHECK(render_text(make(DiagId::RecursiveObject, s, "object contains itself"), sm) ==
          "m.plant:1:8: error[E0108]: object contains itself\n"
          "    1 | object Belt {\n"
          "      |        ^~~~~~\n");
}

TEST_CASE("render_text: tabs before the caret are kept, CRLF is not shown") {
    SourceMap sm;
    int32_t f = sm.add("t.plant", "plant p {\r\n\tflow\ta -> b\r\n}\r\n");
    Diagnostic d = make(DiagId::UnknownName, span_of(sm, f, "b\r"), "unknown name 'b'");
    d.span.end -= 1;  // just the 'b'
    CHECK(render_text(d, sm) ==
          "t.plant:2:12: error[E0101]: unknown name 'b'\n"
          "    2 | \tflow\ta -> b\n"
          "      | \t    \t     ^\n");
}

TEST_CASE("render_text: notes with and without a position") {
    SourceMap sm;
    int32_t f = sm.add("n.plant", "sensor s1\nsensor s1\n");
    Span first{f, 7, 9};
    Span second{f, 17, 19};
    Diagnostic d = make(DiagId::DuplicateName, second, "duplicate name 's1'");
    d.notes.push_back({first, "'s1' declared here"});
    d.notes.push_back({{}, "names must be unique in a plant"});
    CHECK(render_text(d, sm) ==
          "n.plant:2:8: error[E0102]: duplicate name 's1'\n"
          "    2 | sensor s1\n"
          "      |        ^~\n"
          "n.plant:1:8: note: 's1' declared here\n"
          "    1 | sensor s1\n"
          "      |        ^~\n"
          "      = note: names must be unique in a plant\n");
    // Without a position for the error either, the note says where it comes from.
    Diagnostic lone = make(DiagId::DuplicateName, {}, "duplicate name 's1'");
    lone.notes.push_back({{}, "names must be unique in a plant"});
    CHECK(render_text(lone, sm).ends_with("plant: note: names must be unique in a plant\n"));
}

TEST_CASE("render_text: the gutter widens for long line numbers, empty lines have no trailing blank") {
    std::string text(123456, '\n');
    text += "x";
    SourceMap sm;
    int32_t f = sm.add("big.plant", text);
    CHECK(render_text(make(DiagId::Syntax, {f, 123456, 123457}, "bad"), sm) ==
          "big.plant:123457:1: error[E0001]: bad\n"
          "123457 | x\n"
          "       | ^\n");
    CHECK(render_text(make(DiagId::Syntax, {f, 3, 3}, "bad"), sm) ==
          "big.plant:4:1: error[E0001]: bad\n"
          "    4 |\n"
          "      | ^\n");
}

TEST_CASE("render_all_text: joins and counts") {
    SourceMap sm;
    int32_t f = sm.add("a.plant", "abc\n");
    CHECK(render_all_text({}, sm) == "");

    std::vector<Diagnostic> one{make(DiagId::Syntax, {f, 0, 1}, "bad")};
    CHECK(render_all_text(one, sm) ==
          "a.plant:1:1: error[E0001]: bad\n"
          "    1 | abc\n"
          "      | ^\n"
          "1 error generated.\n");

    std::vector<Diagnostic> three{make(DiagId::NoPlant, {}, "no plant"), make(DiagId::NoPlant, {}, "again"),
                                  make(DiagId::LogicCycle, {}, "cycle")};
    CHECK(render_all_text(three, sm) ==
          "plant: error[E0005]: no plant\n"
          "plant: error[E0005]: again\n"
          "plant: warning[W0503]: cycle\n"
          "2 errors, 1 warning generated.\n");

    std::vector<Diagnostic> warnings{make(DiagId::LogicCycle, {}, "a"), make(DiagId::InputNotDriven, {}, "b")};
    CHECK(render_all_text(warnings, sm).ends_with("\n2 warnings generated.\n"));
}

TEST_CASE("Sink: report, notes, counts") {
    Sink sink;
    CHECK(!sink.has_errors());
    sink.report(DiagId::LogicCycle, {}, "cycle");
    CHECK(!sink.has_errors());
    Diagnostic& d = sink.report(DiagId::DuplicateName, {0, 5, 7}, "duplicate name 'x'");
    d.notes.push_back({{0, 1, 2}, "first declared here"});
    CHECK(sink.has_errors());
    CHECK(sink.count(Severity::Error) == 1);
    CHECK(sink.count(Severity::Warning) == 1);
    CHECK(sink.count(Severity::Note) == 0);
    REQUIRE(sink.all().size() == 2);
    CHECK(sink.all()[1].severity == Severity::Error);
    REQUIRE(sink.all()[1].notes.size() == 1);
    CHECK(sink.all()[1].notes[0].message == "first declared here");
}

TEST_CASE("Sink::sorted: by file, offset and code, stable, without duplicates") {
    Sink sink;
    sink.report(DiagId::UnknownName, {1, 10, 12}, "b1");
    sink.report(DiagId::UnknownName, {0, 20, 22}, "a20");
    sink.report(DiagId::Syntax, {0, 20, 21}, "a20 syntax");       // lower code first at the same offset
    sink.report(DiagId::UnknownName, {0, 5, 6}, "a5 first");
    sink.report(DiagId::UnknownName, {0, 5, 6}, "a5 second");     // same key: report order kept
    sink.report(DiagId::UnknownName, {0, 5, 6}, "a5 first");      // duplicate, not adjacent
    sink.report(DiagId::NoPlant, {}, "no position 1");
    sink.report(DiagId::UnknownName, {1, 10, 12}, "b1").notes.push_back({{}, "other notes"});  // duplicate
    sink.report(DiagId::NoPlant, {-1, 99, 99}, "no position 2");
    sink.report(DiagId::NoPlant, {}, "no position 1");            // duplicate
    sink.report(DiagId::UnknownName, {0, 5, 9}, "a5 first");      // different end: kept

    std::vector<std::string> messages;
    for (const Diagnostic& d : sink.sorted()) messages.push_back(d.message);
    CHECK(messages == std::vector<std::string>{"no position 1", "no position 2", "a5 first", "a5 second",
                                               "a5 first", "a20 syntax", "a20", "b1"});
    CHECK(sink.sorted().back().notes.empty());  // the first one reported is kept
    CHECK(sink.all().size() == 11);             // sorting does not touch the sink
}

TEST_CASE("render_json: parses back with every field, in a stable order") {
    SourceMap sm;
    int32_t f = sm.add("j.plant", "sensor s1\nsensor s1\n");
    Diagnostic d = make(DiagId::DuplicateName, {f, 17, 19}, "duplicate name 's1'");
    d.notes.push_back({{f, 7, 9}, "'s1' declared here"});
    d.notes.push_back({{}, "no position"});
    Diagnostic w = make(DiagId::LogicCycle, {}, "cycle \xff");  // invalid UTF-8 must not throw

    std::string text = render_json({d, w}, sm);
    auto doc = nlohmann::ordered_json::parse(text);
    REQUIRE(doc["diagnostics"].size() == 2);

    const auto& e = doc["diagnostics"][0];
    std::vector<std::string> keys;
    for (const auto& [key, value] : e.items()) keys.push_back(key);
    CHECK(keys == std::vector<std::string>{"severity", "code", "file", "line", "col", "end_line", "end_col",
                                           "message", "notes"});
    CHECK(e["severity"] == "error");
    CHECK(e["code"] == "E0102");
    CHECK(e["file"] == "j.plant");
    CHECK(e["line"] == 2);
    CHECK(e["col"] == 8);
    CHECK(e["end_line"] == 2);
    CHECK(e["end_col"] == 10);
    CHECK(e["message"] == "duplicate name 's1'");
    REQUIRE(e["notes"].size() == 2);
    CHECK(e["notes"][0] == nlohmann::ordered_json{{"file", "j.plant"},
                                                   {"line", 1},
                                                   {"col", 8},
                                                   {"message", "'s1' declared here"}});
    // A note without a position of its own is at its diagnostic's.
    CHECK(e["notes"][1]["file"] == "j.plant");
    CHECK(e["notes"][1]["line"] == 2);
    CHECK(e["notes"][1]["col"] == 8);
    CHECK(e["notes"][1]["message"] == "no position");

    const auto& nw = doc["diagnostics"][1];
    CHECK(nw["severity"] == "warning");
    CHECK(nw["code"] == "W0503");
    CHECK(nw["file"].is_null());
    CHECK(nw["line"].is_null());
    CHECK(nw["end_col"].is_null());
    CHECK(nw["notes"].empty());

    CHECK(text.starts_with("{\n  \"diagnostics\": [\n    {\n      \"severity\": \"error\","));
    CHECK(render_json({}, sm) == "{\n  \"diagnostics\": []\n}\n");
}

TEST_CASE("closest_name") {
    CHECK(closest_name("Belt", {"Bel", "Blet", "Bottle"}) == "Bel");   // tie: first candidate
    CHECK(closest_name("Belt", {"Blet", "Bel", "Bottle"}) == "Blet");  // a transposition is one edit
    CHECK(closest_name("Belt", {"Bottle", "Sensor"}) == "");           // too far
    CHECK(closest_name("Belt", {"Belt"}) == "");                       // identical: nothing to suggest
    CHECK(closest_name("Belt", {}) == "");
    CHECK(closest_name("belt", {"bolt", "Belt"}) == "Belt");           // tie broken ignoring case
    CHECK(closest_name("conveyor", {"convoyer"}) == "convoyer");              // 2 <= 8/3
    CHECK(closest_name("conveyor", {"convoyer", "conveyer"}) == "conveyer");  // 1 edit beats 2
    CHECK(closest_name("conveyor", {"cnvyr"}) == "");                  // 3 > 8/3
    CHECK(closest_name("x", {"y"}) == "y");                            // at least one edit allowed
    // Lengths that differ by the limit: still near; by more: not looked at (no distance is less).
    CHECK(closest_name("conveyor", {"convey"}) == "convey");           // 2 shorter, 2 edits
    CHECK(closest_name("conveyor", {"conve", "conveyors"}) == "conveyors");
    CHECK(closest_name("conveyor", {"conveyorbelt"}) == "");           // 4 longer
    CHECK(closest_name("Conveyor", {"cONVEYOR"}) == "");               // 8 edits with case, 0 without
    CHECK(closest_name("Feed", {"feed", "Feet"}) == "feed");           // both 1 edit; 0 ignoring case
}

TEST_CASE("ClosestName takes candidates one at a time as the list does") {
    const std::vector<std::string> names{"speed", "Speed", "spead", "sped", "velocity"};
    ClosestName closest("speeed");
    for (const std::string& n : names) closest.offer(n);
    CHECK(closest.best() == closest_name("speeed", names));
    CHECK(closest.best() == "speed");
    CHECK(ClosestName("anything").best() == "");
}
