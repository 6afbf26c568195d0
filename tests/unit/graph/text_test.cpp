// The text form must round-trip every table and field exactly, and the loader must
// reject broken input with a line number instead of crashing or guessing.
#include "graph/graph.h"
#include "graph/text.h"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <unistd.h>

using namespace plant::graph;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Values chosen to trip a careless writer or reader.
const double kDoubles[] = {0.1,   1e-300, -0.0, 0.0,    -9.81, 1.0 / 3, 150,   5e-324,
                           2.2250738585072014e-308, 1.7976931348623157e308, 1e16,
                           -123456.789, kInf, -kInf, std::nan("")};
const int32_t kInts[] = {-1, 0, 7, std::numeric_limits<int32_t>::max(),
                         std::numeric_limits<int32_t>::min()};
const char* const kNames[] = {"Belt",     "",         "say \"hi\"", "two\nlines",
                              "back\\slash", "tab\tcr\r", "ctrl\x01\x7f", "caf\xc3\xa9",
                              "a=b c",    "-",        "#not a comment", "(1 2 3)"};

template <class E>
int enum_size() {
    int n = 0;
    while (word(static_cast<E>(n)) != "?") ++n;
    return n;
}

// Fills fields from a running counter, so records differ and every value shows up.
struct Filler {
    Graph& g;
    size_t k = 0;
    size_t flips = 0;  // own counters, or these would fall in step with the field layout
    size_t words = 0;

    template <class T, size_t N>
    const T& pick(const T (&a)[N]) { return a[k++ % N]; }

    void operator()(int32_t& v) { v = pick(kInts); }
    template <class R, IdRole Role>
    void operator()(TypedId<R, Role>& id) { (*this)(id.v); }
    void operator()(Detail& d) { (*this)(d.v); }
    void operator()(double& v) { v = pick(kDoubles); }
    void operator()(bool& v) { v = flips++ % 2 == 0; }
    template <class E>
        requires std::is_enum_v<E>
    void operator()(E& e) { e = static_cast<E>(words++ % enum_size<E>()); }
    template <size_t N>
    void operator()(std::array<double, N>& v) {
        for (double& x : v) (*this)(x);
    }
    void operator()(Pose& p) {
        (*this)(p.p);
        (*this)(p.q);
    }
    void operator()(Name& n) { n = k++ % 5 == 4 ? Name{} : g.intern(pick(kNames)); }
    void operator()(Src& s) {
        const Src srcs[] = {Src{}, Src{0, 12, 5}, Src{1, 1, 1}, Src{-1, 3, 4}};
        s = pick(srcs);
    }
};

// A small plant that makes sense: a root with a timer, and one belt.
Graph tiny_graph() {
    Graph g;
    g.plant = g.intern("Line");
    g.files = {"examples/belt.plant"};
    g.do_types.push_back({.name = g.intern("Belt"), .instance_num = 1, .src = {0, 3, 1}});
    g.dos.push_back({.path = g.intern(""), .parent = DoId{}, .type = DoTypeId{}, .ordinal = 0,
                     .comp_adr = Adr<Comp>(0), .comp_num = 1, .pool = CompId{}});
    g.dos.push_back({.path = g.intern("belt1"), .parent = DoId(0), .type = DoTypeId(0), .ordinal = 0,
                     .comp_adr = Adr<Comp>(1), .comp_num = 1, .pool = CompId{},
                     .pose = {{1, 0.1, 0}, {0, 0, 0, 1}}, .src = {0, 12, 3}});
    g.comps.push_back({.name = g.intern("clock"), .kind = CompKind::Timer, .owner = DoId(0),
                       .slot_adr = Adr<Slot>(0), .slot_num = 1, .detail = Detail(Id<Timer>(0)), .src = {0, 20, 5}});
    g.comps.push_back({.name = g.intern("conveyor"), .kind = CompKind::Field, .owner = DoId(1),
                       .slot_adr = Adr<Slot>(1), .slot_num = 1, .detail = Detail(FieldId(0)), .src = {0, 13, 5}});
    g.slots.push_back({.name = g.intern("tick"), .type = SlotType::Void, .dir = Dir::Out,
                       .comp = CompId(0), .value_adr = Adr<Value>{}, .src = {0, 20, 5}});
    g.slots.push_back({.name = g.intern("set_speed"), .type = SlotType::Real, .dir = Dir::In,
                       .comp = CompId(1), .value_adr = Adr<Value>(0), .src = {0, 13, 5}});
    g.values.push_back({.v = 0.5});
    g.fields.push_back({.comp = CompId(1), .body = BodyId{}, .extent = {2, 0.5, 0.1}, .pose = {},
                        .dir = {1, 0, 0}, .speed = 0.5, .gain = 20, .enabled = true});
    g.timers.push_back({.comp = CompId(0), .period = 0.1, .periodic = true, .autostart = true});
    return g;
}

// tiny_graph plus three generated records in every table.
Graph full_graph() {
    Graph g = tiny_graph();
    g.settings = {.rate = 240, .gravity = {0, -0.0, -9.81}};
    g.files.push_back("stdlib/with \"quote\"\n.plant");
    Filler fill{g};
#define FILL_FIELD(T_, f_) fill(r.f_);
#define FILL_TABLE(member, Record, elem, FIELDS) \
    for (int i = 0; i < 3; ++i) {                \
        Record r{};                              \
        FIELDS(FILL_FIELD)                       \
        g.member.push_back(r);                   \
    }
    PLANT_GRAPH_TABLES(FILL_TABLE)
#undef FILL_TABLE
#undef FILL_FIELD
    return g;
}

bool load(const std::string& text, Graph& g, std::string& error) {
    std::istringstream in(text);
    return read_text(in, g, error, Check::Form);  // the form: these graphs are not plants
}

std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
    std::string s;
    for (const auto& l : lines) s += l + "\n";
    return s;
}

// Index of the first line starting with `prefix`.
size_t find_line(const std::vector<std::string>& lines, std::string_view prefix) {
    for (size_t i = 0; i < lines.size(); ++i)
        if (lines[i].starts_with(prefix)) return i;
    FAIL("no line starts with " << prefix);
    return 0;
}

void replace(std::string& s, std::string_view from, std::string_view to) {
    auto at = s.find(from);
    REQUIRE(at != std::string::npos);
    s.replace(at, from.size(), to);
}

// Changes a value so that it differs from what it was.
void bump(Graph&, int32_t& v) { v = v == 1 ? 2 : 1; }
template <class R, IdRole Role>
void bump(Graph& g, TypedId<R, Role>& id) { bump(g, id.v); }
void bump(Graph& g, Detail& d) { bump(g, d.v); }
void bump(Graph&, double& v) { v = v == 1.5 ? 2.5 : 1.5; }
void bump(Graph&, bool& v) { v = !v; }
template <class E>
    requires std::is_enum_v<E>
void bump(Graph&, E& e) { e = static_cast<E>((static_cast<int>(e) + 1) % enum_size<E>()); }
template <size_t N>
void bump(Graph& g, std::array<double, N>& v) { bump(g, v[N - 1]); }
void bump(Graph& g, Pose& p) { bump(g, p.q); }
void bump(Graph& g, Name& n) { n = g.intern(std::string(g.str(n)) + "+"); }
void bump(Graph&, Src& s) { s.col += 1; }

}  // namespace

TEST_SUITE("graph text") {

TEST_CASE("the format, exactly") {
    const char* expected =
        "plant-graph 4\n"
        "plant \"Line\"\n"
        "settings rate=150 gravity=(0 0 -9.81)\n"
        "count files 1\n"
        "file 0 \"examples/belt.plant\"\n"
        "count do_types 1\n"
        "dotype 0 name=\"Belt\" instance_num=1 src=0:3:1\n"
        "count dos 2\n"
        "do 0 path=\"\" parent=-1 type=-1 ordinal=0 comp_adr=0 comp_num=1 pool=-1 "
        "pose=(0 0 0|0 0 0 1) src=-\n"
        "do 1 path=\"belt1\" parent=0 type=0 ordinal=0 comp_adr=1 comp_num=1 pool=-1 "
        "pose=(1 0.1 0|0 0 0 1) src=0:12:3\n"
        "count comps 2\n"
        "comp 0 name=\"clock\" kind=timer owner=0 slot_adr=0 slot_num=1 detail=0 src=0:20:5\n"
        "comp 1 name=\"conveyor\" kind=field owner=1 slot_adr=1 slot_num=1 detail=0 src=0:13:5\n"
        "count slots 2\n"
        "slot 0 name=\"tick\" type=void dir=out comp=0 value_adr=-1 src=0:20:5\n"
        "slot 1 name=\"set_speed\" type=real dir=in comp=1 value_adr=0 src=0:13:5\n"
        "count values 1\n"
        "value 0 v=0.5\n"
        "count flows 0\n"
        "count accesses 0\n"
        "count access_targets 0\n"
        "count logics 0\n"
        "count logic_inputs 0\n"
        "count bodies 0\n"
        "count shapes 0\n"
        "count points 0\n"
        "count fields 1\n"
        "field 0 comp=1 body=-1 extent=(2 0.5 0.1) pose=(0 0 0|0 0 0 1) dir=(1 0 0) speed=0.5 "
        "gain=20 max_force=0 enabled=true radius=0 pivot=(0 0 0)\n"
        "count joints 0\n"
        "count places 0\n"
        "count transitions 0\n"
        "count arcs 0\n"
        "count triggers 0\n"
        "count timers 1\n"
        "timer 0 comp=0 period=0.1 periodic=true autostart=true\n"
        "count grippers 0\n"
        "count sources 0\n"
        "count ids 0\n"
        "count exits 0\n"
        "count routes 0\n"
        "count graphics 0\n"
        "count animations 0\n"
        "count keys 0\n"
        "count variants 0\n"
        "count labels 0\n"
        "count records 0\n"
        "count ports 0\n"
        "count port_targets 0\n"
        "end\n";
    CHECK(to_text(tiny_graph()) == expected);
}

TEST_CASE("every table and field type round-trips") {
    Graph g = full_graph();
#define NOT_EMPTY(member, Record, elem, FIELDS) CHECK_MESSAGE(!g.member.empty(), #member);
    PLANT_GRAPH_TABLES(NOT_EMPTY)
#undef NOT_EMPTY

    std::string text = to_text(g);
    Graph loaded;
    std::string error;
    REQUIRE_MESSAGE(load(text, loaded, error), error);
    CHECK(error.empty());
    CHECK(loaded.same_as(g));
    CHECK(g.same_as(loaded));
    CHECK(to_text(loaded) == text);

    std::ostringstream out;
    write_text(g, out);
    CHECK(out.str() == text);
}

TEST_CASE("awkward values survive exactly") {
    Graph g;
    g.bodies.resize(4);
    g.bodies[BodyId(0)].mass = 0.1;
    g.bodies[BodyId(1)].mass = 1e-300;
    g.bodies[BodyId(2)].mass = -0.0;
    g.bodies[BodyId(3)].mass = 5e-324;
    g.labels.push_back({.comp = CompId(0), .value = g.intern("say \"hi\"\nback\\slash")});
    std::string text = to_text(g);
    CHECK(text.find("mass=0.1 ") != std::string::npos);
    CHECK(text.find("mass=1e-300 ") != std::string::npos);
    CHECK(text.find("mass=-0 ") != std::string::npos);
    CHECK(text.find(R"(value="say \"hi\"\nback\\slash")") != std::string::npos);

    Graph loaded;
    std::string error;
    REQUIRE_MESSAGE(load(text, loaded, error), error);
    CHECK(loaded.bodies[BodyId(0)].mass == 0.1);
    CHECK(loaded.bodies[BodyId(1)].mass == 1e-300);
    CHECK(std::signbit(loaded.bodies[BodyId(2)].mass));
    CHECK(loaded.bodies[BodyId(3)].mass == 5e-324);
    CHECK(loaded.str(loaded.labels[Id<Label>(0)].value) == "say \"hi\"\nback\\slash");
}

TEST_CASE("names are compared by text, not by id") {
    Graph a = tiny_graph();
    Graph b = a;
    b.names.insert(b.names.begin(), "shifted");  // every id moves up by one
#define SHIFT_FIELD(T_, f_) shift(r.f_);
#define SHIFT_TABLE(member, Record, elem, FIELDS) \
    for (Record& r : b.member) { FIELDS(SHIFT_FIELD) }
    auto shift = [](auto& v) {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, Name>)
            if (v.id >= 0) ++v.id;
    };
    shift(b.plant);
    PLANT_GRAPH_TABLES(SHIFT_TABLE)
#undef SHIFT_TABLE
#undef SHIFT_FIELD
    CHECK(a.names != b.names);
    CHECK(a.same_as(b));
    CHECK(to_text(a) == to_text(b));
}

TEST_CASE("same_as sees a change in any field of any table") {
    const Graph g = full_graph();
    auto check_differs = [&](const char* what, const std::function<void(Graph&)>& change) {
        Graph h = g;
        change(h);
        CHECK_MESSAGE(!g.same_as(h), what);
        CHECK_MESSAGE(!h.same_as(g), what);
    };
#define BUMP_FIELD(T_, f_) \
    check_differs(#f_, [&](Graph& h) { bump(h, table_of(h).front().f_); });
#define BUMP_TABLE(member, Record, elem, FIELDS)                     \
    {                                                                \
        auto table_of = [](Graph& h) -> auto& { return h.member; }; \
        FIELDS(BUMP_FIELD)                                           \
        check_differs(#member, [](Graph& h) { h.member.pop_back(); }); \
    }
    PLANT_GRAPH_TABLES(BUMP_TABLE)
#undef BUMP_TABLE
#undef BUMP_FIELD
    check_differs("plant", [](Graph& h) { h.plant = h.intern("Other"); });
    check_differs("plant none", [](Graph& h) { h.plant = Name{}; });
    check_differs("rate", [](Graph& h) { h.settings.rate = 60; });
    check_differs("gravity", [](Graph& h) { h.settings.gravity[2] = -9.8; });
    check_differs("files", [](Graph& h) { h.files[0] += "x"; });
    check_differs("name text", [](Graph& h) { h.names[h.plant.id] = "Renamed"; });
    check_differs("-0 vs 0", [](Graph& h) { h.settings.gravity[1] = 0.0; });

    Graph h = g;
    h.values[Id<Value>(0)].v = std::nan("");
    Graph k = h;
    CHECK(h.same_as(k));  // NaN reads back as NaN, so it must count as the same
}

TEST_CASE("comments, blank lines and CRLF are accepted") {
    std::string text = to_text(tiny_graph());
    std::string edited = "# written by hand\n\n";
    for (const std::string& l : split_lines(text)) edited += l + "\r\n\n";
    Graph g;
    std::string error;
    REQUIRE_MESSAGE(load(edited, g, error), error);
    CHECK(to_text(g) == text);
}

TEST_CASE("load_text_file") {
    auto path = std::filesystem::temp_directory_path() / ("plant_text_test_" + std::to_string(::getpid()) + ".graph");
    {
        std::ofstream out(path, std::ios::binary);
        write_text(full_graph(), out);
    }
    Graph g;
    std::string error;
    CHECK_MESSAGE(load_text_file(path.string(), g, error, Check::Form), error);
    CHECK(g.same_as(full_graph()));
    std::filesystem::remove(path);

    CHECK_FALSE(load_text_file(path.string(), g, error, Check::Form));
    CHECK(error == path.string() + ": cannot open");
}

TEST_CASE("broken input fails with a line number") {
    const std::string good = to_text(tiny_graph());
    const auto lines = split_lines(good);
    auto line_of = [&](std::string_view prefix) { return int(find_line(lines, prefix)) + 1; };
    auto edit_line = [&](std::string_view prefix, std::string_view from, std::string_view to) {
        auto copy = lines;
        replace(copy[find_line(copy, prefix)], from, to);
        return join_lines(copy);
    };
    const int do1 = line_of("do 1");
    const int end = line_of("end");

    struct Case {
        const char* what;
        std::string text;
        int line;
    };
    const Case cases[] = {
        {"empty", "", 1},
        {"wrong header", "plant-graf 1\n", 1},
        {"wrong version", "plant-graph " + std::to_string(kFormatVersion + 1) + "\n", 1},
        {"only the header", "plant-graph " + std::to_string(kFormatVersion) + "\n", 2},
        {"truncated in a line", good.substr(0, good.find("do 1") + 20), do1},
        {"truncated at a line end", good.substr(0, good.find("do 1")), do1},
        {"no end line", good.substr(0, good.find("end\n")), end},
        {"unknown enum word", edit_line("comp 1", "kind=field", "kind=feild"), line_of("comp 1")},
        {"enum word case", edit_line("slot 0", "dir=out", "dir=Out"), line_of("slot 0")},
        {"bad number", edit_line("value 0", "v=0.5", "v=0.5.1"), line_of("value 0")},
        {"not a number", edit_line("settings", "rate=150", "rate=fast"), line_of("settings")},
        {"int out of range", edit_line("do 1", "parent=0", "parent=99999999999"), do1},
        {"int with fraction", edit_line("do 1", "parent=0", "parent=0.5"), do1},
        {"bad bool", edit_line("timer 0", "periodic=true", "periodic=yes"), line_of("timer 0")},
        {"missing field", edit_line("do 1", " src=0:12:3", ""), do1},
        {"extra field", edit_line("do 1", "src=0:12:3", "src=0:12:3 extra=1"), do1},
        {"renamed field", edit_line("do 1", "parent=", "parnet="), do1},
        {"fields swapped", edit_line("do 1", "parent=0 type=0", "type=0 parent=0"), do1},
        {"count too large", edit_line("count dos", "2", "3"), line_of("count comps")},
        {"count too small", edit_line("count dos", "2", "1"), do1},
        {"negative count", edit_line("count dos", "2", "-1"), line_of("count dos")},
        {"huge count", edit_line("count port_targets", "0", "2000000000"), end},
        {"tables out of order", edit_line("count flows", "flows", "accesses"), line_of("count flows")},
        {"id out of order", edit_line("do 1", "do 1", "do 2"), do1},
        {"wrong element word", edit_line("do 1", "do 1", "comp 1"), do1},
        {"unterminated string", edit_line("do 1", "\"belt1\"", "\"belt1"), do1},
        {"unquoted name", edit_line("do 1", "\"belt1\"", "belt1"), do1},
        {"bad escape", edit_line("do 1", "belt1", "belt\\q1"), do1},
        {"short hex escape", edit_line("do 1", "belt1\"", "\\x4\""), do1},
        {"broken name id", edit_line("do 1", "\"belt1\"", "#3"), do1},
        {"vec3 too short", edit_line("field 0", "(2 0.5 0.1)", "(2 0.5)"), line_of("field 0")},
        {"vec3 too long", edit_line("field 0", "(2 0.5 0.1)", "(2 0.5 0.1 1)"), line_of("field 0")},
        {"pose without bar", edit_line("do 1", "(1 0.1 0|", "(1 0.1 0 "), do1},
        {"bad src", edit_line("do 1", "src=0:12:3", "src=0:12"), do1},
        {"double space", edit_line("do 1", " parent", "  parent"), do1},
        {"tab separator", edit_line("do 1", " parent", "\tparent"), do1},
        {"content after end", good + "do 0\n", end + 1},
        {"missing plant line", edit_line("plant \"", "plant", "plnt"), 2},
        {"raw control byte", edit_line("do 1", "belt1", std::string_view("be\0lt1", 6)), do1},
    };
    for (const Case& c : cases) {
        CAPTURE(c.what);
        Graph g = tiny_graph();
        g.plant = g.intern("untouched");
        const std::string before = to_text(g);
        std::string error;
        CHECK_FALSE(load(c.text, g, error));
        INFO(error);
        CHECK(error.starts_with("line " + std::to_string(c.line) + ": "));
        CHECK(to_text(g) == before);  // a failed load leaves the graph alone
    }
}

// Each version of the format and the fingerprint of what it holds (text.h). A change to
// graph.h's tables or fields, an enumeration's words or a kind's fixed slots changes the
// fingerprint, and this fails: give the format a new version (text.h's kFormatVersion), add
// its line here, regenerate the goldens (scripts/update-goldens.sh) and say so in
// docs/graph.md. A graph of the version before is then refused by name.
TEST_CASE("graph text: the format's version changes whenever its fingerprint does") {
    const std::map<int, uint64_t> fingerprints = {
        {2, 0x25fe5fb91eed1146},  // 2026-11-27: the first version pinned (with the field's `enabled` output, the optional settings.steady_transport and a plugin component's placement)
        {3, 0x83904d49bc0b3819},  // 2026-11-28: a plugin's parameters of every type (plugin_param's vec, type, comp, list; plugin_strings)
        {4, 0x7e27fc58da372e89},  // 2026-11-30 (branch curve-model): a turning field's radius and pivot
    };
    REQUIRE_MESSAGE(fingerprints.count(kFormatVersion), "kFormatVersion " << kFormatVersion << " has no fingerprint here");
    CHECK_MESSAGE(format_fingerprint() == fingerprints.at(kFormatVersion),
                  "the text form changed (fingerprint 0x" << std::hex << format_fingerprint()
                                                          << "): give it a new version, see this test's comment");
    CHECK(to_text(tiny_graph()).starts_with("plant-graph " + std::to_string(kFormatVersion) + "\n"));
}

// A graph of another version is refused by its header, saying which and what to do.
TEST_CASE("graph text: another version's graph is refused with what to do") {
    std::string text = to_text(tiny_graph());
    const std::string now = "plant-graph " + std::to_string(kFormatVersion);
    auto with = [&](const std::string& header) { return header + text.substr(now.size()); };
    Graph g;
    std::string error;
    CHECK_FALSE(load(with("plant-graph 1"), g, error));
    CHECK(error.starts_with("line 1: written by an older compiler, in format 1"));
    CHECK(error.find("compile its plant file again, `plant build FILE.plant -o FILE.graph`") != std::string::npos);
    CHECK_FALSE(load(with("plant-graph " + std::to_string(kFormatVersion + 1)), g, error));
    CHECK(error.starts_with("line 1: written by a newer compiler"));
    CHECK_FALSE(load(with("plant-graph two"), g, error));
    CHECK(error.starts_with("line 1: 'two' is not a format version"));
    REQUIRE(load(text, g, error));
}

TEST_CASE("any prefix or damaged copy is handled without crashing") {
    const std::string good = to_text(tiny_graph());
    std::string error;
    for (size_t n = 0; n + 1 < good.size(); ++n) {  // all but the last newline is needed
        Graph g;
        CHECK_FALSE(load(good.substr(0, n), g, error));
        CHECK(error.starts_with("line "));
    }
    // Whatever damage the loader accepts must itself round-trip.
    for (size_t i = 0; i < good.size(); ++i) {
        for (char c : {'x', ' ', '"', '\n', '(', '-', '9', '\0', '\\', '#'}) {
            std::string bad = good;
            bad[i] = c;
            Graph g;
            if (!load(bad, g, error)) {
                CHECK(error.starts_with("line "));
                continue;
            }
            Graph again;
            REQUIRE(load(to_text(g), again, error));
            CHECK(again.same_as(g));
            CHECK(to_text(again) == to_text(g));
        }
    }
}

}  // TEST_SUITE

TEST_SUITE("graph") {

TEST_CASE("intern") {
    Graph g;
    Name a = g.intern("a");
    CHECK(g.intern("b").id == 1);
    CHECK(g.intern("a") == a);
    CHECK(g.intern("").id == 2);
    CHECK(g.str(a) == "a");
    CHECK(g.str(Name{}).empty());

    g.names.push_back("filled by a loader");  // the index must notice
    CHECK(g.intern("filled by a loader").id == 3);
    CHECK(g.intern("c").id == 4);
    CHECK(g.names.size() == 5);
}

TEST_CASE("paths and source positions") {
    Graph g = tiny_graph();
    CHECK(g.comp_path(CompId(0)) == "clock");  // on the root: no leading dot
    CHECK(g.slot_path(SlotId(0)) == "clock.tick");
    CHECK(g.comp_path(CompId(1)) == "belt1.conveyor");
    CHECK(g.slot_path(SlotId(1)) == "belt1.conveyor.set_speed");
    CHECK(g.slot_path(SlotId(99)) == "<slot 99>");
    CHECK(g.comp_path(CompId{}) == "<comp -1>");

    CHECK(g.src_text(g.slots[SlotId(1)].src) == "examples/belt.plant:13:5");
    CHECK(g.src_text(Src{}) == "-");
    CHECK(g.src_text(Src{-1, 3, 4}) == "-");
    CHECK(g.src_text(Src{7, 1, 2}) == "<file 7>:1:2");
}

template <class E>
void check_words(const std::vector<std::string_view>& words) {
    CHECK(enum_size<E>() == int(words.size()));
    for (size_t i = 0; i < words.size(); ++i) {
        E e = static_cast<E>(i);
        CHECK(word(e) == words[i]);
        E back{};
        CHECK(parse_word(words[i], back));
        CHECK(back == e);
    }
    E untouched = static_cast<E>(1);
    CHECK_FALSE(parse_word("nonsense", untouched));
    CHECK_FALSE(parse_word("", untouched));
    CHECK(untouched == static_cast<E>(1));
    CHECK(word(static_cast<E>(200)) == "?");
}

TEST_CASE("enum words") {
    check_words<SlotType>({"void", "bool", "int", "real", "vec3", "quat", "pose", "string", "ref"});
    check_words<Dir>({"in", "out"});
    check_words<CompKind>({"graphics", "body", "field", "constraint", "state", "trigger", "timer",
                           "gripper", "source", "exit", "router", "logic", "label", "plugin"});
    check_words<BodyMode>({"dynamic", "static", "kinematic"});
    check_words<ShapeKind>({"box", "sphere", "cylinder", "capsule", "hull"});
    check_words<JointKind>({"fixed", "hinge", "slider"});
    check_words<Cond>({"source", "target", "both", "either"});
    check_words<LogicOp>({"and", "or"});
}

}  // TEST_SUITE
