// The Modbus TCP protocol core of the link, without sockets of its own: frames a byte
// stream by its MBAP headers, checks each request against the register map and answers it
// with libmodbus (modbus_reply / modbus_reply_exception on the client's socket), and says
// what a write changed. The server's network thread drives it; the fuzz target
// (tests/fuzz/fuzz_modbus.cpp) drives it in-process over a socketpair.
#pragma once

#include "plc/map.h"

#include <modbus/modbus.h>

#include <cstdint>
#include <vector>

namespace plant::plc {

// What a request changed, for the step thread.
struct Change {
    enum Kind : uint8_t { Value, Advance, Fault };
    Kind kind = Value;
    int32_t entry = -1;   // Value, Fault: the map entry
    uint16_t steps = 0;   // Advance: the steps granted
};

// The length of the frame at the start of `data` (MBAP header + PDU): 0 while incomplete,
// -1 for a header no Modbus TCP client sends (protocol id not 0, length outside 2..254):
// the stream cannot be framed any more.
int frame_length(const uint8_t* data, size_t size);

class Tables {
public:
    explicit Tables(const Map& map);
    ~Tables();
    Tables(const Tables&) = delete;
    Tables& operator=(const Tables&) = delete;

    // Answers one frame from frame_length on `ctx`'s socket: the reply, or an exception
    // (ILLEGAL FUNCTION, ILLEGAL DATA ADDRESS outside the map, ILLEGAL DATA VALUE for a bad
    // count, length or control value). Appends what a write changed to `changes`. False
    // when the answer could not be sent (drop the client).
    bool handle(modbus_t* ctx, const uint8_t* frame, int length, std::vector<Change>& changes);

    // The tables libmodbus serves (65536 addresses each).
    modbus_mapping_t& mapping() { return *m_; }
    const Map& map() const { return map_; }
    int64_t exceptions() const { return exceptions_; }

private:
    // Per table and address: the entry there, kControl for the link's own registers, -1.
    static constexpr int32_t kNone = -1, kControl = -2;
    int32_t at(Table t, int32_t address) const { return owner_[size_t(t)][size_t(address)]; }
    bool reply_exception(modbus_t* ctx, const uint8_t* frame, int code);
    // An exception code when [address, address + count) of `t` is not all readable / writable.
    int check_range(Table t, int32_t address, int32_t count) const;
    int check_control_writes(int32_t address, int32_t count, const uint8_t* values) const;
    void note_writes(Table t, int32_t address, int32_t count, std::vector<Change>& changes) const;

    Map map_;
    modbus_mapping_t* m_ = nullptr;
    std::vector<int32_t> owner_[4];
    int64_t exceptions_ = 0;
};

}  // namespace plant::plc
