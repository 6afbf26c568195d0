#include "plc/run_link.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cstdlib>
#include <ostream>

namespace plant::plc {

bool declares_link(const graph::Graph& g) {
    int links = 0;
    map_from_graph(g, &links);
    return links > 0;
}

std::unique_ptr<ServerLink> start_link(const graph::Graph& g, const LinkFlags& flags, std::ostream& err,
                                       std::string& error) {
    int links = 0;
    Map map = map_from_graph(g, &links);
    if (links > 1) {
        error = fmt::format("the plant declares {} Modbus links; plant run serves one", links);
        return nullptr;
    }
    const std::vector<MapError> problems = check_map(map, g);
    if (!problems.empty()) {
        error = fmt::format("the Modbus map: {}", problems.front().message);
        return nullptr;
    }
    ServerOptions options = flags.server;
    if (!flags.port_given && map.port != 0) options.port = map.port;
    if (!flags.host_given && !map.host.empty()) options.host = map.host;
    const size_t entries = map.entries.size();
    auto link = std::make_unique<ServerLink>(g, std::move(map), options);
    link->set_lockstep(flags.server.lockstep);
    if (!link->start(error)) return nullptr;
    fmt::print(err, "plant run: Modbus TCP on {}:{} ({} mapped entr{}{})\n", options.host, link->server().port(),
               entries, entries == 1 ? "y" : "ies",
               flags.server.lockstep ? "; lock-step: write N to holding register 60000 to run N steps" : "");
    err.flush();
    return link;
}

}  // namespace plant::plc
