// Where and when an object was lost (Engine::loss, docs/runtime.md "Lost objects"): the step it
// left the world in, the last conveyor field it rode, the step it was last in it and its
// centre of mass then; the same in the run summary and the trace's `lost` column. Each
// expectation is measured from the bodies' own trajectory, step by step, beside the engine.
#include "../compiler/compile_helper.h"
#include "../stdlib/lookup.h"
#include "engine/engine.h"
#include "app/run_flags.h"
#include "engine/run.h"
#include "engine/times.h"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

using namespace plant;
using namespace plant::test;

namespace {

int32_t do_named(const graph::Graph& g, std::string_view path) {
    for (size_t d = 0; d < g.dos.size(); ++d)
        if (g.str(g.dos[graph::DoId(d)].path) == path) return int32_t(d);
    return -1;
}

// Whether point p lies in field f's box (a std.belts band: not rotated, fixed).
bool in_field(const graph::Graph& g, int32_t f, const graph::Vec3& p) {
    const graph::Field& fd = g.fields[graph::FieldId(f)];
    for (int i = 0; i < 3; ++i)
        if (std::abs(p[i] - fd.pose.p[i]) > fd.extent[i] / 2) return false;
    return true;
}

// Steps `e` until the object of body `main` is lost (at most `steps`), keeping, as the engine
// should, the last step count at which a body of it (listed in `bodies`) had its centre of mass
// in one of `fields`, the first such field in id order, and that centre of mass.
struct Watched {
    int64_t step = -1, out_step = -1;
    int32_t field = -1;
    graph::Vec3 at{};
};
Watched ride_until_lost(engine::Engine& e, const std::vector<int32_t>& bodies, const std::vector<int32_t>& fields, int steps) {
    const graph::Graph& g = e.graph();
    Watched w;
    for (int i = 0; i < steps && w.out_step < 0; ++i) {
        for (int32_t b : bodies) {  // before the step: where the law sees it
            if (!e.body_in_world(graph::BodyId(b))) continue;
            const graph::Vec3 p = e.body_com(graph::BodyId(b));
            for (int32_t f : fields)
                if (e.field_on(graph::FieldId(f)) && in_field(g, f, p) && (e.steps() > w.step || b == bodies[0])) {
                    if (e.steps() > w.step) w = {e.steps(), -1, f, p};
                    break;
                }
        }
        e.step();
        if (!e.body_in_world(graph::BodyId(bodies[0]))) w.out_step = e.steps();
    }
    return w;
}

}  // namespace

TEST_CASE("loss: a bottle that rides off the end of its belt is lost off that belt, where and when it left it") {
    const graph::Graph g = compiled_text(R"(
import std.belts, std.bottle
plant Fall {
    b1: Belt(length = 50 cm)
    b2: Belt(length = 40 cm) at (50 cm, 0 m, 0 m)
    faller: Bottle at (20 cm, 0 m, 0 m)
}
)",
                                    "fall.plant");
    const int32_t d = do_named(g, "faller");
    const std::vector<int32_t> bodies = {row_of_comp(g, g.bodies, "faller.main"), row_of_comp(g, g.bodies, "faller.bottom")};
    const int32_t f1 = row_of_comp(g, g.fields, "b1.drive"), f2 = row_of_comp(g, g.fields, "b2.drive");
    REQUIRE(d >= 0);
    REQUIRE(bodies[0] >= 0);
    REQUIRE(bodies[1] >= 0);
    REQUIRE(f2 >= 0);
    engine::Engine e(g);
    CHECK(e.loss(graph::DoId(d)).step == -1);
    const Watched w = ride_until_lost(e, bodies, {f1, f2}, 5 * 150);
    REQUIRE(w.out_step > 0);
    const engine::Loss& l = e.loss(graph::DoId(d));
    CHECK(l.step == w.out_step);
    CHECK(e.lost_at(graph::DoId(d)) == doctest::Approx(double(w.out_step) * e.dt()));
    REQUIRE(e.lost().size() == 1);
    CHECK(e.lost()[0] == graph::DoId(d));
    // It crossed onto b2 and left it at its end, 0.9 m along, ahead of its fall.
    CHECK(l.field == graph::FieldId(f2));
    CHECK(w.field == f2);
    CHECK(l.field_step == w.step);
    for (int i = 0; i < 3; ++i) CHECK(l.place[i] == doctest::Approx(w.at[i]).epsilon(1e-6));
    CHECK(l.place[0] > 0.88);
    CHECK(l.place[0] < 0.9 + 0.01);
    CHECK(l.field_step < l.step - 100);  // a fall of 10 m takes 1.4 s
    CHECK(l.out[2] < -10);
}

TEST_CASE("loss: a bottle pushed over the side of a belt without rails is lost there, not where it left the world") {
    const graph::Graph g = compiled_text(R"(
import std.belts, std.bottle
plant Push {
    b1: Belt(length = 2 m, rails = false)
    pushed: Bottle at (20 cm, 0 m, 0 m)
}
)",
                                    "push.plant");
    const int32_t d = do_named(g, "pushed");
    const std::vector<int32_t> bodies = {row_of_comp(g, g.bodies, "pushed.main"), row_of_comp(g, g.bodies, "pushed.bottom")};
    const int32_t f1 = row_of_comp(g, g.fields, "b1.drive");
    const int32_t vel = slot_named(g, "pushed.main.set_velocity");
    REQUIRE(vel >= 0);
    engine::Engine e(g);
    for (int i = 0; i < 75; ++i) e.step();  // at belt speed, half a metre on
    const double push[3] = {0.5, 0.4, 0};
    e.input(graph::SlotId(vel), push);
    const Watched w = ride_until_lost(e, bodies, {f1}, 5 * 150);
    REQUIRE(w.out_step > 0);
    const engine::Loss& l = e.loss(graph::DoId(d));
    CHECK(l.step == w.out_step);
    CHECK(l.field == graph::FieldId(f1));
    CHECK(l.field_step == w.step);
    CHECK(l.field_step > 75);
    // Last in the band at its side (the field is 8 cm wide), within a step's travel of it.
    CHECK(l.place[1] == doctest::Approx(w.at[1]));
    CHECK(l.place[1] > 0.04 - 0.4 / 150 - 1e-6);
    CHECK(l.place[1] <= 0.04);
    CHECK(l.place[0] > 0.4);
    CHECK(l.place[0] < 1.5);
}

TEST_CASE("loss: an object that never rode a conveyor is lost where it left the world, and one not lost has no loss") {
    const graph::Graph g = compiled_text(R"(
import std.belts, std.bottle
plant Drop {
    b1: Belt(length = 50 cm)
    dropped: Bottle at (0 m, 1 m, 0 m)
    stays: Bottle at (10 cm, 0 m, 0 m)
}
)",
                                    "drop.plant");
    const int32_t d = do_named(g, "dropped"), s = do_named(g, "stays");
    const int32_t main = row_of_comp(g, g.bodies, "dropped.main");
    engine::Engine e(g);
    int64_t out = -1;
    graph::Vec3 last{};
    for (int i = 0; i < 300 && out < 0; ++i) {
        last = e.body_com(graph::BodyId(main));
        e.step();
        if (!e.body_in_world(graph::BodyId(main))) out = e.steps();
    }
    REQUIRE(out > 0);
    const engine::Loss& l = e.loss(graph::DoId(d));
    CHECK(l.step == out);
    CHECK_FALSE(l.field.valid());
    CHECK(l.field_step == out);
    CHECK(l.place == l.out);
    CHECK(l.out[2] < -10);
    CHECK(l.out[2] > last[2] - 0.5);  // one step's fall past the step before
    CHECK(e.loss(graph::DoId(s)).step == -1);
    REQUIRE(e.lost().size() == 1);
    CHECK(engine::loss_text(e, graph::DoId(d)) ==
          fmt::format("on no conveyor at {} s at ({:.3f} {:.3f} {:.3f}) m", engine::time_text(double(out) * e.dt(), e.dt()),
                      l.out[0] + 0.0, l.out[1] + 0.0, l.out[2]));
}

TEST_CASE("loss: the run summary and the trace say where and when each lost object left the line") {
    const std::string text = R"(
import std.belts, std.bottle
plant Fall {
    b1: Belt(length = 50 cm)
    faller: Bottle at (20 cm, 0 m, 0 m)
    late: Bottle at (5 cm, 0 m, 0 m)
}
)";
    const graph::Graph g = compiled_text(text, "fall_summary.plant");
    // The same run, stepped here: what the summary must print.
    engine::Engine e(g);
    for (int i = 0; i < 4 * 150; ++i) e.step();
    REQUIRE(e.lost().size() == 2);
    const graph::DoId first = e.lost()[0], second = e.lost()[1];
    CHECK(g.str(g.dos[graph::DoId(first)].path) == "faller");
    CHECK(g.str(g.dos[graph::DoId(second)].path) == "late");
    const engine::Loss& l = e.loss(first);
    CHECK(l.place[0] == doctest::Approx(0.5).epsilon(0.02));
    const std::string where = fmt::format("off b1.drive at {} s at ({:.3f} {:.3f} {:.3f}) m", engine::time_text(double(l.field_step) * e.dt(), e.dt()),
                                          std::round(l.place[0] * 1000) / 1000 + 0.0, std::round(l.place[1] * 1000) / 1000 + 0.0,
                                          std::round(l.place[2] * 1000) / 1000 + 0.0);
    CHECK(engine::loss_text(e, first) == where);

    const std::string trace = scratch_dir() / "fall_summary.csv";
    std::ostringstream out, err;
    REQUIRE(app::run_main(g, {"--for", "4s", "--quiet", "--trace", trace, "--trace-rate", "10Hz"}, out, err) == 0);
    const std::string s = out.str();
    CAPTURE(s);
    CHECK(s.find("  lost (left the world): 2 (faller, late)\n    faller: " + where + "; left the world at " +
                 engine::time_text(double(l.step) * e.dt(), e.dt()) + " s\n    late: " + engine::loss_text(e, second) +
                 "; left the world at ") != std::string::npos);

    // The `lost` column: each object once, in the first row at or after the step it left the world.
    std::ifstream in(trace);
    std::string line;
    REQUIRE(std::getline(in, line));
    CHECK(line.ends_with(",lost"));
    int rows_with = 0;
    std::string cells;
    double row_time = 0;
    while (std::getline(in, line)) {
        const std::string cell = line.substr(line.rfind(',') + 1);
        if (cell.empty()) continue;
        ++rows_with;
        cells += (cells.empty() ? "" : ";") + cell;
        if (cell.starts_with("faller ")) row_time = std::stod(line.substr(0, line.find(',')));
    }
    CHECK(cells == "faller " + where + ";late " + engine::loss_text(e, second));
    CHECK(rows_with <= 2);
    CHECK(row_time >= double(l.step) * e.dt() - 1e-9);
    CHECK(row_time < double(l.step) * e.dt() + 0.1 + 1e-9);
}

TEST_CASE("loss: a pooled object issued again starts without the conveyor of its earlier life") {
    const graph::Graph g = compiled_text(R"(
import std.belts, std.bottle
plant Again {
    b1: Belt(length = 50 cm, rails = false)
    trigger end at (45 cm, 0 m, 4 cm) { extent = (4 cm, 10 cm, 10 cm) }
    exit done { trigger = end }
    source store at (20 cm, 0 m, 0 m) {
        object = Bottle
        pool = 1
    }
}
)",
                                    "again.plant");
    const int32_t issue = slot_named(g, "store.issue"), halt = slot_named(g, "b1.drive.disable");
    const int32_t d = do_named(g, "store[0]");
    const int32_t main = row_of_comp(g, g.bodies, "store[0].main");
    const int32_t vel = slot_named(g, "store[0].main.set_velocity");
    REQUIRE(issue >= 0);
    REQUIRE(halt >= 0);
    REQUIRE(d >= 0);
    REQUIRE(vel >= 0);
    engine::Engine e(g);
    // First life: it rides b1 to the exit at its end and is taken, not lost.
    e.input(graph::SlotId(issue));
    e.step();
    REQUIRE(e.body_in_world(graph::BodyId(main)));
    for (int i = 0; i < 3 * 150 && e.body_in_world(graph::BodyId(main)); ++i) e.step();
    REQUIRE_FALSE(e.body_in_world(graph::BodyId(main)));
    CHECK(e.taken(graph::ExitId(0)) == 1);
    CHECK(e.loss(graph::DoId(d)).step == -1);
    // Second life: the band's field is off, so it rides nothing; pushed off the side, it is lost
    // on no conveyor (not off b1.drive, where its first life rode).
    e.input(graph::SlotId(halt));
    e.step();
    e.input(graph::SlotId(issue));
    for (int i = 0; i < 10; ++i) e.step();
    REQUIRE(e.body_in_world(graph::BodyId(main)));
    const double push[3] = {0, 0.5, 0};
    e.input(graph::SlotId(vel), push);
    for (int i = 0; i < 4 * 150 && e.loss(graph::DoId(d)).step < 0; ++i) e.step();
    const engine::Loss& l = e.loss(graph::DoId(d));
    REQUIRE(l.step > 0);
    CHECK_FALSE(l.field.valid());
    CHECK(l.place == l.out);
    CHECK(l.out[2] < -10);
}
