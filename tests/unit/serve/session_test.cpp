// plant serve, what a trainee and an instructor see: a hand carrying a bottle (events that
// replay headless bit for bit), the run's history for a page that comes late, the list of
// forced slots with who forced them and since when, the achieved speed beside the chosen
// one, and the models a plant names (found, replaced by the user's, or refused).
#include "serve_helpers.h"

#include "serve/history.h"
#include "serve/models.h"
#include "serve/report.h"

#include <filesystem>

namespace {

// The dynamic main bodies in the world now, as the page's frame has them.
std::vector<size_t> bottles_in_world(const graph::Graph& g, const view::Frame& f) {
    std::vector<size_t> out;
    for (size_t b = 0; b < g.bodies.size(); ++b)
        if (g.bodies[plant::graph::BodyId(b)].mode == graph::BodyMode::Dynamic && (f.body_state[b] & 1) &&
            g.str(g.comps[g.bodies[plant::graph::BodyId(b)].comp].name) == "main")
            out.push_back(b);
    return out;
}

// Reads until a status whose `holds(status)` is true, within `seconds`.
template <class Holds>
json status_where(Page& page, Holds&& holds, double seconds = 20) {
    json st;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        if (!page.wait_json("status", st, 5)) break;
        if (holds(st)) return st;
    }
    return json();
}

std::string write_file(const std::string& name, const std::string& bytes) {
    const auto path = test::scratch_dir() / "models" / name;
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << bytes;
    return path.string();
}

// The 12-byte header of a binary glTF whose length field says `length`.
std::string glb_header(uint32_t length) {
    std::string h = "glTF";
    const uint32_t version = 2;
    h.append(reinterpret_cast<const char*>(&version), 4);
    h.append(reinterpret_cast<const char*>(&length), 4);
    return h;
}

}  // namespace

TEST_CASE("serve: a hand message is the events-file text of a grab, move, drop or remove") {
    view::ClientMessage m;
    std::string err;
    REQUIRE(view::decode_client_message(R"({"type":"hand","action":"grab","path":"b[0].main","point":[1.5,-0.25,0.08]})", m, err));
    CHECK(m.kind == view::ClientMessage::Kind::Event);
    CHECK(m.path + " " + m.value == "grab b[0].main at 1.5,-0.25,0.08");
    REQUIRE(view::decode_client_message(R"({"type":"hand","action":"move","path":"b[0].main","point":[1,2,3]})", m, err));
    CHECK(m.path + " " + m.value == "move b[0].main to 1,2,3");
    REQUIRE(view::decode_client_message(R"({"type":"hand","action":"drop","path":"b[0].main"})", m, err));
    CHECK(m.path == "drop b[0].main");
    CHECK(m.value.empty());
    for (const char* bad : {R"({"type":"hand","action":"throw","path":"a"})", R"({"type":"hand","action":"grab","path":"a"})",
                            R"({"type":"hand","action":"grab","path":"a","point":[1,2]})",
                            R"({"type":"hand","action":"move","path":"a","point":[1,"x",2]})",
                            R"({"type":"hand","action":"drop","path":"a b"})", R"({"type":"hand","path":"a"})"}) {
        CHECK_FALSE(view::decode_client_message(bad, m, err));
        CHECK_FALSE(err.empty());
    }
}

TEST_CASE("serve: a bottle a page's hand carries, saved as events, replays headless bit for bit") {
    const graph::Graph g = compile_ok("plants/bottling.plant");
    Served s(view::make_live_player(g, {}, {}, false, 0));  // as fast as possible
    view::Frame f = sized_frame(g);
    Page page(s.port, &f);
    json scene;
    REQUIRE(page.wait_json("scene", scene));
    // A bottle standing on the loop (not on the arm's table, not in its gripper).
    size_t b = 0;
    bool found = false;
    for (int i = 0; i < 100000 && !found; ++i) {
        REQUIRE(page.wait_frame());
        for (size_t k : bottles_in_world(g, f))
            if (f.body_pose[7 * k + 2] < 0.05 && f.body_pose[7 * k] < 5.2 && f.time > 8) b = k, found = true;
    }
    REQUIRE(found);
    const std::string path = g.comp_path(g.bodies[plant::graph::BodyId(b)].comp);
    const double x = f.body_pose[7 * b], y = f.body_pose[7 * b + 1], z = f.body_pose[7 * b + 2];
    auto hand = [&](const char* action, double px, double py, double pz) {
        page.send(json{{"type", "hand"}, {"action", action}, {"path", path}, {"point", {px, py, pz}}}.dump());
        json ev;
        REQUIRE(page.wait_json("event", ev));
        CHECK(ev["line"].get<std::string>().find(std::string(action) + " " + path) != std::string::npos);
    };
    hand("grab", x, y, z + 0.04);
    hand("move", x, y, z + 0.14);
    hand("move", x, y - 0.05, z + 0.14);
    page.send(json{{"type", "hand"}, {"action", "drop"}, {"path", path}}.dump());
    json ev;
    REQUIRE(page.wait_json("event", ev));
    const int64_t paused_at = pause(page, f);
    std::string events;
    REQUIRE(http_get(s.port, "/events", &events) == 200);
    CHECK(events.find(" grab " + path + " at ") != std::string::npos);
    CHECK(events.find(" drop " + path) != std::string::npos);
    std::vector<engine::Event> evs;
    std::string err;
    REQUIRE(engine::load_events(g, engine::slot_index(g), test::temp_plant("hands.events", events), evs, err));
    REQUIRE(evs.size() == 4);
    engine::Engine e(g);
    replay(e, evs, paused_at);
    for (size_t k = 0; k < g.bodies.size(); ++k) {
        if (g.bodies[plant::graph::BodyId(k)].mode == graph::BodyMode::Static) continue;
        const graph::Pose p = e.body_pose(plant::graph::BodyId(int32_t(k)));
        for (int c = 0; c < 3; ++c) CHECK(float(p.p[size_t(c)]) == f.body_pose[7 * k + size_t(c)]);
    }
    CHECK(e.warnings().hand_refused == 0);
}

TEST_CASE("serve: a page opened late gets the run's history from t = 0, anew after a restart") {
    const graph::Graph g = compile_ok("plants/bottling.plant");
    Served s(view::make_live_player(g, {}, {}, false, 0));
    view::Frame f = sized_frame(g);
    Page first(s.port, &f);
    json scene;
    REQUIRE(first.wait_json("scene", scene));
    for (int i = 0; i < 100000 && f.time < 20; ++i) REQUIRE(first.wait_frame());
    Page late(s.port);
    json h;
    REQUIRE(late.wait_json("scene", scene));
    REQUIRE(late.wait_json("history", h));
    const auto& t = h["time"];
    REQUIRE(t.size() > 50);
    CHECK(t[0] == 0.0);
    CHECK(t.back().get<double>() >= 19.5);
    CHECK(h["records"].size() == scene["records"].size());
    const auto& issued = h["counters"]["issued"];
    REQUIRE(issued.size() == t.size());
    CHECK(issued[0] == 0.0);
    CHECK(issued.back().get<double>() >= 3);
    for (size_t i = 1; i < issued.size(); ++i) CHECK(issued[i].get<double>() >= issued[i - 1].get<double>());
    // A restart: a new scene, then a history that starts again. Paused first, so the new run
    // stays at t = 0 (at full speed it could be 15 s on before the history is sent).
    late.send(R"({"type":"control","action":"pause"})");
    late.send(R"({"type":"control","action":"restart"})");
    REQUIRE(late.wait_json("scene", scene));
    REQUIRE(late.wait_json("history", h));
    REQUIRE(h["time"].size() == 1);
    CHECK(h["time"][0] == 0.0);
    CHECK(h["counters"]["issued"][0] == 0.0);
}

TEST_CASE("serve: the history keeps a long run's whole shape within its bound") {
    view::History h(3, 1000);  // 9 columns: at most about 111, at least 200 samples
    REQUIRE(h.capacity() == 200);
    const std::vector<double> v(view::kCounters + 3, 1.0);
    for (int i = 0; i <= 18000; ++i)  // an hour at 0.2 s
        if (h.due(i * 0.2)) h.add(i * 0.2, v);
    CHECK(h.samples() <= h.capacity());
    CHECK(h.samples() > h.capacity() / 2);
    const json j = json::parse(h.json());
    CHECK(j["time"][0] == 0.0);
    CHECK(j["time"].back().get<double>() > 3500);
    CHECK(j["every"].get<double>() >= 3600.0 / 200);
    CHECK(j["records"].size() == 3);
    CHECK(j["counters"]["removed"].size() == h.samples());
}

TEST_CASE("serve: forced slots are listed with who forced them and since when, the plant file's in the log only") {
    const graph::Graph g = compile_ok("plants/bottling_faults.plant");
    engine::Event drill;
    std::string err;
    REQUIRE(engine::parse_event(g, engine::slot_index(g), "5s force line[0].s3.sw.to_base open", drill, err));
    // At 20 times real time, not full speed: the plant file's fault lasts from 20 s to 100 s, and
    // at full speed a busy machine's next status may come after it ended.
    Served s(view::make_live_player(g, {}, {}, false, 20, {drill}));
    Page page(s.port);
    json m;
    REQUIRE(page.wait_json("scene", m));
    // The plant file's fault (S2's reader cut from 20 s to 100 s) and the command line's (from 5 s).
    const json st = status_where(page, [](const json& x) { return x["time"].get<double>() > 21; }, 60);
    REQUIRE(st["time"].get<double>() < 100);
    REQUIRE(st.is_object());
    REQUIRE(st.contains("forced"));
    std::map<std::string, json> by_path;
    for (const json& x : st["forced"]) by_path[x["path"].get<std::string>()] = x;
    REQUIRE(by_path.count("line[0].s2.bottle"));
    CHECK(by_path["line[0].s2.bottle"]["by"] == "plant file");
    CHECK(by_path["line[0].s2.bottle"]["how"] == "open");
    CHECK(by_path["line[0].s2.bottle"]["since"].get<double>() == doctest::Approx(20));
    REQUIRE(by_path.count("line[0].s3.sw.to_base"));
    CHECK(by_path["line[0].s3.sw.to_base"]["by"] == "command line");
    // The page forces one and releases another.
    page.send(R"({"type":"force","path":"line[0].s1.sw.to_base","mode":"stuck","value":"off"})");
    page.send(R"({"type":"force","path":"line[0].s3.sw.to_base","mode":"release"})");
    const json st2 = status_where(page, [](const json& x) {
        bool s1 = false, s3 = false;
        for (const json& f : x.value("forced", json::array())) {
            s1 |= f["path"] == "line[0].s1.sw.to_base";
            s3 |= f["path"] == "line[0].s3.sw.to_base";
        }
        return s1 && !s3;
    });
    REQUIRE(st2.is_object());
    for (const json& x : st2["forced"])
        if (x["path"] == "line[0].s1.sw.to_base") CHECK(x["by"].get<std::string>().rfind("page ", 0) == 0);
    // The plant file's fault is in the pages' log, marked, and not in the session's events
    // file (a replay of the plant applies it again); the command line's and the page's are.
    std::string events;
    REQUIRE(http_get(s.port, "/events", &events) == 200);
    CHECK(events.find("force line[0].s2.bottle") == std::string::npos);
    CHECK(events.find("5.000s force line[0].s3.sw.to_base open") != std::string::npos);
    CHECK(events.find("release line[0].s3.sw.to_base") != std::string::npos);
    Page late(s.port);
    REQUIRE(late.wait_json("scene", m));
    bool planned_logged = false;
    json ev;
    for (int i = 0; i < 20 && !planned_logged && late.wait_json("event", ev, 5); ++i)
        if (ev["line"].get<std::string>().find("force line[0].s2.bottle open") != std::string::npos)
            planned_logged = ev.value("planned", false) && ev["by"] == "plant file";
    CHECK(planned_logged);
}

TEST_CASE("serve: the session's events file ends at or after each of its events, also when stopped right after one") {
    // A session at full speed stopped just after a page's event was applied: the last frame
    // published may be a few steps older than the player, and the report (plant serve
    // --report-dir) replays the file to its `# end`, so the end must not fall before the event.
    const graph::Graph g = compile_ok("examples/switch.plant");
    engine::Event ev;
    std::string err;
    REQUIRE(engine::parse_event(g, engine::slot_index(g), "0s force sw.to_base open", ev, err));
    for (int trial = 0; trial < 5; ++trial) {
        CAPTURE(trial);
        auto player = view::make_live_player(g, {}, {}, false, 0);
        player->start();
        std::this_thread::sleep_for(std::chrono::milliseconds(20 + 7 * trial));
        view::Command c;
        c.kind = view::Command::Kind::Event;
        c.event = ev;
        c.client = 1;
        REQUIRE(player->command(c));
        bool logged = false;
        for (int i = 0; i < 5000 && !logged; ++i) {
            logged = player->events_file().find(" force sw.to_base open") != std::string::npos;
            if (!logged) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        REQUIRE(logged);
        player->stop();
        const std::string text = player->events_file();
        view::Session session;
        REQUIRE_MESSAGE(view::replay_session_text(g, "examples/switch.plant", "session.events", text, 0, session, err), err);
        CHECK(session.events.size() == 1);
        CHECK(session.faults.size() == 1);
    }
}

TEST_CASE("serve: the status says the speed achieved beside the one chosen") {
    const graph::Graph g = compile_ok("examples/switch.plant");
    Served s(view::make_live_player(g, {}, {}, false, 0));
    Page page(s.port);
    json m;
    REQUIRE(page.wait_json("scene", m));
    const json fast = status_where(page, [](const json& x) { return x["rtf"].get<double>() > 3; });
    REQUIRE(fast.is_object());  // flat out, a small plant runs many times faster than real time
    CHECK(fast["speed"] == 0.0);
    page.send(R"({"type":"control","action":"speed","speed":1})");
    const auto t0 = std::chrono::steady_clock::now();
    const json paced = status_where(page, [&](const json& x) {
        return x["speed"] == 1.0 && std::chrono::steady_clock::now() - t0 > std::chrono::milliseconds(2500);
    });
    REQUIRE(paced.is_object());
    // Not the average since the start (which the fast second keeps far above 1).
    CHECK(paced["rtf"].get<double>() < 1.3);
    CHECK(paced["rtf"].get<double>() > 0.3);
}

TEST_CASE("serve: models are found under --models, beside the plant, then in the stdlib, and bad ones are refused") {
    const std::string good = write_file("good.glb", glb_header(12));
    write_file("text.glb", "this is not a model at all");
    write_file("cut.glb", glb_header(4000) + std::string(100, '\0'));
    write_file("json.gltf", R"({"asset": {"version": "2.0"}, "scenes": []})");
    write_file("nojson.gltf", "{ not json");
    const std::string huge = write_file("huge.glb", glb_header(200u << 20));
    std::filesystem::resize_file(huge, 200u << 20);  // sparse: 200 MB without writing them
    view::ModelDirs dirs;
    dirs.models_dir = std::filesystem::path(good).parent_path().string();
    dirs.stdlib_dir = PLANT_STDLIB_DIR;
    CHECK(view::find_model(dirs, "good.glb").file == good);
    CHECK(view::find_model(dirs, "good.glb").problem.empty());
    CHECK(view::find_model(dirs, "json.gltf").problem.empty());
    CHECK(view::find_model(dirs, "text.glb").problem.find("not a glTF binary") != std::string::npos);
    CHECK(view::find_model(dirs, "cut.glb").problem.find("cut short") != std::string::npos);
    CHECK(view::find_model(dirs, "nojson.gltf").problem.find("not a glTF (.gltf) file") != std::string::npos);
    const std::string big = view::find_model(dirs, "huge.glb").problem;
    CHECK(big.find("209.7 MB, more than a model may be (32 MB)") != std::string::npos);
    CHECK(view::find_model(dirs, "huge.glb").file.empty());
    CHECK(view::find_model(dirs, "../escape.glb").problem.find("'..'") != std::string::npos);
    CHECK(view::find_model(dirs, "/etc/x.glb").problem.find("refused") != std::string::npos);
    const std::string missing = view::find_model(dirs, "nowhere.glb").problem;
    CHECK(missing.find("'nowhere.glb' was not found (looked in ") != std::string::npos);
    CHECK(missing.find(dirs.models_dir) != std::string::npos);
    CHECK(view::find_model(dirs, "a word, not a file").problem.empty());  // primitives, no notice
    // Over HTTP: the good ones are served, the refused ones are not.
    const graph::Graph g = compile_ok("examples/switch.plant");
    auto player = view::make_live_player(g, {}, dirs, true, 1);
    view::ServerOptions so;
    so.port = 0;
    so.models = dirs;
    view::Server server(*player, so);
    std::string error;
    REQUIRE(server.start(error));
    player->start();
    CHECK(http_get(server.port(), "/models/good.glb") == 200);
    CHECK(http_get(server.port(), "/models/huge.glb") == 404);
    CHECK(http_get(server.port(), "/models/text.glb") == 404);
    CHECK(http_get(server.port(), "/models/../good.glb") == 400);
    server.stop();
    player->stop();
}
