// Scenes saved as graph text files (tests/runtime_scenes/*.graph) load and run. The
// files are written from the builders here: PLANT_UPDATE_SCENES=1 regenerates them.
#include "paths.h"
#include "engine/engine.h"
#include "graph/text.h"
#include "bottling_scene.h"

#include <doctest/doctest.h>

#include <cstdlib>
#include <fstream>

using namespace plant::test;

TEST_CASE("runtime: the bottling scene file loads as the graph it was written from, and runs") {
    const std::string path = std::string(PLANT_SOURCE_DIR) + "/tests/runtime_scenes/bottling.graph";
    const Graph built = bottling_scene();
    if (const char* u = std::getenv("PLANT_UPDATE_SCENES"); u && std::string(u) == "1") {
        std::ofstream out(path, std::ios::binary);
        plant::graph::write_text(built, out);
    }
    Graph loaded;
    std::string error;
    REQUIRE_MESSAGE(plant::graph::load_text_file(path, loaded, error), error);
    CHECK(loaded.same_as(built));
    plant::engine::Engine a(loaded), b(built);
    for (int i = 0; i < 600; ++i) {
        a.step();
        b.step();
    }
    for (size_t body = 0; body < built.bodies.size(); ++body)
        CHECK(a.body_com(plant::graph::BodyId(int32_t(body))) == b.body_com(plant::graph::BodyId(int32_t(body))));
    CHECK(a.warnings().total() == 0);
}
