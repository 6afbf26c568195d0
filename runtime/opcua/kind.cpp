#include "opcua/kind.h"

#include "engine/plugin.h"
#include "engine/events.h"

#include <fmt/format.h>

#include <array>
#include <cstdlib>

namespace plant::opcua {
namespace {

using graph::Dir;
using graph::ParamSpec;
using graph::ParamType;
using graph::SlotType;

enum Param : int { endpoint, name_space, security, users };
constexpr std::array kParams = {
    ParamSpec{"endpoint", ParamType::String, "", false, 0,
              "opc.tcp://HOST:PORT[/PATH]; \"\": 127.0.0.1 and --opcua-port's port, else a free one"},
    ParamSpec{"namespace", ParamType::String, "", false, 0, "the plant's namespace URI; \"\": urn:plant:<plant name>"},
    ParamSpec{"security", ParamType::String, "", false, 0,
              "\"\": None on 127.0.0.1 and Basic256Sha256; \"none\" (127.0.0.1 only); \"basic256sha256\" only"},
    ParamSpec{"users", ParamType::String, "", false, 0,
              "a users file (opcua/passwd.mjs), relative to the plant file; \"\": none"},
};
enum Option : int { unit };
constexpr std::array kNodeOptions = {
    ParamSpec{"unit", ParamType::String, "", false, 0,
              "a real node's engineering unit (\"mm/s\", \"m/min\", ...); \"\": the slot's SI unit"},
};
constexpr std::array kNodeTypes = {SlotType::Void, SlotType::Bool, SlotType::Int, SlotType::Real, SlotType::String};
constexpr std::array kEntries = {
    graph::EntrySpec{"node", "a node the key numbers: a variable, a method (a void input) or a counter (a void output)",
                     Dir::In, kNodeTypes, kNodeOptions, int32_t(kMaxNodeId), graph::EntryKey::Index, true},
};

bool check_opcua(const graph::Graph& g, graph::PluginId plugin, graph::PluginProblem& problem);

constexpr graph::KindDesc kDesc{kWord, "an OPC UA server: the plant's slots as nodes of an address space (docs/plc.md)", {},
                                kParams, kEntries, graph::PluginPhase::None, graph::PluginPhase::None, graph::plugin_check<check_opcua>};

std::string text(const graph::Graph& g, const graph::Plugin& p, int k) {
    return std::string(g.str(g.plugin_params[p.param_adr + k].text));
}

int port_of(const graph::Graph& g, const graph::Plugin& p) {
    std::string host, resource, error;
    int port = 0;
    const std::string ep = text(g, p, endpoint);
    return !ep.empty() && parse_endpoint(ep, host, port, resource, error) ? port : 0;
}

// Another link that serves the same port: an opcua link, or a Modbus link (its `port`).
std::string port_clash(const graph::Graph& g, graph::PluginId plugin, int port) {
    const graph::KindDesc* modbus = graph::find_plugin("modbus");
    int modbus_port = -1;
    for (size_t k = 0; modbus && k < modbus->params.size(); ++k)
        if (modbus->params[k].name == "port") modbus_port = int(k);
    for (graph::PluginId q : graph::ids_of(g.plugins)) {
        if (q == plugin) continue;
        const graph::Plugin& other = g.plugins[q];
        const std::string_view kind = g.str(other.kind);
        const std::string name(g.str(g.comps[other.comp].name));
        if (kind == kWord && q < plugin && port_of(g, other) == port)
            return fmt::format("port {} is taken by the OPC UA link '{}': two links cannot serve one port", port, name);
        if (kind == "modbus" && modbus_port >= 0 && g.plugin_params[other.param_adr + modbus_port].num == port)
            return fmt::format("port {} is taken by the Modbus link '{}': two links cannot serve one port", port, name);
    }
    return "";
}

bool check_opcua(const graph::Graph& g, graph::PluginId plugin, graph::PluginProblem& problem) {
    Link link;
    NodeError error;
    if (!link_of(g, plugin, link, error)) {
        problem = {error.entry, error.message};
        return false;
    }
    if (const std::vector<NodeError> errors = check_link(link, g); !errors.empty()) {
        problem = {errors.front().entry, errors.front().message};
        return false;
    }
    if (link.port == 0) return true;
    if (std::string clash = port_clash(g, plugin, link.port); !clash.empty()) {
        problem = {-1, std::move(clash)};
        return false;
    }
    return true;
}

// The documentation of a slot as its component kind declares it ("" for none).
std::string slot_doc(const graph::Graph& g, graph::SlotId slot) {
    const graph::Slot& s = g.slots[slot];
    const graph::Comp& c = g.comps[s.comp];
    const std::span<const graph::SlotSpec> specs = graph::slots_of(g, s.comp);
    const int32_t k = slot.v - c.slot_adr.v;  // which of its kind's slots
    return k >= 0 && k < graph::count_of(specs) ? std::string(specs[k].doc) : std::string();
}

}  // namespace

bool link_of(const graph::Graph& g, graph::PluginId plugin, Link& out, NodeError& error) {
    const graph::Plugin& p = g.plugins[graph::PluginId(plugin)];
    out = Link{};
    out.name = std::string(g.str(g.comps[p.comp].name));
    out.plant = std::string(g.str(g.plant));
    if (const std::string ep = text(g, p, endpoint); !ep.empty()) {
        std::string why;
        if (!parse_endpoint(ep, out.host, out.port, out.resource, why)) {
            error = {-1, fmt::format("endpoint \"{}\": {}", ep, why)};
            return false;
        }
    }
    out.namespace_uri = text(g, p, name_space);
    if (out.namespace_uri.empty()) out.namespace_uri = fmt::format("urn:plant:{}", g.str(g.plant));
    const std::string sec = text(g, p, security);
    if (sec.empty()) out.security = Security::Auto;
    else if (sec == "none") out.security = Security::None;
    else if (sec == "basic256sha256") out.security = Security::Basic256Sha256;
    else {
        error = {-1, fmt::format("security \"{}\": one of \"\" (by address), \"none\", \"basic256sha256\"", sec)};
        return false;
    }
    out.users = text(g, p, users);
    const engine::SlotIndex index = engine::slot_index(g);
    for (int32_t k = 0; k < p.entry_num; ++k) {
        const graph::PluginEntry& pe = g.plugin_entries[p.entry_adr + k];
        Node n;
        n.id = uint32_t(pe.key);
        for (const graph::PluginEntrySlot& s : g.plugin_entry_slots.slice(pe.slot_adr, pe.slot_num)) n.slots.push_back(s.v);
        if (n.slots.empty()) {
            error = {k, "an entry that names no slot"};
            return false;
        }
        const graph::Slot& first = g.slots[n.slots[0]];
        n.type = first.type;
        n.dir = first.dir;
        n.path = engine::path_of(index, n.slots);
        if (n.path.empty()) n.path = g.slot_path(n.slots[0]);
        n.browse = path_steps(n.path);
        n.cls = n.type != SlotType::Void ? NodeClass::Variable : n.dir == Dir::In ? NodeClass::Method : NodeClass::Counter;
        n.doc = slot_doc(g, n.slots[0]);
        const std::string_view si = slot_si_unit(g, n.slots[0]);
        n.unit = si.empty() ? nullptr : find_unit(si);
        const std::string written = pe.param_num > unit ? std::string(g.str(g.plugin_params[pe.param_adr + unit].text)) : "";
        if (!written.empty()) {
            const Unit* u = find_unit(written);
            if (!u) {
                std::string known;
                for (const Unit& x : units()) known += (known.empty() ? "" : ", ") + std::string(x.symbol);
                error = {k, fmt::format("'{}': no unit \"{}\" (one of {})", n.path, written, known)};
                return false;
            }
            if (n.type != SlotType::Real) {
                error = {k, fmt::format("'{}' is {}: a unit belongs to a real node", n.path, graph::word(n.type))};
                return false;
            }
            if (!si.empty() && u->si != si) {
                error = {k, fmt::format("'{}' is in {}: \"{}\" measures {}", n.path, si, written, u->si)};
                return false;
            }
            n.unit = u;
        }
        out.nodes.push_back(std::move(n));
    }
    return true;
}

std::vector<Link> links_from_graph(const graph::Graph& g) {
    std::vector<Link> out;
    for (graph::PluginId p : graph::ids_of(g.plugins)) {
        if (g.str(g.plugins[p].kind) != kWord) continue;
        Link l;
        NodeError e;
        link_of(g, p, l, e);  // a problem shows in check_link or the kind's check
        out.push_back(std::move(l));
    }
    return out;
}

void register_opcua_kind() {
    static constexpr engine::KindBehaviour kBehaviour{};  // kept by address: no hooks, no state
    static const bool registered = engine::register_plugin(kDesc, kBehaviour);
    if (!registered) std::abort();  // only a second kind named `opcua` could refuse it
}

}  // namespace plant::opcua
