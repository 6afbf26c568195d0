// The OPC UA link in `plant run` and `plant serve` (docs/plc.md, "OPC UA"): the server (a
// node-opcua child process, child.h) as the run's engine::RunLink, started as its flags say
// (app/parts/opcua.cpp reads them):
//
//   --opcua-port N       serve on port N (0: a free one, printed)
//   --opcua-host ADDR    the IPv4 address to listen on (default 127.0.0.1)
//   --opcua-pki DIR      the server's certificates (default: $PLANT_OPCUA_PKI, else opcua/pki)
//   --opcua-users FILE   user names and password hashes (opcua/passwd.mjs)
//   --lockstep           (shared with the Modbus link) step only as clients call Link.Advance
#pragma once

#include "engine/run.h"
#include "opcua/bridge.h"
#include "opcua/child.h"

#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace plant::opcua {

struct LinkFlags {
    bool port_given = false, host_given = false;  // over what the plant's link declares
    int port = 0;
    std::string host = "127.0.0.1";
    std::string pki, users;
    bool lockstep = false;
    double lockstep_timeout = 30;
    bool any() const { return port_given || host_given || !pki.empty() || !users.empty(); }
};

// Whether the plant declares an OPC UA link (an `opcua` component).
bool declares_link(const graph::Graph& g);

class ServerLink : public engine::RunLink {
public:
    ServerLink(const graph::Graph& g, Link link, BridgeOptions options);
    ~ServerLink() override;  // ends the channel; the server shuts down and exits
    bool wait(std::string& error) override;
    void before_step(engine::Engine& e) override { bridge_.before_step(e); }
    std::span<const engine::Event* const> applied() const override { return bridge_.applied(); }
    void after_step(const engine::Engine& e) override { bridge_.after_step(e); }
    std::vector<graph::SlotId> forceable() const override;  // every node's slots: Link.Force reaches them
    Bridge& bridge() { return bridge_; }
    // Starts the server process and waits until it listens; false with `error`.
    bool start(const std::string& config, std::string& ready, std::string& error);

private:
    Bridge bridge_;
    Child child_;
};

// The link for a run of `g`: its node map from the graph, checked, on the plant's endpoint
// unless the flags give one, the server started; one line on `err` says where it listens
// (`tag` starts it: "plant run"). `plant_dir` is the folder a relative users file is in.
// Null with `error` when the map has errors or the server cannot start.
std::unique_ptr<ServerLink> start_link(const graph::Graph& g, const LinkFlags& flags, const std::string& plant_dir,
                                       const std::string& tag, std::ostream& err, std::string& error);

// Where the server's package is: $PLANT_OPCUA_DIR, else this checkout's opcua/.
std::string default_opcua_dir();

}  // namespace plant::opcua
