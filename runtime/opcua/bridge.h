// The plant's end of the channel to its OPC UA server (channel.h; docs/plc.md, "OPC UA"):
// it exchanges with the plant only at step boundaries. The step thread calls, around each
// Engine::step():
//
//   bridge.before_step(engine);   // what clients wrote since: engine::apply_event, in order
//   engine.step();
//   bridge.after_step(engine);    // the step's changes, appended to the server's buffer
//
// and in lock-step first wait(). The step only copies into buffers sized once, under a
// mutex no thread holds for long: two threads of the bridge's own read the server's
// requests and write the buffered steps, so a slow server never slows the plant. When the
// server falls behind by a whole buffer, steps are dropped (counted) and the next one that
// fits carries every node's value.
#pragma once

#include "engine/engine.h"
#include "engine/events.h"
#include "graph/graph.h"
#include "opcua/nodes.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace plant::opcua {

struct BridgeOptions {
    bool lockstep = false;         // the plant steps only as clients call Link.Advance
    double lockstep_timeout = 30;  // s without a grant before wait() fails
    size_t buffer = 0;             // bytes of steps held for the server; 0: room for 8 full snapshots, >= 1 MiB
};

struct BridgeStats {
    int64_t requests = 0;  // requests from the server (writes, calls, forces, advances)
    int64_t refused = 0;   // ... answered with a Bad status (out of range, not writable, ...)
    int64_t applied = 0;   // events applied to the plant
    int64_t steps = 0;     // steps sent to the server
    int64_t dropped = 0;   // steps dropped because the server was a buffer behind
    int64_t bytes = 0;     // sent to the server
};

class Bridge {
public:
    // The link must have passed check_link for `g`.
    Bridge(const graph::Graph& g, Link link, BridgeOptions options = {});
    ~Bridge();  // closes the channel and joins its threads
    Bridge(const Bridge&) = delete;
    Bridge& operator=(const Bridge&) = delete;

    // Takes over `fd`, one end of a stream socket to the server, and starts the threads.
    void attach(int fd);
    // Sends the configuration (JSON) and waits up to `timeout` s for the server to be
    // ready: its answer (JSON), or false with `error` (what it said, or that it went away).
    bool handshake(const std::string& config, double timeout, std::string& ready, std::string& error);

    // Lock-step: returns once a client granted a step; false with `error` when none did
    // within lockstep_timeout or the server went away, false without one on SIGINT /
    // SIGTERM. Otherwise only false with `error` when the server went away.
    bool wait(std::string& error);
    void before_step(engine::Engine& e);
    std::span<const engine::Event* const> applied() const;  // by the last before_step
    void after_step(const engine::Engine& e);

    // Sends what is buffered, then tells the server the run is over (its end of the socket
    // reads end-of-stream); a server that has not read it all within `timeout` s is cut off.
    // The reader keeps going until the server closes its end.
    void finish(double timeout = 10);
    // Joins the reader (after the server has gone: its end closed) and closes the socket.
    void close();
    bool alive() const;
    BridgeStats stats() const;
    const Link& link() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace plant::opcua
