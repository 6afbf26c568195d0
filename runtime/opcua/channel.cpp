#include "opcua/channel.h"

#include "engine/fd_io.h"

namespace plant::opcua {

std::vector<uint8_t> frame(char type, std::string_view payload) {
    std::vector<uint8_t> out(kFrameHeader + payload.size());
    Writer w(out.data(), out.size());
    w.put_u32(uint32_t(payload.size() + 1));
    w.put_u8(uint8_t(type));
    w.put(payload.data(), payload.size());
    return out;
}

bool read_frame(int fd, char& type, std::vector<uint8_t>& payload, std::string& error) {
    uint8_t head[kFrameHeader];
    if (!engine::read_all(fd, head, kFrameHeader)) {
        error = "the channel closed";
        return false;
    }
    Reader r(head, kFrameHeader);
    const uint32_t length = r.u32();
    type = char(r.u8());
    if (length < 1 || length > kMaxFrame) {
        error = "a frame of " + std::to_string(length) + " bytes on the channel";
        return false;
    }
    payload.resize(length - 1);
    if (!engine::read_all(fd, payload.data(), payload.size())) {
        error = "the channel closed in a frame";
        return false;
    }
    return true;
}

}  // namespace plant::opcua
