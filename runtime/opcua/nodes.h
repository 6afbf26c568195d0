// The node map of an OPC UA link (docs/plc.md, "OPC UA"): which slot each node of the
// plant's namespace stands for, what it is to a client, and where the server listens.
// A plain value the `opcua` component is lowered to (kind.h); the server (link.h) serves it.
//
// The address space mirrors the plant's tree: under Objects, an object for the plant and
// below it an object per step of a mapped slot's dotted path (`line[0]`, `s2`), string
// NodeIds from the path; each entry is one node with the numeric NodeId its key gives:
//   a bool, int, real or string slot: a variable (Boolean, Int32, Double, String), read
//     only for an output, read and write for an input;
//   a void input: a method without arguments (a call fires the input once);
//   a void output: a UInt32 counter of the steps it was active in, and an event
//     (SlotEventType) from its object in each of those steps.
#pragma once

#include "graph/graph.h"
#include "opcua/units.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace plant::opcua {

enum class NodeClass : uint8_t { Variable, Method, Counter };

struct Node {
    uint32_t id = 0;                  // ns=<plant namespace>;i=id
    std::string path;                 // the slot's (or port's) dotted path
    std::vector<std::string> browse;  // its steps: objects, then the node's browse name
    std::vector<graph::SlotId> slots;       // what it feeds (an input port: several) or shows
    graph::SlotType type = graph::SlotType::Bool;
    graph::Dir dir = graph::Dir::Out;
    NodeClass cls = NodeClass::Variable;
    const Unit* unit = nullptr;       // EngineeringUnits; nullptr: none
    std::string doc;                  // the slot's one-line documentation
};

enum class Security : uint8_t {
    Auto,            // "": None and Basic256Sha256 on 127.0.0.1, Basic256Sha256 elsewhere
    None,            // "none": 127.0.0.1 only
    Basic256Sha256,  // "basic256sha256": signed, or signed and encrypted, only
};

struct Link {
    std::string name;              // the component's name
    std::string plant;             // the plant's name: its object under Objects
    std::string host;              // the IPv4 address to listen on ("": --opcua-host's, else 127.0.0.1)
    int port = 0;                  // 0: --opcua-port's, else a free one
    std::string resource;          // the endpoint's path ("/plant" of opc.tcp://h:p/plant)
    std::string namespace_uri;     // the plant's namespace
    Security security = Security::Auto;
    std::string users;             // a users file (opcua/passwd.mjs); "": none
    std::vector<Node> nodes;
};

std::string_view security_name(Security s);
std::string_view type_name(const Node& n);  // its OPC UA DataType ("Boolean", ...; "" for a method)
// Whether `ipv4` is 127.0.0.1, the one address served without security: SecurityPolicy None
// and anonymous writes. Any other, 127.0.0.2 and the rest of 127/8 too, is served as if it
// faced the network (Basic256Sha256, anonymous clients read only): one rule, and the secure
// path can be tested on a machine with no other interface.
bool is_loopback(std::string_view ipv4);

// `opc.tcp://HOST:PORT[/PATH]`, HOST an IPv4 address or `localhost`; false with `error`.
bool parse_endpoint(std::string_view text, std::string& host, int& port, std::string& resource, std::string& error);

// Splits a dotted path into its steps: "line[0].s2.id" -> line[0], s2, id.
std::vector<std::string> path_steps(std::string_view path);

// A problem with a link: which entry (-1: the component) and what.
struct NodeError {
    int32_t entry = -1;
    std::string message;
};

// The link of the `opcua` component `plugin` (a row of Graph::plugins); false with `error`
// for what makes no link at all (a bad endpoint, security or unit word).
bool link_of(const graph::Graph& g, graph::PluginId plugin, Link& out, NodeError& error);
// What two nodes (or a node and the rest of the plant) cannot share: a NodeId, a slot, a
// browse path; an id of 0; a unit on a slot that is not real, or of another dimension.
std::vector<NodeError> check_link(const Link& link, const graph::Graph& g);

// The links the plant declares (empty: none), in declaration order.
std::vector<Link> links_from_graph(const graph::Graph& g);

enum class MapFormat : uint8_t { Markdown, Csv };
// The node map for people (Markdown) or a PLC project's import (CSV): the plant's nodes
// by NodeId, then the Link object's.
std::string format_nodes(const Link& link, MapFormat format = MapFormat::Markdown);

// The namespace index of the plant's nodes on our server (0 is OPC UA's, 1 the server's own).
constexpr int kPlantNamespace = 2;
constexpr uint32_t kMaxNodeId = 0x7fffffff;

}  // namespace plant::opcua
