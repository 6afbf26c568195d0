// The OPC UA link's part of the commands (docs/plc.md, "OPC UA"): `plant run` and `plant
// serve` with --opcua-port, --opcua-host, --opcua-pki, --opcua-users; `plant info
// --opcua[=csv]`.
#include "app/parts.h"

#include "opcua/nodes.h"
#include "opcua/run_link.h"

#include <fmt/format.h>

#include <ostream>

namespace plant::app {

namespace {

class OpcuaPart : public Part {
public:
    void add_flags(Cli& cli, Where where) override {
        if (where == Where::Info) {
            cli.flag_value("--opcua", map_, "md",
                           "the plant's OPC UA node map (NodeIds, browse paths, data types,\naccess, units) as a "
                           "Markdown table (=csv: as CSV), then the\nLink object's nodes",
                           "csv");
            return;
        }
        port_ = cli.value("--opcua-port", port_text_,
                          "serve the plant's OPC UA link on port N (0: a free port,\nprinted; a plant with an `opcua` "
                          "component is served without it)",
                          "N");
        host_ = cli.value("--opcua-host", host_text_,
                          "the address it listens on (default 127.0.0.1; elsewhere only\nBasic256Sha256, and anonymous "
                          "clients may only read)",
                          "ADDR");
        cli.value("--opcua-pki", flags_.pki, "the server's certificates (default $PLANT_OPCUA_PKI, else opcua/pki)",
                  "DIR");
        cli.value("--opcua-users", flags_.users, "user names and password hashes (node opcua/passwd.mjs NAME)", "FILE");
    }
    bool check(Where where, std::string& error) override {
        if (where == Where::Info) {
            if (map_.empty() || map_ == "md" || map_ == "csv") return true;
            error = fmt::format("--opcua takes csv or nothing, not '{}'", map_);
            return false;
        }
        if (host_->count()) {
            std::string host, resource, why;
            int port = 0;
            if (!opcua::parse_endpoint("opc.tcp://" + host_text_ + ":0", host, port, resource, why)) {
                error = fmt::format("--opcua-host: '{}' is not an IPv4 address (e.g. 127.0.0.1, 0.0.0.0 for every interface)",
                                    host_text_);
                return false;
            }
            flags_.host = host;
            flags_.host_given = true;
        }
        if (port_->count()) {
            long port = 0;
            if (!whole_number(port_text_, 0, 65535, port)) {
                error = fmt::format("--opcua-port: '{}' is not a port number (0 to 65535; 0 picks a free one)", port_text_);
                return false;
            }
            flags_.port = int(port);
            flags_.port_given = true;
        }
        return true;
    }
    std::string link_name() const override { return "OPC UA"; }
    bool wanted(const graph::Graph& g) const override { return flags_.any() || opcua::declares_link(g); }
    std::unique_ptr<engine::RunLink> start(const graph::Graph& g, bool lockstep, const RunPlace& place, std::ostream& err,
                                           std::string& error) override {
        opcua::LinkFlags flags = flags_;
        flags.lockstep = lockstep;
        return opcua::start_link(g, flags, place.plant_dir, place.tag, err, error);
    }
    void info(const graph::Graph& g, std::ostream& out) override {
        if (map_.empty()) return;
        const std::vector<opcua::Link> links = opcua::links_from_graph(g);
        out << "opcua (the OPC UA link's node map, docs/plc.md):\n";
        if (links.empty()) out << "(no opcua component: `plant run --opcua-port N` serves the Link object alone)\n";
        for (const auto& link : links)
            out << opcua::format_nodes(link, map_ == "csv" ? opcua::MapFormat::Csv : opcua::MapFormat::Markdown);
    }

private:
    opcua::LinkFlags flags_;
    std::string port_text_, host_text_, map_;
    CLI::Option* port_ = nullptr;
    CLI::Option* host_ = nullptr;
};

}  // namespace

std::unique_ptr<Part> make_opcua_part() { return std::make_unique<OpcuaPart>(); }

}  // namespace plant::app
