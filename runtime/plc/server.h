// The Modbus TCP server of a PLC link (docs/plc.md): libmodbus on its own thread, a
// select() loop serving several clients, exchanging with the plant only at step
// boundaries. The step thread calls, around each Engine::step():
//
//   server.before_step(engine);   // what clients wrote since: engine::apply_event, in order
//   engine.step();
//   server.after_step(engine);    // the mapped outputs, encoded into the served snapshot
//
// and in lock-step first wait_for_step(). The step only ever takes a mutex for a copy of
// preallocated buffers; the network never blocks it.
#pragma once

#include "engine/engine.h"
#include "engine/events.h"
#include "graph/graph.h"
#include "plc/map.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace plant::plc {

struct ServerOptions {
    std::string host = "127.0.0.1";  // an IPv4 address
    int port = 0;                     // 0: a free port (port() says which)
    bool lockstep = false;            // the plant steps only when a client grants steps
    double lockstep_timeout = 30;     // s without a grant before wait_for_step fails
    int max_clients = 64;             // more are accepted and closed at once
    double partial_timeout = 2;       // s a client may leave a frame half sent
};

struct ServerStats {
    int64_t requests = 0;        // frames answered (exceptions included)
    int64_t exceptions = 0;      // exception responses
    int64_t accepted = 0;        // clients
    int64_t left = 0;            // ... that closed their connection (mid-request or not)
    int64_t dropped = 0;         // ... closed by the server: not Modbus TCP, a frame half sent
                                 // for partial_timeout, or answers it does not read
    int64_t refused = 0;         // ... over max_clients
    int64_t clients = 0;         // connected now
    int64_t applied = 0;         // events applied to the plant
    int64_t rejected = 0;        // written values not applied (not finite)
};

class Server {
public:
    // The map must have passed check_map for `g`.
    Server(const graph::Graph& g, Map map, ServerOptions options = {});
    ~Server();  // stops the thread, closes every socket
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    // Listens and starts the network thread; false with `error` (bad host, port in use).
    bool start(std::string& error);
    int port() const;
    void stop();

    void before_step(engine::Engine& e);
    // The events the last before_step applied, in order (valid until the next one).
    std::span<const engine::Event* const> applied() const;
    void after_step(const engine::Engine& e);
    // Lock-step: returns once a client has granted a step (holding register 60000); false
    // with `error` when none did within lockstep_timeout, or the server stopped; false
    // without one on SIGINT / SIGTERM (engine::InterruptGuard).
    bool wait_for_step(std::string& error);

    ServerStats stats() const;
    const Map& map() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace plant::plc
