// The bottling plant compiled once, a register map over its slots built in code (until
// the link kind declares one in the plant), and a libmodbus client for the tests.
#pragma once

#include "../compiler/compile_helper.h"
#include "../../plc/bottling_map.h"
#include "engine/events.h"
#include "plc/map.h"

#include <doctest/doctest.h>
#include <modbus/modbus.h>

#include <string>

namespace plant::test {

inline const graph::Graph& bottling_graph() {
    static const Compilation c = [] {
        Compilation k;
        compile_repo_file("plants/bottling.plant", k);
        return k;
    }();
    REQUIRE(c.ok());
    return c.graph;
}

inline plc::Entry plc_entry(const engine::SlotIndex& index, plc::Table t, int32_t address, const std::string& path,
                            plc::Encoding enc, double scale = 1, const std::string& unit = "", int32_t length = 1) {
    plc::Entry e;
    std::string error;
    const bool ok = plc::make_entry(index, {t, address, path, enc, scale, unit, length}, e, error);
    INFO(error);
    REQUIRE(ok);
    return e;
}

inline plc::Map bottling_map(const graph::Graph& g) {
    plc::Map m;
    std::string error;
    const bool ok = bottling_map(g, m, error);
    INFO(error);
    REQUIRE(ok);
    return m;
}

// A libmodbus client connected to the server on `port` (closed at scope end).
struct PlcClient {
    modbus_t* ctx = nullptr;
    explicit PlcClient(int port) {
        ctx = modbus_new_tcp("127.0.0.1", port);
        REQUIRE(ctx);
        modbus_set_response_timeout(ctx, 2, 0);
        REQUIRE(modbus_connect(ctx) == 0);
    }
    ~PlcClient() {
        modbus_close(ctx);
        modbus_free(ctx);
    }
    PlcClient(const PlcClient&) = delete;
    PlcClient& operator=(const PlcClient&) = delete;
    uint16_t ir(int address) {
        uint16_t v = 0;
        REQUIRE(modbus_read_input_registers(ctx, address, 1, &v) == 1);
        return v;
    }
    uint32_t steps() {
        uint16_t v[2] = {};
        REQUIRE(modbus_read_input_registers(ctx, plc::kStatusSteps, 2, v) == 2);
        return (uint32_t(v[0]) << 16) | v[1];
    }
};

}  // namespace plant::test
