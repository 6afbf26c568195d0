// #19 §4, the soak: the bottling plant for one simulated hour. Nothing lost, nothing
// stalled, no NaN, every bottle commissioned in the lane its code names (checked per bottle
// where it leaves), and resident memory at the end within 5 % of what it was after the
// first simulated minute (the step allocates nothing; pools and Bullet's caches are warm by
// then). Runs in the ci build (about a minute); skipped under the sanitizers, which multiply
// its time by ten.
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "../stdlib/lookup.h"

#include <doctest/doctest.h>

#include <fstream>
#include <map>
#include <string>

#include <unistd.h>

using namespace plant::test;

namespace {

// Resident set size of this process in KiB (/proc/self/statm: pages).
long resident_kib() {
    std::ifstream in("/proc/self/statm");
    long size = 0, resident = 0;
    in >> size >> resident;
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

}  // namespace

TEST_CASE("soak: the bottling plant for a simulated hour" * doctest::skip(PLANT_SANITIZED != 0)) {
    plant::Compilation c;
    compile_repo_file("plants/bottling.plant", c);
    REQUIRE(c.ok());
    const plant::graph::Graph& g = c.graph;
    std::map<char, std::pair<int32_t, int32_t>> exits;  // lane -> (taken, id)
    for (char lane : std::string("abcde")) {
        const std::string e = std::string("line[0].exit_") + lane + ".away.";
        exits[char(lane - 'a' + 'A')] = {slot_named(g, e + "taken"), slot_named(g, e + "id")};
        REQUIRE(exits[char(lane - 'a' + 'A')].first >= 0);
    }
    plant::engine::Engine e(g);
    for (const auto& [lane, s] : exits) e.watch(plant::graph::SlotId(s.second));
    const int64_t minute = int64_t(60 / e.dt() + 0.5), hour = 60 * minute;
    long rss_minute = 0;
    int64_t commissioned = 0, wrong = 0;
    for (int64_t i = 1; i <= hour; ++i) {
        e.step();
        for (const auto& [lane, s] : exits) {
            if (!e.active(plant::graph::SlotId(s.first))) continue;
            const std::string id(e.str(int32_t(e.value(plant::graph::SlotId(s.second))[0])));
            ++commissioned;
            if (id.empty() || id[0] != lane) {
                ++wrong;
                FAIL_CHECK("bottle '" << id << "' commissioned in lane " << lane << " at " << e.time() << " s");
            }
        }
        if (i == minute) rss_minute = resident_kib();
    }
    const long rss_hour = resident_kib();
    MESSAGE("commissioned " << commissioned << " in an hour; resident " << rss_minute << " KiB after a minute, "
                            << rss_hour << " KiB after the hour");
    CHECK(wrong == 0);
    CHECK(commissioned >= 600);  // about 13 a minute once the line is full
    int lost = 0;
    for (size_t d = 0; d < g.dos.size(); ++d) lost += e.lost_at(plant::graph::DoId(int32_t(d))) >= 0 ? 1 : 0;
    CHECK(lost == 0);
    int stalled = 0;
    for (size_t b = 0; b < g.bodies.size(); ++b)
        stalled += e.body_in_world(plant::graph::BodyId(int32_t(b))) && e.stalled_for(plant::graph::BodyId(int32_t(b))) > 30 ? 1 : 0;
    CHECK(stalled == 0);
    CHECK(e.warnings().nan_state == 0);
    CHECK(e.warnings().total() == 0);
    CHECK(double(rss_hour) <= 1.05 * double(rss_minute));
}
