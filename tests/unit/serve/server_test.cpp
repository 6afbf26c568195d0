// plant serve over loopback: the protocol, one way in for events (a session replays
// headless bit for bit), replay of a recording against the trace of the same run, and
// pages that misbehave. Every wait is bounded.
#include "app/run_flags.h"
#include "serve_helpers.h"

TEST_CASE("serve: client messages are decoded or refused, never thrown") {
    view::ClientMessage m;
    std::string err;
    CHECK(view::decode_client_message(R"({"type":"event","path":"s1.to_working"})", m, err));
    CHECK(m.kind == view::ClientMessage::Kind::Event);
    CHECK(view::decode_client_message(R"({"type":"event","path":"b.set_speed","value":0.25})", m, err));
    CHECK(m.value == "0.25");
    CHECK(view::decode_client_message(R"({"type":"control","action":"speed","speed":0})", m, err));
    // A force is an event whose text is the events-file line's (parsed by the server).
    CHECK(view::decode_client_message(R"({"type":"force","path":"s1.to_base","mode":"open"})", m, err));
    CHECK(m.kind == view::ClientMessage::Kind::Event);
    CHECK(m.path + " " + m.value == "force s1.to_base open");
    CHECK(view::decode_client_message(R"({"type":"force","path":"r.id","mode":"stuck","value":"\"A-1\""})", m, err));
    CHECK(m.path + " " + m.value == "force r.id stuck \"A-1\"");
    CHECK(view::decode_client_message(R"({"type":"force","path":"r.id","mode":"release"})", m, err));
    CHECK(m.path == "release r.id");
    CHECK(m.value.empty());
    for (const char* bad : {R"({"type":"force","path":"a"})", R"({"type":"force","path":"a","mode":"melt"})",
                            R"({"type":"force","path":"a b","mode":"open"})", R"({"type":"force","mode":"open"})"}) {
        CHECK_FALSE(view::decode_client_message(bad, m, err));
        CHECK_FALSE(err.empty());
    }
    for (const char* bad : {"", "{", "[]", "null", R"({"type":5})", R"({"type":"nope"})",
                            R"({"type":"control","action":"fly"})", R"({"type":"control","action":"speed","speed":-1})",
                            R"({"type":"hello","fps":1000})", R"({"type":"event"})", R"({"type":"event","path":"a b"})",
                            R"({"type":"event","path":"a","value":{}})", R"({"type":"seek","time":-1})",
                            "{\"type\":\"event\",\"path\":\"\xff\xfe\"}"}) {
        CHECK_FALSE(view::decode_client_message(bad, m, err));
        CHECK_FALSE(err.empty());
    }
}

TEST_CASE("serve: the scene has every body, then full and partial frames follow") {
    const graph::Graph g = compile_ok("examples/switch.plant");
    Served s(view::make_live_player(g, {}, {}, false, 0));
    view::Frame f = sized_frame(g);
    Page page(s.port, &f);
    json scene;
    REQUIRE(page.wait_json("scene", scene));
    CHECK(scene["version"] == view::kProtocolVersion);
    CHECK(scene["bodies"].size() == g.bodies.size());
    CHECK(scene["graphics"].size() == g.graphics.size());
    REQUIRE(page.wait_frame());
    // Statics come with the graph's pose: frames carry world poses.
    for (size_t b = 0; b < g.bodies.size(); ++b)
        if (g.bodies[plant::graph::BodyId(b)].mode == graph::BodyMode::Static) CHECK(f.body_pose[7 * b] == float(g.bodies[plant::graph::BodyId(b)].pose.p[0]));
    json status;
    REQUIRE(page.wait_json("status", status));
    CHECK(status["counters"].contains("issued"));
    CHECK(status["fields"].size() == g.fields.size());
}

// Every pump of a page asking for 5 frames a second or fewer has a status due (every 200 ms):
// until 2026-12-03 the status went out first and the frame, seeing a write under way, was
// dropped, so such a page never got a frame after the first.
TEST_CASE("serve: a page that asks for 2 frames a second gets them") {
    const graph::Graph g = compile_ok("examples/switch.plant");
    Served s(view::make_live_player(g, {}, {}, false, 1));
    Page page(s.port);
    page.send(R"({"type":"hello","fps":2})");
    int frames = 0, statuses = 0;
    page.wait([&](const std::string& msg, bool binary) {
        if (binary) ++frames;
        else if (msg.find("\"type\":\"status\"") != std::string::npos) ++statuses;
        return frames >= 5;
    }, 6);
    CHECK(frames >= 5);
    CHECK(statuses >= 3);  // the status still goes with them
}

TEST_CASE("serve: a session's events, saved, replay headless bit for bit") {
    const graph::Graph g = compile_ok("plants/bottling.plant");
    Served s(view::make_live_player(g, {}, {}, false, 0));  // as fast as possible
    view::Frame f = sized_frame(g);
    Page page(s.port, &f);
    json scene;
    REQUIRE(page.wait_json("scene", scene));
    REQUIRE(page.wait_frame());
    // A port of an object type and a component slot, at whatever steps they arrive.
    page.send(R"({"type":"event","path":"line[0].s1.to_working"})");
    json ev;
    REQUIRE(page.wait_json("event", ev));
    CHECK(ev["line"].get<std::string>().find("s" " line[0].s1.to_working") != std::string::npos);
    page.send(R"({"type":"event","path":"line[0].b1.set_speed","value":"0.3"})");
    REQUIRE(page.wait_json("event", ev));
    // A forced fault is an event too: it replays the same way.
    page.send(R"({"type":"force","path":"line[0].s1.sw.to_base","mode":"open"})");
    REQUIRE(page.wait_json("event", ev));
    CHECK(ev["line"].get<std::string>().find("s force line[0].s1.sw.to_base open") != std::string::npos);
    pause(page, f);
    const view::Frame& last = f;
    std::string events;
    REQUIRE(http_get(s.port, "/events", &events) == 200);
    const std::string path = test::temp_plant("session.events", events);
    engine::Engine e(g);
    std::vector<engine::Event> evs;
    std::string err;
    REQUIRE(engine::load_events(g, engine::slot_index(g), path, evs, err));
    REQUIRE(evs.size() == 3);
    CHECK(evs[0].slots.size() == 1);
    CHECK(evs[2].force);
    replay(e, evs, last.step);
    CHECK(evs.back().time <= e.time() + 1e-9);  // every event was applied
    int moving = 0;
    for (size_t b = 0; b < g.bodies.size(); ++b) {
        if (g.bodies[plant::graph::BodyId(b)].mode == graph::BodyMode::Static) continue;
        const graph::Pose p = e.body_pose(plant::graph::BodyId(int32_t(b)));
        for (int k = 0; k < 3; ++k) CHECK(float(p.p[size_t(k)]) == last.body_pose[7 * b + size_t(k)]);
        moving += e.body_in_world(plant::graph::BodyId(int32_t(b))) ? 1 : 0;
    }
    CHECK(moving > 0);
}

TEST_CASE("serve: bad pages get errors, the run and the other pages go on") {
    const graph::Graph g = compile_ok("examples/switch.plant");
    Served s(view::make_live_player(g, {}, {}, false, 1));
    view::Frame f = sized_frame(g);
    Page watcher(s.port, &f), bad(s.port);
    Page stalled(s.port);  // connects, then never reads a byte
    json m;
    REQUIRE(watcher.wait_json("scene", m));
    REQUIRE(bad.wait_json("scene", m));
    auto error_for = [&](const std::string& msg) {
        bad.send(msg);
        json e;
        REQUIRE(bad.wait_json("error", e));
        return e["message"].get<std::string>();
    };
    CHECK(error_for("{not json") == "malformed JSON");
    CHECK(error_for(R"({"type":"teleport"})").find("unknown message type") != std::string::npos);
    const std::string typo = error_for(R"({"type":"event","path":"sw.to_workin"})");
    CHECK(typo.find("did you mean 'sw.to_working'") != std::string::npos);
    CHECK(error_for(R"({"type":"event","path":"sw.net.BasePos.tokens"})").find("output") != std::string::npos);
    // A value of the wrong type.
    // The scene lists each object's slots as [name, type, dir, port] in scene.slot_lists.
    bool has_real = false;
    for (const auto& o : m["dos"]) {
        for (const auto& sl : m["slot_lists"][o["slots"].get<size_t>()])
            if (sl[1] == "real" && sl[2] == "in") {
                has_real = true;
                const std::string prefix = o["path"].get<std::string>();
                const std::string path = (prefix.empty() ? "" : prefix + ".") + sl[0].get<std::string>();
                const std::string bad_value =
                    error_for(json{{"type", "event"}, {"path", path}, {"value", "fast"}}.dump());
                CHECK_MESSAGE(bad_value.find("not a real value") != std::string::npos, bad_value);
                break;
            }
        if (has_real) break;
    }
    CHECK(has_real);
    // A burst: 10,000 messages, most of them garbage.
    for (int i = 0; i < 10000; ++i) bad.send(i % 2 ? "{\"type\":\"hello\",\"fps\":30}" : "garbage");
    REQUIRE(watcher.wait_frame());
    const double t0 = f.time;
    // A page that goes away in the middle of a frame it sends: a header promising more bytes.
    {
        net::io_context ioc;
        tcp::socket raw(ioc);
        raw.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), s.port));
        const std::string upgrade =
            "GET /ws HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
            "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";
        net::write(raw, net::buffer(upgrade));
        const unsigned char half[] = {0x81, 0xfe, 0x01, 0x00, 1, 2, 3, 4, 'x', 'y'};  // masked, 256 bytes promised
        net::write(raw, net::buffer(half, sizeof half));
        raw.close();
    }
    // The run goes on and the watcher keeps receiving frames.
    double t1 = t0;
    for (int i = 0; i < 40 && t1 <= t0 + 0.2; ++i) {
        REQUIRE(watcher.wait_frame());
        t1 = f.time;
    }
    CHECK(t1 > t0 + 0.2);
    // The burst's 5,000 garbage messages are each refused; the server may still be reading
    // them (under sanitizers): wait for it, at most 20 s.
    {
        INFO("errors: ", s.server->stats().errors);
        CHECK(eventually(20, [&] { return s.server->stats().errors >= 5000; }));
    }
    // The page gone mid-frame is let go as the server reads its end: wait for it, at most 5 s.
    // The watcher, the bad page and the stalled one stay.
    {
        INFO("connected: ", s.server->stats().clients);
        CHECK(eventually(5, [&] { return s.server->stats().clients == 3; }));
    }
    // Paths outside the page's folder are refused.
    CHECK(http_get(s.port, "/../../etc/passwd") == 400);
    CHECK(http_get(s.port, "/%2e%2e/etc/passwd") == 400);
    CHECK(http_get(s.port, "/.git/config") == 400);
    CHECK(http_get(s.port, "/no_such_file.js") == 404);
}

TEST_CASE("serve: a replay shows the bottles where the trace of the same run has them, a seek plots from 0 s") {
    const graph::Graph g = compile_ok("plants/bottling.plant");
    const std::string rec_path = (test::scratch_dir() / "run.rec").string();
    const std::string trace_path = (test::scratch_dir() / "run.csv").string();
    {
        view::Recorder rec(g, rec_path, {});
        REQUIRE(rec.ok());
        std::ostringstream out, err;
        REQUIRE(app::run_main(g, {"--for", "60s", "--trace", trace_path, "--trace-bodies", "--trace-rate", "10Hz",
                                     "--quiet"},
                                 out, err, &rec) == 0);
    }
    // The trace's rows at three times: time -> column values.
    std::ifstream in(trace_path);
    std::string header, line;
    REQUIRE(std::getline(in, header));
    std::vector<std::string> cols;
    for (std::stringstream hs(header); std::getline(hs, line, ',');) cols.push_back(line);
    std::map<int, std::vector<double>> rows;  // tenths of a second -> values
    while (std::getline(in, line)) {
        std::vector<double> v;  // an empty cell (a parked body) reads NaN
        for (size_t at = 0;;) {
            const size_t comma = line.find(',', at);
            const std::string cell = line.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
            v.push_back(cell.empty() ? std::nan("") : std::stod(cell));
            if (comma == std::string::npos) break;
            at = comma + 1;
        }
        REQUIRE(v.size() == cols.size());
        rows[int(std::lround(v[0] * 10))] = v;
    }
    view::Recording rec;
    std::string err;
    REQUIRE(view::load_recording(rec_path, rec, err));
    CHECK(rec.duration == doctest::Approx(60).epsilon(1e-6));
    Served s(view::make_replay_player(std::move(rec), true, 1));
    view::Frame f = sized_frame(g);
    Page page(s.port, &f);
    json scene;
    REQUIRE(page.wait_json("scene", scene));
    CHECK(scene["mode"] == "replay");
    std::map<std::string, size_t> col_of;
    for (size_t c = 0; c < cols.size(); ++c) col_of[cols[c]] = c;
    for (int tenth : {100, 333, 600}) {  // 10 s, 33.3 s, 60 s: on the frame grid of 1/30 s
        page.send(json{{"type", "seek"}, {"time", tenth / 10.0}}.dump());
        // The frame at that time, and the plots' history rebuilt from the recording: every
        // 0.2 s from 0 s to there, no gap for a line to cross.
        json h;
        bool at = false, history = false;
        REQUIRE(page.wait([&](const std::string& msg, bool binary) {
            if (binary) at = at || std::abs(f.time - tenth / 10.0) < 1e-6;
            else if (json j = json::parse(msg, nullptr, false); j.is_object() && j.value("type", "") == "history") {
                h = j;
                history = !j["time"].empty() && j["time"].back().get<double>() >= tenth / 10.0 - 0.25;
            }
            return at && history;
        }, 10));
        REQUIRE(f.time == doctest::Approx(tenth / 10.0));
        CHECK(h["time"][0] == 0.0);
        CHECK(h["time"].back().get<double>() <= tenth / 10.0 + 1e-9);
        CHECK(h["time"].size() >= size_t(tenth / 2) - 2);  // a sample every 0.2 s
        for (size_t i = 1; i < h["time"].size(); ++i)
            CHECK(h["time"][i].get<double>() - h["time"][i - 1].get<double>() < 0.21);
        const auto& row = rows.at(tenth);
        int compared = 0;
        for (size_t b = 0; b < g.bodies.size(); ++b) {
            const std::string base = g.comp_path(g.bodies[plant::graph::BodyId(b)].comp);
            if (g.bodies[plant::graph::BodyId(b)].mode != graph::BodyMode::Dynamic) continue;
            // Parked in the replay exactly when the trace has empty cells.
            CHECK(bool(f.body_state[b] & 1) == !std::isnan(row[col_of.at(base + ".x")]));
            if (!(f.body_state[b] & 1)) continue;
            // The trace has the centre of mass: the frame's body pose, moved by the body's com offset.
            const float* p = &f.body_pose[7 * b];
            const double x = p[3], y = p[4], z = p[5], w = p[6];
            const graph::Vec3 c = g.bodies[plant::graph::BodyId(b)].com.p;
            const double tx = 2 * (y * c[2] - z * c[1]), ty = 2 * (z * c[0] - x * c[2]), tz = 2 * (x * c[1] - y * c[0]);
            const double com[3] = {p[0] + c[0] + w * tx + (y * tz - z * ty), p[1] + c[1] + w * ty + (z * tx - x * tz),
                                   p[2] + c[2] + w * tz + (x * ty - y * tx)};
            for (int k = 0; k < 3; ++k)
                CHECK(std::abs(com[k] - row[col_of.at(base + "." + std::string(1, "xyz"[k]))]) < 1e-4);
            ++compared;
        }
        CHECK(compared > 3);
    }
}

// The plant's own scheduled faults (a `faults` component) apply in a live session as in
// `plant run`: the paused frame is the headless run's with engine::plant_events, not the
// one without them; and they are not logged as a client's events.
TEST_CASE("serve: a plant's scheduled faults apply as plant run applies them") {
    const graph::Graph g = compile_ok("plants/bottling_faults.plant");
    Served s(view::make_live_player(g, {}, {}, false, 0));  // as fast as possible
    view::Frame f = sized_frame(g);
    Page page(s.port, &f);
    json scene;
    REQUIRE(page.wait_json("scene", scene));
    // Past 45 s: S2's reader has been cut since 20 s, and bottles for lane B passed it.
    for (int i = 0; i < 100000 && f.step < 45 * 150; ++i) REQUIRE(page.wait_frame());
    const int64_t paused_at = pause(page, f);
    std::string events;
    REQUIRE(http_get(s.port, "/events", &events) == 200);
    CHECK(events.find("force") == std::string::npos);
    // The same steps headless, with and without the plant's events.
    auto differing = [&](std::vector<engine::Event> evs) {
        engine::Engine e(g);
        replay(e, evs, paused_at);
        int differ = 0;
        for (size_t b = 0; b < g.bodies.size(); ++b) {
            if (g.bodies[plant::graph::BodyId(b)].mode == graph::BodyMode::Static) continue;
            const graph::Pose p = e.body_pose(plant::graph::BodyId(int32_t(b)));
            for (int k = 0; k < 3; ++k) differ += float(p.p[size_t(k)]) != f.body_pose[7 * b + size_t(k)] ? 1 : 0;
        }
        return differ;
    };
    const std::vector<engine::Event> planned = engine::plant_events(g);
    REQUIRE(planned.size() == 2);
    CHECK(differing(planned) == 0);
    CHECK(differing({}) > 0);
}
