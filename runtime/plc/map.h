// The register map of a Modbus TCP link (docs/plc.md): which slot each coil, discrete
// input, input register and holding register stands for, and how its value is encoded.
// A plain value the link component is lowered to; the server (server.h) serves it.
//
// Coils and holding registers are written by the PLC and drive input slots; discrete
// inputs and input registers are read by the PLC and show output slots. Addresses are
// 0-based; each table is its own address space. Two-register values put the high word
// first; strings hold two ASCII bytes per register, high byte first, NUL padded.
#pragma once

#include "engine/events.h"
#include "graph/graph.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace plant::plc {

enum class Table : uint8_t { Coil, DiscreteInput, InputRegister, HoldingRegister };

enum class Encoding : uint8_t {
    Bit,      // bool, void: one coil or discrete input (or a register holding 0 / 1)
    Int16,    // int: one signed 16-bit register (saturated)
    Int32,    // int: two registers, signed, high word first
    Scaled,   // real: one signed 16-bit register holding round(value * scale) (saturated)
    Float32,  // real: an IEEE 754 float over two registers, high word first
    String,   // string: `length` registers, two ASCII bytes each, high byte first, NUL padded
    Count,    // void output: a 16-bit count of the steps it was active in (wraps at 65536)
};

struct Entry {
    Table table = Table::Coil;
    int32_t address = 0;           // 0-based, in its table
    std::string path;              // the slot's (or port's) dotted path
    std::vector<graph::SlotId> slots;    // what the path feeds (an input port: several) or shows
    graph::SlotType type = graph::SlotType::Bool;
    graph::Dir dir = graph::Dir::In;
    Encoding encoding = Encoding::Bit;
    double scale = 1;              // Scaled: register = round(value * scale)
    std::string unit;              // Scaled: the unit of the register's value, for the table
    int32_t length = 1;            // String: registers
};

struct Map {
    std::vector<Entry> entries;
    int port = 0;      // the port the link declares (0: none; --modbus-port or a free one)
    std::string host;  // the address it declares ("": --modbus-host or 127.0.0.1)
};

// Addresses an entry takes in its table (1, 2 or its string length).
int32_t width(const Entry& e);
bool is_bit_table(Table t);
// Coils and holding registers drive inputs; discrete inputs and input registers show outputs.
bool written_by_plc(Table t);
std::string_view table_name(Table t);
std::string_view encoding_name(Encoding e);

// The link's own registers (docs/plc.md, "The control block"), above every mapped address.
constexpr int32_t kControlBase = 60000;  // addresses from here on are not for entries
constexpr int32_t kAdvance = 60000;      // HR: write N to run N more steps (lock-step)
constexpr int32_t kStatusSteps = 60000;  // IR 60000-60001: steps run (uint32, high word first)
constexpr int32_t kStatusTimeMs = 60002; // IR 60002-60003: simulated time in ms (uint32)
constexpr int32_t kStatusLockstep = 60004;  // IR: 1 in lock-step
constexpr int32_t kStatusCount = 5;
constexpr int32_t kFaultBase = 60100;    // HR 60100 + 4*i: the fault registers of entry i
constexpr int32_t kFaultStride = 4;      // mode (0 release, 1 stuck, 2 open, 3 invert), value (float32), spare
constexpr int32_t kMaxEntries = (65536 - kFaultBase) / kFaultStride;

// A problem with a map: which entry (-1: the map as a whole) and what.
struct MapError {
    int32_t entry = -1;
    std::string message;
};
// Overlapping addresses, out of range (0..59999; the control block is above), a type or
// encoding that does not fit its table, a direction mismatch, a bad scale or length.
std::vector<MapError> check_map(const Map& map, const graph::Graph& g);

// An entry for the slot or port at `path` in `index` (engine::slot_index); false with
// `error` when there is none. Type and direction come from the graph.
struct EntrySpec {
    Table table = Table::Coil;
    int32_t address = 0;
    std::string path{};
    Encoding encoding = Encoding::Bit;
    double scale = 1;
    std::string unit{};
    int32_t length = 1;
};
bool make_entry(const engine::SlotIndex& index, const EntrySpec& spec, Entry& out, std::string& error);

enum class MapFormat : uint8_t { Markdown, Csv };
// The map as a table for people (Markdown) or for a PLC project's import (CSV), entries in
// table and address order, then the control block.
std::string format_map(const Map& map, const graph::Graph& g, MapFormat format = MapFormat::Markdown);

// The map of the plant's link component (kind.h; docs/plc.md, "Declaring the link in a
// plant"): empty for a plant without one. `links` (when given) gets how many it declares.
Map map_from_graph(const graph::Graph& g, int* links = nullptr);

}  // namespace plant::plc
