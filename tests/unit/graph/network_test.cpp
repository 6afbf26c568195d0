// The logic network analysis (graph/network.h): a flow end's slots, and a cycle through
// dynamic ends and labels that W0503 and the runtime's cut agree on.
#include "../compiler/compile_helper.h"
#include "graph/network.h"
#include "graph/kinds.h"
#include "graph/text.h"
#include "paths.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

using namespace plant::graph;

namespace {

SlotId slot_at_path(const Graph& g, const std::string& path) {
    for (SlotId s : ids_of(g.slots))
        if (g.slot_path(s) == path) return s;
    FAIL("no slot " << path);
    return {};
}

std::vector<std::string> paths(const Graph& g, const std::vector<SlotId>& slots) {
    std::vector<std::string> out;
    for (SlotId s : slots) out.push_back(g.slot_path(s));
    return out;
}

}  // namespace

TEST_CASE("network: a dynamic end is every access target, a dynamic source also reads its reference") {
    plant::Compilation c;
    plant::test::compile_repo_file("tests/golden/lower/dynamic_access.plant", c);
    REQUIRE(c.ok());
    const Graph& g = c.graph;
    const SlotId object = slot_at_path(g, "seen.object");
    std::vector<SlotId> read, written;
    for (const Flow& f : g.flows) {
        if (f.from_access.valid()) {
            CHECK(f.from == object);  // the contract: from holds the reference slot
            each_read_slot(g, f, [&](SlotId s) { read.push_back(s); });
        }
        if (f.to_access.valid()) {
            CHECK(f.to == object);
            each_written_slot(g, f, [&](SlotId s) { written.push_back(s); });
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
    CHECK(n.delayed[0] == FlowId(0));
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

namespace {

// The analysis as its contract states it (graph/network.h), by brute force: an edge from
// every node that makes a slot active to every node that reads it, each slot on its own,
// smallest ready node first, a stuck walk to the smallest predecessor not gone. The
// analysis itself joins a dynamic end's slots into one group node; this is what it must
// equal.
Network network_by_slots(const Graph& g) {
    std::vector<Node> nodes;
    for (size_t f = 0; f < g.flows.size(); ++f) nodes.push_back({NodeKind::Flow, int32_t(f)});
    for (size_t l = 0; l < g.logics.size(); ++l) nodes.push_back({NodeKind::Logic, int32_t(l)});
    for (size_t c = 0; c < g.comps.size(); ++c)
        if (g.comps[CompId(c)].kind == CompKind::Router) nodes.push_back({NodeKind::Router, int32_t(c)});
    for (size_t l = 0; l < g.labels.size(); ++l) nodes.push_back({NodeKind::Label, int32_t(l)});
    const size_t nn = nodes.size();
    IdVector<SlotId, std::vector<int32_t>> makes(g.slots.count()), reads(g.slots.count()), target_reads(g.slots.count());
    for (size_t n = 0; n < nn; ++n) {
        const Node& node = nodes[n];
        if (node.kind == NodeKind::Flow) {
            const Flow& f = g.flows[node.flow()];
            each_written_slot(g, f, [&](SlotId x) {
                makes[x].push_back(int32_t(n));
                if (f.cond != Cond::Source) target_reads[x].push_back(int32_t(n));
            });
            each_read_slot(g, f, [&](SlotId x) { reads[x].push_back(int32_t(n)); });
        } else if (node.kind == NodeKind::Logic) {
            const Logic& l = g.logics[node.logic()];
            for (Id<LogicIn> i : children(l.in_adr, l.in_num)) reads[g.logic_inputs[i].slot].push_back(int32_t(n));
            makes[l.out_slot].push_back(int32_t(n));
        } else if (node.kind == NodeKind::Router) {
            reads[g.comps[node.router()].slot_adr + routerslot::query].push_back(int32_t(n));
            for (const Route& r : g.routes)
                if (r.comp == node.router()) makes[r.out_slot].push_back(int32_t(n));
        } else {
            const Comp& c = g.comps[g.labels[node.label()].comp];
            reads[c.slot_adr + labelslot::set].push_back(int32_t(n));
            makes[c.slot_adr + labelslot::value].push_back(int32_t(n));
        }
    }
    std::vector<std::vector<int32_t>> pred(nn);
    for (SlotId x : ids_of(g.slots)) {
        for (int32_t p : makes[x])
            for (int32_t r : reads[x])
                if (p != r) pred[size_t(r)].push_back(p);
        for (int32_t r : target_reads[x])
            for (int32_t p : makes[x])
                if (std::find(target_reads[x].begin(), target_reads[x].end(), p) == target_reads[x].end())
                    pred[size_t(r)].push_back(p);
    }
    Network net;
    std::vector<uint8_t> gone(nn, 0);
    auto waits = [&](size_t n) {
        return std::any_of(pred[n].begin(), pred[n].end(), [&](int32_t p) { return !gone[size_t(p)]; });
    };
    for (size_t done = 0; done < nn; ++done) {
        size_t n = 0;
        while (n < nn && (gone[n] || waits(n))) ++n;
        if (n < nn) {  // the smallest node whose predecessors are all gone
            net.order.push_back(nodes[n]);
            gone[n] = 1;
            continue;
        }
        std::vector<int32_t> path, pos(nn, -1);
        int32_t cur = 0;
        while (gone[size_t(cur)]) ++cur;
        while (pos[size_t(cur)] < 0) {
            pos[size_t(cur)] = int32_t(path.size());
            path.push_back(cur);
            int32_t next = -1;
            for (int32_t p : pred[size_t(cur)])
                if (!gone[size_t(p)] && (next < 0 || p < next)) next = p;
            cur = next;
        }
        int32_t cut = -1;
        for (size_t i = size_t(pos[size_t(cur)]); i < path.size(); ++i)
            if (nodes[size_t(path[i])].kind == NodeKind::Flow && (cut < 0 || path[i] < cut)) cut = path[i];
        if (cut < 0) cut = cur;
        if (nodes[size_t(cut)].kind == NodeKind::Flow) net.delayed.push_back(nodes[size_t(cut)].flow());
        else net.order.push_back(nodes[size_t(cut)]);
        gone[size_t(cut)] = 1;
    }
    return net;
}

bool same_order(const Network& a, const Network& b) {
    auto same = [](const Node& x, const Node& y) { return x.kind == y.kind && x.index == y.index; };
    return a.delayed == b.delayed && std::equal(a.order.begin(), a.order.end(), b.order.begin(), b.order.end(), same);
}

}  // namespace

TEST_CASE("network: the order, with a dynamic end's slots as one node, is the order slot by slot, in every golden graph") {
    std::vector<std::string> files;
    for (const char* dir : {"/tests/golden", "/tests/plants"})
        for (const auto& e : std::filesystem::recursive_directory_iterator(std::string(PLANT_SOURCE_DIR) + dir))
            if (e.is_regular_file() && e.path().extension() == ".graph") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    int compared = 0, dynamic = 0, cut = 0;
    for (const std::string& file : files) {
        CAPTURE(file);
        Graph g;
        std::string error;
        if (!load_text_file(file, g, error)) continue;  // a golden of a refused graph
        const Network n = analyse_network(g);
        CHECK(same_order(n, network_by_slots(g)));
        ++compared;
        dynamic += !g.accesses.empty();
        cut += !n.delayed.empty();
    }
    MESSAGE(compared, " graphs, ", dynamic, " with dynamic ends, ", cut, " with a cycle cut");
    CHECK(compared > 50);
    CHECK(dynamic >= 5);
    CHECK(cut >= 2);
}

TEST_CASE("network: flows reading and writing through dynamic ends are ordered as slot by slot") {
    // The second flow reads every tag's value and may set each tag's label, whose value the
    // first flow reads through the same kind of end.
    plant::Compilation c;
    plant::test::compile_text(R"(object Tag {
    label code { value = "x" }
}
plant P {
    t1: Tag
    t2: Tag
    trigger seen { extent = (5 cm, 5 cm, 5 cm); filter = Tag }
    label copy { value = "none" }
    flow (seen.object as Tag).code.value -> copy.set
    flow (seen.object as Tag).code.value -> (seen.object as Tag).code.set
}
)",
                              c, "dynamic_both.plant");
    REQUIRE(c.ok());
    const Network n = analyse_network(c.graph);
    CHECK(same_order(n, network_by_slots(c.graph)));
    CHECK(n.order.size() + n.delayed.size() == c.graph.flows.size() + c.graph.labels.size());
}

// Flow 0 may set every tag's code (a write group for the codes' `set`) and waits for label src;
// flow 1 reads every code's value through a read group.
const char* const kDynamicWrite = R"(object Tag {
    label code { value = "x" }
}
plant P {
    t1: Tag
    t2: Tag
    trigger seen { extent = (5 cm, 5 cm, 5 cm); filter = Tag }
    trigger other { extent = (5 cm, 5 cm, 5 cm); filter = Tag }
    label src { value = "F-1" }
    router r { "F-*" => f; * => g }
    flow src.value -> (seen.object as Tag).code.set
    flow (other.object as Tag).code.value -> r.query
}
)";

TEST_CASE("network: flows writing through a dynamic end stand as one write group, ordered as slot by slot") {
    // The first flow may set every tag's code (a write group for the codes' `set`); it waits for
    // label src, so without the group's edges each tag's label (which reads its `set`, and has
    // no other predecessor) would run before it. The router's flow reads every code's value
    // through a read group, after the labels.
    plant::Compilation c;
    plant::test::compile_text(kDynamicWrite, c, "dynamic_write.plant");
    REQUIRE(c.ok());
    const Network n = analyse_network(c.graph);
    CHECK(same_order(n, network_by_slots(c.graph)));
    CHECK(n.delayed.empty());
    auto at = [&](NodeKind kind, int32_t index) {
        for (size_t i = 0; i < n.order.size(); ++i)
            if (n.order[i].kind == kind && n.order[i].index == index) return int(i);
        return -1;
    };
    const int writer = at(NodeKind::Flow, 0), reader = at(NodeKind::Flow, 1);
    REQUIRE(writer >= 0);
    REQUIRE(reader >= 0);
    int labels = 0;
    for (Id<Label> l : ids_of(c.graph.labels)) {
        if (c.graph.comp_path(c.graph.labels[l].comp).find("code") == std::string::npos) continue;
        ++labels;
        CHECK(at(NodeKind::Label, l.v) > writer);
        CHECK(at(NodeKind::Label, l.v) < reader);
    }
    CHECK(labels == 2);
    // The bottling plant: its stations set each bottle's code through a dynamic end.
    plant::Compilation b;
    plant::CompileOptions opts;
    opts.stdlib_dir = PLANT_STDLIB_DIR;
    opts.overrides = {"lines=2"};
    plant::compile_file(std::string(PLANT_SOURCE_DIR) + "/plants/bottling.plant", opts, b);
    REQUIRE(b.ok());
    CHECK(same_order(analyse_network(b.graph), network_by_slots(b.graph)));
}

TEST_CASE("network: a write group feeding a read group, and a writer reading its own group, as slot by slot") {
    // No compiled plant has either (a flow reads outputs and writes inputs); a graph written by
    // hand may. The compiled graph is changed in memory: a flow reads one slot of the group it
    // writes, and another reads the written slots through a dynamic source of the same access.
    plant::Compilation c;
    plant::test::compile_text(kDynamicWrite, c, "dynamic_write_by_hand.plant");
    REQUIRE(c.ok());
    REQUIRE(c.graph.flows.size() == 2);
    const Flow writer = c.graph.flows[FlowId(0)];
    REQUIRE(writer.to_access.valid());
    const Access& code_set = c.graph.accesses[writer.to_access];
    REQUIRE(code_set.target_num == 2);
    {  // the reader reads the codes' `set` through the writer's access: a write group, then a read group
        Graph g = c.graph;
        g.flows[FlowId(1)].from_access = writer.to_access;
        const Network n = analyse_network(g);
        CHECK(same_order(n, network_by_slots(g)));
        CHECK(n.delayed.empty());
    }
    {  // the writer reads t2's `set`, a slot of the group it writes
        Graph g = c.graph;
        g.flows[FlowId(0)].from = g.access_targets.slice(code_set.target_adr, code_set.target_num)[1].v;
        const Network n = analyse_network(g);
        CHECK(same_order(n, network_by_slots(g)));
    }
    {  // the writer reads the slots it writes, through its own access (a node's own slot is no
       // edge in the slot-by-slot order)
        Graph g = c.graph;
        g.flows[FlowId(0)].from_access = writer.to_access;
        g.flows[FlowId(0)].from = writer.to;
        const Network n = analyse_network(g);
        CHECK(same_order(n, network_by_slots(g)));
    }
}
