// What the commands that compile a plant share: their flags (--set, --stdlib,
// --diagnostics, --color), compiling with them, and reading a graph from a .plant or a
// built .graph.
#pragma once

#include "app/cli.h"
#include "compiler.h"
#include "graph/graph.h"

#include <string>
#include <vector>

namespace plant::app {

struct CompileFlags {
    std::vector<std::string> sets;  // NAME=VALUE
    std::string stdlib;             // "": $PLANT_STDLIB or the bundled one
    std::string diagnostics = "text";
    std::string color;  // accepted, and diagnostics stay plain
};
void add_compile_flags(Cli& cli, CompileFlags& f);
// After parsing: the flags' values; -1 when they are fine, else the exit code (2).
int check_compile_flags(const Cli& cli, const CompileFlags& f, std::ostream& err);

std::string stdlib_of(const CompileFlags& f);
// Compiles `file`, printing its diagnostics on stderr; whether it has no error.
bool compile(const std::string& file, const CompileFlags& f, Compilation& c, bool require_plant = true);
// The graph of a .plant (compiled) or a built .graph (loaded); false after printing why,
// with the exit code in `code`.
bool load_graph(const Cli& cli, const std::string& file, const CompileFlags& f, graph::Graph& g, int& code);

}  // namespace plant::app
