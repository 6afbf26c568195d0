// The messages a page sends to `plant serve` (docs/viewer.md), decoded without trusting
// them: anything malformed is an error string for that client, never an exception.
#pragma once

#include <string>
#include <string_view>

namespace plant::view {

struct ClientMessage {
    enum class Kind { Hello, Control, Event, Inspect, Seek, Drill, DrillCancel };
    Kind kind = Kind::Hello;
    int fps = 30;              // hello
    std::string action;        // control: pause, run, step, restart, speed
    double speed = 1;          // control speed: 0 (as fast as possible), 0.1 .. 100
    std::string path;          // event: the input's dotted path; inspect: an object ("" the plant);
                               // drill: its line (faults/drill.h)
    bool stop_inspect = false; // inspect with a null path
    std::string value;         // event: the value as in an events file ("" for none)
    double time = 0;           // seek
    int drill = 0;             // drill cancel: the drill's number (1-based, as the status lists it)
};

// At most this many bytes in one message (a longer one is refused before it is parsed).
constexpr size_t kMaxClientMessage = 16 * 1024;

bool decode_client_message(std::string_view text, ClientMessage& m, std::string& error);

}  // namespace plant::view
