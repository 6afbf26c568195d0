#include "dot/dot.h"
#include "graph/kinds.h"

#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

using namespace plant::graph;

namespace {

int put_slot(Graph& g, int comp, std::string_view name, SlotType type, Dir dir) {
    Slot s;
    s.name = g.intern(name);
    s.type = type;
    s.dir = dir;
    s.comp = CompId(comp);
    g.slots.push_back(s);
    g.comps[CompId(comp)].slot_num++;
    return static_cast<int>(g.slots.size()) - 1;
}

int put_comp(Graph& g, int owner, CompKind kind, std::string_view name, int detail = -1) {
    Comp c;
    c.name = g.intern(name);
    c.kind = kind;
    c.owner = DoId(owner);
    c.slot_adr = next_adr(g.slots);
    c.detail.v = detail;
    g.comps.push_back(c);
    int id = static_cast<int>(g.comps.size()) - 1;
    for (const SlotSpec& s : fixed_slots(kind)) put_slot(g, id, s.name, s.type, s.dir);
    return id;
}

int slot_of(const Graph& g, int comp, std::string_view name) {
    const Comp& c = g.comps[CompId(comp)];
    for (SlotId s : children(c.slot_adr, c.slot_num))
        if (g.str(g.slots[s].name) == name) return s.v;
    FAIL("no slot ", name);
    return -1;
}

// A plant with one switch-like DO: a body, a trigger, a two-place net and, in the
// root, an AND connector; names carry the characters DOT treats specially.
Graph sample() {
    Graph g;
    g.plant = g.intern("Demo");
    Do root;
    root.path = g.intern("");
    root.parent = {};
    g.dos.push_back(root);
    Do sw;
    sw.path = g.intern("sw.\"a\"[1]");
    sw.parent = DoId(0);
    g.dos.push_back(sw);
    g.do_types.push_back({g.intern("Bottle"), 1, {}});

    int body = put_comp(g, 1, CompKind::Body, "blade");
    int eye = put_comp(g, 1, CompKind::Trigger, "eye|<1>");
    int net = put_comp(g, 1, CompKind::State, "net");
    for (std::string_view place : {"Base", "Work\\"}) {
        Place p;
        p.comp = CompId(net);
        p.name = g.intern(place);
        p.initial = place == "Base" ? 1 : 0;
        std::string n(place);
        p.put_slot = SlotId(put_slot(g, net, n + ".put", SlotType::Void, Dir::In));
        p.entered_slot = SlotId(put_slot(g, net, n + ".entered", SlotType::Void, Dir::Out));
        p.tokens_slot = SlotId(put_slot(g, net, n + ".tokens", SlotType::Int, Dir::Out));
        g.places.push_back(p);
    }
    g.arcs.push_back({PlaceId(0), 2});
    g.arcs.push_back({PlaceId(1), 1});
    Transition t;
    t.comp = CompId(net);
    t.name = g.intern("tw");
    t.in_adr = Adr<Arc>(0);
    t.in_num = 1;
    t.out_adr = Adr<Arc>(1);
    t.out_num = 1;
    t.fired_slot = SlotId(put_slot(g, net, "tw.fired", SlotType::Void, Dir::Out));
    g.transitions.push_back(t);

    int go = put_comp(g, 0, CompKind::Logic, "go", 0);
    int in0 = put_slot(g, go, "in0", SlotType::Void, Dir::In);
    int in1 = put_slot(g, go, "in1", SlotType::Void, Dir::In);
    g.logic_inputs.push_back({SlotId(in0), false});
    g.logic_inputs.push_back({SlotId(in1), true});
    g.logics.push_back({CompId(go), LogicOp::And, Adr<LogicIn>(0), 2, SlotId(slot_of(g, go, "out"))});

    Flow f;
    f.from = SlotId(slot_of(g, eye, "on_enter"));
    f.to = SlotId(in1);
    f.from_access = f.to_access = AccessId{};
    g.flows.push_back(f);  // 0: into the negated input
    f.from = SlotId(slot_of(g, go, "out"));
    f.to = g.places[PlaceId(1)].put_slot;
    g.flows.push_back(f);  // 1: connector puts a token
    f.from = g.places[PlaceId(1)].entered_slot;
    f.to = SlotId(slot_of(g, body, "collision_on"));
    f.cond = Cond::Both;
    f.once = true;
    g.flows.push_back(f);  // 2: non-default condition, singular
    Access a;
    a.ref_slot = SlotId(slot_of(g, eye, "object"));
    a.do_type = DoTypeId(0);
    a.member = g.intern("body.set_velocity");
    g.accesses.push_back(a);
    f = Flow{};
    f.from = SlotId(slot_of(g, body, "velocity"));
    f.to = a.ref_slot;  // a dynamic end holds its reference slot
    f.from_access = {};
    f.to_access = AccessId(0);
    g.flows.push_back(f);  // 3: into the object the trigger sees
    return g;
}

std::string render(const Graph& g) {
    std::ostringstream o;
    plant::dot::write_dot(g, o);
    return o.str();
}

// Braces outside quoted strings nest properly.
bool balanced(const std::string& s) {
    int depth = 0;
    bool quoted = false;
    for (size_t i = 0; i < s.size(); ++i) {
        if (quoted && s[i] == '\\') ++i;
        else if (s[i] == '"') quoted = !quoted;
        else if (!quoted && s[i] == '{') ++depth;
        else if (!quoted && s[i] == '}' && --depth < 0) return false;
    }
    return depth == 0 && !quoted;
}

}  // namespace

TEST_CASE("dot: clusters, component tables, nets, connectors and flows") {
    Graph g = sample();
    std::string out = render(g);
    INFO(out);
    CHECK(out.rfind("digraph \"Demo\" {\n", 0) == 0);
    CHECK(balanced(out));
    CHECK(out == render(g));  // deterministic

    CHECK(out.find("  subgraph \"cluster_do0\" {\n    label=\"Demo\";\n") != std::string::npos);
    CHECK(out.find("subgraph \"cluster_do1\" {\n      label=\"sw.\\\"a\\\"[1]\";\n") != std::string::npos);
    // Components are tables: inputs left, the component in the middle, outputs right.
    CHECK(out.find("\"c0\" [shape=plaintext, label=<<TABLE ") != std::string::npos);
    CHECK(out.find("<TR><TD PORT=\"s0\">set_pose</TD><TD ROWSPAN=\"9\">body blade</TD><TD PORT=\"s9\">pose</TD></TR>") !=
          std::string::npos);
    // Names are escaped for HTML-like labels.
    CHECK(out.find("<TD ROWSPAN=\"5\">trigger eye|&lt;1&gt;</TD><TD PORT=\"s14\">on_enter</TD>") != std::string::npos);
    CHECK(out.find("subgraph \"cluster_net2\" {\n        label=\"state net\";\n") != std::string::npos);
    CHECK(out.find("\"p0\" [shape=circle, fixedsize=false, label=\"Base\\n1 token\"];") != std::string::npos);
    CHECK(out.find("\"p1\" [shape=circle, fixedsize=false, label=\"Work\\\\\"];") != std::string::npos);
    CHECK(out.find("\"t0\" [shape=box") != std::string::npos);
    CHECK(out.find("\"p0\" -> \"t0\" [label=\"2\"];") != std::string::npos);
    CHECK(out.find("\"t0\" -> \"p1\";") != std::string::npos);
    CHECK(out.find("\"c3\" [shape=diamond, width=0.4, height=0.4, fontsize=8, label=\"and\", xlabel=\"go\"];") !=
          std::string::npos);

    int on_enter = slot_of(g, 1, "on_enter"), on = slot_of(g, 0, "collision_on");
    CHECK(out.find("  \"c1\":\"s" + std::to_string(on_enter) +
                   "\":e -> \"c3\" [arrowhead=odot, headlabel=\"not\"];") != std::string::npos);
    CHECK(out.find("  \"c3\" -> \"p1\" [headlabel=\"put\"];") != std::string::npos);
    CHECK(out.find("  \"p1\" -> \"c0\":\"s" + std::to_string(on) +
                   "\":w [label=\"when both, once\", taillabel=\"entered\"];") != std::string::npos);
    CHECK(out.find("\"a0\" [shape=note, fontsize=9, label=\"Bottle.body.set_velocity\"];") !=
          std::string::npos);
    int velocity = slot_of(g, 0, "velocity");
    CHECK(out.find("  \"c0\":\"s" + std::to_string(velocity) + "\":e -> \"a0\" [style=dashed];") !=
          std::string::npos);
}

TEST_CASE("dot: an empty graph is still one digraph") {
    Graph g;
    std::string out = render(g);
    CHECK(out.rfind("digraph \"plant\" {", 0) == 0);
    CHECK(balanced(out));
}

TEST_CASE("dot: graphviz accepts the output") {
    if (std::system("command -v dot >/dev/null 2>&1") != 0) return;
    auto path = std::filesystem::temp_directory_path() /
                ("plant_dot_test_" + std::to_string(std::random_device{}()) + ".dot");
    {
        std::ofstream f(path);
        plant::dot::write_dot(sample(), f);
    }
    std::string cmd = "dot -Tsvg '" + path.string() + "' -o /dev/null";
    int rc = std::system(cmd.c_str());
    std::filesystem::remove(path);
    CHECK(rc == 0);
}
