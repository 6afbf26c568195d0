// The local channel between the plant and its OPC UA server (opcua/server.mjs, a child
// process; docs/plc.md, "OPC UA"): frames over two pipes, `[u32 length][u8 type][payload]`,
// little-endian, the length counting the type byte and the payload.
//
// Plant to server:
//   'C' the configuration (JSON: endpoint, security, the node map), once, first
//   'S' steps: records, in step order --
//       'T' f64 steps, f64 simulated time      a step's header; its records follow
//       'V' u32 node, f64 value                a variable's value, a counter's count
//       'X' u32 node, u32 length, bytes        a string variable's value
//       'E' u32 node, f64 count                a counter after an activation: its count and one event
//       'Q' u32 node, u8 force mode            the node's slot forced (0 none, 1 stuck, 2 open, 3 invert)
//       'D' u32 steps                          steps lost since the last record (the server fell
//                                              behind): a step with every node's value follows
//   'K' u32 request, u32 status, f64 steps     the answer to a request (an OPC UA StatusCode)
// Server to plant:
//   'R' ready (JSON: the endpoint URLs it listens on), or 'E' text: it could not start
//   'W' u32 request, u32 node, f64 value       a write to a Boolean, Int32 or Double node
//   'Y' u32 request, u32 node, u32 length, bytes   ... to a String node
//   'M' u32 request, u32 node                  a method call: fire the void input
//   'F' u32 request, u32 node, u8 mode, f64 value, u32 length, bytes   force (mode 0: release)
//   'A' u32 request, u32 steps                 lock-step: run N more steps; answered once they ran
#pragma once

#include "engine/fd_io.h"

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace plant::opcua {

// OPC UA StatusCodes the plant answers with (Part 6, A.2).
namespace status {
constexpr uint32_t Good = 0;
constexpr uint32_t BadTooManyOperations = 0x80100000;
constexpr uint32_t BadShutdown = 0x800c0000;
constexpr uint32_t BadNodeIdUnknown = 0x80340000;
constexpr uint32_t BadNotWritable = 0x803b0000;
constexpr uint32_t BadOutOfRange = 0x803c0000;
constexpr uint32_t BadTypeMismatch = 0x80740000;
constexpr uint32_t BadInvalidArgument = 0x80ab0000;
constexpr uint32_t BadInvalidState = 0x80af0000;
constexpr uint32_t BadDataEncodingInvalid = 0x80380000;
}  // namespace status

constexpr size_t kFrameHeader = 5;             // length and type
constexpr uint32_t kMaxFrame = 64u << 20;      // a longer frame is a broken channel
constexpr size_t kMaxText = 1024;              // longer strings are cut (docs/plc.md)

// Appends to a buffer with a fixed capacity: no allocation once it is sized.
class Writer {
public:
    Writer(uint8_t* data, size_t capacity) : data_(data), cap_(capacity) {}
    bool put_u8(uint8_t v) { return put(&v, 1); }
    bool put_u32(uint32_t v) {
        uint8_t b[4] = {uint8_t(v), uint8_t(v >> 8), uint8_t(v >> 16), uint8_t(v >> 24)};
        return put(b, 4);
    }
    bool put_f64(double v) {
        uint64_t u;
        std::memcpy(&u, &v, 8);
        return put_u32(uint32_t(u)) && put_u32(uint32_t(u >> 32));
    }
    bool put_text(std::string_view s) {
        const size_t n = s.size() < kMaxText ? s.size() : kMaxText;
        return put_u32(uint32_t(n)) && put(s.data(), n);
    }
    bool put(const void* p, size_t n) {
        if (size_ + n > cap_) return ok_ = false;
        if (n > 0) std::memcpy(data_ + size_, p, n);  // an empty text's data() may be null
        size_ += n;
        return true;
    }
    size_t size() const { return size_; }
    bool ok() const { return ok_; }

private:
    uint8_t* data_;
    size_t cap_, size_ = 0;
    bool ok_ = true;
};

// Reads a frame's payload; every read past its end fails and leaves `ok()` false.
class Reader {
public:
    Reader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
    uint8_t u8() { return ok(1) ? data_[at_++] : 0; }
    uint32_t u32() {
        if (!ok(4)) return 0;
        const uint8_t* b = data_ + at_;
        at_ += 4;
        return uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
    }
    double f64() {
        const uint64_t lo = u32(), hi = u32();
        const uint64_t u = lo | hi << 32;
        double v;
        std::memcpy(&v, &u, 8);
        return v;
    }
    std::string_view text() {
        const uint32_t n = u32();
        if (!ok(n)) return {};
        const std::string_view s(reinterpret_cast<const char*>(data_ + at_), n);
        at_ += n;
        return s;
    }
    bool good() const { return good_; }
    bool done() const { return at_ == size_; }

private:
    bool ok(size_t n) {
        if (good_ && at_ + n <= size_) return true;
        good_ = false;
        return false;
    }
    const uint8_t* data_;
    size_t size_, at_ = 0;
    bool good_ = true;
};

// One whole frame (header and payload) of `type`.
std::vector<uint8_t> frame(char type, std::string_view payload);
// Writes all of `n` bytes to a blocking fd; false when it is closed (engine/fd_io.h).
using engine::write_all;
// Reads one frame from a blocking fd: its type and payload; false at the end of the stream
// or for a frame longer than kMaxFrame (`error` says which).
bool read_frame(int fd, char& type, std::vector<uint8_t>& payload, std::string& error);

}  // namespace plant::opcua
