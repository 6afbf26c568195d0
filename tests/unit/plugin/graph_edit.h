// What the plugin kinds' tests share: a slot found by its path, and a graph's text form
// loaded with one edit (the loader's error, "" when it loads).
#pragma once

#include "graph/graph.h"
#include "graph/text.h"

#include <doctest/doctest.h>

#include <sstream>
#include <string>
#include <string_view>

namespace plant::test {

inline graph::SlotId slot_of(const graph::Graph& g, std::string_view path) {
    for (graph::SlotId s : graph::ids_of(g.slots))
        if (g.slot_path(s) == path) return s;
    FAIL("no slot " << path);
    return {};
}

inline std::string load_edited(std::string text, std::string_view from, std::string_view to) {
    const size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
    graph::Graph g;
    std::string error;
    std::istringstream in(text);
    graph::read_text(in, g, error);
    return error;
}

}  // namespace plant::test
