// The network side of `plant serve`: HTTP (the page, its packages, models, the session's
// events file) and WebSocket (docs/viewer.md), on Boost.Beast, one I/O thread. Each page
// has its own queue: a slow page gets fewer frames and never slows the player or the
// other pages; a page that sends garbage gets error replies.
#pragma once

#include "serve/player.h"

#include <cstdint>
#include <memory>
#include <string>

namespace plant::view {

struct ServerOptions {
    std::string host = "127.0.0.1";
    uint16_t port = 8150;  // 0: any free port
    std::string viewer_dir;
    ModelDirs models;
};

struct ServerStats {
    uint64_t clients = 0;          // connected pages now
    uint64_t messages = 0;         // messages received
    uint64_t errors = 0;           // messages refused
    uint64_t frames = 0;           // binary frames sent
    uint64_t dropped_replies = 0;  // error replies not queued (a flooding page)
    uint64_t refused_http = 0;     // HTTP requests refused (bad path, method)
};

class Server {
public:
    Server(Player& player, ServerOptions opt);
    ~Server();
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    bool start(std::string& error);  // binds and starts the I/O thread
    uint16_t port() const;
    void stop();
    ServerStats stats() const;
    // Blocks until SIGINT or SIGTERM.
    void wait_for_signal();

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace plant::view
