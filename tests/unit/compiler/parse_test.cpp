#include "parse/parser.h"

#include <doctest/doctest.h>

using namespace plant;

namespace {
ast::Module parse_text(const std::string& text, SourceMap& sm, Sink& sink) {
    int32_t f = sm.add("t.plant", text);
    return parse::parse_module(sm, f, sink);
}
}  // namespace

TEST_CASE("parse: objects, components and flows become AST nodes with spans") {
    SourceMap sm;
    Sink sink;
    auto m = parse_text(R"(import std.belts, parts.x
object A(l: length = 2 m) {
    in go: void => t.start
    timer t: periodic { period = 1 s }
    flow t.tick -> t.stop when both once
}
plant P { a: A(l = 3 m) at (0 m, 0 m, 0 m) rotate z by 90 deg }
)", sm, sink);
    REQUIRE_FALSE(sink.has_errors());
    REQUIRE(m.imports.size() == 2);
    CHECK(m.imports[1].module == "parts.x");
    REQUIRE(m.objects.size() == 2);
    const auto& a = m.objects[0];
    CHECK(a.name.text == "A");
    REQUIRE(a.params.size() == 1);
    CHECK(a.params[0].type.text == "length");
    REQUIRE(a.members.size() == 3);
    const auto& comp = std::get<ast::ComponentDecl>(a.members[1]);
    CHECK(comp.kind.text == "timer");
    CHECK(comp.mode->text == "periodic");
    auto lc = sm.line_col(comp.name.span.file, comp.name.span.begin);
    CHECK(lc.line == 4);
    CHECK(lc.col == 11);
    const auto& flow = std::get<ast::FlowDecl>(a.members[2]);
    CHECK(flow.once);
    CHECK(flow.condition->text == "both");
    CHECK(flow.from.segs.size() == 2);
    CHECK(m.objects[1].is_plant);
}

TEST_CASE("parse: compound units only without spaces") {
    SourceMap sm;
    Sink sink;
    auto m = parse_text("plant P { let a = 50 cm/s\n let b = 10 cm * w }", sm, sink);
    REQUIRE_FALSE(sink.has_errors());
    const auto& a = std::get<ast::LetDecl>(m.objects[0].members[0]);
    CHECK(a.value->kind == ast::ExprKind::Number);
    CHECK(a.value->text == "cm/s");
    const auto& b = std::get<ast::LetDecl>(m.objects[0].members[1]);
    CHECK(b.value->kind == ast::ExprKind::Binary);
    CHECK(b.value->text == "*");
}

TEST_CASE("parse: syntax errors name the expected tokens in words") {
    SourceMap sm;
    Sink sink;
    parse_text("plant P {\n  flow a.b -> \n}\n", sm, sink);
    REQUIRE(sink.has_errors());
    const auto& d = sink.all()[0];
    CHECK(d.id == DiagId::Syntax);
    CHECK(d.message.find("expected") != std::string::npos);
    CHECK(d.message.find("a name") != std::string::npos);
    CHECK(sm.line_col(d.span.file, d.span.begin).line == 3);
}

TEST_CASE("parse: spans are byte offsets even after non-ASCII comments") {
    SourceMap sm;
    Sink sink;
    auto m = parse_text("// µ → ü\nplant P { x = 1 }", sm, sink);
    REQUIRE_FALSE(sink.has_errors());
    const auto& s = std::get<ast::SettingDecl>(m.objects[0].members[0]);
    auto lc = sm.line_col(s.name.span.file, s.name.span.begin);
    CHECK(lc.line == 2);
    CHECK(lc.col == 11);
    CHECK(sm.text(0).substr(s.name.span.begin, 1) == "x");
}

TEST_CASE("parse: transitions split their arcs at the arrow, with weights") {
    SourceMap sm;
    Sink sink;
    auto m = parse_text("object N { state s { place A = 1, B\n transition t: 2 A + B -> 3 * B\n transition u: A -> } }", sm, sink);
    REQUIRE_FALSE(sink.has_errors());
    const auto& c = std::get<ast::ComponentDecl>(m.objects[0].members[0]);
    REQUIRE(c.transitions.size() == 2);
    REQUIRE(c.transitions[0].inputs.size() == 2);
    CHECK(c.transitions[0].inputs[0].weight == 2);
    REQUIRE(c.transitions[0].outputs.size() == 1);
    CHECK(c.transitions[0].outputs[0].weight == 3);
    CHECK(c.transitions[1].outputs.empty());
}
