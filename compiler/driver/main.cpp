// The `plant` command: check, build, graph (and run, when the runtime is built in).
// Diagnostics go to stderr, results to stdout or -o.
#include "ast/print.h"
#include "compiler.h"
#include "dot/dot.h"
#include "graph/network.h"
#include "graph/text.h"
#include "driver/fmt.h"
#include "driver/sweep/sweep.h"
#include "lsp/lsp.h"

#ifdef PLANT_HAS_RUNTIME
#include "engine/link_chain.h"
#include "engine/run.h"
#endif
#ifdef PLANT_HAS_FAULTS
#include "faults/kind.h"
#include "faults/operable.h"
#endif
#ifdef PLANT_HAS_PANEL
#include "panel/kind.h"
#endif
#ifdef PLANT_HAS_PLC
#include "plc/kind.h"
#include "plc/run_link.h"
#endif
#ifdef PLANT_HAS_OPCUA
#include "opcua/kind.h"
#include "opcua/run_link.h"
#endif
#ifdef PLANT_HAS_SERVE
#include "serve/record.h"
#include "serve/serve.h"
#endif

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

constexpr const char* kUsage = R"(plant - compile and run automation plants

usage: plant <command> [options] FILE...

commands:
  check FILE...         check plant files; exit code 0 when there is no error
  build FILE -o OUT     compile FILE and write the graph's text form to OUT (- for stdout)
  graph FILE            an overview of the plant as Graphviz DOT (--object PATH: one object
                        in full, with its slots, flows and Petri nets)
  info FILE...          compile and print what each plant holds (objects, slots, flows, ...)
  run FILE              run a plant (.plant or .graph) headless; see `plant run --help`
  fmt FILE...           format plant files in the canonical layout (--check: only report);
                        `plant fmt --help`
  lsp                   a language server (LSP) on stdin/stdout for editors; `plant lsp --help`
  serve FILE            run a plant paced to the wall clock and show it in the browser (3D,
                        controls, inspector); `plant serve --help`
  sweep SPEC            many runs of a plant over parameter values, -j N or under mpirun;
                        CSV, summary and plot; `plant sweep --help`

common options:
  --set NAME=VALUE      give the plant's parameter NAME the value VALUE, an expression with
                        its unit (`--set k=4kg/s`, `--set "mass=20 g"`); repeatable
  --stdlib DIR          where `import std.x` looks (default: $PLANT_STDLIB or the bundled stdlib)
  --diagnostics=FORMAT  text (default) or json
  --emit=ast|graph      with check: print the AST or the graph text to stdout
  --color=never         diagnostics are plain text (always, for now)
  -h, --help            this help
)";

constexpr const char* kCheckHelp = R"(usage: plant check [--emit=ast|graph] [--diagnostics=text|json] [--stdlib DIR] [--set NAME=VALUE]... FILE...

Parses and checks each FILE: names, slot types and directions, units, values and Petri
nets. Prints every diagnostic as file:line:col with the source line and a caret.
--set NAME=VALUE gives the plant's parameter NAME a value (checked against its type;
errors in VALUE are reported at --set:1:COL). Exit code: 0 no errors (warnings
allowed), 1 errors, 2 bad usage.
)";

constexpr const char* kBuildHelp = R"(usage: plant build FILE -o OUT [--diagnostics=text|json] [--stdlib DIR] [--set NAME=VALUE]...

Compiles FILE into the flat graph and writes its text form (stable, diffable, loadable
by `plant run OUT`) to OUT, or to stdout with `-o -`.
)";

constexpr const char* kGraphHelp = R"(usage: plant graph FILE [--object PATH | --full] [-o OUT] [--stdlib DIR] [--set NAME=VALUE]...

Writes the compiled plant as Graphviz DOT. By default an overview: the plant's objects
(or, for a plant that wraps one line, the line's) as single nodes, its own components as
small nodes (a Petri net as one), and the flows between them bundled per pair of nodes.
--object PATH draws that object in full: a cluster per object inside it, components as
tables of their slots, flows as edges, each Petri net as places and transitions.
--full draws the whole plant so (large plants give very large drawings).
Render with: plant graph FILE | dot -Tsvg -o plant.svg
)";

constexpr const char* kInfoHelp = R"(usage: plant info [--slots] [--schedule] [--modbus[=csv]] [--opcua[=csv]] [--stdlib DIR] [--set NAME=VALUE]... FILE...

Compiles each FILE and prints one line of counts (objects, components, slots, flows,
connectors, places, transitions, bodies, force fields, triggers, warnings), then the
plant's parameters with their types and defaults (change them with --set NAME=VALUE).
--slots also lists every input and output by its dotted path, direction and type: the
objects' declared ports and the components' slots (the paths events address).
--schedule also prints the logic phase as the runtime runs it: one line per flow,
connector, router and label in order, then the flows delayed to cut a cycle (W0503).
--modbus prints the plant's PLC link register map as a Markdown table (--modbus=csv: as
CSV for a PLC project), then the link's control block (docs/plc.md).
--opcua prints the plant's OPC UA node map (NodeIds, browse paths, data types, access,
units) as a Markdown table (--opcua=csv: as CSV), then the Link object's nodes.
)";

constexpr const char* kRunHelp = R"(usage: plant run FILE [options]

Runs FILE (a .plant, or a .graph written by `plant build`) headless and prints a summary:
objects issued, taken, on the line, lost and stalled; records; warnings; wall time and
the real-time factor.

  --for 10s                 simulated time (s, ms, min; default 10 s)
  --rate 150Hz              physics rate (Hz, kHz; default the plant's settings.rate)
  --set NAME=VALUE          a plant parameter (.plant files only); repeatable
  --trace FILE              write a CSV trace
  --trace-bodies, --trace-places, --trace-slots
                            the trace's column groups (any subset; default all)
  --trace-rate 50Hz         sample rate of the trace (default every step)
  --event "5s PATH [VALUE]" a timed external input to the slot PATH; repeatable
  --events FILE             one event per line, # comments
  --record FILE             write what the viewer needs (poses, graphics, status,
                            events) for `plant serve --replay FILE`
  --record-rate 10Hz        frames recorded per second of simulated time (default
                            30Hz; events are all kept)
  --record-compress zstd|none
                            compress the recording (default zstd; --replay reads both)
  --realtime                not faster than real time
  --modbus-port N           serve the plant's PLC link over Modbus TCP on port N
                            (0: a free port, printed; see docs/plc.md)
  --modbus-host ADDR        the address it listens on (default 127.0.0.1)
  --opcua-port N            serve the plant's OPC UA link on port N (0: a free port,
                            printed; a plant with an `opcua` component is served without it)
  --opcua-host ADDR         the address it listens on (default 127.0.0.1; elsewhere only
                            Basic256Sha256, and anonymous clients may only read)
  --opcua-pki DIR           the server's certificates (default $PLANT_OPCUA_PKI, else opcua/pki)
  --opcua-users FILE        user names and password hashes (node opcua/passwd.mjs NAME)
  --lockstep                step only as a client grants steps: a Modbus client, or an
                            OPC UA client calling Link.Advance (docs/plc.md)
  --broadphase dbvt|sap     Bullet's broadphase (default dbvt)
  --threads N               threads for a plant in several physics regions
                            (default: one per core; the results do not depend on it)
  --steady-transport on|off bottles in steady transport leave Bullet's solver (default on,
                            as the plant's settings.steady_transport; docs/runtime.md)
  --quiet                   no progress line
See docs/runtime.md ("plant run") for the event values and the trace format.
)";

constexpr const char* kServeHelp = R"(usage: plant serve FILE [options]
       plant serve --replay RECORDING [options]

Runs FILE (a .plant, or a .graph written by `plant build`) paced to the wall clock and
serves a page that shows it in 3D: open the printed URL. The page pauses, steps, changes
the speed, restarts, and acts on any input slot or port through the inspector; every
action is an event, logged on the page, and /events is the session's events file
(`plant run FILE --events events.txt` replays it headless, bit for bit). With --replay it
plays a recording made by `plant run FILE --record RECORDING`, with a timeline.

  --port N                  TCP port (default 8150; 0: any free port)
  --host ADDR               address to listen on (default 127.0.0.1: this machine only)
  --set NAME=VALUE          a plant parameter (.plant files only); repeatable
  --speed X                 times real time (default 1; 0: as fast as possible)
  --paused                  start paused
  --viewer DIR              the page's folder (default: $PLANT_VIEWER, else viewer/)
  --models DIR              where glTF/GLB models are found first (then beside the plant,
                            then the standard library's models, stdlib/models)
  --threads N               physics threads (as plant run)
  --steady-transport on|off as plant run
  --opcua-port N, --opcua-host ADDR, --opcua-pki DIR, --opcua-users FILE
                            the plant's OPC UA link (as plant run; a plant with an `opcua`
                            component is served without them)
  --event "5s PATH [VALUE]" a timed event, as plant run (repeatable; forces, hands too)
  --events FILE             one such event per line (an instructor's drill)
  --tls-cert FILE, --tls-key FILE
                            serve https and wss only, with this certificate and key (PEM)
  --open                    no roles: every page has full control (any --host)
  --no-roles                the same on this machine; refused on another address without --open
Roles: it prints the instructor's URL (with a secret token) and the trainees' URL; a
trainee's page operates only the plant's `operable` inputs and the hand, and is not shown
forces. On 127.0.0.1 a page without a token is the instructor's.
Stop with Ctrl-C. The protocol and the page: docs/viewer.md.
)";

struct Options {
    std::string command;
    std::vector<std::string> files;
    std::string out;
    std::string emit;
    bool json = false;
    std::string stdlib;
    std::vector<std::string> sets;  // --set NAME=VALUE, in order
    std::vector<std::string> rest;  // passed to `run`
    bool help = false;
    bool slots = false;  // info --slots
    bool schedule = false;  // info --schedule
    std::string modbus;  // info --modbus: "md" or "csv"
    std::string opcua;   // info --opcua: "md" or "csv"
    bool full = false;   // graph --full
    std::string object;  // graph --object PATH
    bool has_object = false;
};

// The standard library's folder: --stdlib, else $PLANT_STDLIB or this checkout's.
std::string stdlib_of(const Options& o) { return o.stdlib.empty() ? plant::default_stdlib_dir() : o.stdlib; }

int usage_error(const std::string& msg) {
    std::cerr << "plant: error: " << msg << "\n(see `plant --help`)\n";
    return 2;
}

bool write_output(const std::string& path, const std::string& text) {
    if (path.empty() || path == "-") {
        std::cout << text;
        return static_cast<bool>(std::cout);
    }
    std::ofstream f(path, std::ios::binary);
    f << text;
    return static_cast<bool>(f);
}

void print_diagnostics(const plant::Compilation& c, bool json) {
    auto sorted = c.sink.sorted();
    if (json) std::cerr << plant::render_json(sorted, c.sources);
    else if (!sorted.empty()) std::cerr << plant::render_all_text(sorted, c.sources);
}

bool compile(const std::string& file, const Options& o, plant::Compilation& c, bool require_plant = true) {
    plant::CompileOptions opts;
    opts.require_plant = require_plant;
    opts.stdlib_dir = o.stdlib.empty() ? plant::default_stdlib_dir() : o.stdlib;
    opts.overrides = o.sets;
    plant::compile_file(file, opts, c);
    print_diagnostics(c, o.json);
    return c.ok();
}

int cmd_check(const Options& o) {
    if (o.files.empty()) return usage_error("check needs at least one FILE");
    bool ok = true;
    for (const auto& f : o.files) {
        plant::Compilation c;
        ok = compile(f, o, c, false) && ok;
        if (o.emit == "ast") {
            for (const auto& m : c.program.modules) plant::ast::print(*m.ast, c.sources, std::cout);
        } else if (o.emit == "graph" && c.ok()) {
            plant::graph::write_text(c.graph, std::cout);
        }
    }
    return ok ? 0 : 1;
}

int cmd_build(const Options& o) {
    if (o.files.size() != 1) return usage_error("build takes one FILE");
    if (o.out.empty()) return usage_error("build needs -o OUT (use -o - for stdout)");
    plant::Compilation c;
    if (!compile(o.files[0], o, c)) return 1;
    if (!write_output(o.out, plant::graph::to_text(c.graph))) {
        std::cerr << "plant: error: cannot write '" << o.out << "'\n";
        return 1;
    }
    return 0;
}

int cmd_graph(const Options& o) {
    if (o.files.size() != 1) return usage_error("graph takes one FILE");
    plant::Compilation c;
    if (!compile(o.files[0], o, c)) return 1;
    std::ostringstream dot;
    if (o.has_object) {
        if (!plant::dot::write_dot_object(c.graph, o.object, dot)) {
            std::cerr << "plant: error: --object: no object '" << o.object << "' (`plant info --slots` lists paths)\n";
            return 1;
        }
    } else if (o.full) {
        plant::dot::write_dot(c.graph, dot);
    } else {
        plant::dot::write_overview(c.graph, dot);
    }
    if (!write_output(o.out, dot.str())) {
        std::cerr << "plant: error: cannot write '" << o.out << "'\n";
        return 1;
    }
    return 0;
}

// The root file's plant parameters, as written: `  bottles: count = 40`.
void print_plant_params(const plant::Compilation& c, std::ostream& out) {
    const auto& p = c.program;
    if (p.root < 0) return;
    for (const auto& obj : p.modules[size_t(p.root)].ast->objects) {
        if (!obj.is_plant) continue;
        for (const auto& prm : obj.params) {
            out << "  parameter " << prm.name.text;
            if (!prm.type.text.empty()) out << ": " << prm.type.text;
            if (prm.default_value) {
                const auto& sp = prm.default_value->span;
                out << " = " << c.sources.text(sp.file).substr(sp.begin, sp.end - sp.begin);
            }
            out << "\n";
        }
    }
}

// Every input and output a user can address (events, the viewer, tools): each object's
// ports, then its components' slots, objects in graph order.
void print_slots(const plant::graph::Graph& g, std::ostream& out) {
    using namespace plant::graph;
    std::vector<std::vector<int32_t>> ports(g.dos.size());
    for (size_t p = 0; p < g.ports.size(); ++p) ports[size_t(g.ports[p].owner)].push_back(int32_t(p));
    auto line = [&](Dir dir, SlotType type, const std::string& path, const std::string& note) {
        out << "  " << (dir == Dir::In ? "in " : "out") << "  " << word(type)
            << std::string(size_t(std::max(1, 8 - int(word(type).size()))), ' ') << path << note << "\n";
    };
    for (size_t d = 0; d < g.dos.size(); ++d) {
        for (int32_t p : ports[d]) {
            const Port& pt = g.ports[size_t(p)];
            std::string to;
            for (int32_t k = 0; k < pt.target_num; ++k)
                to += (k ? ", " : "") + g.slot_path(g.port_targets[size_t(pt.target_adr + k)].v);
            line(pt.dir, pt.type, g.port_path(p), (pt.dir == Dir::In ? "  (port => " : "  (port <= ") + to + ")");
        }
        const Do& o = g.dos[d];
        for (int32_t c = o.comp_adr; c < o.comp_adr + o.comp_num; ++c) {
            const Comp& cp = g.comps[size_t(c)];
            for (int32_t sl = cp.slot_adr; sl < cp.slot_adr + cp.slot_num; ++sl)
                line(g.slots[size_t(sl)].dir, g.slots[size_t(sl)].type, g.slot_path(sl), "");
        }
    }
}

int cmd_info(const Options& o) {
    if (o.files.empty()) return usage_error("info needs at least one FILE");
    bool ok = true;
    for (const auto& f : o.files) {
        plant::Compilation c;
        if (!compile(f, o, c)) {
            ok = false;
            continue;
        }
        const auto& g = c.graph;
        std::cout << f << ": plant " << g.str(g.plant) << " - " << g.dos.size() << " objects, " << g.comps.size()
                  << " components, " << g.slots.size() << " slots, " << g.flows.size() << " flows, " << g.logics.size()
                  << " connectors, " << g.places.size() << " places, " << g.transitions.size() << " transitions, "
                  << g.bodies.size() << " bodies, " << g.fields.size() << " force fields, " << g.triggers.size()
                  << " triggers; " << c.sink.count(plant::Severity::Warning) << " warnings\n";
        print_plant_params(c, std::cout);
        if (o.slots) {
            std::cout << "slots (direction, type, path; events address inputs by path):\n";
            print_slots(g, std::cout);
        }
        if (o.schedule) {
            std::cout << "logic phase (in order; a delayed flow acts in the next step):\n";
            std::cout << plant::graph::network_text(g, plant::graph::analyse_network(g));
        }
        if (!o.modbus.empty()) {
#ifdef PLANT_HAS_PLC
            const plant::plc::Map map = plant::plc::map_from_graph(g);
            std::cout << "modbus (the PLC link's register map, docs/plc.md):\n"
                      << plant::plc::format_map(map, g, o.modbus == "csv" ? plant::plc::MapFormat::Csv
                                                                          : plant::plc::MapFormat::Markdown);
#else
            return usage_error("this build has no PLC link: --modbus is not available");
#endif
        }
        if (!o.opcua.empty()) {
#ifdef PLANT_HAS_OPCUA
            const std::vector<plant::opcua::Link> links = plant::opcua::links_from_graph(g);
            std::cout << "opcua (the OPC UA link's node map, docs/plc.md):\n";
            if (links.empty()) std::cout << "(no opcua component: `plant run --opcua-port N` serves the Link object alone)\n";
            for (const auto& link : links)
                std::cout << plant::opcua::format_nodes(link, o.opcua == "csv" ? plant::opcua::MapFormat::Csv
                                                                                 : plant::opcua::MapFormat::Markdown);
#else
            return usage_error("this build has no OPC UA link: --opcua is not available");
#endif
        }
    }
    return ok ? 0 : 1;
}

#ifdef PLANT_HAS_RUNTIME
// The graph of a .plant (compiled) or a built .graph (loaded); false after printing why.
bool load_graph(const std::string& f, const Options& o, plant::graph::Graph& g, int& code) {
    if (f.size() > 6 && f.substr(f.size() - 6) == ".graph") {
        if (!o.sets.empty()) {
            code = usage_error("--set needs a .plant file; a built .graph has its values already");
            return false;
        }
        std::string err;
        if (!plant::graph::load_text_file(f, g, err)) {
            std::cerr << "plant: error: " << err << "\n";
            code = 1;
            return false;
        }
        return true;
    }
    plant::Compilation c;
    if (!compile(f, o, c)) {
        code = 1;
        return false;
    }
    g = std::move(c.graph);
    return true;
}

int cmd_run(const Options& o) {
    if (o.files.size() != 1) return usage_error("run takes one FILE (.plant or .graph)");
    const std::string& f = o.files[0];
    plant::graph::Graph g;
    int code = 0;
    if (!load_graph(f, o, g, code)) return code;
    std::vector<std::string> rest;
    std::string record;
    for (size_t i = 0; i < o.rest.size(); ++i) {
        if (o.rest[i] != "--record") {
            rest.push_back(o.rest[i]);
            continue;
        }
        if (i + 1 >= o.rest.size()) return usage_error("--record needs a FILE");
        record = o.rest[++i];
    }
#ifdef PLANT_HAS_SERVE
    plant::view::RecordOptions record_opt;
    const size_t before_record_flags = rest.size();
    std::string record_error;
    if (!plant::view::take_record_flags(rest, record_opt, record_error)) return usage_error(record_error);
    if (record.empty() && rest.size() != before_record_flags)
        return usage_error("--record-rate and --record-compress need --record FILE");
#endif
    plant::engine::RunLink* link = nullptr;
    std::vector<plant::engine::RunLink*> links;
    const std::string plant_dir = std::filesystem::path(f).parent_path().string();
#ifdef PLANT_HAS_OPCUA
    // Before the Modbus link's flags, which take --lockstep: it goes to the link the plant has.
    plant::opcua::LinkFlags ua_flags;
    std::string ua_error;
    if (!plant::opcua::take_link_flags(rest, ua_flags, ua_error)) return usage_error(ua_error);
    const bool ua_on = ua_flags.any() || plant::opcua::declares_link(g);
#else
    const bool ua_on = false;
#endif
#ifdef PLANT_HAS_PLC
    plant::plc::LinkFlags link_flags;
    std::string link_error;
    if (!plant::plc::take_link_flags(rest, link_flags, link_error)) return usage_error(link_error);
    const bool lockstep = link_flags.server.lockstep;
    const bool modbus_on = plant::plc::declares_link(g) || link_flags.port_given || link_flags.host_given || (lockstep && !ua_on);
    if (modbus_on && ua_on && lockstep)
        return usage_error("--lockstep: the plant is served over Modbus and OPC UA; lock-step takes one link "
                           "(leave out --modbus-port, or the opcua component)");
    std::unique_ptr<plant::plc::ServerLink> server;
    if (modbus_on && !(server = plant::plc::start_link(g, link_flags, std::cerr, link_error))) {
        std::cerr << "plant run: error: " << link_error << "\n";
        return 1;
    }
    if (server) links.push_back(server.get());
#endif
#ifdef PLANT_HAS_OPCUA
    std::unique_ptr<plant::opcua::ServerLink> ua;
    if (ua_on && !(ua = plant::opcua::start_link(g, ua_flags, plant_dir, "plant run", std::cerr, ua_error))) {
        std::cerr << "plant run: error: " << ua_error << "\n";
        return 1;
    }
    if (ua) links.push_back(ua.get());
#endif
    plant::engine::LinkChain chain(links);
    link = links.size() > 1 ? &chain : links.empty() ? nullptr : links[0];
    if (record.empty()) return plant::engine::run_main(g, rest, std::cout, std::cerr, nullptr, link);
#ifdef PLANT_HAS_SERVE
    plant::view::ModelDirs dirs;
    dirs.plant_dir = std::filesystem::path(f).parent_path().string();
    dirs.stdlib_dir = stdlib_of(o);
    plant::view::Recorder rec(g, record, dirs, record_opt);
    if (!rec.ok()) {
        std::cerr << "plant run: error: --record: cannot write '" << record << "'\n";
        return 2;
    }
    return plant::engine::run_main(g, rest, std::cout, std::cerr, &rec, link);
#else
    return usage_error("this build has no viewer: --record is not available");
#endif
}

#ifdef PLANT_HAS_SERVE
int cmd_serve(const Options& o) {
    if (o.files.size() != 1) return usage_error("serve takes one FILE (.plant, .graph, or a recording with --replay)");
    const std::string& f = o.files[0];
    if (std::find(o.rest.begin(), o.rest.end(), "--replay") != o.rest.end()) {
        if (!o.sets.empty()) return usage_error("--set does not apply to a replay");
        return plant::view::serve_main(nullptr, f, o.rest, std::cout, std::cerr, nullptr, stdlib_of(o));
    }
    plant::graph::Graph g;
    int code = 0;
    if (!load_graph(f, o, g, code)) return code;
    std::vector<std::string> rest = o.rest;
    plant::engine::RunLink* link = nullptr;
#ifdef PLANT_HAS_OPCUA
    plant::opcua::LinkFlags ua_flags;
    std::string ua_error;
    if (!plant::opcua::take_link_flags(rest, ua_flags, ua_error)) return usage_error(ua_error);
    if (ua_flags.lockstep) return usage_error("--lockstep: plant serve runs paced by the wall clock; lock-step is plant run's");
    std::unique_ptr<plant::opcua::ServerLink> ua;
    if ((ua_flags.any() || plant::opcua::declares_link(g)) &&
        !(ua = plant::opcua::start_link(g, ua_flags, std::filesystem::path(f).parent_path().string(), "plant serve",
                                        std::cerr, ua_error))) {
        std::cerr << "plant serve: error: " << ua_error << "\n";
        return 1;
    }
    link = ua.get();
#endif
    return plant::view::serve_main(&g, f, rest, std::cout, std::cerr, link, stdlib_of(o));
}
#endif
#endif

}  // namespace

int run_command(int argc, char** argv);

// Whatever escapes a command (a library's exception: a bug of ours, or memory running out)
// is an internal error with its own exit code, never an abort.
int main(int argc, char** argv) {
    try {
        return run_command(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "plant: internal error: " << e.what() << "\n(please report it, with the input that caused it)\n";
    } catch (...) {
        std::cerr << "plant: internal error: an unknown exception\n";
    }
    return 3;
}

int run_command(int argc, char** argv) {
#ifdef PLANT_HAS_PLC
    plant::plc::register_modbus_kind();  // the plugin kinds this program has (docs/architecture.md)
#endif
#ifdef PLANT_HAS_OPCUA
    plant::opcua::register_opcua_kind();
#endif
#ifdef PLANT_HAS_FAULTS
    plant::faults::register_faults_kind();
    plant::faults::register_operable_kind();
#endif
#ifdef PLANT_HAS_PANEL
    plant::panel::register_panel_kinds();
#endif
    std::vector<std::string> args(argv + 1, argv + argc);
    Options o;
    if (args.empty()) {
        std::cerr << kUsage;
        return 2;
    }
    if (args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
        std::cout << kUsage;
        return 0;
    }
    o.command = args[0];
    // `plant sweep` has options of its own (compiler/driver/sweep).
    if (o.command == "sweep") return plant::sweep::sweep_main({args.begin() + 1, args.end()}, std::cout, std::cerr);
    if (o.command == "fmt") return plant::formatter::fmt_main({args.begin() + 1, args.end()}, std::cin, std::cout, std::cerr);
    if (o.command == "lsp") {  // a language server on stdin/stdout: docs/editors.md
        std::ios::sync_with_stdio(false);
        return plant::lsp::lsp_main({args.begin() + 1, args.end()}, std::cin, std::cout, std::cerr,
                                    plant::default_stdlib_dir());
    }
    for (size_t i = 1; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&](const std::string& flag) -> std::string {
            if (a.size() > flag.size() && a.compare(0, flag.size() + 1, flag + "=") == 0) return a.substr(flag.size() + 1);
            if (i + 1 < args.size()) return args[++i];
            return "";
        };
        if (a == "-h" || a == "--help") o.help = true;
        else if (a == "--slots" && o.command == "info") o.slots = true;
        else if (a == "--schedule" && o.command == "info") o.schedule = true;
        else if ((a == "--modbus" || a == "--modbus=csv") && o.command == "info") o.modbus = a == "--modbus" ? "md" : "csv";
        else if ((a == "--opcua" || a == "--opcua=csv") && o.command == "info") o.opcua = a == "--opcua" ? "md" : "csv";
        else if (a == "--full" && o.command == "graph") o.full = true;
        else if (a == "--object" && o.command == "graph") {
            if (i + 1 >= args.size()) return usage_error("--object needs an object's dotted path");
            o.object = args[++i];
            o.has_object = true;
        }
        else if (a == "-o" || a.rfind("--output", 0) == 0) o.out = value(a == "-o" ? "-o" : "--output");
        else if (a.rfind("--emit", 0) == 0) o.emit = value("--emit");
        else if (a.rfind("--stdlib", 0) == 0) o.stdlib = value("--stdlib");
        else if (a == "--set" || a.rfind("--set=", 0) == 0) {
            if (a == "--set" && i + 1 >= args.size()) return usage_error("--set needs NAME=VALUE");
            o.sets.push_back(value("--set"));
        }
        else if (a.rfind("--diagnostics", 0) == 0) {
            std::string v = value("--diagnostics");
            if (v != "json" && v != "text") return usage_error("--diagnostics takes text or json");
            o.json = v == "json";
        } else if (a.rfind("--color", 0) == 0) (void)value("--color");
        else if ((o.command == "run" || o.command == "serve") && a.size() > 1 && a[0] == '-') {
            o.rest.push_back(a);
            // Flags of `run` and `serve` that take a value.
            static const char* kWithValue[] = {"--for", "--rate", "--trace", "--events", "--event", "--seed",
                                               "--trace-rate", "--broadphase", "--threads", "--steady-transport", "--record",
                                               "--record-rate", "--record-compress",
                                               "--port", "--host", "--viewer", "--models", "--speed",
                                               "--modbus-port", "--modbus-host", "--opcua-port", "--opcua-host",
                                               "--opcua-pki", "--opcua-users"};
            for (const char* w : kWithValue)
                if (a == w && i + 1 < args.size()) o.rest.push_back(args[++i]);
        } else if (a.size() > 1 && a[0] == '-') return usage_error("unknown option '" + a + "'");
        else o.files.push_back(a);
    }
    if (o.emit != "" && o.emit != "ast" && o.emit != "graph") return usage_error("--emit takes ast or graph");
    if (o.command == "check") {
        if (o.help) return std::cout << kCheckHelp, 0;
        return cmd_check(o);
    }
    if (o.command == "build") {
        if (o.help) return std::cout << kBuildHelp, 0;
        return cmd_build(o);
    }
    if (o.command == "graph") {
        if (o.help) return std::cout << kGraphHelp, 0;
        return cmd_graph(o);
    }
    if (o.command == "info") {
        if (o.help) return std::cout << kInfoHelp, 0;
        return cmd_info(o);
    }
    if (o.command == "run") {
#ifdef PLANT_HAS_RUNTIME
        if (o.help) return std::cout << kRunHelp, 0;
        return cmd_run(o);
#else
        return usage_error("this build has no runtime");
#endif
    }
    if (o.command == "serve") {
#ifdef PLANT_HAS_SERVE
        if (o.help) return std::cout << kServeHelp, 0;
        return cmd_serve(o);
#else
        return usage_error("this build has no viewer server");
#endif
    }
    return usage_error("unknown command '" + o.command + "'");
}
