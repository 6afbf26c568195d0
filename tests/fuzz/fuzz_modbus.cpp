// Target `modbus`: a byte stream from a Modbus TCP client to the PLC link (docs/plc.md):
// framed by its MBAP headers and answered by the link's protocol core (plc/frames.h) with
// libmodbus, in-process, over a socketpair, against a map with every table and encoding.
// Invariant: no crash, no sanitizer report (each frame is handed over in a buffer of its
// exact length); every frame gets exactly one answer: its transaction id, its function
// code (or the same with the exception bit); a write's changes name mapped entries.
#include "fuzz.h"
#include "plc/frames.h"

#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <vector>

namespace {

struct Link {
    plant::plc::Tables tables{map()};
    modbus_t* ctx = modbus_new_tcp("127.0.0.1", 502);
    int fd[2] = {-1, -1};
    Link() {
        if (socketpair(AF_UNIX, SOCK_STREAM, 0, fd) != 0 || !ctx) plant::fuzz::broken("no socketpair");
        fcntl(fd[0], F_SETFL, O_NONBLOCK);
        fcntl(fd[1], F_SETFL, O_NONBLOCK);
        modbus_set_socket(ctx, fd[0]);
    }
    static plant::plc::Map map() {
        using plant::graph::Dir;
        using plant::graph::SlotType;
        using plant::plc::Encoding;
        using plant::plc::Table;
        plant::plc::Map m;
        auto add = [&](Table t, int32_t a, SlotType type, Dir d, Encoding e, int32_t length = 1) {
            plant::plc::Entry x;
            x.table = t;
            x.address = a;
            x.path = "p";
            x.slots = {plant::graph::SlotId(0)};
            x.type = type;
            x.dir = d;
            x.encoding = e;
            x.scale = 10;
            x.length = length;
            m.entries.push_back(x);
        };
        add(Table::Coil, 0, SlotType::Void, Dir::In, Encoding::Bit);
        add(Table::Coil, 1, SlotType::Bool, Dir::In, Encoding::Bit);
        add(Table::DiscreteInput, 0, SlotType::Bool, Dir::Out, Encoding::Bit);
        add(Table::InputRegister, 0, SlotType::Int, Dir::Out, Encoding::Int32);
        add(Table::InputRegister, 2, SlotType::String, Dir::Out, Encoding::String, 4);
        add(Table::HoldingRegister, 0, SlotType::Real, Dir::In, Encoding::Scaled);
        add(Table::HoldingRegister, 1, SlotType::Real, Dir::In, Encoding::Float32);
        add(Table::HoldingRegister, 3, SlotType::Bool, Dir::In, Encoding::Bit);
        return m;
    }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static Link link;
    std::vector<plant::plc::Change> changes;
    size_t at = 0;
    for (int frames = 0; frames < 64; ++frames) {
        const int len = plant::plc::frame_length(data + at, size - at);
        if (len <= 0) break;
        const std::vector<uint8_t> frame(data + at, data + at + len);
        changes.clear();
        if (!link.tables.handle(link.ctx, frame.data(), len, changes)) plant::fuzz::broken("an answer was not sent");
        uint8_t rsp[2 * MODBUS_TCP_MAX_ADU_LENGTH];
        const ssize_t n = read(link.fd[1], rsp, sizeof rsp);
        if (n <= 0 || plant::plc::frame_length(rsp, size_t(n)) != n) plant::fuzz::broken("not exactly one answer");
        if (rsp[0] != frame[0] || rsp[1] != frame[1]) plant::fuzz::broken("an answer with another transaction id");
        if ((rsp[7] & 0x7f) != (frame[7] & 0x7f)) plant::fuzz::broken("an answer to another function");
        for (const plant::plc::Change& c : changes)
            if (c.kind != plant::plc::Change::Advance &&
                (c.entry < 0 || size_t(c.entry) >= link.tables.map().entries.size()))
                plant::fuzz::broken("a change to no entry");
        at += size_t(len);
    }
    return 0;
}
