// plant serve's roles (docs/viewer.md, "Roles"): the instructor's token, trainees that may
// operate only what the plant lists as operable and never see a force, wrong tokens refused,
// logged and throttled while the run goes on, --no-roles refused off loopback, and TLS.
// Every connection is to loopback; every loop is bounded.
#include "serve_helpers.h"

#include "serve/report.h"

#include "faults/operable.h"
#include "serve/roles.h"
#include "serve/serve.h"

#include <boost/asio/ssl.hpp>
#include <boost/beast/ssl.hpp>

#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace {

constexpr const char* kToken = "0123456789abcdef0123456789abcdef";

// A clock the trainee may stop and start, a second it may not touch, a fault the plant file
// schedules on that second one, and a body for the hand.
constexpr const char* kRoom = R"(
plant Room {
    timer clock: periodic { period = 100 ms; autostart = true }
    timer other: periodic { period = 1 s; autostart = true }
    physics crate: dynamic at (0 m, 0 m, 5 cm) { mass = 1 kg; shape box(10 cm, 10 cm, 10 cm) }
    physics floor: static { shape box(2 m, 2 m, 2 cm) at (0 m, 0 m, -1 cm) }
    operable desk {
        input 1 => clock.start
        input 0 => clock.stop(label = "stop the clock")
    }
    faults drill {
        open 0.1 s => other.tick
    }
    panel ops {
        button go { label = "Go" }
        lamp shown { label = "Shown" }
    }
}
)";

graph::Graph room() {
    Compilation c;
    test::compile_text(kRoom, c, "room.plant");
    REQUIRE_MESSAGE(c.ok(), render_all_text(c.sink.sorted(), c.sources));
    return std::move(c.graph);
}

// stderr, captured while alive (the server logs refusals there).
struct CaptureErr {
    std::ostringstream text;
    std::streambuf* old = std::cerr.rdbuf(text.rdbuf());
    ~CaptureErr() { std::cerr.rdbuf(old); }
};

std::string error_for(Page& page, const std::string& msg) {
    page.send(msg);
    json e;
    REQUIRE(page.wait_json("error", e));
    return e["message"].get<std::string>();
}

}  // namespace

TEST_CASE("roles: the token is 128 random bits, compared whole, and the query's values are read") {
    std::string error;
    const std::string a = view::make_token(error), b = view::make_token(error);
    CHECK(a.size() == 32);
    CHECK(a.find_first_not_of("0123456789abcdef") == std::string::npos);
    CHECK(a != b);
    CHECK(view::same_token(a, a));
    CHECK_FALSE(view::same_token(b, a));
    CHECK_FALSE(view::same_token(a.substr(0, 31), a));
    CHECK_FALSE(view::same_token("", ""));  // no secret: nothing matches
    bool present = false;
    CHECK(view::query_value("/ws?role=trainee&token=ab", "token", present) == "ab");
    CHECK(present);
    CHECK(view::query_value("/ws?role=trainee&token=ab", "role", present) == "trainee");
    view::query_value("/ws?tokens=1", "token", present);
    CHECK_FALSE(present);
    view::query_value("/ws", "token", present);
    CHECK_FALSE(present);
}

TEST_CASE("roles: an address that keeps giving wrong tokens is locked out, longer each time") {
    using namespace std::chrono_literals;
    view::TokenGate gate(10s);
    const auto t0 = view::TokenGate::Clock::now();
    view::TokenGate::Clock::duration wait{};
    for (int i = 1; i < view::TokenGate::kMaxFailures; ++i) CHECK_FALSE(gate.failed("10.0.0.1", t0));
    CHECK(gate.may_try("10.0.0.1", t0, wait));
    CHECK(gate.failed("10.0.0.1", t0));  // the fifth: locked out
    CHECK_FALSE(gate.may_try("10.0.0.1", t0 + 9s, wait));
    CHECK(wait == 1s);
    CHECK(gate.may_try("10.0.0.2", t0, wait));  // another address is not
    CHECK(gate.may_try("10.0.0.1", t0 + 10s, wait));
    for (int i = 0; i < view::TokenGate::kMaxFailures; ++i) gate.failed("10.0.0.1", t0 + 10s);
    CHECK_FALSE(gate.may_try("10.0.0.1", t0 + 29s, wait));  // twice as long the second time
    CHECK(gate.may_try("10.0.0.1", t0 + 30s, wait));
    gate.succeeded("10.0.0.1");
    CHECK(gate.failures("10.0.0.1") == 0);
}

TEST_CASE("roles: the plant's operable inputs, in their keys' order, with their labels") {
    const graph::Graph g = room();
    const auto ins = faults::operable_inputs(g);
    REQUIRE(ins.size() == 2);  // the panel's inputs are not listed: the server adds them
    CHECK(g.slot_path(ins[0].slots[0]) == "clock.stop");
    CHECK(ins[0].label == "stop the clock");
    CHECK(g.slot_path(ins[1].slots[0]) == "clock.start");
    CHECK(ins[1].label.empty());
}

TEST_CASE("roles: a trainee's force, fire on an unmarked input and wrong token are refused and logged") {
    const graph::Graph g = room();
    CaptureErr err;
    Served s(view::make_live_player(g, {}, {}, false, 1), [](view::ServerOptions& o) { o.token = kToken; });
    Page trainee(s.port, nullptr, "/ws?role=trainee");
    json welcome;
    REQUIRE(trainee.wait_json("welcome", welcome));
    CHECK(welcome["role"] == "trainee");
    REQUIRE(welcome["operable"].size() == 5);  // the two listed, then the button's press, release, hold
    CHECK(welcome["operable"][2]["panel"] == true);
    CHECK(welcome["operable"][0]["path"] == "clock.stop");
    CHECK(welcome["operable"][0]["label"] == "stop the clock");

    const std::string force = error_for(trainee, R"({"type":"force","path":"other.tick","mode":"open"})");
    CHECK(force.find("refused: a trainee may not force") != std::string::npos);
    // The same force dressed as an event is parsed first, and refused alike.
    CHECK(error_for(trainee, R"({"type":"event","path":"force","value":"other.tick open"})").find("may not force") !=
          std::string::npos);
    const std::string fire = error_for(trainee, R"({"type":"event","path":"other.stop"})");
    CHECK(fire.find("'other.stop' is not an input a trainee may operate") != std::string::npos);
    CHECK(error_for(trainee, R"({"type":"control","action":"pause"})").find("instructor runs") != std::string::npos);
    // A panel's lamp is the plant's to light, not the operator's.
    CHECK(error_for(trainee, R"({"type":"event","path":"ops.shown.on"})").find("is not an input a trainee may") !=
          std::string::npos);
    // What a trainee may do goes through: the operable input, the hand.
    trainee.send(R"({"type":"event","path":"clock.stop"})");
    json ev;
    REQUIRE(trainee.wait_json("event", ev));
    CHECK(ev["line"].get<std::string>().find("clock.stop") != std::string::npos);
    trainee.send(R"({"type":"event","path":"ops.go.press"})");  // a panel's button: an operator's
    REQUIRE(trainee.wait([&](const std::string& m, bool bin) {
        const json j = bin ? json::object() : json::parse(m, nullptr, false);
        if (j.value("type", "") == "error") FAIL("the button was refused: " << m);
        return j.value("type", "") == "event" && j["line"].get<std::string>().find("ops.go.press") != std::string::npos;
    }, 10));
    trainee.send(R"({"type":"hand","action":"grab","path":"crate","point":[0,0,0.1]})");
    REQUIRE(trainee.wait([&](const std::string& m, bool bin) {
        if (bin) return false;
        const json j = json::parse(m, nullptr, false);
        if (j.value("type", "") == "error") FAIL("the hand was refused: " << m);
        return j.value("type", "") == "event" && j["line"].get<std::string>().find("grab crate") != std::string::npos;
    }, 10));

    // A forged token: told so, and closed.
    Page forged(s.port, nullptr, "/ws?token=00000000000000000000000000000000");
    json e;
    REQUIRE(forged.wait_json("error", e));
    CHECK(e["message"].get<std::string>().find("wrong token") != std::string::npos);
    std::string msg;
    bool binary = false;
    CHECK_FALSE(forged.read(msg, binary, 5));
    CHECK(s.server->stats().bad_tokens == 1);
    CHECK(s.server->stats().trainee_refused == 5);
    // The instructor's token: the instructor's page, which may force.
    Page instructor(s.port, nullptr, std::string("/ws?token=") + kToken);
    REQUIRE(instructor.wait_json("welcome", welcome));
    CHECK(welcome["role"] == "instructor");
    instructor.send(R"({"type":"force","path":"other.stop","mode":"open"})");
    CHECK(instructor.wait([&](const std::string& m, bool bin) {
        const json j = bin ? json::object() : json::parse(m, nullptr, false);
        return j.is_object() && j.value("type", "") == "event" &&
               j["line"].get<std::string>().find("force other.stop open") != std::string::npos;
    }, 10));
    // The log names the role and the client's address.
    const std::string log = err.text.str();
    CHECK(log.find("(trainee at 127.0.0.1:") != std::string::npos);
    CHECK(log.find("refused: a trainee may not force") != std::string::npos);
    CHECK(log.find("is not an input a trainee may operate") != std::string::npos);
    CHECK(log.find("127.0.0.1:") != std::string::npos);
    CHECK(log.find(": refused: wrong token") != std::string::npos);
    // The events file is the instructor's.
    CHECK(http_get(s.port, "/events?role=trainee") == 403);
    CHECK(http_get(s.port, "/events?token=nope") == 403);
    std::string events;
    REQUIRE(http_get(s.port, std::string("/events?token=") + kToken, &events) == 200);
    CHECK(events.find("force other.stop open") != std::string::npos);
    // Each line after who sent it, in what role, when; the file ends where the session stands:
    // the session report (serve/report.h) replays it and tells the instructor from the trainee.
    CHECK(events.find(" (instructor) at 20") != std::string::npos);  // # by page 4 (instructor) at 2026-...
    CHECK(events.find(" (trainee) at 20") != std::string::npos);
    CHECK(events.find("\n# end ") != std::string::npos);
    const auto file = test::scratch_dir() / "roles_session.events";
    std::ofstream(file, std::ios::binary) << events;
    view::Session session;
    std::string error;
    REQUIRE_MESSAGE(view::replay_session(g, "room.plant", file.string(), 0, session, error), error);
    bool trainee_grab = false, instructor_force = false;
    for (const view::SessionEvent& ev : session.events) {
        trainee_grab |= ev.role == "trainee" && ev.line.find("grab crate") != std::string::npos;
        instructor_force |= ev.role == "instructor" && ev.line.find("force other.stop open") != std::string::npos;
        if (!ev.planned) CHECK(ev.wall.size() == 24);  // 2026-11-27T14:03:05.120Z
    }
    CHECK(trainee_grab);
    CHECK(instructor_force);
    bool forced = false;  // the instructor's fault, beside the plant file's own
    for (const view::SessionFault& f : session.faults) forced |= f.path == "other.stop" && f.set_by.starts_with("page ");
    CHECK(forced);
}

TEST_CASE("roles: a trainee's page is sent no force: not in the status, the inspector or the event log") {
    const graph::Graph g = room();
    Served s(view::make_live_player(g, {}, {}, false, 1), [](view::ServerOptions& o) { o.token = kToken; });
    Page instructor(s.port), trainee(s.port, nullptr, "/ws?role=trainee");
    json m;
    REQUIRE(instructor.wait_json("welcome", m));
    CHECK(m["role"] == "instructor");  // loopback, no token: the instructor (one user, this machine)
    REQUIRE(trainee.wait_json("welcome", m));
    REQUIRE(m["role"] == "trainee");
    instructor.send(R"({"type":"force","path":"clock.stop","mode":"open"})");
    instructor.send(R"({"type":"event","path":"other.stop"})");
    instructor.send(R"({"type":"inspect","path":""})");
    trainee.send(R"({"type":"inspect","path":""})");
    // The instructor sees the plan's fault and its own force; the trainee sees neither, but
    // sees the ordinary event.
    int forced_seen = 0;
    REQUIRE(instructor.wait([&](const std::string& msg, bool bin) {
        const json j = bin ? json::object() : json::parse(msg, nullptr, false);
        if (j.value("type", "") == "status" && j.contains("inspect"))
            for (const auto& sl : j["inspect"]["slots"])
                if (sl["path"] == "clock.stop" && sl["forced"] == "open") forced_seen |= 1;
        if (j.value("type", "") == "status" && j.contains("forced") && j["forced"].size() == 2) forced_seen |= 2;
        return forced_seen == 3;
    }, 20));
    bool other_stop = false;
    int statuses = 0;
    REQUIRE(trainee.wait([&](const std::string& msg, bool bin) {
        if (bin) return false;
        const json j = json::parse(msg, nullptr, false);
        const std::string type = j.value("type", "");
        if (type == "event") {
            const std::string line = j["line"].get<std::string>();
            CHECK_MESSAGE(line.find("force") == std::string::npos, line);
            CHECK_MESSAGE(line.find("release") == std::string::npos, line);
            CHECK_FALSE(j.contains("planned"));
            if (line.find("other.stop") != std::string::npos) other_stop = true;
        }
        if (type == "status") {
            CHECK_FALSE(j.contains("forced"));
            if (j.contains("inspect")) {
                ++statuses;
                for (const auto& sl : j["inspect"]["slots"]) CHECK(sl["forced"].is_null());
            }
        }
        return other_stop && statuses >= 5;
    }, 20));
}

TEST_CASE("roles: 1,000 wrong tokens are throttled and logged sparingly, the run goes on") {
    const graph::Graph g = room();
    CaptureErr err;
    Served s(view::make_live_player(g, {}, {}, false, 1), [](view::ServerOptions& o) { o.token = kToken; });
    view::Frame f = sized_frame(g);
    Page watcher(s.port, &f, "/ws?role=trainee");
    REQUIRE(watcher.wait_frame());
    const double t0 = f.time;
    int wrong = 0, locked = 0;
    for (int i = 0; i < 1000; ++i) {
        Page guess(s.port, nullptr, "/ws?token=" + std::string(32, char('a' + i % 6)));
        json e;
        REQUIRE(guess.wait_json("error", e, 5));
        const std::string m = e["message"].get<std::string>();
        wrong += m.starts_with("wrong token");
        locked += m.starts_with("too many wrong tokens from 127.0.0.1");
    }
    // Five compared, then the address is locked out (30 s): not one more is compared.
    CHECK(wrong == view::TokenGate::kMaxFailures);
    CHECK(locked == 1000 - view::TokenGate::kMaxFailures);
    CHECK(s.server->stats().bad_tokens == 1000);
    // Even the right token is refused while the address is locked out.
    {
        Page right(s.port, nullptr, std::string("/ws?token=") + kToken);
        json e;
        REQUIRE(right.wait_json("error", e, 5));
        CHECK(e["message"].get<std::string>().find("too many wrong tokens") != std::string::npos);
    }
    // The run went on meanwhile: the trainee's page still gets frames of a later time.
    for (int i = 0; i < 200 && f.time <= t0 + 0.2; ++i) REQUIRE(watcher.wait_frame());
    CHECK(f.time > t0 + 0.2);
    // The log says so, without a line per guess.
    const std::string log = err.text.str();
    CHECK(log.find("too many wrong tokens from 127.0.0.1") != std::string::npos);
    size_t lines = 0;
    for (char c : log) lines += c == '\n';
    CHECK(lines < 30);
}

TEST_CASE("roles: after the lockout the right token is the instructor's again") {
    const graph::Graph g = room();
    CaptureErr err;
    Served s(view::make_live_player(g, {}, {}, false, 1), [](view::ServerOptions& o) {
        o.token = kToken;
        o.lockout = std::chrono::milliseconds(1000);
    });
    auto first = [&](const std::string& target) {
        Page p(s.port, nullptr, target);
        json m;
        REQUIRE(p.wait([&](const std::string& msg, bool) {
            m = json::parse(msg, nullptr, false);
            return m.is_object() && (m["type"] == "welcome" || m["type"] == "error");
        }, 5));
        return m;
    };
    for (int i = 0; i < view::TokenGate::kMaxFailures; ++i) CHECK(first("/ws?token=nope")["type"] == "error");
    CHECK(first(std::string("/ws?token=") + kToken)["type"] == "error");  // locked out
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    const json m = first(std::string("/ws?token=") + kToken);
    CHECK(m["type"] == "welcome");
    CHECK(m["role"] == "instructor");
}

TEST_CASE("roles: --open asks no token: every page is the instructor's unless it asks to be a trainee") {
    const graph::Graph g = room();
    Served s(view::make_live_player(g, {}, {}, false, 1), [](view::ServerOptions& o) { o.open = true; });
    Page any(s.port, nullptr, "/ws?token=whatever"), trainee(s.port, nullptr, "/ws?role=trainee");
    json m;
    REQUIRE(any.wait_json("welcome", m));
    CHECK(m["role"] == "instructor");
    REQUIRE(trainee.wait_json("welcome", m));
    CHECK(m["role"] == "trainee");
    CHECK(s.server->stats().bad_tokens == 0);
}

TEST_CASE("roles: --no-roles on an address other than loopback is refused before listening") {
    const graph::Graph g = room();
    for (const char* host : {"0.0.0.0", "192.0.2.7", "::"}) {
        std::ostringstream out, err;
        view::ServeOptions o;  // plant serve --host HOST --no-roles --port 0 (app/serve.cpp)
        o.server.host = host;
        o.server.port = 0;
        o.no_roles = true;
        CHECK(view::serve_main(&g, "room.plant", o, out, err) == 2);
        CHECK(err.str().find("--no-roles on " + std::string(host) + " would give everyone") != std::string::npos);
        CHECK(out.str().find("http") == std::string::npos);  // nothing served
    }
    std::ostringstream out, err;
    view::ServeOptions o;
    o.server.tls_cert = "c.pem";
    CHECK(view::serve_main(&g, "room.plant", o, out, err) == 2);
    CHECK(err.str().find("--tls-cert needs --tls-key too") != std::string::npos);
    CHECK(view::loopback_host("127.0.0.1"));
    CHECK(view::loopback_host("::1"));
    CHECK_FALSE(view::loopback_host("0.0.0.0"));
    CHECK_FALSE(view::loopback_host("10.1.2.3"));
}

TEST_CASE("roles: with a certificate the page is served over https and the pages over wss") {
    namespace ssl = net::ssl;
    const auto dir = test::scratch_dir() / "tls";
    std::filesystem::create_directories(dir);
    const std::string cert = (dir / "cert.pem").string(), key = (dir / "key.pem").string();
    const std::string cmd = "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=127.0.0.1 -keyout '" + key +
                            "' -out '" + cert + "' >/dev/null 2>&1";
    REQUIRE(std::system(cmd.c_str()) == 0);
    const graph::Graph g = room();
    Served s(view::make_live_player(g, {}, {}, false, 1), [&](view::ServerOptions& o) {
        o.token = kToken;
        o.tls_cert = cert;
        o.tls_key = key;
    });
    net::io_context ioc;
    ssl::context ctx(ssl::context::tls_client);
    ctx.load_verify_file(cert);  // the self-signed certificate is the one trusted
    ctx.set_verify_mode(ssl::verify_peer);
    {
        beast::ssl_stream<beast::tcp_stream> stream(ioc, ctx);
        beast::get_lowest_layer(stream).expires_after(std::chrono::seconds(10));
        beast::get_lowest_layer(stream).connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), s.port));
        stream.handshake(ssl::stream_base::client);
        http::request<http::empty_body> req{http::verb::get, "/", 11};
        req.set(http::field::host, "127.0.0.1");
        http::write(stream, req);
        beast::flat_buffer buf;
        http::response<http::string_body> res;
        http::read(stream, buf, res);
        CHECK(res.result_int() == 200);
        CHECK(res.body().find("<html") != std::string::npos);
    }
    {
        websocket::stream<beast::ssl_stream<beast::tcp_stream>> ws(ioc, ctx);
        beast::get_lowest_layer(ws).expires_after(std::chrono::seconds(10));
        beast::get_lowest_layer(ws).connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), s.port));
        ws.next_layer().handshake(ssl::stream_base::client);
        ws.handshake("127.0.0.1", std::string("/ws?token=") + kToken);
        beast::flat_buffer buf;
        ws.read(buf);
        const json welcome = json::parse(beast::buffers_to_string(buf.data()), nullptr, false);
        CHECK(welcome["type"] == "welcome");
        CHECK(welcome["role"] == "instructor");
    }
    // Plain HTTP to the TLS port gets no page.
    CHECK(http_get(s.port, "/") == 0);
}

TEST_CASE("roles: drills are the instructor's, a hidden drill's force reaches no trainee, a shown one does") {
    const graph::Graph g = room();
    CaptureErr err;
    Served s(view::make_live_player(g, {}, {}, false, 1), [](view::ServerOptions& o) { o.token = kToken; });
    Page instructor(s.port, nullptr, std::string("/ws?token=") + kToken), trainee(s.port, nullptr, "/ws?role=trainee");
    json m;
    REQUIRE(instructor.wait_json("welcome", m));
    REQUIRE(trainee.wait_json("welcome", m));
    CHECK(error_for(trainee, R"({"type":"drill","line":"now force other.stop open"})").find("refused: drills are the "
                                                                                          "instructor's") !=
          std::string::npos);
    CHECK(error_for(instructor, R"({"type":"drill","line":"when clock.tock >= 3 force other.stop open"})")
              .find("drill: no slot 'clock.tock' in the plant (did you mean 'clock.tick'?)") != std::string::npos);
    instructor.send(R"({"type":"drill","line":"when clock.tick >= 3 force other.stop open"})");
    instructor.send(R"({"type":"drill","line":"shown when clock.tick >= 4 force other.start open"})");
    // The instructor sees both fire, in the log and in the status's drills.
    bool hidden_fired = false, shown_fired = false, holding = false;
    REQUIRE(instructor.wait([&](const std::string& msg, bool bin) {
        const json j = bin ? json::object() : json::parse(msg, nullptr, false);
        if (j.value("type", "") == "event" && j.value("by", "") == "drill 1")
            hidden_fired |= j["line"].get<std::string>().find("force other.stop open") != std::string::npos;
        if (j.value("type", "") == "event" && j.value("by", "") == "drill 2")
            shown_fired |= j["line"].get<std::string>().find("force other.start open") != std::string::npos;
        if (j.value("type", "") == "status" && j.contains("drills") && j["drills"].size() == 2)
            holding = j["drills"][0]["state"] == "holding" && j["drills"][1]["state"] == "holding" &&
                      j["drills"][0]["shown"] == false && j["drills"][1]["shown"] == true;
        return hidden_fired && shown_fired && holding;
    }, 20));
    // The trainee: the shown one (its event, its force in the status), never the hidden one,
    // and no drills.
    bool saw_shown = false, status_shown = false;
    REQUIRE(trainee.wait([&](const std::string& msg, bool bin) {
        if (bin) return false;
        const json j = json::parse(msg, nullptr, false);
        if (j.value("type", "") == "event") {
            const std::string line = j["line"].get<std::string>();
            CHECK_MESSAGE(line.find("other.stop") == std::string::npos, line);
            saw_shown |= line.find("force other.start open") != std::string::npos;
        }
        if (j.value("type", "") == "status") {
            CHECK_FALSE(j.contains("drills"));
            if (j.contains("forced")) {
                CHECK(j["forced"].size() == 1);
                status_shown = j["forced"][0]["path"] == "other.start";
            }
        }
        return saw_shown && status_shown;
    }, 20));
    // The session's events file has each as the timed event it became, after who fired it.
    std::string events;
    REQUIRE(http_get(s.port, std::string("/events?token=") + kToken, &events) == 200);
    CHECK(events.find("# by drill 1 (instructor) at 20") != std::string::npos);
    // Each drill as scheduled, before anything it fired: the report names the fault's drill.
    CHECK(events.find("# drill 1 by page 1 (instructor): when clock.tick >= 3 force other.stop open\n") <
          events.find("# by drill 1 (instructor)"));
    CHECK(events.find("s force other.stop open\n") != std::string::npos);
    CHECK(events.find("\nwhen") == std::string::npos);  // only the comment says the condition
    // The report: the instructor's only; a trainee's ask is refused and logged.
    CHECK(http_get(s.port, "/report.md?role=trainee") == 403);
    CHECK(http_get(s.port, "/report?role=trainee") == 403);
    CHECK(err.text.str().find("(trainee): refused: the session report is the instructor's") != std::string::npos);
    std::string md;
    REQUIRE(http_get(s.port, std::string("/report.md?token=") + kToken, &md) == 200);
    CHECK(md.find("### 2. `other.stop` open") != std::string::npos);  // after the plant file's own fault
    CHECK(md.find("by drill 1") != std::string::npos);
    CHECK(md.find("| drill | 1 by page 1 (instructor): when clock.tick >= 3 force other.stop open |") != std::string::npos);
}

TEST_CASE("roles: the instructor cancels a waiting drill, which never fires, and a trainee's cancel is refused and logged") {
    const graph::Graph g = room();
    CaptureErr err;
    // Paused, so the drills are scheduled and the first cancelled before any step; then as
    // fast as it goes.
    Served s(view::make_live_player(g, {}, {}, true, 0), [](view::ServerOptions& o) { o.token = kToken; });
    Page instructor(s.port, nullptr, std::string("/ws?token=") + kToken), trainee(s.port, nullptr, "/ws?role=trainee");
    json m;
    REQUIRE(instructor.wait_json("welcome", m));
    REQUIRE(trainee.wait_json("welcome", m));
    instructor.send(R"({"type":"drill","line":"1s force other.stop open"})");
    instructor.send(R"({"type":"drill","line":"now force other.start open"})");
    CHECK(error_for(trainee, R"({"type":"drill","cancel":1})").find("refused: drills are the instructor's") !=
          std::string::npos);
    CHECK(err.text.str().find("(trainee at 127.0.0.1:") != std::string::npos);
    CHECK(err.text.str().find("refused: drills are the instructor's") != std::string::npos);
    CHECK(error_for(instructor, R"({"type":"drill","cancel":"one"})").find("\"cancel\" is a drill's number") !=
          std::string::npos);
    instructor.send(R"({"type":"drill","cancel":1})");
    instructor.send(R"({"type":"control","action":"run"})");
    // Drill 2 fires at the first step; cancelling it then is refused, in the instructor's log.
    bool cancelled = false, refused = false, past = false;
    REQUIRE(instructor.wait([&](const std::string& msg, bool bin) {
        const json j = bin ? json::object() : json::parse(msg, nullptr, false);
        if (j.value("type", "") == "drill" && j["id"] == 1) cancelled = j.value("state", "") == "cancelled";
        return j.value("type", "") == "status" && j.contains("drills") && j["drills"][1]["state"] == "holding";
    }, 20));
    instructor.send(R"({"type":"drill","cancel":2})");
    REQUIRE(instructor.wait([&](const std::string& msg, bool bin) {
        const json j = bin ? json::object() : json::parse(msg, nullptr, false);
        if (j.value("type", "") == "drill" && j["id"] == 1) cancelled = j.value("state", "") == "cancelled";
        if (j.value("type", "") == "drill" && j["id"] == 2)
            refused = j.value("refused", "").find("drill 2 has fired") != std::string::npos;
        if (j.value("type", "") == "event") CHECK(j.value("by", "") != "drill 1");
        if (j.value("type", "") == "status" && j.value("time", 0.0) > 2 && j.contains("drills")) {
            past = true;
            CHECK(j["drills"][0]["state"] == "cancelled");
            CHECK(j["drills"][0]["fired"] == -1);
        }
        return cancelled && refused && past;
    }, 20));
    // A trainee's page hears nothing of drills.
    REQUIRE(trainee.wait([&](const std::string& msg, bool bin) {
        const json j = bin ? json::object() : json::parse(msg, nullptr, false);
        CHECK(j.value("type", "") != "drill");
        return j.value("type", "") == "status" && j.value("time", 0.0) > 2;
    }, 20));
    // The events file: the cancellation is a comment (a replay skips it), drill 1 set nothing.
    std::string events;
    REQUIRE(http_get(s.port, std::string("/events?token=") + kToken, &events) == 200);
    CHECK(events.find("# drill 1 cancelled at 0.000s by page 1 (instructor) at 20") != std::string::npos);
    std::istringstream lines(events);
    for (std::string l; std::getline(lines, l);)
        if (!l.starts_with("#")) CHECK_MESSAGE(l.find("other.stop") == std::string::npos, l);
    CHECK(events.find("# drill 2 cancelled") == std::string::npos);
    // The report (a replay of that file) says what became of each drill.
    std::string md;
    REQUIRE(http_get(s.port, std::string("/report.md?token=") + kToken, &md) == 200);
    CHECK(md.find("## Drills") != std::string::npos);
    CHECK_MESSAGE(md.find("| 1. by page 1 (instructor): 1s force other.stop open | cancelled before it fired, at 0.000 s by "
                          "page 1 (instructor) at 20") != std::string::npos,
                  md);
    CHECK_MESSAGE(md.find("| 2. by page 1 (instructor): now force other.start open | set fault 1 at 0.007 s |") != std::string::npos, md);
}
