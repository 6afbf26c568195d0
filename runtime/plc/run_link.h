// The PLC link in `plant run` (docs/plc.md): the Modbus server as the run's
// engine::RunLink, started as its flags say (app/parts/modbus.cpp reads them:
// --modbus-port N, --modbus-host ADDR, --lockstep).
#pragma once

#include "engine/run.h"
#include "plc/server.h"

#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace plant::plc {

struct LinkFlags {
    bool port_given = false, host_given = false;  // over what the plant's link declares
    ServerOptions server;
};

class ServerLink : public engine::RunLink {
public:
    ServerLink(const graph::Graph& g, Map map, ServerOptions options) : forceable_(mapped_slots(map)),
        server_(g, std::move(map), std::move(options)) {}
    bool start(std::string& error) { return server_.start(error); }
    Server& server() { return server_; }
    bool wait(std::string& error) override { return !lockstep_ || server_.wait_for_step(error); }
    void before_step(engine::Engine& e) override { server_.before_step(e); }
    std::span<const engine::Event* const> applied() const override { return server_.applied(); }
    void after_step(const engine::Engine& e) override { server_.after_step(e); }
    std::vector<graph::SlotId> forceable() const override { return forceable_; }  // the fault block's reach
    void set_lockstep(bool on) { lockstep_ = on; }

private:
    static std::vector<graph::SlotId> mapped_slots(const Map& m) {
        std::vector<graph::SlotId> out;
        for (const Entry& e : m.entries) out.insert(out.end(), e.slots.begin(), e.slots.end());
        return out;
    }
    std::vector<graph::SlotId> forceable_;
    Server server_;
    bool lockstep_ = false;
};

// Whether the plant declares a link (a `modbus` component): `plant run` then serves it.
bool declares_link(const graph::Graph& g);

// The link for a run of `g` with `flags`: its map from the graph (map_from_graph), checked,
// on the plant's port and host unless the flags give them, the server started; one line on `err` says where it listens. Null with `error` when the
// map has errors or the server cannot listen.
std::unique_ptr<ServerLink> start_link(const graph::Graph& g, const LinkFlags& flags, std::ostream& err,
                                       std::string& error);

}  // namespace plant::plc
