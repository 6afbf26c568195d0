// validate(): a damaged .graph file fails to load with the record at fault and its line,
// one case per kind of check; the graph the compiler wrote for the bottling plant passes;
// every golden graph, damaged in each way the compiler guards, is refused.
#include "paths.h"
#include "graph/text.h"
#include "graph/validate.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

using namespace plant::graph;

namespace {

std::string fmt_line(int line) { return "line " + std::to_string(line) + ": "; }

std::string bottling_text() {
    std::ifstream in(std::string(PLANT_SOURCE_DIR) + "/tests/plants/bottling.graph", std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

struct Damage {
    std::string elem;   // the record's element word, "settings" for the settings line
    int32_t row;        // its id
    std::string field;  // the field to overwrite
    std::string value;  // its new text
    std::string says;   // a piece of the expected message
};

// Overwrites one field of one record; returns the 1-based line it is on.
int damage(std::string& text, const Damage& d) {
    const std::string head = d.elem == "settings" ? "settings " : d.elem + " " + std::to_string(d.row) + " ";
    size_t at = text.starts_with(head) ? 0 : text.find("\n" + head);
    REQUIRE_MESSAGE(at != std::string::npos, "no record '" << head << "'");
    if (at > 0) ++at;
    const size_t end = text.find('\n', at);
    std::string line = text.substr(at, end - at);
    const std::regex field(" " + d.field + R"(=(\([^)]*\)|"[^"]*"|\S+))");
    REQUIRE_MESSAGE(std::regex_search(line, field), "no field '" << d.field << "' in: " << line);
    line = std::regex_replace(line, field, " " + d.field + "=" + d.value, std::regex_constants::format_first_only);
    text.replace(at, end - at, line);
    return 1 + int(std::count(text.begin(), text.begin() + long(at), '\n'));
}

// The rows one damage is tried on, of a table of `n` from `first`: the first three, the
// middle one and the last (validate checks every row by the same code; all rows of every
// golden made this test quadratic, 81 s under the sanitizers).
std::vector<size_t> some_rows(size_t n, size_t first = 0) {
    std::vector<size_t> rows;
    for (size_t i : {first, first + 1, first + 2, first + (n - first) / 2, n - 1})
        if (i >= first && i < n && (rows.empty() || i > rows.back())) rows.push_back(i);
    return rows;
}

}  // namespace

TEST_CASE("validate: the compiler's bottling graph passes, and every kind of damage is named with its line") {
    const std::string good = bottling_text();
    Graph g;
    std::string error;
    {
        std::istringstream in(good);
        REQUIRE_MESSAGE(read_text(in, g, error), error);
        GraphProblem p;
        CHECK(validate(g, p));
    }
    // Rows picked from the graph itself, so that each damage trips the check it names.
    auto first = [&](auto&& rows, auto&& pred) {
        for (auto i : ids_of(rows))
            if (pred(rows[i])) return i.v;
        FAIL("no such row");
        return int32_t(-1);
    };
    const int32_t dyn = first(g.bodies, [](const Body& b) { return b.mode == BodyMode::Dynamic; });
    const int32_t box = first(g.shapes, [](const Shape& s) { return s.kind == ShapeKind::Box; });
    const int32_t hull = first(g.shapes, [](const Shape& s) { return s.kind == ShapeKind::Hull; });
    const int32_t periodic = first(g.timers, [](const Timer& t) { return t.periodic; });
    const int32_t typed_do = first(g.dos, [](const Do& d) { return d.type.valid(); });
    const int32_t place = first(g.places, [](const Place& p) { return p.tokens_slot.valid() && p.put_slot.valid(); });
    const int32_t child = first(g.graphics, [](const Graphics& x) { return x.parent.valid(); });
    const int32_t multi = first(g.animations, [](const Animation& a) { return a.key_num >= 2; });
    // A place of another state component than arc 0's transition's.
    const int32_t foreign = first(g.places, [&](const Place& p) { return p.comp != g.places[g.arcs[Id<Arc>(0)].place].comp; });
    const int32_t event = first(g.flows, [&](const Flow& f) {
        return !f.from_access.valid() && !f.to_access.valid() && g.slots[f.from].type == SlotType::Void;
    });
    const int32_t vec_in = first(g.slots, [](const Slot& s) { return s.type == SlotType::Vec3 && s.dir == Dir::In; });
    const int32_t pose_slot = first(g.slots, [](const Slot& s) { return s.type == SlotType::Pose; });
    const int32_t void_out = first(g.slots, [](const Slot& s) { return s.type == SlotType::Void && s.dir == Dir::Out; });
    const int32_t body_comp = g.bodies[BodyId(0)].comp.v;
    const int32_t inertial = first(g.bodies, [](const Body& b) { return b.inertia_set; });
    const int32_t dyn_from = first(g.flows, [](const Flow& f) { return f.from_access.valid(); });
    const int32_t dyn_to = first(g.flows, [](const Flow& f) { return f.to_access.valid(); });
    // A dynamic end holds its access's reference slot; any other slot is refused.
    const std::string ref_from = std::to_string(g.accesses[g.flows[FlowId(dyn_from)].from_access].ref_slot.v);
    const std::string ref_to = std::to_string(g.accesses[g.flows[FlowId(dyn_to)].to_access].ref_slot.v);
    const Access& a0 = g.accesses[AccessId(0)];
    const std::string n = std::to_string(g.do_types[a0.do_type].instance_num - 1);
    // A pose slot's values starting 6 before the end of the table: one short.
    const std::string pose_adr = std::to_string(g.values.size() - 6);
    const std::string values_num = std::to_string(g.values.size());

    const std::vector<Damage> cases = {
        {"settings", 0, "rate", "0", "settings: rate 0 is not between 1 Hz and 1 MHz"},
        {"body", dyn, "mass", "nan", "field 'mass' is not a finite number"},
        {"do", 1, "pose", "(0 0 0|0 0 0 2)", "field 'pose' has a rotation that is not a unit quaternion"},
        {"comp", 0, "src", "99:1:1", "field 'src' names file 99, not one of the " + std::to_string(g.files.size()) + " files"},
        {"do", 1, "parent", "5", "field 'parent' must name an earlier DO"},
        {"do", typed_do, "ordinal", "100000", "field 'ordinal' = 100000 is not below its type's instance_num"},
        {"comp", 0, "owner", "100000", "field 'owner' = 100000 is not a row of dos (" + std::to_string(g.dos.size()) + " rows)"},
        {"comp", body_comp, "slot_num", "3", "a body has 14 fixed slots, field 'slot_num' is 3"},
        {"comp", body_comp, "slot_adr", "0", "slot 0 in its slot range belongs to component"},
        {"comp", body_comp, "detail", "5000", "field 'detail' = 5000 is not a row of bodies (237 rows)"},
        {"slot", pose_slot, "value_adr", pose_adr, "a pose slot needs 7 values there, the graph has " + values_num},
        {"flow", 0, "from", "99999", "field 'from' = 99999 is not a row of slots"},
        {"flow", event, "to", std::to_string(vec_in), "its source is not 3 values wide, as its target is"},
        {"access", 0, "target_num", n, "its type has " + std::to_string(std::stoi(n) + 1) + " instances"},
        {"logic", 0, "out_slot", "-1", "field 'out_slot' = -1 is not a row of slots"},
        {"body", dyn, "mass", "0", "a dynamic body needs a mass above 0"},
        {"body", dyn, "shape_num", "0", "a body needs at least one shape"},
        {"flow", event, "to", std::to_string(void_out), "its target is not an input slot"},
        {"place", place, "initial", "1000001", "field 'initial' must lie in [0, 1000000]"},
        {"arc", 0, "weight", "2000000000", "field 'weight' must lie in [1, 1000000]"},
        {"body", 0, "friction", "-1", "friction and restitution must be 0 or more"},
        {"body", 0, "comp", std::to_string(g.bodies[BodyId(1)].comp.v), "that component is a body whose detail is 1, not this body"},
        {"shape", box, "size", "(0 1 1)", "field 'size' must be above 0 where the shape uses it"},
        {"shape", hull, "point_num", "0", "a hull needs points"},
        {"shape", hull, "point_num", "1", "a hull encloses no volume: all its points coincide"},
        {"field", 0, "dir", "(0 0 0)", "field 'dir' is the zero vector"},
        {"do", 1, "pose", "(2e5 0 0|0 0 0 1)", "field 'pose' is 200000 m out along x, beyond 100 km"},
        {"body", dyn, "com", "(0 0 -3e5|0 0 0 1)", "field 'com' is -300000 m along z, beyond 100 km"},
        {"body", dyn, "mass", "2e6", "field 'mass' is 2e+06 kg, above 1,000 t"},
        {"body", inertial, "inertia", "(1 2e16 1)", "field 'inertia' has a moment of 2e+16 kg·m², above 1e16 kg·m²"},
        {"shape", box, "size", "(1 2e5 1)", "field 'size' is 200000 m, beyond 100 km"},
        {"field", 0, "extent", "(1 1 1e6)", "field 'extent' is 1e+06 m, beyond 100 km"},
        {"joint", 0, "frame_b", "(0 1e9 0|0 0 0 1)", "field 'frame_b' is 1e+09 m along y, beyond 100 km"},
        {"trigger", 0, "pose", "(0 0 -1e300|0 0 0 1)", "field 'pose' is -1e+300 m out along z, beyond 100 km"},
        {"body", dyn, "mass", "1e-300", "field 'mass' is 1e-300 kg, below 1 mg"},
        {"body", inertial, "inertia", "(1 1e-300 1)", "field 'inertia' has a moment of 1e-300 kg·m², below 1e-14 kg·m²"},
        {"shape", box, "size", "(1 1 5e-5)", "field 'size' is 5e-05 m, below 0.1 mm"},
        {"field", 0, "speed", "-2e5", "field 'speed' is -200000 m/s, beyond 100 km/s"},
        {"field", 0, "gain", "1e300", "field 'gain' is 1e+300 kg/s, above 1e12 kg/s"},
        {"field", 0, "radius", "-0.3", "field 'radius' is negative or not finite"},
        {"field", 0, "radius", "inf", "field 'radius' is not a finite number"},
        {"field", 0, "pivot", "(0 nan 0)", "field 'pivot' is not a finite number"},
        {"settings", 0, "gravity", "(0 0 -1e4)", "settings: gravity is beyond 1 km/s² along an axis"},
        {"joint", 0, "body_b", std::to_string(g.joints[JointId(0)].body_a.v), "a joint joins two different bodies"},
        {"place", place, "tokens_slot", std::to_string(g.places[PlaceId(place)].put_slot.v), "expected int out"},
        {"arc", 0, "weight", "0", "field 'weight' must lie in [1, 1000000]"},
        {"arc", 0, "place", std::to_string(foreign), "a place of another state component than its transition's"},
        {"transition", 0, "in_adr", "100000", "fields 'in_adr' + num"},
        {"trigger", 0, "filter", "999", "field 'filter' = 999 is not -1 or a row of do_types"},
        {"timer", periodic, "period", "0", "field 'period' must be above 0"},
        {"gripper", 0, "trigger", "999", "field 'trigger' = 999 is not a row of triggers"},
        {"source", 0, "rate", "-1", "field 'rate' is negative"},
        {"exit", 0, "trigger", "-1", "field 'trigger' = -1 is not a row of triggers"},
        {"route", 0, "out_slot", std::to_string(pose_slot), "expected void out"},
        {"graphics", child, "parent", std::to_string(child), "field 'parent' must name an earlier graphics"},
        {"graphics", 0, "variant", "99", "field 'variant' = 99 is not -1 or the index of one of its"},
        {"animation", 0, "play_slot", std::to_string(pose_slot), "expected void in"},
        {"key", (g.animations[AnimationId(multi)].key_adr + 1).v, "t", "-1", "its time is not later than the key before it"},
        {"variant", 0, "graphics", "-1", "field 'graphics' = -1 is not a row of graphics"},
        {"label", 0, "comp", std::to_string(body_comp), "that component is a body"},
        {"record", 0, "slot", "-2", "field 'slot' = -2 is not a row of slots"},
        {"flow", dyn_from, "from", std::to_string(void_out),
         "field 'from' = " + std::to_string(void_out) + ": a dynamic source holds its access's ref_slot " + ref_from},
        {"flow", dyn_to, "to", std::to_string(vec_in),
         "field 'to' = " + std::to_string(vec_in) + ": a dynamic target holds its access's ref_slot " + ref_to},
    };
    for (const Damage& d : cases) {
        CAPTURE(d.elem);
        CAPTURE(d.field);
        CAPTURE(d.value);
        std::string text = good;
        const int line = damage(text, d);
        std::istringstream in(text);
        Graph out;
        out.intern("untouched");
        CHECK_FALSE(read_text(in, out, error));
        const std::string where = d.elem == "settings" ? fmt_line(line) : fmt_line(line) + d.elem + " " + std::to_string(d.row) + ": ";
        CHECK_MESSAGE(error.starts_with(where), error);
        CHECK_MESSAGE(error.find(d.says) != std::string::npos, error);
        CHECK(out.names.size() == 1);  // a graph that fails is not replaced
        // The form alone still reads.
        std::istringstream again(text);
        CHECK(read_text(again, out, error, Check::Form));
    }
}

static std::string num(double v) {
    std::ostringstream o;
    o.precision(17);
    o << v;
    return o.str();
}

TEST_CASE("validate: a hull whose points lie on a line or in a plane encloses no volume") {
    // The first hull of the bottling graph, its points moved onto a line, then into a plane.
    std::string error;
    Graph g;
    {
        std::istringstream in(bottling_text());
        REQUIRE_MESSAGE(read_text(in, g, error), error);
    }
    int32_t hull = -1;
    for (size_t i = 0; i < g.shapes.size() && hull < 0; ++i)
        if (g.shapes[Id<Shape>(i)].kind == ShapeKind::Hull) hull = int32_t(i);
    REQUIRE(hull >= 0);
    const Shape& s = g.shapes[Id<Shape>(hull)];
    REQUIRE(s.point_num >= 4);
    struct Flat {
        const char* name;
        std::string (*at)(int);  // the k-th point's new text
        const char* says;
    };
    const Flat flats[] = {
        {"line", [](int k) { return "(" + num(0.01 * k) + " 0 0)"; }, "its points lie on one line"},
        {"plane", [](int k) { return "(" + num(0.01 * (k % 2)) + " " + num(0.01 * (k / 2)) + " 0.5)"; },
         "its points lie in one plane"},
        // Within the tolerance (1 um) of one point: merged.
        {"one point", [](int k) { return "(0.1 0.1 " + num(1e-7 * k) + ")"; }, "all its points coincide"},
    };
    for (const Flat& f : flats) {
        CAPTURE(f.name);
        std::string text = bottling_text();
        for (int k = 0; k < s.point_num; ++k) damage(text, {"point", (s.point_adr + k).v, "p", f.at(k), ""});
        std::istringstream in(text);
        Graph out;
        CHECK_FALSE(read_text(in, out, error));
        CHECK_MESSAGE(error.find("shape " + std::to_string(hull) + ": a hull encloses no volume: " + f.says) != std::string::npos, error);
    }
}

// The loader refuses what the compiler refuses, on every graph the suite holds: each golden
// graph passes, then each of its records is damaged in each way the compiler guards (a value
// out of its range, a broken structure), one damage at a time, and validate() must refuse it.
TEST_CASE("validate: every golden graph, damaged in each way the compiler guards, is refused") {
    std::vector<std::string> files;
    for (const char* dir : {"/tests/golden", "/tests/plants"})
        for (const auto& e : std::filesystem::recursive_directory_iterator(std::string(PLANT_SOURCE_DIR) + dir))
            if (e.is_regular_file() && e.path().extension() == ".graph") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    REQUIRE(files.size() > 50);
    size_t tried = 0;
    std::set<std::string> kinds;  // each damage tried on some row of some graph
    for (const std::string& file : files) {
        CAPTURE(file);
        Graph good;
        std::string error;
        if (!load_text_file(file, good, error)) continue;  // a golden of a refused graph
        // One damage: change the working copy, and the loader's check must refuse it; then
        // the copy is made good again by assignment, which reuses its tables' storage.
        Graph work = good;
        auto refused = [&](const std::string what, auto&& change) {
            change(work);
            GraphProblem p;
            ++tried;
            kinds.insert(what);
            CHECK_MESSAGE(!validate(work, p), file << ": " << what);
            work = good;
        };
        refused("rate below 1 Hz", [](Graph& g) { g.settings.rate = 0.5; });
        refused("rate above 1 MHz", [](Graph& g) { g.settings.rate = 2e6; });
        refused("gravity not finite", [](Graph& g) { g.settings.gravity[2] = std::nan(""); });
        refused("gravity beyond 1 km/s²", [](Graph& g) { g.settings.gravity[0] = 1001; });
        for (size_t i : some_rows(good.bodies.size())) {
            if (good.bodies[BodyId(i)].mode == BodyMode::Dynamic) {
                refused("a dynamic body's mass 0", [&](Graph& g) { g.bodies[BodyId(i)].mass = 0; });
                refused("a dynamic body without shapes", [&](Graph& g) { g.bodies[BodyId(i)].shape_num = 0; });
            }
            if (good.bodies[BodyId(i)].inertia_set) refused("inertia 0", [&](Graph& g) { g.bodies[BodyId(i)].inertia[0] = 0; });
            refused("friction below 0", [&](Graph& g) { g.bodies[BodyId(i)].friction = -0.1; });
            refused("restitution below 0", [&](Graph& g) { g.bodies[BodyId(i)].restitution = -0.1; });
            refused("linear damping above 1", [&](Graph& g) { g.bodies[BodyId(i)].linear_damping = 1.5; });
            refused("friction above 10", [&](Graph& g) { g.bodies[BodyId(i)].friction = 10.5; });
            if (good.bodies[BodyId(i)].mode != BodyMode::Dynamic) {
                refused("a static or kinematic body with a mass", [&](Graph& g) { g.bodies[BodyId(i)].mass = 1; });
                refused("a static or kinematic body with damping", [&](Graph& g) { g.bodies[BodyId(i)].angular_damping = 0.5; });
            }
            refused("angular damping below 0", [&](Graph& g) { g.bodies[BodyId(i)].angular_damping = -1; });
            refused("a body placed beyond 100 km", [&](Graph& g) { g.bodies[BodyId(i)].pose.p[1] = -1.5e5; });
            refused("a centre of mass beyond 100 km", [&](Graph& g) { g.bodies[BodyId(i)].com.p[2] = 1e308; });
            refused("a mass above 1,000 t", [&](Graph& g) { g.bodies[BodyId(i)].mass = 2e6; });
            if (good.bodies[BodyId(i)].mode == BodyMode::Dynamic)
                refused("a mass below 1 mg", [&](Graph& g) { g.bodies[BodyId(i)].mass = 9e-7; });
            if (good.bodies[BodyId(i)].inertia_set) refused("inertia below 1e-14", [&](Graph& g) { g.bodies[BodyId(i)].inertia[2] = 1e-15; });
        }
        for (size_t i : some_rows(good.dos.size(), 1))
            refused("an object placed beyond 100 km", [&](Graph& g) { g.dos[DoId(i)].pose.p[0] = 1e19; });
        for (size_t i : some_rows(good.shapes.size())) {
            if (good.shapes[Id<Shape>(i)].kind != ShapeKind::Hull) {
                refused("a shape of size 0", [&](Graph& g) { g.shapes[Id<Shape>(i)].size[0] = 0; });
                refused("a shape larger than 100 km", [&](Graph& g) { g.shapes[Id<Shape>(i)].size[0] = 2e5; });
                refused("a shape smaller than 0.1 mm", [&](Graph& g) { g.shapes[Id<Shape>(i)].size[0] = 9e-5; });
                refused("a shape offset beyond 100 km", [&](Graph& g) { g.shapes[Id<Shape>(i)].local.p[0] = 2e5; });
                continue;
            }
            refused("a hull whose points coincide", [&](Graph& g) {
                for (int32_t k = 1; k < g.shapes[Id<Shape>(i)].point_num; ++k)
                    g.points[Id<Point>(g.shapes[Id<Shape>(i)].point_adr + k)] = g.points[g.shapes[Id<Shape>(i)].point_adr.first()];
            });
            refused("a hull point beyond 100 km", [&](Graph& g) { g.points[g.shapes[Id<Shape>(i)].point_adr.first()].p[2] = -1e40; });
        }
        for (size_t i : some_rows(good.fields.size())) {
            refused("a field's extent 0", [&](Graph& g) { g.fields[FieldId(i)].extent[1] = 0; });
            refused("a field's gain below 0", [&](Graph& g) { g.fields[FieldId(i)].gain = -1; });
            refused("a field's direction zero", [&](Graph& g) { g.fields[FieldId(i)].dir = {0, 0, 0}; });
            refused("a field's max_force below 0", [&](Graph& g) { g.fields[FieldId(i)].max_force = -1; });
            refused("a field placed beyond 100 km", [&](Graph& g) { g.fields[FieldId(i)].pose.p[2] = -2e5; });
            refused("a field longer than 100 km", [&](Graph& g) { g.fields[FieldId(i)].extent[0] = 2e5; });
            refused("a field thinner than 0.1 mm", [&](Graph& g) { g.fields[FieldId(i)].extent[2] = 1e-300; });
            refused("a field faster than 100 km/s", [&](Graph& g) { g.fields[FieldId(i)].speed = -1.5e5; });
            refused("a field's gain above 1e12 kg/s", [&](Graph& g) { g.fields[FieldId(i)].gain = 2e12; });
        }
        for (size_t i : some_rows(good.joints.size())) {
            refused("a joint on one body", [&](Graph& g) { g.joints[JointId(i)].body_b = g.joints[JointId(i)].body_a; });
            if (good.joints[JointId(i)].kind == JointKind::Hinge)
                refused("a hinge's limits spanning more than a turn", [&](Graph& g) {
                    g.joints[JointId(i)].lower = -4;
                    g.joints[JointId(i)].upper = 4;
                });
            if (good.joints[JointId(i)].kind != JointKind::Fixed && good.joints[JointId(i)].lower <= good.joints[JointId(i)].upper)
                refused("a joint's limits not finite", [&](Graph& g) { g.joints[JointId(i)].upper = std::nan(""); });
        }
        for (size_t i : some_rows(good.places.size())) {
            refused("tokens below 0", [&](Graph& g) { g.places[PlaceId(i)].initial = -1; });
            refused("tokens above the limit", [&](Graph& g) { g.places[PlaceId(i)].initial = kMaxInitialTokens + 1; });
        }
        for (size_t i : some_rows(good.arcs.size())) {
            refused("an arc's weight 0", [&](Graph& g) { g.arcs[Id<Arc>(i)].weight = 0; });
            refused("an arc's weight above the limit", [&](Graph& g) { g.arcs[Id<Arc>(i)].weight = kMaxArcWeight + 1; });
        }
        for (size_t i : some_rows(good.transitions.size()))
            refused("a transition without input places", [&](Graph& g) { g.transitions[TransitionId(i)].in_num = 0; });
        for (size_t i : some_rows(good.triggers.size()))
            refused("a trigger's extent 0", [&](Graph& g) { g.triggers[TriggerId(i)].extent[2] = 0; });
        for (size_t i : some_rows(good.timers.size()))
            refused("a timer's period 0", [&](Graph& g) { g.timers[Id<Timer>(i)].period = 0; });
        for (size_t i : some_rows(good.sources.size()))
            refused("a source's rate below 0", [&](Graph& g) { g.sources[SourceId(i)].rate = -1; });
        for (size_t i : some_rows(good.flows.size())) {
            const Flow& f = good.flows[FlowId(i)];
            if (f.to_access.valid()) continue;
            // Into an output: the flow's own source will do, when the source is static.
            if (!f.from_access.valid()) refused("a flow into an output", [&](Graph& g) { g.flows[FlowId(i)].to = g.flows[FlowId(i)].from; });
        }
        for (SlotId i : ids_of(good.slots))
            if (good.slots[i].value_adr.valid()) {
                refused("a slot's values beyond the table", [&](Graph& g) { g.slots[i].value_adr = next_adr(g.values); });
                break;
            }
    }
    MESSAGE(tried << " damages of " << kinds.size() << " kinds over " << files.size() << " graphs");
    CHECK(tried > 500);
    CHECK(kinds.size() == 48);  // every refused(...) above
}

// The reference checks follow from the field types (graph/ids.h): every Id<R> field of
// every table is refused one past the end of R's table, and -1 unless graph.h lists it as
// optional; every Adr<R> list is refused when it runs past R's table.
TEST_CASE("validate: every typed id field is checked against the table its type names") {
    const std::string good = bottling_text();
    Graph g;
    std::string error;
    {
        std::istringstream in(good);
        REQUIRE_MESSAGE(read_text(in, g, error), error);
    }
    int checked = 0;
    auto expect = [&](const std::string& elem, const std::string& field, const std::string& value,
                      const std::string& says) {
        CAPTURE(elem);
        CAPTURE(field);
        CAPTURE(value);
        std::string text = good;
        const int line = damage(text, {elem, 0, field, value, says});
        std::istringstream in(text);
        Graph out;
        CHECK_FALSE(read_text(in, out, error));
        CHECK_MESSAGE(error.starts_with(fmt_line(line) + elem + " 0: "), error);
        CHECK_MESSAGE(error.find(says) != std::string::npos, error);
        ++checked;
    };
    struct Pending {
        std::string field, rows;
    } adr;  // an Adr field waiting for its num, the field after it
    auto visit = [&]<class T>(const std::string& elem, const std::string& field, const T& v) {
        if constexpr (is_typed_id<T>) {
            using R = typename T::record;
            const std::string rows = std::to_string(g.rows<R>().size());
            if constexpr (T::role == IdRole::Adr) {
                if constexpr (!std::is_same_v<R, Value>) adr = {field, rows};  // a slot's values: no num
            } else {
                const std::string target(table_name<R>());
                const bool optional = is_optional_id<T>;
                expect(elem, field, rows,
                       "field '" + field + "' = " + rows + " is not " + (optional ? "-1 or " : "") + "a row of " +
                           target + " (" + rows + " rows)");
                if (!optional) expect(elem, field, "-1", "field '" + field + "' = -1 is not a row of " + target);
            }
        } else if constexpr (std::is_same_v<T, int32_t>) {
            if (!adr.field.empty() && v > 0)
                expect(elem, adr.field, adr.rows, "fields '" + adr.field + "' + num (" + adr.rows + " + ");
            adr = {};
        }
    };
#define CHECK_FIELD(T_, f_) visit(word_, #f_, r.f_);
#define CHECK_TABLE(member, Record, word, FIELDS)   \
    if (!g.member.empty()) {                       \
        const Record& r = g.member.front();             \
        auto visit_row = [&](const std::string& word_) { FIELDS(CHECK_FIELD) }; \
        visit_row(#word);                 \
    }
    PLANT_GRAPH_TABLES(CHECK_TABLE)
#undef CHECK_TABLE
#undef CHECK_FIELD
    CHECK(checked > 60);
}
