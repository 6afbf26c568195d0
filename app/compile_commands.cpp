// The commands that compile a plant and print what it is: check, build, graph, info.
#include "app/command.h"
#include "app/compile.h"
#include "app/parts.h"
#include "ast/print.h"
#include "dot/dot.h"
#include "graph/network.h"
#include "graph/text.h"

#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>

namespace plant::app {

namespace {

bool write_output(const std::string& path, const std::string& text) {
    if (path.empty() || path == "-") {
        std::cout << text;
        return static_cast<bool>(std::cout);
    }
    std::ofstream f(path, std::ios::binary);
    f << text;
    return static_cast<bool>(f);
}

// A compiling command's command line: its own flags, then the shared ones (compile.h).
struct Line {
    Cli cli;
    CompileFlags flags;
    std::vector<std::string> files;
    Line(const char* command, const char* usage, const char* about) : cli(command, usage, about) {
        cli.errors_as("plant", std::string("plant ") + command + " --help");
    }
    // -1 to go on, else the exit code.
    int parse(const std::vector<std::string>& args) {
        add_compile_flags(cli, flags);
        cli.positionals(files);
        if (const int code = cli.parse(args, std::cout, std::cerr); code >= 0) return code;
        return check_compile_flags(cli, flags, std::cerr);
    }
};

int check_command(const std::vector<std::string>& args) {
    Line l("check", "[options] FILE...", R"(Parses and checks each FILE: names, slot types and directions, units, values and Petri
nets. Prints every diagnostic as file:line:col with the source line and a caret.
--set NAME=VALUE gives the plant's parameter NAME a value (checked against its type;
errors in VALUE are reported at --set:1:COL). Exit code: 0 no errors (warnings
allowed), 1 errors, 2 bad usage.)");
    std::string emit;
    l.cli.value("--emit", emit, "print the AST or the graph's text form to stdout", "ast|graph", "ast or graph");
    if (const int code = l.parse(args); code >= 0) return code;
    if (emit != "" && emit != "ast" && emit != "graph") return l.cli.usage_error(std::cerr, "--emit takes ast or graph");
    if (l.files.empty()) return l.cli.usage_error(std::cerr, "check needs at least one FILE");
    bool ok = true;
    for (const auto& f : l.files) {
        Compilation c;
        ok = compile(f, l.flags, c, false) && ok;
        if (emit == "ast") {
            for (const auto& m : c.program.modules) ast::print(*m.ast, c.sources, std::cout);
        } else if (emit == "graph" && c.ok()) {
            graph::write_text(c.graph, std::cout);
        }
    }
    return ok ? 0 : 1;
}

int build_command(const std::vector<std::string>& args) {
    Line l("build", "FILE -o OUT [options]", R"(Compiles FILE into the flat graph and writes its text form (stable, diffable, loadable
by `plant run OUT`) to OUT, or to stdout with `-o -`.)");
    std::string out;
    l.cli.value("-o,--output", out, "where the graph's text form goes (- for stdout)", "OUT");
    if (const int code = l.parse(args); code >= 0) return code;
    if (l.files.size() != 1) return l.cli.usage_error(std::cerr, "build takes one FILE");
    if (out.empty()) return l.cli.usage_error(std::cerr, "build needs -o OUT (use -o - for stdout)");
    Compilation c;
    if (!compile(l.files[0], l.flags, c)) return 1;
    if (!write_output(out, graph::to_text(c.graph))) {
        std::cerr << "plant: error: cannot write '" << out << "'\n";
        return 1;
    }
    return 0;
}

int graph_command(const std::vector<std::string>& args) {
    Line l("graph", "FILE [--object PATH | --full] [-o OUT] [options]", R"(Writes the compiled plant as Graphviz DOT. By default an overview: the plant's objects
(or, for a plant that wraps one line, the line's) as single nodes, its own components as
small nodes (a Petri net as one), and the flows between them bundled per pair of nodes.
Render with: plant graph FILE | dot -Tsvg -o plant.svg)");
    std::string out, object;
    bool full = false;
    const CLI::Option* has_object = l.cli.value(
        "--object", object,
        "that object in full: a cluster per object inside it, components as\ntables of their slots, flows as edges, "
        "each Petri net as places and\ntransitions",
        "PATH", "an object's dotted path");
    l.cli.flag("--full", full, "the whole plant so (large plants give very large drawings)");
    l.cli.value("-o,--output", out, "where the drawing goes (default stdout)", "OUT");
    if (const int code = l.parse(args); code >= 0) return code;
    if (l.files.size() != 1) return l.cli.usage_error(std::cerr, "graph takes one FILE");
    Compilation c;
    if (!compile(l.files[0], l.flags, c)) return 1;
    std::ostringstream dot;
    if (has_object->count()) {
        if (!dot::write_dot_object(c.graph, object, dot)) {
            std::cerr << "plant: error: --object: no object '" << object << "' (`plant info --slots` lists paths)\n";
            return 1;
        }
    } else if (full) {
        dot::write_dot(c.graph, dot);
    } else {
        dot::write_overview(c.graph, dot);
    }
    if (!write_output(out, dot.str())) {
        std::cerr << "plant: error: cannot write '" << out << "'\n";
        return 1;
    }
    return 0;
}

// The root file's plant parameters, as written: `  bottles: count = 40`.
void print_plant_params(const Compilation& c, std::ostream& out) {
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
void print_slots(const graph::Graph& g, std::ostream& out) {
    using namespace graph;
    IdVector<DoId, std::vector<PortId>> ports(g.dos.count());
    for (PortId p : ids_of(g.ports)) ports[g.ports[p].owner].push_back(p);
    auto line = [&](Dir dir, SlotType type, const std::string& path, const std::string& note) {
        out << "  " << (dir == Dir::In ? "in " : "out") << "  " << word(type)
            << std::string(size_t(std::max(1, 8 - int(word(type).size()))), ' ') << path << note << "\n";
    };
    for (DoId d : ids_of(g.dos)) {
        for (PortId p : ports[d]) {
            const Port& pt = g.ports[p];
            std::string to;
            for (const PortTarget& t : g.port_targets.slice(pt.target_adr, pt.target_num))
                to += (to.empty() ? "" : ", ") + g.slot_path(t.v);
            line(pt.dir, pt.type, g.port_path(p), (pt.dir == Dir::In ? "  (port => " : "  (port <= ") + to + ")");
        }
        const Do& o = g.dos[d];
        for (CompId c : children(o.comp_adr, o.comp_num)) {
            const Comp& cp = g.comps[c];
            for (SlotId sl : children(cp.slot_adr, cp.slot_num))
                line(g.slots[sl].dir, g.slots[sl].type, g.slot_path(sl), "");
        }
    }
}

int info_command(const std::vector<std::string>& args) {
    Line l("info", "[options] FILE...", R"(Compiles each FILE and prints one line of counts (objects, components, slots, flows,
connectors, places, transitions, bodies, force fields, triggers, warnings), then the
plant's parameters with their types and defaults (change them with --set NAME=VALUE).)");
    bool slots = false, schedule = false;
    l.cli.flag("--slots", slots,
               "also every input and output by its dotted path, direction and type:\nthe objects' declared ports and "
               "the components' slots (the paths\nevents address)");
    l.cli.flag("--schedule", schedule,
               "also the logic phase as the runtime runs it: one line per flow,\nconnector, router and label in "
               "order, then the flows delayed to\ncut a cycle (W0503)");
    std::vector<std::unique_ptr<Part>> all = parts();
    for (auto& p : all) p->add_flags(l.cli, Where::Info);
    if (const int code = l.parse(args); code >= 0) return code;
    std::string error;
    for (auto& p : all)
        if (!p->check(Where::Info, error)) return l.cli.usage_error(std::cerr, error);
    if (l.files.empty()) return l.cli.usage_error(std::cerr, "info needs at least one FILE");
    bool ok = true;
    for (const auto& f : l.files) {
        Compilation c;
        if (!compile(f, l.flags, c)) {
            ok = false;
            continue;
        }
        const auto& g = c.graph;
        std::cout << f << ": plant " << g.str(g.plant) << " - " << g.dos.size() << " objects, " << g.comps.size()
                  << " components, " << g.slots.size() << " slots, " << g.flows.size() << " flows, " << g.logics.size()
                  << " connectors, " << g.places.size() << " places, " << g.transitions.size() << " transitions, "
                  << g.bodies.size() << " bodies, " << g.fields.size() << " force fields, " << g.triggers.size()
                  << " triggers; " << c.sink.count(Severity::Warning) << " warnings\n";
        print_plant_params(c, std::cout);
        if (slots) {
            std::cout << "slots (direction, type, path; events address inputs by path):\n";
            print_slots(g, std::cout);
        }
        if (schedule) {
            std::cout << "logic phase (in order; a delayed flow acts in the next step):\n";
            std::cout << graph::network_text(g, graph::analyse_network(g));
        }
        for (auto& p : all) p->info(g, std::cout);
    }
    return ok ? 0 : 1;
}

}  // namespace

extern const Command kCheckCommand{"check", "check plant files; exit code 0 when there is no error", check_command};
extern const Command kBuildCommand{"build", "compile FILE and write the graph's text form to OUT (- for stdout)",
                                   build_command};
extern const Command kGraphCommand{"graph", "an overview of the plant as Graphviz DOT (--object PATH: one object in full)",
                                   graph_command};
extern const Command kInfoCommand{"info", "compile and print what each plant holds (objects, slots, flows, ...)",
                                  info_command};

}  // namespace plant::app
