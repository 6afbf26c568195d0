// The page learns of operator panels from the scene (docs/viewer.md, scene `panels`) and
// draws what the runtime says each element shows (status `panel`), never the click itself.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/run.h"
#include "engine/events.h"
#include "serve/view.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

using namespace plant;

TEST_CASE("serve: the scene lists each panel's elements, the status what each shows") {
    Compilation c;
    test::compile_text(R"(
plant Desk {
    panel ops {
        title = "Desk"
        button start { label = "Start"; color = "green" }
        selector mode { names = "Manual/Auto"; initial = 1 }
        lamp running { color = "red" }
        display count { unit = "bottles"; digits = 1 }
    }
    flow ops.start.down -> ops.running.lit
}
)",
                       c, "desk_view.plant");
    REQUIRE(c.ok());
    const graph::Graph& g = c.graph;
    const nlohmann::json scene = nlohmann::json::parse(view::scene_json(g, {}, false, 0));
    REQUIRE(scene["panels"].size() == 1);
    const nlohmann::json& p = scene["panels"][0];
    CHECK(p["path"] == "ops");
    CHECK(p["title"] == "Desk");
    REQUIRE(p["elements"].size() == 4);
    CHECK(p["elements"][0]["kind"] == "button");
    CHECK(p["elements"][0]["path"] == "ops.start");
    CHECK(p["elements"][0]["name"] == "start");
    CHECK(p["elements"][0]["label"] == "Start");
    CHECK(p["elements"][0]["color"] == "green");
    CHECK(p["elements"][1]["positions"] == 2);
    CHECK(p["elements"][1]["names"] == "Manual/Auto");
    CHECK(p["elements"][1]["initial"] == 1);
    CHECK(p["elements"][2]["label"] == "");
    CHECK(p["elements"][3]["unit"] == "bottles");
    CHECK(p["elements"][3]["digits"] == 1);

    engine::Engine e(g);
    const engine::RecordTally tally(g);
    e.step();
    CHECK(nlohmann::json::parse(view::status_json(e, tally, {}))["panel"] == nlohmann::json::array({0, 1, 0, 0}));
    engine::Event ev;
    std::string error;
    const engine::SlotIndex index = engine::slot_index(g);
    REQUIRE_MESSAGE(engine::parse_input(g, index, "ops.start.press", ev, error), error);
    engine::apply_event(e, ev);
    for (int i = 0; i < 3; ++i) e.step();  // pressed; the flow lights the lamp; it shows
    CHECK(nlohmann::json::parse(view::status_json(e, tally, {}))["panel"] == nlohmann::json::array({1, 1, 1, 0}));
}
