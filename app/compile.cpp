#include "app/compile.h"

#include "diag/diagnostic.h"
#include "graph/text.h"

#include <iostream>

namespace plant::app {

void add_compile_flags(Cli& cli, CompileFlags& f) {
    cli.values("--set", f.sets,
               "give the plant's parameter NAME the value VALUE, an expression with\nits unit (`--set k=4kg/s`, "
               "`--set \"mass=20 g\"`); repeatable",
               "NAME=VALUE", "NAME=VALUE");
    cli.value("--stdlib", f.stdlib, "where `import std.x` looks (default: $PLANT_STDLIB or the bundled\nstdlib)", "DIR",
              "a DIR");
    cli.value("--diagnostics", f.diagnostics, "text (default) or json", "FORMAT", "text or json");
    cli.value("--color", f.color, "never: diagnostics are plain text (always, for now)", "WHEN");
}

int check_compile_flags(const Cli& cli, const CompileFlags& f, std::ostream& err) {
    if (f.diagnostics != "json" && f.diagnostics != "text") return cli.usage_error(err, "--diagnostics takes text or json");
    return -1;
}

std::string stdlib_of(const CompileFlags& f) { return f.stdlib.empty() ? default_stdlib_dir() : f.stdlib; }

bool compile(const std::string& file, const CompileFlags& f, Compilation& c, bool require_plant) {
    CompileOptions opts;
    opts.require_plant = require_plant;
    opts.stdlib_dir = stdlib_of(f);
    opts.overrides = f.sets;
    compile_file(file, opts, c);
    auto sorted = c.sink.sorted();
    if (f.diagnostics == "json") std::cerr << render_json(sorted, c.sources);
    else if (!sorted.empty()) std::cerr << render_all_text(sorted, c.sources);
    return c.ok();
}

bool load_graph(const Cli& cli, const std::string& file, const CompileFlags& f, graph::Graph& g, int& code) {
    if (file.size() > 6 && file.substr(file.size() - 6) == ".graph") {
        if (!f.sets.empty()) {
            code = cli.usage_error(std::cerr, "--set needs a .plant file; a built .graph has its values already");
            return false;
        }
        std::string err;
        if (!graph::load_text_file(file, g, err)) {
            std::cerr << "plant: error: " << err << "\n";
            code = 1;
            return false;
        }
        return true;
    }
    Compilation c;
    if (!compile(file, f, c)) {
        code = 1;
        return false;
    }
    g = std::move(c.graph);
    return true;
}

}  // namespace plant::app
