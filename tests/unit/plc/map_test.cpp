// The register map: its checks (diagnostics as values, one per problem and entry), its
// table for people and PLC projects, and the register encodings.
#include "plc/codec.h"
#include "plc/map.h"
#include "plc_fixture.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace plant;
using namespace plant::test;
using plc::Encoding;
using plc::Table;

namespace {

// The messages check_map gives for entry `i`.
std::string errors_of(const std::vector<plc::MapError>& errors, int32_t i) {
    std::string all;
    for (const plc::MapError& e : errors)
        if (e.entry == i) all += e.message + "\n";
    return all;
}

}  // namespace

TEST_CASE("plc map: the test map over the bottling plant passes its checks") {
    const graph::Graph& g = bottling_graph();
    const plc::Map m = bottling_map(g);
    const auto errors = plc::check_map(m, g);
    for (const auto& e : errors) INFO(e.message);
    CHECK(errors.empty());
    // An input port feeds every slot it forwards to.
    CHECK(m.entries[6].slots.size() == 2);
}

TEST_CASE("plc map: overlaps, ranges, encodings and directions are reported per entry") {
    const graph::Graph& g = bottling_graph();
    const engine::SlotIndex idx = engine::slot_index(g);
    plc::Map m;
    m.entries = {
        plc_entry(idx, Table::InputRegister, 4, "line[0].b1.speed_now", Encoding::Float32),         // 0: 4-5
        plc_entry(idx, Table::InputRegister, 5, "line[0].s2.sw.reader.volume.count", Encoding::Int16),  // 1: overlaps 0
        plc_entry(idx, Table::Coil, 5, "line[0].b1.stop", Encoding::Bit),                           // 2: fine (own table)
        plc_entry(idx, Table::HoldingRegister, 59999, "line[0].b1.set_speed", Encoding::Float32),   // 3: into the control block
        plc_entry(idx, Table::Coil, 0, "line[0].b1.set_speed", Encoding::Bit),                      // 4: real as a bit
        plc_entry(idx, Table::Coil, 1, "line[0].s2.seen", Encoding::Bit),                           // 5: an output on a coil
        plc_entry(idx, Table::DiscreteInput, 0, "line[0].b1.stop", Encoding::Bit),                  // 6: an input on a DI
        plc_entry(idx, Table::InputRegister, 20, "line[0].b1.speed_now", Encoding::Scaled, 0),      // 7: scale 0
        plc_entry(idx, Table::HoldingRegister, 30, "line[0].s2.to_working", Encoding::Count),       // 8: count on an HR
        plc_entry(idx, Table::InputRegister, 40, "line[0].s2.id", Encoding::String, 1, "", 0),      // 9: no registers
        plc_entry(idx, Table::InputRegister, -1, "line[0].s2.working", Encoding::Int32),            // 10: negative
    };
    const auto errors = plc::check_map(m, g);
    CHECK(errors_of(errors, 0).empty());
    CHECK(errors_of(errors, 1).find("overlaps 'line[0].b1.speed_now' at 4") != std::string::npos);
    CHECK(errors_of(errors, 2).empty());
    CHECK(errors_of(errors, 3).find("out of range") != std::string::npos);
    CHECK(errors_of(errors, 4).find("cannot be encoded as bit") != std::string::npos);
    CHECK(errors_of(errors, 5).find("is an output: a coil is written by the PLC") != std::string::npos);
    CHECK(errors_of(errors, 6).find("is an input: a discrete input is read by the PLC") != std::string::npos);
    CHECK(errors_of(errors, 7).find("scale 0") != std::string::npos);
    CHECK(errors_of(errors, 8).find("input register") != std::string::npos);
    CHECK(errors_of(errors, 9).find("1 to 123 registers") != std::string::npos);
    CHECK(errors_of(errors, 10).find("out of range") != std::string::npos);
    CHECK(errors.size() == 9);
}

TEST_CASE("plc map: a misspelt path gets a suggestion") {
    const graph::Graph& g = bottling_graph();
    plc::Entry e;
    std::string error;
    CHECK_FALSE(plc::make_entry(engine::slot_index(g), {Table::Coil, 0, "line[0].b1.stp", Encoding::Bit}, e, error));
    CHECK(error == "no slot 'line[0].b1.stp'; did you mean 'line[0].b1.stop'?");
}

TEST_CASE("plc map: as a Markdown table and as CSV, in table and address order") {
    const graph::Graph& g = bottling_graph();
    const plc::Map m = bottling_map(g);
    const std::string md = plc::format_map(m, g);
    CHECK(md.find("| coil | 0 | `line[0].b1.stop` | in void | bit | 1 fires the input (once per write) |") != std::string::npos);
    CHECK(md.find("| input register | 3-4 | `line[0].b1.speed_now` | out real | float32 |") != std::string::npos);
    CHECK(md.find("| input register | 2 | `line[0].b1.speed_now` | out real | scaled | value x 1000 (mm/s) |") != std::string::npos);
    CHECK(md.find("coil | 0") < md.find("discrete input | 0"));
    CHECK(md.find("| holding register | 60100-60139 | (link) faults |") != std::string::npos);
    const std::string csv = plc::format_map(m, g, plc::MapFormat::Csv);
    CHECK(csv.rfind("table,address,path,slot,encoding,meaning\n", 0) == 0);
    CHECK(csv.find("input register,10-17,line[0].s2.id,out string,string,\"16 ASCII bytes, high byte first, NUL padded\"") !=
          std::string::npos);
}

TEST_CASE("plc map: the plant file declares no link yet, so its map is empty") {
    CHECK(plc::map_from_graph(bottling_graph()).entries.empty());
}

TEST_CASE("plc codec: registers hold values as docs/plc.md says") {
    plc::Entry e;
    uint16_t r[8] = {};
    const double minus_two[1] = {-2}, big[1] = {1e9}, speed[1] = {0.4567};
    e.type = graph::SlotType::Int;
    e.encoding = Encoding::Int16;
    plc::encode(e, minus_two, "", false, 0, r);
    CHECK(r[0] == 0xfffe);
    CHECK(plc::decode(e, r) == -2);
    plc::encode(e, big, "", false, 0, r);  // saturated
    CHECK(r[0] == 0x7fff);
    e.encoding = Encoding::Int32;
    plc::encode(e, big, "", false, 0, r);  // 1e9 = 0x3B9ACA00, high word first
    CHECK(r[0] == 0x3b9a);
    CHECK(r[1] == 0xca00);
    CHECK(plc::decode(e, r) == 1e9);
    e.type = graph::SlotType::Real;
    e.encoding = Encoding::Scaled;
    e.scale = 1000;
    plc::encode(e, speed, "", false, 0, r);
    CHECK(r[0] == 457);
    CHECK(plc::decode(e, r) == doctest::Approx(0.457));
    e.encoding = Encoding::Float32;
    plc::encode(e, speed, "", false, 0, r);
    CHECK(plc::decode(e, r) == doctest::Approx(0.4567).epsilon(1e-7));
    const double one[1] = {1};
    plc::encode(e, one, "", false, 0, r);  // 1.0f = 0x3F800000
    CHECK(r[0] == 0x3f80);
    CHECK(r[1] == 0);
    e.type = graph::SlotType::String;
    e.encoding = Encoding::String;
    e.length = 3;
    plc::encode(e, {}, "B-12x", false, 0, r);
    CHECK(r[0] == (('B' << 8) | '-'));
    CHECK(r[1] == (('1' << 8) | '2'));
    CHECK(r[2] == ('x' << 8));
    std::string text;
    plc::decode_text(e, r, text);
    CHECK(text == "B-12x");
    e.type = graph::SlotType::Void;
    e.encoding = Encoding::Count;
    plc::encode(e, {}, "", true, 65537, r);  // wraps
    CHECK(r[0] == 1);
    e.encoding = Encoding::Bit;
    plc::encode(e, {}, "", true, 0, r);
    CHECK(r[0] == 1);
    plc::encode(e, {}, "", false, 5, r);
    CHECK(r[0] == 0);
}
