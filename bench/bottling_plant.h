// The bundled bottling plant as the benches run it: compiled with `lines` lines, `bottles`
// per storage and a bottle set down every second, and kept as `plant run` keeps it (the
// graph; the program and its sources released); and its bottles in circulation.
#pragma once

#include "compiler.h"
#include "diag/diagnostic.h"
#include "engine/engine.h"
#include "graph/graph.h"

#include <cstdio>
#include <string>
#include <utility>

namespace plant::bench {

// False, with the diagnostics on stderr, if the plant does not compile.
inline bool compile_bottling(const std::string& path, int lines, int bottles, graph::Graph& g) {
    CompileOptions opt;
    opt.stdlib_dir = default_stdlib_dir();
    opt.overrides = {"lines=" + std::to_string(lines), "bottles=" + std::to_string(bottles), "feed_every=1s"};
    Compilation c;
    compile_file(path, opt, c);
    if (!c.ok()) {
        std::fprintf(stderr, "%s does not compile with lines=%d:\n%s", path.c_str(), lines,
                     render_all_text(c.sink.sorted(), c.sources).c_str());
        return false;
    }
    g = std::move(c.graph);
    return true;
}

// Objects issued by the sources and not yet taken by an exit.
inline long circulating(const engine::Engine& e, const graph::Graph& g) {
    long n = 0;
    for (graph::SourceId s : g.sources.ids()) n += long(e.issued(s));
    for (graph::ExitId x : g.exits.ids()) n -= long(e.taken(x));
    return n;
}

}  // namespace plant::bench
