// Helpers of the plant serve tests: a page over loopback (a WebSocket client whose reads
// time out), a server on a free port, bounded waits, raw HTTP. Every wait is bounded.
#pragma once

#include "paths.h"
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "engine/run.h"
#include "engine/events.h"
#include "serve/player.h"
#include "serve/protocol.h"
#include "serve/record.h"
#include "serve/server.h"

#include <utility>  // before Boost 1.74's asio (std::exchange)

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

using namespace plant;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using json = nlohmann::json;

namespace {

[[maybe_unused]] graph::Graph compile_ok(const std::string& repo_path, std::vector<std::string> overrides = {}) {
    Compilation c;
    CompileOptions opts;
    opts.stdlib_dir = PLANT_STDLIB_DIR;
    opts.overrides = std::move(overrides);
    compile_file(std::string(PLANT_SOURCE_DIR) + "/" + repo_path, opts, c);
    REQUIRE(c.ok());
    return std::move(c.graph);
}

// A page, as far as the protocol goes: a WebSocket client whose reads time out.
struct Page {
    net::io_context ioc;
    websocket::stream<beast::tcp_stream> ws{ioc};
    bool open = false;
    view::Frame* frame = nullptr;  // every binary frame read is applied to it

    // `target`: the WebSocket's path and query (`/ws?role=trainee`, `/ws?token=...`).
    explicit Page(uint16_t port, view::Frame* f = nullptr, const std::string& target = "/ws") : frame(f) {
        beast::get_lowest_layer(ws).connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
        ws.handshake("127.0.0.1", target);
        open = true;
    }
    void send(const std::string& text) {
        ws.text(true);
        ws.write(net::buffer(text));
    }
    // The next message within `seconds`; false on a time-out or a closed socket.
    bool read(std::string& msg, bool& binary, double seconds = 10) {
        if (!open) return false;
        beast::flat_buffer buf;
        bool done = false;
        beast::error_code ec;
        ws.async_read(buf, [&](beast::error_code e, size_t) {
            ec = e;
            done = true;
        });
        ioc.restart();
        ioc.run_for(std::chrono::milliseconds(int64_t(seconds * 1000)));
        if (!done) {
            beast::get_lowest_layer(ws).cancel();
            ioc.restart();
            ioc.run_for(std::chrono::seconds(1));
            open = false;
            return false;
        }
        if (ec) {
            open = false;
            return false;
        }
        msg = beast::buffers_to_string(buf.data());
        binary = ws.got_binary();
        bool full = false;
        if (binary && frame && !view::decode_frame(msg, *frame, full)) return false;
        return true;
    }
    // Reads until `done(message, binary)` holds, within `seconds`.
    template <class Done>
    bool wait(Done&& done, double seconds) {
        const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        std::string msg;
        bool binary = false;
        while (std::chrono::steady_clock::now() < end) {
            const double left = std::chrono::duration<double>(end - std::chrono::steady_clock::now()).count();
            if (!read(msg, binary, std::max(0.05, left))) return false;
            if (done(msg, binary)) return true;
        }
        return false;
    }
    // Reads until a JSON message of `type` arrives (skipping others).
    bool wait_json(const std::string& type, json& out, double seconds = 10) {
        return wait([&](const std::string& msg, bool binary) {
            if (binary) return false;
            out = json::parse(msg, nullptr, false);
            return out.is_object() && out.value("type", "") == type;
        }, seconds);
    }
    // Reads until a binary frame arrives (applied to `frame`).
    bool wait_frame(double seconds = 10) {
        return wait([](const std::string&, bool binary) { return binary; }, seconds);
    }
};

// Whether `holds()` comes true within `seconds`, asked every 50 ms: for what the server's
// thread does in its own time.
template <class Holds>
bool eventually(double seconds, Holds&& holds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (!holds()) {
        if (std::chrono::steady_clock::now() >= end) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return true;
}

view::Frame sized_frame(const graph::Graph& g) { return view::Frame::sized(g.bodies.size(), g.graphics.size()); }

// A raw HTTP GET; the status code (0 when there was no answer).
int http_get(uint16_t port, const std::string& target, std::string* body = nullptr) {
    net::io_context ioc;
    beast::tcp_stream stream(ioc);
    stream.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
    http::request<http::empty_body> req{http::verb::get, target, 11};
    req.set(http::field::host, "127.0.0.1");
    http::write(stream, req);
    beast::flat_buffer buf;
    http::response<http::string_body> res;
    beast::error_code ec;
    http::read(stream, buf, res, ec);
    if (ec) return 0;
    if (body) *body = res.body();
    return int(res.result_int());
}

// Pauses the session: the status says at which step, then a frame of that step (in `f`).
[[maybe_unused]] int64_t pause(Page& page, view::Frame& f) {
    page.send(R"({"type":"control","action":"pause"})");
    json st;
    for (int i = 0; i < 100; ++i) {
        REQUIRE(page.wait_json("status", st));
        if (st["paused"] == true) break;
    }
    REQUIRE(st["paused"] == true);
    const int64_t paused_at = st["step"].get<int64_t>();
    for (int i = 0; i < 100 && f.step != paused_at; ++i) REQUIRE(page.wait_frame());
    REQUIRE(f.step == paused_at);
    return paused_at;
}

// `evs` applied headless as `plant run` applies them, to step `until`.
[[maybe_unused]] void replay(engine::Engine& e, const std::vector<engine::Event>& evs, int64_t until) {
    size_t next = 0;
    while (e.steps() < until) {
        for (; next < evs.size() && engine::due(e, evs[next]); ++next) engine::apply_event(e, evs[next]);
        e.step();
    }
}

struct Served {
    std::unique_ptr<view::Player> player;
    std::unique_ptr<view::Server> server;
    uint16_t port = 0;
    // `edit` changes the server's options (a token, TLS) before it starts.
    template <class Edit = void (*)(view::ServerOptions&)>
    Served(std::unique_ptr<view::Player> p, Edit edit = [](view::ServerOptions&) {}) : player(std::move(p)) {
        view::ServerOptions so;
        so.port = 0;
        so.viewer_dir = std::string(PLANT_SOURCE_DIR) + "/viewer";
        edit(so);
        server = std::make_unique<view::Server>(*player, so);
        std::string error;
        REQUIRE(server->start(error));
        port = server->port();
        player->start();
    }
    ~Served() {
        server->stop();
        player->stop();
    }
};

}  // namespace
