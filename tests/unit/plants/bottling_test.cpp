// The bundled bottling plant (plants/bottling.plant), end to end: compiled from the
// file, run for 120 simulated seconds, its material flow checked step by step.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "../stdlib/lookup.h"

#include <doctest/doctest.h>

#include <map>
#include <string>
#include <vector>

using namespace plant::test;
using plant::engine::Engine;
using plant::graph::Graph;

TEST_CASE("plants/bottling.plant: bottles are filled, capped and commissioned in the lane of their code") {
    plant::Compilation c;
    compile_repo_file("plants/bottling.plant", c);
    REQUIRE(c.ok());
    const Graph& g = c.graph;

    // Exits by lane; the switch places that take requests.
    std::map<char, std::pair<int32_t, int32_t>> exits;  // lane -> (taken, id)
    for (char lane : std::string("abcde")) {
        const std::string e = std::string("line[0].exit_") + lane + ".away.";
        exits[char(lane - 'a' + 'A')] = {slot_named(g, e + "taken"), slot_named(g, e + "id")};
        REQUIRE(exits[char(lane - 'a' + 'A')].first >= 0);
    }
    std::vector<int32_t> requests;
    for (int k = 1; k <= 5; ++k)
        for (const char* p : {"MoveToBasePos", "MoveToWorkingPos"}) {
            requests.push_back(place_named(g, "line[0].s" + std::to_string(k) + ".sw.net", p));  // a RoutedSwitch
            REQUIRE(requests.back() >= 0);
        }
    const int32_t filled = slot_named(g, "line[0].fill.core.work.tick"),
                  capped = slot_named(g, "line[0].cap.core.work.tick");
    REQUIRE(filled >= 0);
    REQUIRE(capped >= 0);

    // The sections behind the separators: from WP (the separator's origin) to the
    // station's pin, along the top side (heading −x at y = top).
    struct Section {
        double from, to;  // x range
    };
    const double right = 5.3, r = 0.3, top = 2.1;
    const Section sections[] = {{right - r - 0.65, right - r - 0.3}, {right - r - 2.05, right - r - 1.7}};
    std::vector<int32_t> mains;
    for (size_t b = 0; b < g.bodies.size(); ++b)
        if (g.comp_path(g.bodies[plant::graph::BodyId(b)].comp).ends_with(".main")) mains.push_back(int32_t(b));
    REQUIRE(mains.size() == 40);

    Engine e(g);
    int wrong_lane = 0, taken = 0, fills = 0, caps = 0, crowded = 0, piled = 0;
    for (int step = 0; step < 150 * 120; ++step) {
        e.step();
        for (auto& [lane, ex] : exits) {
            if (!e.active(plant::graph::SlotId(ex.first))) continue;
            ++taken;
            const std::string id(e.str(int32_t(e.value(plant::graph::SlotId(ex.second))[0])));
            if (id.empty() || id[0] != lane) ++wrong_lane;
        }
        fills += e.active(plant::graph::SlotId(filled));
        caps += e.active(plant::graph::SlotId(capped));
        for (int32_t p : requests) piled += e.tokens(plant::graph::PlaceId(p)) > 1;
        for (const Section& s : sections) {
            int in = 0;
            for (int32_t b : mains) {
                if (!e.body_in_world(plant::graph::BodyId(b))) continue;
                const auto p = e.body_com(plant::graph::BodyId(b));
                in += p[0] > s.from && p[0] < s.to && std::abs(p[1] - top) < 0.05;
            }
            crowded += in > 1;
        }
    }
    int on_line = 0;
    for (int32_t b : mains) on_line += e.body_in_world(plant::graph::BodyId(b));
    int64_t issued = 0;
    for (size_t s = 0; s < g.sources.size(); ++s) issued += e.issued(plant::graph::SourceId(int32_t(s)));

    CHECK(e.warnings().left_world == 0);     // no bottle lost
    CHECK(e.warnings().total() == 0);
    CHECK(issued == taken + on_line);        // every issued bottle commissioned or still on the line
    CHECK(taken >= 20);
    CHECK(wrong_lane == 0);                  // each in the lane its code names
    CHECK(fills >= taken);                   // only processed bottles leave
    CHECK(caps >= taken);
    CHECK(crowded == 0);                     // one bottle at a time behind each separator
    CHECK(piled == 0);                       // the switches never accumulate requests
    for (int32_t b : mains)
        if (e.body_in_world(plant::graph::BodyId(b))) CHECK(e.stalled_for(plant::graph::BodyId(b)) < 30);  // nothing jammed
}
