// The OPC UA link declared in a plant (opcua/kind.h): the `opcua` kind's entries become the
// node map, its checks report at the entry or the component, the loader refuses a graph
// whose map is broken; the endpoint parser, the units, the node map's tables.
#include "../compiler/compile_helper.h"
#include "graph/text.h"
#include "graph/validate.h"
#include "opcua/kind.h"
#include "opcua/nodes.h"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <sstream>

using namespace plant;

namespace {

constexpr const char* kUaLinked = R"(import std.belts, std.switch
plant Linked {
    b1: Belt(length = 1 m)
    sw: Switch(side = 1) at (1 m, 0 m, 0 m)
    timer t: periodic { period = 1 s; autostart = true }
    opcua ua {
        endpoint = "opc.tcp://localhost:4850/plant"
        namespace = "urn:plant:linked"
        security = "basic256sha256"
        users = "plant.users"
        node 7 => sw.seen
        node 2 => sw.id
        node 3 => sw.working
        node 4 => sw.to_working
        node 5 => b1.speed_now(unit = "mm/s")
        node 6 => b1.set_speed(unit = "m/min")
        node 1 => t.elapsed
        node 8 => t.running
    }
}
)";

std::string ua_diagnostics(const std::string& link) {
    Compilation c;
    test::compile_text("import std.belts\nplant P {\n    b1: Belt(length = 1 m)\n" + link + "\n}\n", c, "ua_bad.plant");
    std::string out;
    for (const auto& d : c.sink.all())
        out += fmt::format("{}:{} {} {}\n", c.sources.line_col(d.span.file, d.span.begin).line,
                           c.sources.line_col(d.span.file, d.span.begin).col, info(d.id).code, d.message);
    return out;
}

}  // namespace

TEST_CASE("opcua kind: the declared entries are the node map the server serves") {
    Compilation c;
    test::compile_text(kUaLinked, c, "ua_linked.plant");
    for (const auto& d : c.sink.all()) INFO(d.message);
    REQUIRE(c.ok());
    const std::vector<opcua::Link> links = opcua::links_from_graph(c.graph);
    REQUIRE(links.size() == 1);
    const opcua::Link& l = links[0];
    CHECK(l.name == "ua");
    CHECK(l.plant == "Linked");
    CHECK(l.host == "127.0.0.1");  // localhost
    CHECK(l.port == 4850);
    CHECK(l.resource == "/plant");
    CHECK(l.namespace_uri == "urn:plant:linked");
    CHECK(l.security == opcua::Security::Basic256Sha256);
    CHECK(l.users == "plant.users");
    CHECK(opcua::check_link(l, c.graph).empty());
    REQUIRE(l.nodes.size() == 8);
    CHECK(l.nodes[0].id == 7);
    CHECK(l.nodes[0].cls == opcua::NodeClass::Counter);  // a void output
    CHECK(opcua::type_name(l.nodes[0]) == "UInt32");
    CHECK(l.nodes[0].browse == std::vector<std::string>{"sw", "seen"});
    CHECK(opcua::type_name(l.nodes[1]) == "String");
    CHECK(opcua::type_name(l.nodes[2]) == "Int32");
    CHECK(l.nodes[3].cls == opcua::NodeClass::Method);  // a void input
    CHECK(l.nodes[3].dir == graph::Dir::In);
    REQUIRE(l.nodes[4].unit);
    CHECK(l.nodes[4].unit->code == "C16");
    CHECK(l.nodes[4].unit->factor == doctest::Approx(1e-3));
    CHECK(l.nodes[5].unit->symbol == "m/min");
    CHECK(l.nodes[5].dir == graph::Dir::In);
    REQUIRE(l.nodes[6].unit);  // a timer's elapsed time: seconds, from the slot's kind
    CHECK(l.nodes[6].unit->symbol == "s");
    CHECK(opcua::type_name(l.nodes[7]) == "Boolean");
    CHECK_FALSE(l.nodes[7].doc.empty());  // the slot's documentation, for the node's Description
    // A plant without a link has none.
    Compilation none;
    test::compile_text("import std.belts\nplant P { b1: Belt(length = 1 m) }\n", none, "ua_unlinked.plant");
    REQUIRE(none.ok());
    CHECK(opcua::links_from_graph(none.graph).empty());
}

TEST_CASE("opcua kind: each problem is reported at the entry or the component, with its code") {
    CHECK(ua_diagnostics("opcua ua {\n node 5 => b1.speed_now\n node 5 => b1.stop\n}") ==
          "6:2 E0315 'b1.stop': node 5 is taken by 'b1.speed_now'\n");
    CHECK(ua_diagnostics("opcua ua { node 0 => b1.stop }") ==
          "4:12 E0315 'b1.stop': node 0 (a NodeId's number is 1 to 2147483647; 0 is no node)\n");
    CHECK(ua_diagnostics("opcua ua {\n node 1 => b1.set_speed\n node 2 => b1.set_speed\n}") ==
          "6:2 E0315 'b1.set_speed' is node 1 already: one node per slot\n");
    CHECK(ua_diagnostics("opcua ua { endpoint = \"opc.tcp://127.0.0.1\" }") ==
          "4:7 E0315 endpoint \"opc.tcp://127.0.0.1\": no port (opc.tcp://HOST:PORT; OPC UA's own is 4840)\n");
    CHECK(ua_diagnostics("opcua ua { endpoint = \"http://127.0.0.1:80\" }") ==
          "4:7 E0315 endpoint \"http://127.0.0.1:80\": an endpoint starts with opc.tcp://\n");
    CHECK(ua_diagnostics("opcua ua { endpoint = \"opc.tcp://plant.local:4840\" }").find("is not an IPv4 address") !=
          std::string::npos);
    CHECK(ua_diagnostics("opcua ua { endpoint = \"opc.tcp://127.0.0.1:70000\" }").find("port '70000' is not a port number") !=
          std::string::npos);
    CHECK(ua_diagnostics("opcua ua {\n endpoint = \"opc.tcp://10.0.0.5:4840\"\n security = \"none\"\n}") ==
          "4:7 E0315 security \"none\" serves 10.0.0.5 unencrypted and unauthenticated: only 127.0.0.1 may, elsewhere "
          "Basic256Sha256\n");
    CHECK(ua_diagnostics("opcua ua { security = \"aes\" }") ==
          "4:7 E0315 security \"aes\": one of \"\" (by address), \"none\", \"basic256sha256\"\n");
    CHECK(ua_diagnostics("opcua ua { namespace = \"plant\" }") ==
          "4:7 E0315 namespace \"plant\" is not a URI (e.g. urn:plant:bottling)\n");
    CHECK(ua_diagnostics("opcua ua { node 1 => b1.speed_now(unit = \"kg\") }") ==
          "4:12 E0315 'b1.speed_now' is in m/s: \"kg\" measures kg\n");
    CHECK(ua_diagnostics("opcua ua { node 1 => b1.speed_now(unit = \"mph\") }").find("no unit \"mph\" (one of m, mm,") !=
          std::string::npos);
    CHECK(ua_diagnostics("opcua ua { node 1 => b1.stop(unit = \"s\") }") ==
          "4:12 E0315 'b1.stop' is void: a unit belongs to a real node\n");
    CHECK(ua_diagnostics("modbus plc { port = 4840 }\nopcua ua { endpoint = \"opc.tcp://127.0.0.1:4840\" }") ==
          "5:7 E0315 port 4840 is taken by the Modbus link 'plc': two links cannot serve one port\n");
    CHECK(ua_diagnostics("opcua a { endpoint = \"opc.tcp://127.0.0.1:4840\" }\nopcua b { endpoint = \"opc.tcp://127.0.0.1:4840\" }") ==
          "5:7 E0315 port 4840 is taken by the OPC UA link 'a': two links cannot serve one port\n");
    // The generic entry checks: a word, an option, a type the kind does not take.
    CHECK(ua_diagnostics("opcua ua { variable 1 => b1.stop }").find("E0106 an opcua takes no entry 'variable'") != std::string::npos);
    CHECK(ua_diagnostics("opcua ua { node 1 => b1.stop(scale = 2) }").find("E0303 a 'node' entry has no option 'scale'") !=
          std::string::npos);
    CHECK(ua_diagnostics("physics box: dynamic { shape box(1 m, 1 m, 1 m); mass = 1 kg }\nopcua ua { node 1 => box.position }")
              .find("E0201 a 'node' entry takes a void, bool, int, real or string slot, but 'box.position' is vec3") !=
          std::string::npos);
}

TEST_CASE("opcua kind: an object on the way to a node cannot be a node itself") {
    Compilation c;
    test::compile_text("import std.belts\nplant P {\n b1: Belt(length = 1 m)\n opcua ua { node 1 => b1.stop }\n}\n", c,
                       "ua_objects.plant");
    REQUIRE(c.ok());
    opcua::Link l = opcua::links_from_graph(c.graph).at(0);
    opcua::Node shadow = l.nodes[0];  // a hand-made node whose path is the object b1
    shadow.id = 2;
    shadow.path = "b1";
    shadow.browse = {"b1"};
    shadow.slots = {graph::SlotId(shadow.slots[0].v + 1)};
    l.nodes.push_back(shadow);
    const std::vector<opcua::NodeError> errors = opcua::check_link(l, c.graph);
    REQUIRE(errors.size() == 1);
    CHECK(errors[0].entry == 1);
    CHECK(errors[0].message == "'b1' is an object on the way to 'b1.stop': a node cannot have its browse path");
    l.nodes[1].slots = {c.graph.slots.next_id()};
    CHECK(opcua::check_link(l, c.graph).at(0).message == "'b1': a slot id out of the graph's range");
}

TEST_CASE("opcua kind: the loader runs the kind's check") {
    Compilation c;
    test::compile_text(kUaLinked, c, "ua_loader.plant");
    REQUIRE(c.ok());
    std::ostringstream text;
    graph::write_text(c.graph, text);
    std::string good = text.str(), error;
    graph::Graph g;
    {
        std::istringstream in(good);
        CHECK(graph::read_text(in, g, error));
    }
    // Two nodes with one NodeId: entry 1 takes entry 0's key.
    const std::string from = "plugin_entry 1 word=\"node\" key=2 ";
    const size_t at = good.find(from);
    REQUIRE(at != std::string::npos);
    good.replace(at, from.size(), "plugin_entry 1 word=\"node\" key=7 ");
    std::istringstream in(good);
    CHECK_FALSE(graph::read_text(in, g, error));
    CHECK(error.find("node 7 is taken by 'sw.seen'") != std::string::npos);
}

TEST_CASE("opcua kind: endpoints, path steps and units") {
    std::string host, resource, error;
    int port = -1;
    CHECK(opcua::parse_endpoint("opc.tcp://0.0.0.0:4840", host, port, resource, error));
    CHECK(host == "0.0.0.0");
    CHECK(port == 4840);
    CHECK(resource.empty());
    CHECK_FALSE(opcua::parse_endpoint("opc.tcp://127.0.0.1:-1", host, port, resource, error));
    CHECK_FALSE(opcua::parse_endpoint("opc.tcp://:4840", host, port, resource, error));
    CHECK(opcua::is_loopback("127.0.0.1"));
    CHECK_FALSE(opcua::is_loopback("127.0.0.2"));  // served as any other address: the secure path's test uses it
    CHECK_FALSE(opcua::is_loopback("0.0.0.0"));
    CHECK_FALSE(opcua::is_loopback("192.168.1.20"));
    CHECK(opcua::path_steps("line[0].s2.sw.reader.volume.on_stay") ==
          std::vector<std::string>{"line[0]", "s2", "sw", "reader", "volume", "on_stay"});
    CHECK(opcua::unit_id("MTR") == 0x4D5452);  // OPC UA Part 8: the code's characters
    CHECK(opcua::unit_id("C16") == 0x433136);
    for (const opcua::Unit& u : opcua::units()) {
        INFO(u.symbol);
        const opcua::Unit* si = opcua::find_unit(u.si);
        REQUIRE(si);  // every unit's SI unit is in the table too, with factor 1
        CHECK(si->factor == 1);
        CHECK(u.factor > 0);
    }
    CHECK(opcua::find_unit("m/min")->factor * 60 == doctest::Approx(1));
}

TEST_CASE("opcua kind: the node map as a table and as CSV") {
    Compilation c;
    test::compile_text(kUaLinked, c, "ua_table.plant");
    REQUIRE(c.ok());
    const opcua::Link l = opcua::links_from_graph(c.graph).at(0);
    const std::string md = opcua::format_nodes(l);
    CHECK(md.find("endpoint opc.tcp://127.0.0.1:4850/plant, namespace urn:plant:linked (ns=2), security basic256sha256\n") == 0);
    CHECK(md.find("| ns=2;i=1 | Objects/Linked/t/elapsed | Variable | Double | read | s | `out real t.elapsed` |") !=
          std::string::npos);
    CHECK(md.find("| ns=2;i=4 | Objects/Linked/sw/to_working | Method |  | call |  | `in void sw.to_working` |") !=
          std::string::npos);
    CHECK(md.find("| ns=2;i=6 | Objects/Linked/b1/set_speed | Variable | Double | read, write | m/min |") != std::string::npos);
    CHECK(md.find("| ns=1;s=Link.Advance | Objects/Link/Advance | Method |") != std::string::npos);
    CHECK(md.find("ns=2;i=1 ") < md.find("ns=2;i=2 "));  // by NodeId, not as declared
    const std::string csv = opcua::format_nodes(l, opcua::MapFormat::Csv);
    CHECK(csv.rfind("node,browse path,class,data type,access,unit,slot,meaning\n", 0) == 0);
    CHECK(csv.find("ns=2;i=7,Objects/Linked/sw/seen,Variable (counter),UInt32,\"read, events\",,out void sw.seen,") !=
          std::string::npos);
}
