// The viewer's status message lists each lost object with where it left the line
// (docs/viewer.md, status `lost`), so the page can mark where it fell.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/run.h"
#include "serve/view.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

using namespace plant;
using json = nlohmann::json;

TEST_CASE("serve: status lists the lost objects with the time, place and conveyor each left") {
    Compilation c;
    test::compile_text(R"(
import std.belts, std.bottle
plant Fall {
    b1: Belt(length = 50 cm)
    faller: Bottle at (20 cm, 0 m, 0 m)
    stays: Bottle at (0 m, 2 m, 0 m)
}
)",
                       c, "fall_status.plant");
    REQUIRE(c.ok());
    const graph::Graph& g = c.graph;
    engine::Engine e(g);
    const engine::RecordTally tally(g);
    CHECK(json::parse(view::status_json(e, tally, {}))["lost"].empty());
    for (int i = 0; i < 3 * 150; ++i) e.step();
    const json s = json::parse(view::status_json(e, tally, {}));
    REQUIRE(e.lost().size() == 2);  // `stays` stands in the void: it falls too
    REQUIRE(s["lost"].size() == 2);
    CHECK(s["counters"]["lost"] == 2);
    for (size_t i = 0; i < 2; ++i) {
        const graph::DoId d = e.lost()[i];
        const engine::Loss& l = e.loss(d);
        const json& j = s["lost"][i];
        CHECK(j["do"] == d.v);
        CHECK(j["path"] == std::string(g.str(g.dos[graph::DoId(d)].path)));
        CHECK(j["time"].get<double>() == doctest::Approx(double(l.step) * e.dt()));
        CHECK(j["left"].get<double>() == doctest::Approx(double(l.field_step) * e.dt()));
        for (int k = 0; k < 3; ++k) {
            CHECK(j["place"][k].get<double>() == l.place[size_t(k)]);
            CHECK(j["out"][k].get<double>() == l.out[size_t(k)]);
        }
        if (l.field.valid()) CHECK(j["field"] == l.field.v);
        else CHECK(j["field"].is_null());
    }
    // The one that rode b1 left it at its end; the other never rode a conveyor.
    const json& faller = s["lost"][0]["path"] == "faller" ? s["lost"][0] : s["lost"][1];
    const json& stays = s["lost"][0]["path"] == "faller" ? s["lost"][1] : s["lost"][0];
    REQUIRE(faller["field"].is_number());
    CHECK(g.comp_path(g.fields[graph::FieldId(faller["field"].get<size_t>())].comp) == "b1.drive");
    CHECK(faller["place"][0].get<double>() == doctest::Approx(0.5).epsilon(0.02));
    CHECK(stays["field"].is_null());
    CHECK(stays["time"].get<double>() == stays["left"].get<double>());
}
