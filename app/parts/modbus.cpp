// The Modbus link's part of the commands (docs/plc.md): `plant run --modbus-port N
// --modbus-host ADDR` and `plant info --modbus[=csv]`.
#include "app/parts.h"

#include "plc/map.h"
#include "plc/run_link.h"

#include <fmt/format.h>

#include <ostream>

namespace plant::app {

namespace {

class ModbusPart : public Part {
public:
    void add_flags(Cli& cli, Where where) override {
        where_ = where;
        if (where == Where::Run) {
            port_ = cli.value("--modbus-port", port_text_,
                              "serve the plant's PLC link over Modbus TCP on port N\n(0: a free port, printed; see "
                              "docs/plc.md)",
                              "N");
            host_ = cli.value("--modbus-host", flags_.server.host, "the address it listens on (default 127.0.0.1)",
                              "ADDR");
        } else if (where == Where::Info) {
            cli.flag_value("--modbus", map_, "md",
                           "the plant's PLC link register map as a Markdown table\n(=csv: as CSV for a PLC project), "
                           "then the link's control block",
                           "csv");
        }
    }
    bool check(Where where, std::string& error) override {
        if (where == Where::Info && !map_.empty() && map_ != "md" && map_ != "csv") {
            error = fmt::format("--modbus takes csv or nothing, not '{}'", map_);
            return false;
        }
        if (where != Where::Run) return true;
        flags_.host_given = host_->count() > 0;
        flags_.port_given = port_->count() > 0;
        long port = 0;
        if (flags_.port_given && !whole_number(port_text_, 0, 65535, port)) {
            error = fmt::format("--modbus-port: '{}' is not a port number (0 to 65535; 0 picks a free one)", port_text_);
            return false;
        }
        flags_.server.port = int(port);
        return true;
    }
    std::string link_name() const override { return "Modbus"; }
    bool wanted(const graph::Graph& g) const override {
        return where_ == Where::Run && (flags_.port_given || flags_.host_given || plc::declares_link(g));
    }
    bool lockstep_default() const override { return true; }
    std::unique_ptr<engine::RunLink> start(const graph::Graph& g, bool lockstep, const RunPlace&, std::ostream& err,
                                           std::string& error) override {
        plc::LinkFlags flags = flags_;
        flags.server.lockstep = lockstep;
        return plc::start_link(g, flags, err, error);
    }
    void info(const graph::Graph& g, std::ostream& out) override {
        if (map_.empty()) return;
        out << "modbus (the PLC link's register map, docs/plc.md):\n"
            << plc::format_map(plc::map_from_graph(g), g, map_ == "csv" ? plc::MapFormat::Csv : plc::MapFormat::Markdown);
    }

private:
    Where where_ = Where::Run;  // the Modbus link serves runs only
    plc::LinkFlags flags_;
    std::string port_text_, map_;
    CLI::Option* port_ = nullptr;
    CLI::Option* host_ = nullptr;
};

}  // namespace

std::unique_ptr<Part> make_modbus_part() { return std::make_unique<ModbusPart>(); }

}  // namespace plant::app
