// The network side of `plant serve`: HTTP (the page, its packages, models, the session's
// events file) and WebSocket (docs/viewer.md), on Boost.Beast, one I/O thread. Each page
// has its own queue: a slow page gets fewer frames and never slows the player or the
// other pages; a page that sends garbage gets error replies. Each page has a role
// (serve/roles.h): the instructor's page does everything, a trainee's acts only on the
// plant's operable inputs and with the hand, and is never sent a force (docs/viewer.md,
// "Roles"). With a certificate and key the same is served over TLS (https, wss).
#pragma once

#include "serve/player.h"

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

namespace plant::view {

struct ServerOptions {
    std::string host = "127.0.0.1";
    uint16_t port = 8150;  // 0: any free port
    std::string viewer_dir;
    ModelDirs models;
    // The instructor's secret: a page that gives it (`?token=`) is the instructor; a wrong
    // one is refused and counted against its address. "": no page can give it.
    std::string token;
    // Every page an instructor, no token asked (--open, --no-roles); `?role=trainee` still
    // gives a trainee's page.
    bool open = false;
    // How long an address that gave TokenGate::kMaxFailures wrong tokens is locked out
    // first (it doubles with each lockout in a row).
    std::chrono::milliseconds lockout{30000};
    // PEM files: both given, the server speaks only TLS (https, wss).
    std::string tls_cert, tls_key;
    // The plant file, as the session report names it (/report, serve/report.h).
    std::string plant_file;
};

struct ServerStats {
    uint64_t clients = 0;          // connected pages now
    uint64_t messages = 0;         // messages received
    uint64_t errors = 0;           // messages refused
    uint64_t frames = 0;           // binary frames sent
    uint64_t dropped_replies = 0;  // error replies not queued (a flooding page)
    uint64_t refused_http = 0;     // HTTP requests refused (bad path, method)
    uint64_t bad_tokens = 0;       // connections refused for a wrong token (or while locked out)
    uint64_t trainee_refused = 0;  // trainees' messages refused for their role
    uint64_t reports = 0;          // session reports made (/report, /report.md)
};

// Whether `host` (an IP address) is a loopback address: a page from there is on this machine.
bool loopback_host(const std::string& host);

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
