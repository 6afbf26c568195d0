#include "opcua/nodes.h"

#include <arpa/inet.h>
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <map>

namespace plant::opcua {

using graph::SlotType;

std::string_view security_name(Security s) {
    switch (s) {
    case Security::Auto: return "";
    case Security::None: return "none";
    case Security::Basic256Sha256: return "basic256sha256";
    }
    return "?";
}

std::string_view type_name(const Node& n) {
    switch (n.cls) {
    case NodeClass::Method: return "";
    case NodeClass::Counter: return "UInt32";
    case NodeClass::Variable: break;
    }
    switch (n.type) {
    case SlotType::Bool: return "Boolean";
    case SlotType::Int: return "Int32";
    case SlotType::Real: return "Double";
    case SlotType::String: return "String";
    default: return "?";
    }
}

bool is_loopback(std::string_view ipv4) {
    in_addr a{};
    return inet_pton(AF_INET, std::string(ipv4).c_str(), &a) == 1 && ntohl(a.s_addr) == INADDR_LOOPBACK;
}

bool parse_endpoint(std::string_view text, std::string& host, int& port, std::string& resource, std::string& error) {
    constexpr std::string_view scheme = "opc.tcp://";
    if (text.substr(0, scheme.size()) != scheme) {
        error = "an endpoint starts with opc.tcp://";
        return false;
    }
    std::string_view rest = text.substr(scheme.size());
    const size_t slash = rest.find('/');
    resource = slash == std::string_view::npos ? "" : std::string(rest.substr(slash));
    rest = rest.substr(0, slash);
    const size_t colon = rest.rfind(':');
    if (colon == std::string_view::npos) {
        error = "no port (opc.tcp://HOST:PORT; OPC UA's own is 4840)";
        return false;
    }
    const std::string_view h = rest.substr(0, colon), p = rest.substr(colon + 1);
    int value = -1;
    const auto [end, ec] = std::from_chars(p.data(), p.data() + p.size(), value);
    if (p.empty() || ec != std::errc() || end != p.data() + p.size() || value < 0 || value > 65535) {
        error = fmt::format("port '{}' is not a port number (0 to 65535; 0 picks a free one)", p);
        return false;
    }
    in_addr probe{};
    if (h == "localhost") host = "127.0.0.1";
    else if (inet_pton(AF_INET, std::string(h).c_str(), &probe) == 1) host = std::string(h);
    else {
        error = fmt::format("host '{}' is not an IPv4 address (e.g. 127.0.0.1, 0.0.0.0 for every interface) or localhost", h);
        return false;
    }
    port = value;
    return true;
}

std::vector<std::string> path_steps(std::string_view path) {
    std::vector<std::string> out;
    size_t begin = 0;
    int depth = 0;  // dots inside an index ("a[i.j]") do not split; plant paths have none, but be safe
    for (size_t i = 0; i <= path.size(); ++i) {
        if (i < path.size() && path[i] == '[') ++depth;
        if (i < path.size() && path[i] == ']') --depth;
        if (i == path.size() || (path[i] == '.' && depth == 0)) {
            out.emplace_back(path.substr(begin, i - begin));
            begin = i + 1;
        }
    }
    return out;
}

std::vector<NodeError> check_link(const Link& link, const graph::Graph& g) {
    std::vector<NodeError> out;
    if (link.namespace_uri.empty() || link.namespace_uri.find(':') == std::string::npos ||
        link.namespace_uri.find_first_of(" \t\n\"") != std::string::npos)
        out.push_back({-1, fmt::format("namespace \"{}\" is not a URI (e.g. urn:plant:bottling)", link.namespace_uri)});
    if (link.security == Security::None && !link.host.empty() && !is_loopback(link.host))
        out.push_back({-1, fmt::format("security \"none\" serves {} unencrypted and unauthenticated: only 127.0.0.1 may, "
                                       "elsewhere Basic256Sha256",
                                       link.host)});
    std::map<uint32_t, size_t> ids;
    std::map<std::vector<graph::SlotId>, size_t> slots;
    std::map<std::string, size_t> objects;  // every object a node's path passes through
    for (size_t i = 0; i < link.nodes.size(); ++i) {
        std::string prefix;
        for (size_t s = 0; s + 1 < link.nodes[i].browse.size(); ++s) {
            prefix += (s ? "." : "") + link.nodes[i].browse[s];
            objects.emplace(prefix, i);
        }
    }
    for (size_t i = 0; i < link.nodes.size(); ++i) {
        const Node& n = link.nodes[i];
        auto error = [&](std::string m) { out.push_back({int32_t(i), std::move(m)}); };
        bool bad_slot = n.slots.empty();
        for (graph::SlotId s : n.slots) bad_slot |= !g.slots.contains(s);
        if (bad_slot) {
            error(fmt::format("'{}': a slot id out of the graph's range", n.path));
            continue;
        }
        if (n.id == 0 || n.id > kMaxNodeId)
            error(fmt::format("'{}': node {} (a NodeId's number is 1 to {}; 0 is no node)", n.path, n.id, kMaxNodeId));
        if (auto [it, fresh] = ids.emplace(n.id, i); !fresh)
            error(fmt::format("'{}': node {} is taken by '{}'", n.path, n.id, link.nodes[it->second].path));
        if (auto [it, fresh] = slots.emplace(n.slots, i); !fresh)
            error(fmt::format("'{}' is node {} already: one node per slot", n.path, link.nodes[it->second].id));
        if (auto it = objects.find(n.path); it != objects.end())
            error(fmt::format("'{}' is an object on the way to '{}': a node cannot have its browse path",
                              n.path, link.nodes[it->second].path));
    }
    return out;
}

namespace {

std::string access(const Node& n) {
    switch (n.cls) {
    case NodeClass::Method: return "call";
    case NodeClass::Counter: return "read, events";
    case NodeClass::Variable: break;
    }
    return n.dir == graph::Dir::In ? "read, write" : "read";
}

std::string meaning(const Node& n) {
    switch (n.cls) {
    case NodeClass::Method: return "a call fires the input once, at the next step";
    case NodeClass::Counter: return "steps the output was active in (wraps at 2^32); an event in each";
    case NodeClass::Variable: break;
    }
    const std::string value = n.unit && n.unit->factor != 1 ? fmt::format("the value in {} (SI / {:g})", n.unit->symbol, n.unit->factor)
                                                             : std::string("the value");
    return n.dir == graph::Dir::In ? value + "; a write sets it at the next step" : value + " after the last step";
}

}  // namespace

std::string format_nodes(const Link& link, MapFormat format) {
    struct Row {
        std::string node, browse, cls, type, access, unit, slot, meaning;
    };
    std::vector<const Node*> order;
    for (const Node& n : link.nodes) order.push_back(&n);
    std::stable_sort(order.begin(), order.end(), [](const Node* a, const Node* b) { return a->id < b->id; });
    std::vector<Row> rows;
    for (const Node* n : order) {
        std::string browse = "Objects/" + link.plant;
        for (const std::string& s : n->browse) browse += "/" + s;
        rows.push_back({fmt::format("ns={};i={}", kPlantNamespace, n->id), browse,
                        n->cls == NodeClass::Method ? "Method" : n->cls == NodeClass::Counter ? "Variable (counter)" : "Variable",
                        std::string(type_name(*n)), access(*n), n->unit ? std::string(n->unit->symbol) : "",
                        fmt::format("{} {} {}", n->dir == graph::Dir::In ? "in" : "out", graph::word(n->type), n->path),
                        meaning(*n)});
    }
    auto link_row = [&](std::string_view name, std::string cls, std::string type, std::string acc, std::string what) {
        rows.push_back({fmt::format("ns=1;s=Link.{}", name), fmt::format("Objects/Link/{}", name), std::move(cls),
                        std::move(type), std::move(acc), "", "(link)", std::move(what)});
    };
    link_row("Steps", "Variable", "UInt64", "read", "steps run");
    link_row("SimulatedTime", "Variable", "Double", "read", "simulated seconds at the end of the last step");
    link_row("Rate", "Variable", "Double", "read", "steps per simulated second");
    link_row("Lockstep", "Variable", "Boolean", "read", "true: the plant steps only as Advance grants");
    link_row("Dropped", "Variable", "UInt32", "read", "steps whose changes the server missed (it fell behind)");
    link_row("Advance", "Method", "", "call", "Advance(Steps: UInt32) -> Steps: UInt64: lock-step, runs N steps, returns once they ran");
    link_row("Force", "Method", "", "call",
             "Force(Node: NodeId, Mode: String, Value): \"stuck\" (at Value), \"open\", \"invert\", from the next step");
    link_row("Release", "Method", "", "call", "Release(Node: NodeId): the node's slot back to normal at the next step");
    std::string out;
    if (format == MapFormat::Csv) {
        auto quote = [](const std::string& s) {
            if (s.find_first_of(",\"") == std::string::npos) return s;
            std::string q = "\"";
            for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
            return q + "\"";
        };
        out = "node,browse path,class,data type,access,unit,slot,meaning\n";
        for (const Row& r : rows)
            out += fmt::format("{},{},{},{},{},{},{},{}\n", quote(r.node), quote(r.browse), quote(r.cls), quote(r.type),
                               quote(r.access), quote(r.unit), quote(r.slot), quote(r.meaning));
        return out;
    }
    out = fmt::format("endpoint opc.tcp://{}:{}{}, namespace {} (ns={}), security {}\n\n",
                      link.host.empty() ? "127.0.0.1" : link.host, link.port == 0 ? std::string("PORT") : std::to_string(link.port),
                      link.resource, link.namespace_uri, kPlantNamespace,
                      link.security == Security::Auto ? "by address" : security_name(link.security));
    out += "| node | browse path | class | data type | access | unit | slot | meaning |\n|---|---|---|---|---|---|---|---|\n";
    for (const Row& r : rows)
        out += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", r.node, r.browse, r.cls, r.type, r.access, r.unit,
                           r.slot == "(link)" ? r.slot : "`" + r.slot + "`", r.meaning);
    return out;
}

}  // namespace plant::opcua
