// The page learns of operator panels from the scene (docs/viewer.md, scene `panels`) and
// draws what the runtime says each element shows (status `panel`), never the click itself.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/run.h"
#include "engine/events.h"
#include "graph/text.h"
#include "serve/view.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>

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

TEST_CASE("serve: a panel placed in the scene has its world pose in the scene, one not placed has none") {
    Compilation c;
    test::compile_text(R"(
object Room {
    panel desk at (1 m, 0 m, 1.2 m) rotate z by 90 deg { button go { label = "Go" } }
}
plant P {
    room: Room at (0 m, 2 m, 0 m)
    panel wall { lamp on_ { } }
}
)",
                       c, "placed_view.plant");
    REQUIRE_MESSAGE(c.ok(), render_all_text(c.sink.sorted(), c.sources));
    const nlohmann::json scene = nlohmann::json::parse(view::scene_json(c.graph, {}, false, 0));
    REQUIRE(scene["panels"].size() == 2);
    const nlohmann::json* placed = nullptr;
    const nlohmann::json* flat = nullptr;
    for (const nlohmann::json& p : scene["panels"]) (p["path"] == "room.desk" ? placed : flat) = &p;
    REQUIRE(placed);
    REQUIRE(flat);
    CHECK_FALSE(flat->contains("pose"));
    REQUIRE((*placed)["pose"].size() == 7);
    // In the object's frame: the room at y = 2 m, the panel 1 m along its x, turned about z.
    const std::vector<double> pose = (*placed)["pose"];
    CHECK(pose[0] == doctest::Approx(1));
    CHECK(pose[1] == doctest::Approx(2));
    CHECK(pose[2] == doctest::Approx(1.2));
    CHECK(pose[5] == doctest::Approx(std::sqrt(0.5)));
    CHECK(pose[6] == doctest::Approx(std::sqrt(0.5)));
    // The graph keeps it (placed, pose) through its text form; a placement on a kind that
    // takes none is refused by the loader as by the compiler (E0311).
    graph::Graph back;
    std::string error;
    const std::string text = graph::to_text(c.graph);
    std::istringstream good(text);
    REQUIRE_MESSAGE(graph::read_text(good, back, error), error);
    CHECK(graph::to_text(back) == text);
    const size_t button = text.find("kind=\"button\"");
    REQUIRE(button != std::string::npos);
    std::string bad = text;
    const size_t flag = bad.find("placed=false", button);
    REQUIRE(flag != std::string::npos);
    bad.replace(flag, 12, "placed=true");
    std::istringstream broken(bad);
    CHECK_FALSE(graph::read_text(broken, back, error));
    CHECK_MESSAGE(error.find("a button takes no placement, field 'placed' is true") != std::string::npos, error);
}
