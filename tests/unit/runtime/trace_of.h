// A run of `steps` steps as its CSV trace, to compare runs byte for byte.
#pragma once

#include "engine/engine.h"
#include "engine/trace.h"

#include <sstream>
#include <string>

namespace plant::test {

inline std::string trace_of(const graph::Graph& g, int steps, engine::Options opt = {},
                            engine::TraceSelect sel = {}) {
    engine::Engine e(g, opt);
    std::ostringstream out;
    engine::TraceWriter w(e, engine::trace_columns(g, sel), out);
    w.header();
    for (int i = 0; i < steps; ++i) {
        e.step();
        w.row();
    }
    w.flush();
    return out.str();
}

}  // namespace plant::test
