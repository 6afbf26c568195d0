// The plant's end of the OPC UA link (opcua/bridge.h) against a server played by the test
// over a socket pair: requests reach the plant only at step boundaries and are answered with
// OPC UA status codes; every step's changes go out; lock-step; a server a buffer behind, a
// server gone, a run restarted. No node-opcua here (robustness_test.cpp has the real one).
#include "../compiler/compile_helper.h"
#include "engine/engine.h"
#include "opcua/bridge.h"
#include "opcua/channel.h"
#include "opcua/kind.h"

#include <doctest/doctest.h>

#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <thread>

using namespace plant;
using opcua::Reader;
using opcua::Writer;
namespace ua_status = opcua::status;

namespace {

// Node indices (the declaration order below) of the bridge plant.
enum : uint32_t { kSetSpeed, kSpeedNow, kStop, kTick, kCode, kSetCode, kRunning };

const graph::Graph& bridge_graph() {
    static const Compilation c = [] {
        Compilation k;
        test::compile_text(R"(import std.belts
plant Bridged {
    b1: Belt(length = 1 m)
    timer t: periodic { period = 20 ms; autostart = true }
    label code { value = "F-0001" }
    opcua ua {
        node 1 => b1.set_speed(unit = "mm/s")
        node 2 => b1.speed_now
        node 3 => b1.stop
        node 4 => t.tick
        node 5 => code.value
        node 6 => code.set
        node 7 => t.running
    }
}
)", k, "bridged.plant");
        return k;
    }();
    for (const auto& d : c.sink.all()) INFO(d.message);
    REQUIRE(c.ok());
    return c.graph;
}

struct Record {
    char tag = 0;
    uint32_t node = 0;
    double value = 0;
    std::string text;
};

// The server's side: requests out, frames in.
struct FakeServer {
    int fd = -1;
    explicit FakeServer(int f) : fd(f) {}
    ~FakeServer() {
        if (fd >= 0) ::close(fd);
    }
    void send(char type, const std::vector<uint8_t>& payload) {
        const std::vector<uint8_t> f = opcua::frame(type, std::string_view(reinterpret_cast<const char*>(payload.data()), payload.size()));
        REQUIRE(opcua::write_all(fd, f.data(), f.size()));
    }
    static std::vector<uint8_t> body(std::initializer_list<uint32_t> u32, double f64 = 0, bool with_f64 = false) {
        std::vector<uint8_t> b(64);
        Writer w(b.data(), b.size());
        for (uint32_t v : u32) w.put_u32(v);
        if (with_f64) w.put_f64(f64);
        b.resize(w.size());
        return b;
    }
    void write(uint32_t id, uint32_t node, double v) { send('W', body({id, node}, v, true)); }
    void call(uint32_t id, uint32_t node) { send('M', body({id, node})); }
    void advance(uint32_t id, uint32_t steps) { send('A', body({id, steps})); }
    void force(uint32_t id, uint32_t node, uint8_t mode, double v = 0, std::string_view text = {}) {
        std::vector<uint8_t> b(64 + text.size());
        Writer w(b.data(), b.size());
        w.put_u32(id);
        w.put_u32(node);
        w.put_u8(mode);
        w.put_f64(v);
        w.put_text(text);
        b.resize(w.size());
        send('F', b);
    }
    void write_text(uint32_t id, uint32_t node, std::string_view text) {
        std::vector<uint8_t> b(64 + text.size());
        Writer w(b.data(), b.size());
        w.put_u32(id);
        w.put_u32(node);
        w.put_text(text);
        b.resize(w.size());
        send('Y', b);
    }
    // The next frame: its type, and its records ('S') or answer ('K': node = request, value = status).
    char next(std::vector<Record>& out, double& steps) {
        char type = 0;
        std::vector<uint8_t> payload;
        std::string error;
        REQUIRE(opcua::read_frame(fd, type, payload, error));
        Reader r(payload.data(), payload.size());
        out.clear();
        if (type == 'K') {
            Record k{'K', r.u32(), double(r.u32()), {}};
            steps = r.f64();
            out.push_back(k);
        }
        while (type == 'S' && !r.done()) {
            Record rec{char(r.u8()), 0, 0, {}};
            if (rec.tag == 'T') {
                rec.value = r.f64();
                r.f64();
            } else if (rec.tag == 'D') {
                rec.value = r.u32();
            } else {
                rec.node = r.u32();
                if (rec.tag == 'X') rec.text = std::string(r.text());
                else if (rec.tag == 'Q') rec.value = r.u8();
                else rec.value = r.f64();
            }
            REQUIRE(r.good());
            out.push_back(rec);
        }
        return type;
    }
    // The answer to request `id`, skipping step frames.
    uint32_t answer(uint32_t id, double* steps = nullptr) {
        for (int i = 0; i < 1000; ++i) {
            std::vector<Record> recs;
            double s = 0;
            if (next(recs, s) == 'K' && recs[0].node == id) {
                if (steps) *steps = s;
                return uint32_t(recs[0].value);
            }
        }
        FAIL("no answer to request " << id);
        return 0;
    }
    // Every record of the step frames until one holds `steps` steps.
    std::vector<Record> until_step(double steps) {
        std::vector<Record> all;
        for (int i = 0; i < 10000; ++i) {
            std::vector<Record> recs;
            double s = 0;
            if (next(recs, s) != 'S') continue;
            all.insert(all.end(), recs.begin(), recs.end());
            for (const Record& r : recs)
                if (r.tag == 'T' && r.value >= steps) return all;
        }
        FAIL("no step " << steps);
        return all;
    }
};

struct Linked {
    const graph::Graph& g = bridge_graph();
    engine::Engine e{g};
    std::unique_ptr<opcua::Bridge> bridge;
    std::unique_ptr<FakeServer> server;
    explicit Linked(opcua::BridgeOptions o = {}) {
        int sv[2];
        REQUIRE(socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) == 0);
        bridge = std::make_unique<opcua::Bridge>(g, opcua::links_from_graph(g).at(0), o);
        bridge->attach(sv[0]);
        server = std::make_unique<FakeServer>(sv[1]);
    }
    ~Linked() {
        ::shutdown(server->fd, SHUT_RDWR);
        bridge->finish(1);
        bridge->close();
    }
    void step() {
        bridge->before_step(e);
        e.step();
        bridge->after_step(e);
    }
    const Record* find(const std::vector<Record>& recs, char tag, uint32_t node) {
        for (const Record& r : recs)
            if (r.tag == tag && r.node == node) return &r;
        return nullptr;
    }
};

}  // namespace

TEST_CASE("opcua bridge: the configuration goes first, the server's ready answer ends the handshake") {
    Linked l;
    std::thread server([&] {
        char type = 0;
        std::vector<uint8_t> payload;
        std::string error;
        REQUIRE(opcua::read_frame(l.server->fd, type, payload, error));
        CHECK(type == 'C');
        CHECK(std::string(payload.begin(), payload.end()) == "{\"nodes\":[]}");
        l.server->send('R', {'{', '}'});
    });
    std::string ready, error;
    CHECK(l.bridge->handshake("{\"nodes\":[]}", 5, ready, error));
    CHECK(ready == "{}");
    server.join();
}

TEST_CASE("opcua bridge: a server that says why it cannot start fails the handshake with its words") {
    Linked l;
    std::thread server([&] {
        char type = 0;
        std::vector<uint8_t> payload;
        std::string error;
        REQUIRE(opcua::read_frame(l.server->fd, type, payload, error));
        const std::string why = "the OPC UA server cannot listen on 127.0.0.1:4840: the port is in use";
        l.server->send('E', std::vector<uint8_t>(why.begin(), why.end()));
    });
    std::string ready, error;
    CHECK_FALSE(l.bridge->handshake("{}", 5, ready, error));
    CHECK(error == "the OPC UA server cannot listen on 127.0.0.1:4840: the port is in use");
    server.join();
    std::string wait_error;
    CHECK_FALSE(l.bridge->wait(wait_error));  // the server has gone: the run ends with a reason
    CHECK(wait_error.find("went away") != std::string::npos);
}

TEST_CASE("opcua bridge: writes and calls reach the plant only at step boundaries, as events") {
    Linked l;
    l.step();
    std::vector<Record> first = l.server->until_step(1);
    CHECK(l.find(first, 'V', kSpeedNow));  // the first step carries every node's value
    CHECK(l.find(first, 'X', kCode)->text == "F-0001");
    CHECK(l.find(first, 'Q', kStop));      // ... and whether it is forced
    const double before = l.e.value(graph::SlotId(l.bridge->link().nodes[kSpeedNow].slots[0]))[0];

    l.server->write(1, kSetSpeed, 0.25);  // SI: the server converts mm/s
    CHECK(l.server->answer(1) == ua_status::Good);
    CHECK(l.e.value(graph::SlotId(l.bridge->link().nodes[kSpeedNow].slots[0]))[0] == before);  // not before a step
    l.server->call(2, kStop);
    l.server->call(3, kStop);
    CHECK(l.server->answer(2) == ua_status::Good);
    CHECK(l.server->answer(3) == ua_status::Good);
    l.server->write_text(4, kSetCode, "C-0042");
    CHECK(l.server->answer(4) == ua_status::Good);

    l.step();
    REQUIRE(l.bridge->applied().size() == 3);  // the speed, one call, the code: in node order
    CHECK(l.bridge->applied()[0]->path == "b1.set_speed");
    CHECK(l.bridge->applied()[1]->path == "b1.stop");
    CHECK(l.bridge->applied()[2]->text == "C-0042");
    std::vector<Record> second = l.server->until_step(2);
    // The band's speed now: 0, as b1.stop came in the same step; the target is the write's.
    REQUIRE(l.find(second, 'V', kSpeedNow));
    CHECK(l.find(second, 'V', kSpeedNow)->value == 0);
    CHECK(l.e.value(graph::SlotId(l.bridge->link().nodes[kSetSpeed].slots[0]))[0] == 0.25);
    CHECK(l.find(second, 'X', kCode)->text == "C-0042");
    CHECK_FALSE(l.find(second, 'V', kRunning));  // unchanged: not sent again
    l.step();
    REQUIRE(l.bridge->applied().size() == 1);  // the second call, a step later
    CHECK(l.bridge->applied()[0]->path == "b1.stop");
    l.step();
    CHECK(l.bridge->applied().empty());
    // A write of what the input already holds is no input (a PLC writes every scan).
    l.server->write(5, kSetSpeed, 0.25);
    CHECK(l.server->answer(5) == ua_status::Good);
    l.step();
    CHECK(l.bridge->applied().empty());
}

TEST_CASE("opcua bridge: each bad request gets its OPC UA status code and reaches nothing") {
    Linked l;
    l.server->write(1, kSpeedNow, 1);  // an output
    CHECK(l.server->answer(1) == ua_status::BadNotWritable);
    l.server->write(2, kSetSpeed, std::nan(""));
    CHECK(l.server->answer(2) == ua_status::BadOutOfRange);
    l.server->write(3, kSetSpeed, 1e9);  // beyond graph/range.h's 100 km/s
    CHECK(l.server->answer(3) == ua_status::BadOutOfRange);
    l.server->write(4, 99, 1);
    CHECK(l.server->answer(4) == ua_status::BadNodeIdUnknown);
    l.server->write_text(5, kSetSpeed, "fast");
    CHECK(l.server->answer(5) == ua_status::BadTypeMismatch);
    l.server->write(6, kSetCode, 1);
    CHECK(l.server->answer(6) == ua_status::BadTypeMismatch);
    std::vector<uint8_t> longer = FakeServer::body({7, kSetCode, uint32_t(opcua::kMaxText + 1)});
    longer.resize(longer.size() + opcua::kMaxText + 1, 'x');  // put_text would cut it
    l.server->send('Y', longer);
    CHECK(l.server->answer(7) == ua_status::BadOutOfRange);
    l.server->call(8, kSetSpeed);  // not a method
    CHECK(l.server->answer(8) == ua_status::BadInvalidArgument);
    l.server->advance(9, 5);  // not in lock-step
    CHECK(l.server->answer(9) == ua_status::BadInvalidState);
    l.server->force(10, kSpeedNow, uint8_t(engine::ForceMode::Invert));  // invert takes a bool
    CHECK(l.server->answer(10) == ua_status::BadInvalidArgument);
    l.server->force(11, kRunning, 9);
    CHECK(l.server->answer(11) == ua_status::BadInvalidArgument);
    l.server->force(12, kSetSpeed, uint8_t(engine::ForceMode::Stuck), 1e9);
    CHECK(l.server->answer(12) == ua_status::BadOutOfRange);
    l.server->send('M', FakeServer::body({13}));  // cut short: no node
    CHECK(l.server->answer(13) == ua_status::BadInvalidArgument);
    l.server->write_text(14, kSetCode, "A-\xff\xfe");  // not UTF-8 (graph/utf8.h), as the Modbus link refuses it
    CHECK(l.server->answer(14) == ua_status::BadDataEncodingInvalid);
    l.server->force(15, kSetCode, uint8_t(engine::ForceMode::Stuck), 0, "\xc0\xaf");  // an overlong '/'
    CHECK(l.server->answer(15) == ua_status::BadDataEncodingInvalid);
    l.step();
    CHECK(l.bridge->applied().empty());
    CHECK(l.bridge->stats().refused == 15);
}

TEST_CASE("opcua bridge: a counter and its events, forces and releases") {
    Linked l;
    l.server->force(1, kTick, uint8_t(engine::ForceMode::Open));
    CHECK(l.server->answer(1) == ua_status::Good);
    int ticks = 0;
    for (int i = 0; i < 12; ++i) l.step();  // 80 ms: the timer would have ticked four times
    for (const Record& r : l.server->until_step(12)) ticks += r.tag == 'E';
    CHECK(ticks == 0);
    CHECK(l.e.forced(graph::SlotId(l.bridge->link().nodes[kTick].slots[0])) == engine::ForceMode::Open);
    l.server->force(2, kTick, uint8_t(engine::ForceMode::None));
    CHECK(l.server->answer(2) == ua_status::Good);
    for (int i = 0; i < 12; ++i) l.step();
    std::vector<Record> after = l.server->until_step(24);
    REQUIRE(l.find(after, 'Q', kTick));
    CHECK(l.find(after, 'Q', kTick)->value == 0);  // released
    double last = 0;
    for (const Record& r : after)
        if (r.tag == 'E' && r.node == kTick) {
            CHECK(r.value == last + 1);  // the count, one up per active step
            last = r.value;
        }
    CHECK(last >= 3);
    l.server->force(3, kSetCode, uint8_t(engine::ForceMode::Stuck), 0, "X-9");
    CHECK(l.server->answer(3) == ua_status::Good);
    l.step();
    CHECK(l.bridge->applied().size() == 1);
    CHECK(l.bridge->applied()[0]->force);
}

TEST_CASE("opcua bridge: in lock-step the plant steps only as Advance grants, answered once the steps ran") {
    opcua::BridgeOptions o;
    o.lockstep = true;
    o.lockstep_timeout = 0.3;
    Linked l(o);
    std::string error;
    const auto t0 = std::chrono::steady_clock::now();
    CHECK_FALSE(l.bridge->wait(error));  // nobody granted
    CHECK(std::chrono::steady_clock::now() - t0 >= std::chrono::milliseconds(250));
    CHECK(error.find("no client advanced the plant for 0.3 s (call Link.Advance") != std::string::npos);
    l.server->advance(7, 3);
    l.server->advance(8, 0);  // nothing to run: answered at once
    double steps = -1;
    CHECK(l.server->answer(8, &steps) == ua_status::Good);
    CHECK(steps == 0);
    for (int i = 0; i < 3; ++i) {
        REQUIRE(l.bridge->wait(error));
        l.step();
    }
    CHECK(l.server->answer(7, &steps) == ua_status::Good);
    CHECK(steps == 3);
    CHECK_FALSE(l.bridge->wait(error));  // the grant is used up
}

TEST_CASE("opcua bridge: a server a buffer behind loses steps, never the plant's time, then gets every value") {
    opcua::BridgeOptions o;
    o.buffer = 1;  // one step's records at most
    Linked l(o);
    const int small = 4096;
    setsockopt(l.server->fd, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
    for (int i = 0; i < 2000; ++i) l.step();  // the server reads nothing meanwhile
    const opcua::BridgeStats s = l.bridge->stats();
    CHECK(s.dropped > 0);
    CHECK(s.steps + s.dropped == 2000);
    l.server->until_step(1);  // now it reads: the steps it got, then ...
    bool resync = false;
    for (int i = 0; i < 5000 && !resync; ++i) {
        l.step();  // each step sends a frame, or one is on its way: the read below always ends
        std::vector<Record> recs;
        double steps = 0;
        if (l.server->next(recs, steps) != 'S') continue;
        for (size_t k = 0; k < recs.size(); ++k)
            if (recs[k].tag == 'D') {  // ... the steps it missed, and a step with every value
                CHECK(recs[k].value >= 1);
                CHECK(l.find(recs, 'V', kSpeedNow));
                CHECK((l.find(recs, 'V', kTick) || l.find(recs, 'E', kTick)));  // a counter's count
                CHECK(l.find(recs, 'X', kCode));
                resync = true;
            }
    }
    CHECK(resync);
}

TEST_CASE("opcua bridge: a restarted run sends every value again, counts from zero") {
    Linked l;
    for (int i = 0; i < 10; ++i) l.step();
    l.server->until_step(10);
    engine::Engine fresh(l.g);  // plant serve's restart: a new engine
    l.bridge->before_step(fresh);
    fresh.step();
    l.bridge->after_step(fresh);
    const std::vector<Record> recs = l.server->until_step(1);
    CHECK(l.find(recs, 'V', kSpeedNow));
    CHECK(l.find(recs, 'X', kCode));
}

TEST_CASE("opcua bridge: the server gone ends the run with a reason") {
    Linked l;
    ::shutdown(l.server->fd, SHUT_RDWR);
    std::string error;
    bool waited = true;
    for (int i = 0; i < 200 && waited; ++i) {
        waited = l.bridge->wait(error);
        if (waited) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    CHECK_FALSE(waited);
    CHECK(error == "the OPC UA server went away (the channel closed)");
    l.step();  // a step after it is harmless
}
