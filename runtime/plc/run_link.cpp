#include "plc/run_link.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cstdlib>
#include <ostream>

namespace plant::plc {

bool take_link_flags(std::vector<std::string>& args, LinkFlags& flags, std::string& error) {
    std::vector<std::string> rest;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a != "--modbus-port" && a != "--modbus-host" && a != "--lockstep") {
            rest.push_back(a);
            continue;
        }
        flags.on = true;
        if (a == "--lockstep") {
            flags.server.lockstep = true;
            continue;
        }
        if (i + 1 >= args.size()) {
            error = fmt::format("{} needs a value", a);
            return false;
        }
        const std::string& v = args[++i];
        if (a == "--modbus-host") {
            flags.server.host = v;
            flags.host_given = true;
            continue;
        }
        char* end = nullptr;
        const long port = std::strtol(v.c_str(), &end, 10);
        if (v.empty() || *end || port < 0 || port > 65535) {
            error = fmt::format("--modbus-port: '{}' is not a port number (0 to 65535; 0 picks a free one)", v);
            return false;
        }
        flags.server.port = int(port);
        flags.port_given = true;
    }
    args = std::move(rest);
    return true;
}

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
