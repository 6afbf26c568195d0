#include "opcua/run_link.h"

#include "opcua/kind.h"

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <ostream>

namespace plant::opcua {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr double kStartTimeout = 60;  // s for the server to load node-opcua and listen (~2 s)

std::string env_or(const char* name, std::string fallback) {
    const char* v = std::getenv(name);
    return v && *v ? std::string(v) : fallback;
}

json node_json(const Node& n) {
    json j{{"id", n.id},
           {"path", n.path},
           {"browse", n.browse},
           {"class", n.cls == NodeClass::Method ? "method" : n.cls == NodeClass::Counter ? "counter" : "variable"},
           {"type", type_name(n)},
           {"writable", n.cls == NodeClass::Variable && n.dir == graph::Dir::In},
           {"description", fmt::format("{} {} {}{}{}", n.dir == graph::Dir::In ? "in" : "out", graph::word(n.type), n.path,
                                       n.doc.empty() ? "" : ": ", n.doc)}};
    if (n.unit)
        j["unit"] = {{"symbol", n.unit->symbol},
                     {"code", n.unit->code},
                     {"unitId", unit_id(n.unit->code)},
                     {"description", n.unit->description},
                     {"factor", n.unit->factor}};
    return j;
}

}  // namespace

std::string default_opcua_dir() { return env_or("PLANT_OPCUA_DIR", PLANT_OPCUA_DIR); }

bool declares_link(const graph::Graph& g) { return !links_from_graph(g).empty(); }

ServerLink::ServerLink(const graph::Graph& g, Link link, BridgeOptions options) : bridge_(g, std::move(link), options) {}

ServerLink::~ServerLink() {
    bridge_.finish();  // the server reads the end of the channel, closes its sessions and exits
    child_.stop(10);
    bridge_.close();
}

bool ServerLink::start(const std::string& config, std::string& ready, std::string& error) {
    const std::string dir = default_opcua_dir();
    std::error_code ec;
    if (!fs::is_directory(fs::path(dir) / "node_modules" / "node-opcua", ec)) {
        error = fmt::format("the OPC UA server's packages are not installed in {}: run scripts/setup.sh (npm ci in opcua/)", dir);
        return false;
    }
    int fd = -1;
    if (!child_.start(env_or("PLANT_NODE", "node"), (fs::path(dir) / "server.mjs").string(), fd, error)) return false;
    bridge_.attach(fd);
    if (bridge_.handshake(config, kStartTimeout, ready, error)) return true;
    bridge_.finish();
    if (const std::string how = child_.stop(5); !how.empty()) error += fmt::format(" (the server: {})", how);
    bridge_.close();
    return false;
}

bool ServerLink::wait(std::string& error) {
    if (bridge_.wait(error)) return true;
    if (!bridge_.alive())
        if (const std::string how = child_.ended(); !how.empty()) error += fmt::format("; the server: {}", how);
    return false;
}

std::vector<graph::SlotId> ServerLink::forceable() const {
    std::vector<graph::SlotId> out;
    for (const Node& n : bridge_.link().nodes) out.insert(out.end(), n.slots.begin(), n.slots.end());
    return out;
}

std::unique_ptr<ServerLink> start_link(const graph::Graph& g, const LinkFlags& flags, const std::string& plant_dir,
                                       const std::string& tag, std::ostream& err, std::string& error) {
    std::vector<Link> links = links_from_graph(g);
    if (links.size() > 1) {
        error = fmt::format("the plant declares {} OPC UA links; one server serves one", links.size());
        return nullptr;
    }
    Link link = links.empty() ? Link{} : std::move(links[0]);
    if (links.empty()) {  // flags alone: the Link object (Steps, Advance, ...) and no nodes
        link.plant = std::string(g.str(g.plant));
        link.namespace_uri = fmt::format("urn:plant:{}", link.plant);
    }
    if (const std::vector<NodeError> problems = check_link(link, g); !problems.empty()) {
        error = fmt::format("the OPC UA node map: {}", problems.front().message);
        return nullptr;
    }
    if (flags.host_given || link.host.empty()) link.host = flags.host;
    if (flags.port_given) link.port = flags.port;
    const bool loopback = is_loopback(link.host);
    if (link.security == Security::None && !loopback) {
        error = fmt::format("the OPC UA link's security is \"none\": it serves 127.0.0.1 only, not {} (use Basic256Sha256: "
                            "security = \"\" or \"basic256sha256\")", link.host);
        return nullptr;
    }
    std::string users = flags.users.empty() ? link.users : flags.users;
    if (!users.empty() && flags.users.empty() && fs::path(users).is_relative() && !plant_dir.empty())
        users = (fs::path(plant_dir) / users).string();
    json policies = json::array();
    if (link.security != Security::Basic256Sha256 && loopback) policies.push_back("None");
    if (link.security != Security::None) policies.push_back("Basic256Sha256");
    const std::string dir = default_opcua_dir();
    json config{{"plant", link.plant},
                {"link", link.name},
                {"host", link.host},
                {"port", link.port},
                {"resource", link.resource},
                {"namespace", link.namespace_uri},
                {"policies", policies},
                {"anonymousWrites", loopback},
                {"pki", !flags.pki.empty() ? flags.pki : env_or("PLANT_OPCUA_PKI", (fs::path(dir) / "pki").string())},
                {"users", users},
                {"lockstep", flags.lockstep},
                {"step", 1.0 / g.settings.rate}};  // as declared; the server corrects it from the steps (a --rate)
    json nodes = json::array();
    for (const Node& n : link.nodes) nodes.push_back(node_json(n));
    config["nodes"] = std::move(nodes);

    BridgeOptions options;
    options.lockstep = flags.lockstep;
    options.lockstep_timeout = flags.lockstep_timeout;
    const size_t count = link.nodes.size();
    auto server = std::make_unique<ServerLink>(g, std::move(link), options);
    std::string ready;
    if (!server->start(config.dump(-1, ' ', false, json::error_handler_t::replace), ready, error)) return nullptr;
    const json r = json::parse(ready, nullptr, false);
    const std::string url = r.is_object() && r.contains("url") && r["url"].is_string() ? r["url"].get<std::string>() : "?";
    std::string sec;
    for (const auto& p : policies) sec += (sec.empty() ? "" : ", ") + p.get<std::string>();
    fmt::print(err, "{}: OPC UA on {} ({} node{}, namespace {}; security {}{}{})\n", tag, url, count, count == 1 ? "" : "s",
               config["namespace"].get<std::string>(), sec, loopback ? "" : "; anonymous clients may only read",
               flags.lockstep ? "; lock-step: call Link.Advance to run N steps" : "");
    err.flush();
    return server;
}

}  // namespace plant::opcua
