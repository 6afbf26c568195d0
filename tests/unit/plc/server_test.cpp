// The Modbus TCP server over the bottling plant, driven step by step from the test with
// a libmodbus client on loopback: exchange at step boundaries, exceptions for bad
// requests, faults from the link, and lock-step runs that replay bit for bit.
#include "engine/engine.h"
#include "plc/codec.h"
#include "plc/server.h"
#include "plc_fixture.h"

#include <doctest/doctest.h>

#include <cerrno>
#include <chrono>
#include <thread>
#include <vector>

using namespace plant;
using namespace plant::test;

namespace {

void steps(plc::Server& s, engine::Engine& e, int n) {
    for (int i = 0; i < n; ++i) {
        s.before_step(e);
        e.step();
        s.after_step(e);
    }
}

// The bottling plant, its server on bottling_map, a client connected.
struct Served {
    const graph::Graph& g = bottling_graph();
    engine::Engine e{g};
    plc::Server s{g, bottling_map(g)};
    bool started = start(s);
    PlcClient c{s.port()};
    static bool start(plc::Server& server) {
        std::string error;
        const bool ok = server.start(error);
        INFO(error);
        REQUIRE(ok);
        return ok;
    }
};

int32_t field_named(const graph::Graph& g, const std::string& path) {
    for (size_t f = 0; f < g.fields.size(); ++f)
        if (g.comp_path(g.fields[graph::FieldId(f)].comp) == path) return int32_t(f);
    return -1;
}

int32_t slot_of(const graph::Graph& g, const std::string& path) {
    for (plant::graph::SlotId s : plant::graph::ids_of(g.slots))
        if (g.slot_path(s) == path) return s.v;
    return -1;
}

}  // namespace

TEST_CASE("plc server: clients read outputs and drive inputs, exchanged only at step boundaries") {
    const graph::Graph& g = bottling_graph();
    engine::Engine e(g);
    plc::Server s(g, bottling_map(g));
    std::string error;
    REQUIRE(s.start(error));
    REQUIRE(s.port() > 0);
    PlcClient c(s.port());
    steps(s, e, 10);
    CHECK(c.steps() == 10);
    CHECK(c.ir(2) == 500);  // 0.5 m/s as mm/s
    uint16_t f[2];
    REQUIRE(modbus_read_input_registers(c.ctx, 3, 2, f) == 2);
    CHECK(plc::get_float(f) == doctest::Approx(0.5));

    REQUIRE(modbus_write_register(c.ctx, 0, 250) == 1);  // set_speed 0.25 m/s
    CHECK(c.ir(2) == 500);                                // nothing reaches the plant between steps
    steps(s, e, 1);
    CHECK(c.ir(2) == 250);
    REQUIRE(modbus_write_register(c.ctx, 0, 250) == 1);  // the same value again: not a new input
    steps(s, e, 1);
    CHECK(s.stats().applied == 1);

    const int32_t drive = field_named(g, "line[0].b1.drive");
    REQUIRE(drive >= 0);
    CHECK(e.field_on(plant::graph::FieldId(drive)));
    REQUIRE(modbus_write_bit(c.ctx, 0, 1) == 1);  // coil 0: b1.stop
    steps(s, e, 2);
    CHECK_FALSE(e.field_on(plant::graph::FieldId(drive)));
    REQUIRE(modbus_write_bit(c.ctx, 1, 1) == 1);  // coil 1: b1.go
    steps(s, e, 2);
    CHECK(e.field_on(plant::graph::FieldId(drive)));
    uint8_t coils[2] = {};
    REQUIRE(modbus_read_bits(c.ctx, 0, 2, coils) == 2);  // coils read back as written
    CHECK(coils[0] == 1);
    CHECK(coils[1] == 1);
    CHECK(s.stats().exceptions == 0);
}

TEST_CASE("plc server: requests outside the map or malformed get Modbus exceptions, and service goes on") {
    Served p;
    engine::Engine& e = p.e;
    plc::Server& s = p.s;
    PlcClient& c = p.c;
    steps(s, e, 3);
    uint16_t r[16];
    uint8_t b[16];
    CHECK(modbus_read_input_registers(c.ctx, 500, 1, r) == -1);
    CHECK(errno == EMBXILADD);
    CHECK(modbus_read_input_registers(c.ctx, 0, 11, r) == -1);  // 5..9 are not mapped
    CHECK(errno == EMBXILADD);
    CHECK(modbus_write_register(c.ctx, 5, 1) == -1);
    CHECK(errno == EMBXILADD);
    CHECK(modbus_write_bit(c.ctx, 7, 1) == -1);
    CHECK(errno == EMBXILADD);
    CHECK(modbus_read_input_bits(c.ctx, 65535, 2, b) == -1);  // past the end of the table
    CHECK(errno == EMBXILADD);
    // The fault block: mode 3 (invert) on a void slot, mode 9.
    CHECK(modbus_write_register(c.ctx, plc::kFaultBase, 3) == -1);
    CHECK(errno == EMBXILVAL);
    CHECK(modbus_write_register(c.ctx, plc::kFaultBase, 9) == -1);
    CHECK(errno == EMBXILVAL);
    // An unknown function code (0x41) and one libmodbus knows but the link does not serve
    // (0x11, report server id).
    for (uint8_t fc : {uint8_t(0x41), uint8_t(0x11)}) {
        const uint8_t raw[] = {0xff, fc};
        REQUIRE(modbus_send_raw_request(c.ctx, raw, 2) > 0);
        uint8_t rsp[MODBUS_TCP_MAX_ADU_LENGTH];
        CHECK(modbus_receive_confirmation(c.ctx, rsp) > 0);
        CHECK(rsp[7] == (fc | 0x80));
        CHECK(rsp[8] == MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
    }
    // A read with a byte too many (its length does not fit its function), a read of more
    // registers than a response holds (libmodbus's client refuses to send it).
    for (const std::vector<uint8_t>& raw : {std::vector<uint8_t>{0xff, 0x04, 0x00, 0x00, 0x00, 0x01, 0x00},
                                            std::vector<uint8_t>{0xff, 0x03, 0x00, 0x00, 0x00, 126}}) {
        REQUIRE(modbus_send_raw_request(c.ctx, raw.data(), int(raw.size())) > 0);
        uint8_t rsp[MODBUS_TCP_MAX_ADU_LENGTH];
        CHECK(modbus_receive_confirmation(c.ctx, rsp) > 0);
        CHECK(rsp[7] == (raw[1] | 0x80));
        CHECK(rsp[8] == MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
    }
    steps(s, e, 3);
    CHECK(c.steps() == 6);  // the same client is still served
    CHECK(s.stats().exceptions == 11);
    CHECK(s.stats().dropped == 0);
}

TEST_CASE("plc server: the fault block forces a mapped slot and releases it") {
    Served p;
    const graph::Graph& g = p.g;
    engine::Engine& e = p.e;
    plc::Server& s = p.s;
    PlcClient& c = p.c;
    steps(s, e, 2);
    uint8_t bit = 1;
    REQUIRE(modbus_read_input_bits(c.ctx, 0, 1, &bit) == 1);
    CHECK(bit == 0);  // no bottle at S2's reader yet
    // Entry 0 (the reader's on_stay) stuck on: mode 1, value 1.0 as a float.
    uint16_t regs[3] = {1, 0, 0};
    plc::put_float(1.0f, regs + 1);
    const int32_t on_stay = slot_of(g, "line[0].s2.sw.reader.volume.on_stay");
    REQUIRE(on_stay >= 0);
    REQUIRE(modbus_write_registers(c.ctx, plc::kFaultBase, 3, regs) == 3);
    s.before_step(e);  // the force, as the events file would say it (the run's summary lists it)
    REQUIRE(s.applied().size() == 1);
    // At the time of the step it feeds, the third (3 / 150 s), as a page's event: logged or
    // recorded, it replays there.
    CHECK(engine::format_event(g, *s.applied()[0]) == "0.020s force line[0].s2.sw.reader.volume.on_stay stuck on");
    e.step();
    s.after_step(e);
    steps(s, e, 1);
    CHECK(e.forced(plant::graph::SlotId(on_stay)) == engine::ForceMode::Stuck);
    REQUIRE(modbus_read_input_bits(c.ctx, 0, 1, &bit) == 1);
    CHECK(bit == 1);
    CHECK(c.ir(1) == 0);  // S2's `seen` (on_enter) is another slot: not forced
    REQUIRE(modbus_write_register(c.ctx, plc::kFaultBase, 0) == 1);  // release
    steps(s, e, 2);
    CHECK(e.forced(plant::graph::SlotId(on_stay)) == engine::ForceMode::None);
    REQUIRE(modbus_read_input_bits(c.ctx, 0, 1, &bit) == 1);
    CHECK(bit == 0);
}

namespace {

// One lock-step run: the plant steps only as the client grants; the client's fixed
// sequence of writes and grants; per step a fingerprint of every dynamic body's position.
std::vector<double> lockstep_run() {
    const graph::Graph& g = bottling_graph();
    engine::Engine e(g);
    plc::ServerOptions o;
    o.lockstep = true;
    o.lockstep_timeout = 10;
    plc::Server s(g, bottling_map(g), o);
    std::string error;
    REQUIRE(s.start(error));
    std::vector<double> trace;
    trace.reserve(2000);
    std::thread stepper([&] {
        std::string why;
        for (int i = 0; i < 2000 && s.wait_for_step(why); ++i) {
            s.before_step(e);
            e.step();
            s.after_step(e);
            double sum = e.field_speed(plant::graph::FieldId(0));
            for (size_t b = 0; b < g.bodies.size(); ++b)
                if (g.bodies[graph::BodyId(b)].mode == graph::BodyMode::Dynamic && e.body_in_world(plant::graph::BodyId(int32_t(b)))) {
                    const graph::Vec3 p = e.body_com(plant::graph::BodyId(int32_t(b)));
                    sum += p[0] + 2 * p[1] + 3 * p[2];
                }
            trace.push_back(sum);
        }
    });
    {
        PlcClient c(s.port());
        auto advance = [&](uint16_t n, uint32_t until) {
            REQUIRE(modbus_write_register(c.ctx, plc::kAdvance, n) == 1);
            for (int tries = 0; tries < 2000 && c.steps() < until; ++tries)
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
            REQUIRE(c.steps() == until);
            uint16_t left = 1;
            REQUIRE(modbus_read_registers(c.ctx, plc::kAdvance, 1, &left) == 1);
            CHECK(left == 0);
        };
        advance(300, 300);
        REQUIRE(modbus_write_register(c.ctx, 0, 300) == 1);
        advance(100, 400);
        REQUIRE(modbus_write_bit(c.ctx, 0, 1) == 1);
        advance(150, 550);
        REQUIRE(modbus_write_bit(c.ctx, 1, 1) == 1);
        advance(150, 700);
    }
    s.stop();
    stepper.join();
    return trace;
}

}  // namespace

TEST_CASE("plc server: lock-step: the same client sequence gives the same trace twice") {
    const std::vector<double> a = lockstep_run();
    const std::vector<double> b = lockstep_run();
    REQUIRE(a.size() == 700);
    CHECK(a == b);
}

TEST_CASE("plc server: lock-step without a client fails after its timeout with a clear error") {
    const graph::Graph& g = bottling_graph();
    plc::ServerOptions o;
    o.lockstep = true;
    o.lockstep_timeout = 0.2;
    plc::Server s(g, bottling_map(g), o);
    std::string error;
    REQUIRE(s.start(error));
    const auto t0 = std::chrono::steady_clock::now();
    CHECK_FALSE(s.wait_for_step(error));
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >= 0.19);
    CHECK(error.find("lock-step: no client advanced the plant for 0.2 s (write N to holding register 60000") == 0);
}

TEST_CASE("plc server: a bad host or a port in use is refused with a message") {
    const graph::Graph& g = bottling_graph();
    plc::ServerOptions o;
    o.host = "localhost:1";
    plc::Server bad(g, {}, o);
    std::string error;
    CHECK_FALSE(bad.start(error));
    CHECK(error == "modbus host 'localhost:1' is not an IPv4 address (e.g. 127.0.0.1)");
    plc::Server first(g, {});
    REQUIRE(first.start(error));
    o.host = "127.0.0.1";
    o.port = first.port();
    plc::Server second(g, {}, o);
    CHECK_FALSE(second.start(error));
    CHECK(error.find("cannot listen on 127.0.0.1:") == 0 + std::string("modbus: ").size());
}

TEST_CASE("plc server: a written value beyond the physics' range is rejected like one that is not finite") {
    const graph::Graph& g = bottling_graph();
    engine::Engine e(g);
    plc::Map m = bottling_map(g);  // and the belt's speed as a float32 in HR 20-21
    m.entries.push_back(plc_entry(engine::slot_index(g), plc::Table::HoldingRegister, 20, "line[0].b1.set_speed",
                                  plc::Encoding::Float32));
    REQUIRE(plc::check_map(m, g).empty());
    plc::Server s(g, m);
    std::string error;
    REQUIRE(s.start(error));
    PlcClient c(s.port());
    steps(s, e, 2);
    uint16_t regs[2];
    plc::put_float(1e30f, regs);  // finite, but a belt at 1e30 m/s is past graph/range.h's 100 km/s
    REQUIRE(modbus_write_registers(c.ctx, 20, 2, regs) == 2);
    steps(s, e, 2);
    CHECK(s.stats().rejected == 1);
    CHECK(s.stats().applied == 0);
    CHECK(c.ir(2) == 500);  // still 0.5 m/s
    plc::put_float(2.0f, regs);
    REQUIRE(modbus_write_registers(c.ctx, 20, 2, regs) == 2);
    steps(s, e, 2);
    CHECK(s.stats().rejected == 1);
    CHECK(s.stats().applied == 1);
    CHECK(c.ir(2) == 2000);
}

TEST_CASE("plc server: a written string that is not UTF-8 is rejected, a UTF-8 one applied") {
    const graph::Graph& g = bottling_graph();
    engine::Engine e(g);
    plc::Map m = bottling_map(g);  // and S1's route query as a 4-register string at HR 30
    m.entries.push_back(plc_entry(engine::slot_index(g), plc::Table::HoldingRegister, 30, "line[0].s1.route.query",
                                  plc::Encoding::String, 1, "", 4));
    REQUIRE(plc::check_map(m, g).empty());
    plc::Server s(g, m);
    std::string error;
    REQUIRE(s.start(error));
    PlcClient c(s.port());
    steps(s, e, 2);
    const uint16_t latin1[4] = {uint16_t('A' << 8 | '-'), uint16_t(0xE4 << 8 | 0), 0, 0};  // "A-ä" in Latin-1
    REQUIRE(modbus_write_registers(c.ctx, 30, 4, latin1) == 4);
    steps(s, e, 2);
    CHECK(s.stats().rejected == 1);
    CHECK(s.stats().applied == 0);
    const uint16_t utf8[4] = {uint16_t('A' << 8 | '-'), uint16_t(0xC3 << 8 | 0xA4), 0, 0};  // "A-ä" in UTF-8
    REQUIRE(modbus_write_registers(c.ctx, 30, 4, utf8) == 4);
    steps(s, e, 2);
    CHECK(s.stats().rejected == 1);
    CHECK(s.stats().applied == 1);
}
