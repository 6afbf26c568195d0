// The logic network analysis (graph/network.h): a flow end's slots, and a cycle through
// dynamic ends and labels that W0503 and the runtime's cut agree on.
#include "../compiler/compile_helper.h"
#include "graph/network.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <string>
#include <vector>

using namespace plant::graph;

namespace {

int32_t slot_at_path(const Graph& g, const std::string& path) {
    for (size_t s = 0; s < g.slots.size(); ++s)
        if (g.slot_path(int32_t(s)) == path) return int32_t(s);
    FAIL("no slot " << path);
    return -1;
}

std::vector<std::string> paths(const Graph& g, const std::vector<int32_t>& slots) {
    std::vector<std::string> out;
    for (int32_t s : slots) out.push_back(g.slot_path(s));
    return out;
}

}  // namespace

TEST_CASE("network: a dynamic end is every access target, a dynamic source also reads its reference") {
    plant::Compilation c;
    plant::test::compile_repo_file("tests/golden/lower/dynamic_access.plant", c);
    REQUIRE(c.ok());
    const Graph& g = c.graph;
    const int32_t object = slot_at_path(g, "seen.object");
    std::vector<int32_t> read, written;
    for (const Flow& f : g.flows) {
        if (f.from_access >= 0) {
            CHECK(f.from == object);  // the contract: from holds the reference slot
            each_read_slot(g, f, [&](int32_t s) { read.push_back(s); });
        }
        if (f.to_access >= 0) {
            CHECK(f.to == object);
            each_written_slot(g, f, [&](int32_t s) { written.push_back(s); });
        }
    }
    CHECK(paths(g, read) == std::vector<std::string>{"seen.object", "t1.code.value", "t2.code.value"});
    CHECK(paths(g, written) == std::vector<std::string>{"t1.code.set", "t2.code.set"});
}

TEST_CASE("network: a loop through a dynamic end and labels is cut at its lowest flow, and W0503 says where") {
    plant::Compilation c;
    plant::test::compile_text(R"(object Tag {
    label code { value = "x" }
}
plant P {
    t1: Tag
    trigger seen { extent = (5 cm, 5 cm, 5 cm); filter = Tag }
    label copy { value = "none" }
    flow (seen.object as Tag).code.value -> copy.set
    flow copy.value -> (seen.object as Tag).code.set
}
)",
                              c, "dynamic_loop.plant");
    REQUIRE(c.ok());
    const Network n = analyse_network(c.graph);
    REQUIRE(n.delayed.size() == 1);
    CHECK(n.delayed[0] == 0);
    CHECK(n.order.size() + n.delayed.size() == c.graph.flows.size() + c.graph.labels.size());
    CHECK(std::none_of(n.order.begin(), n.order.end(),
                       [](const Node& x) { return x.kind == NodeKind::Flow && x.index == 0; }));
    int warned = 0;
    for (const auto& d : c.sink.all())
        if (plant::info(d.id).code == "W0503") {
            ++warned;
            CHECK(d.message.find("label 'copy'") != std::string::npos);
            CHECK(d.message.find("label 'code'") != std::string::npos);
        }
    CHECK(warned == 1);
    const std::string text = network_text(c.graph, n);
    CHECK(text.find("flow 0 seen.object.code.value -> copy.set  (delayed: cuts a cycle)\n") != std::string::npos);
}
