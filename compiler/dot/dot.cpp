#include "dot/dot.h"

#include <algorithm>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace plant::dot {
namespace {

using namespace plant::graph;

template <class T>
bool in_range(const std::vector<T>& v, int32_t i) {
    return i >= 0 && static_cast<size_t>(i) < v.size();
}

// A DOT double-quoted string. Backslashes are doubled so that a name never forms an
// escape sequence of its own (\n, \N, \G ...).
std::string q(std::string_view s) {
    std::string r = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') r += '\\';
        if (c == '\n') r += "\\n";
        else r += c;
    }
    return r + "\"";
}

// Text inside an HTML-like label: the XML special characters escaped.
std::string html(std::string_view s) {
    std::string r;
    for (char c : s) {
        switch (c) {
        case '&': r += "&amp;"; break;
        case '<': r += "&lt;"; break;
        case '>': r += "&gt;"; break;
        case '"': r += "&quot;"; break;
        case '\n': r += ' '; break;
        default: r += c;
        }
    }
    return r;
}

// Where a slot is drawn: the node and, for component tables, the port; `note` names
// the slot when the node itself does not show it (places, transitions).
struct End {
    std::string node;
    std::string port;
    std::string note;
};

class Writer {
public:
    Writer(const Graph& g, std::ostream& o) : g_(g), o_(o) {}
    void run();

private:
    void cluster(int32_t d, int depth);
    void component(int32_t c, int depth);
    void net(int32_t c, int depth);
    void access(int32_t a, int depth);
    void edges();
    std::string indent(int depth) const { return std::string(2 * depth, ' '); }
    std::string comp_label(int32_t c) const {
        return std::string(word(g_.comps[c].kind)) + " " + std::string(g_.str(g_.comps[c].name));
    }
    std::string ep(const End& e) const { return e.port.empty() ? e.node : e.node + ":" + e.port; }

    const Graph& g_;
    std::ostream& o_;
    std::vector<std::vector<int32_t>> child_dos_, do_comps_, do_accesses_;
    std::vector<int32_t> top_dos_, top_comps_, top_accesses_;
    std::vector<char> drawn_;  // per DO, guards against a parent cycle in a loaded graph
    std::vector<End> ends_;    // per slot
};

int32_t owner_of_slot(const Graph& g, int32_t slot) {
    if (!in_range(g.slots, slot) || !in_range(g.comps, g.slots[slot].comp)) return -1;
    return g.comps[g.slots[slot].comp].owner;
}

void Writer::run() {
    size_t nd = g_.dos.size();
    child_dos_.resize(nd);
    do_comps_.resize(nd);
    do_accesses_.resize(nd);
    drawn_.assign(nd, 0);
    for (size_t d = 0; d < nd; ++d) {
        int32_t p = g_.dos[d].parent;
        (in_range(g_.dos, p) && p != static_cast<int32_t>(d) ? child_dos_[p] : top_dos_)
            .push_back(static_cast<int32_t>(d));
    }
    for (size_t c = 0; c < g_.comps.size(); ++c) {
        int32_t d = g_.comps[c].owner;
        (in_range(g_.dos, d) ? do_comps_[d] : top_comps_).push_back(static_cast<int32_t>(c));
    }
    for (size_t a = 0; a < g_.accesses.size(); ++a) {
        int32_t d = owner_of_slot(g_, g_.accesses[a].ref_slot);
        (in_range(g_.dos, d) ? do_accesses_[d] : top_accesses_).push_back(static_cast<int32_t>(a));
    }

    ends_.assign(g_.slots.size(), {});
    for (size_t s = 0; s < g_.slots.size(); ++s) {
        int32_t c = g_.slots[s].comp;
        if (!in_range(g_.comps, c)) continue;
        // The compass point keeps a flow on the side of the table its slot is drawn on.
        std::string port = q("s" + std::to_string(s));
        port += g_.slots[s].dir == Dir::In ? ":w" : ":e";
        ends_[s] = {q("c" + std::to_string(c)), port, {}};
        if (g_.comps[c].kind == CompKind::Logic) ends_[s].port.clear();
    }
    auto note = [&](int32_t slot, const std::string& node, std::string_view owner_name) {
        if (!in_range(g_.slots, slot)) return;
        std::string_view n = g_.str(g_.slots[slot].name);
        if (n.substr(0, owner_name.size()) == owner_name && n.size() > owner_name.size() &&
            n[owner_name.size()] == '.')
            n.remove_prefix(owner_name.size() + 1);  // "BasePos.entered" -> "entered"
        ends_[slot] = {node, {}, std::string(n)};
    };
    for (size_t p = 0; p < g_.places.size(); ++p) {
        const Place& pl = g_.places[p];
        std::string node = q("p" + std::to_string(p));
        for (int32_t s : {pl.put_slot, pl.entered_slot, pl.tokens_slot}) note(s, node, g_.str(pl.name));
    }
    for (size_t t = 0; t < g_.transitions.size(); ++t)
        note(g_.transitions[t].fired_slot, q("t" + std::to_string(t)), g_.str(g_.transitions[t].name));

    std::string_view plant = g_.str(g_.plant);
    o_ << "digraph " << q(plant.empty() ? "plant" : plant) << " {\n"
       << "  graph [rankdir=LR, compound=true, fontname=\"Helvetica\", fontsize=11];\n"
       << "  node [fontname=\"Helvetica\", fontsize=10];\n"
       << "  edge [fontname=\"Helvetica\", fontsize=9];\n";
    for (int32_t d : top_dos_) cluster(d, 1);
    for (int32_t c : top_comps_) component(c, 1);
    for (int32_t a : top_accesses_) access(a, 1);
    edges();
    o_ << "}\n";
}

void Writer::cluster(int32_t d, int depth) {
    if (drawn_[d]) return;
    drawn_[d] = 1;
    const Do& x = g_.dos[d];
    std::string label(g_.str(x.path));
    if (x.parent < 0 && label.empty()) label = g_.str(g_.plant);
    std::string in = indent(depth);
    o_ << in << "subgraph " << q("cluster_do" + std::to_string(d)) << " {\n"
       << in << "  label=" << q(label) << ";\n";
    for (int32_t c : do_comps_[d]) component(c, depth + 1);
    for (int32_t a : do_accesses_[d]) access(a, depth + 1);
    for (int32_t child : child_dos_[d]) cluster(child, depth + 1);
    o_ << in << "}\n";
}

void Writer::component(int32_t c, int depth) {
    const Comp& k = g_.comps[c];
    std::string in = indent(depth);
    std::string id = q("c" + std::to_string(c));
    if (k.kind == CompKind::State) return net(c, depth);
    if (k.kind == CompKind::Logic) {
        std::string_view op = "logic";
        if (in_range(g_.logics, k.detail)) op = word(g_.logics[k.detail].op);
        o_ << in << id << " [shape=diamond, width=0.4, height=0.4, fontsize=8, label=" << q(op)
           << ", xlabel=" << q(g_.str(k.name)) << "];\n";
        return;
    }
    // A table: inputs down the left, the component in the middle, outputs down the
    // right, each slot a port. (HTML-like labels, not records: graphviz loses flat
    // edges between record nodes.)
    std::vector<int32_t> ins, outs;
    for (int32_t s = k.slot_adr; s < k.slot_adr + k.slot_num; ++s)
        if (in_range(g_.slots, s)) (g_.slots[s].dir == Dir::In ? ins : outs).push_back(s);
    const size_t rows = std::max({ins.size(), outs.size(), size_t(1)});
    auto cell = [&](const std::vector<int32_t>& side, size_t r) {
        if (r >= side.size()) return std::string("<TD BORDER=\"0\"></TD>");
        return "<TD PORT=\"s" + std::to_string(side[r]) + "\">" + html(g_.str(g_.slots[side[r]].name)) + "</TD>";
    };
    std::string label = "<TABLE BORDER=\"0\" CELLBORDER=\"1\" CELLSPACING=\"0\" CELLPADDING=\"3\">";
    for (size_t r = 0; r < rows; ++r) {
        label += "<TR>" + cell(ins, r);
        if (r == 0) label += "<TD ROWSPAN=\"" + std::to_string(rows) + "\">" + html(comp_label(c)) + "</TD>";
        label += cell(outs, r) + "</TR>";
    }
    label += "</TABLE>";
    o_ << in << id << " [shape=plaintext, label=<" << label << ">];\n";
}

void Writer::net(int32_t c, int depth) {
    std::string in = indent(depth);
    o_ << in << "subgraph " << q("cluster_net" + std::to_string(c)) << " {\n"
       << in << "  label=" << q(comp_label(c)) << ";\n"
       << in << "  style=rounded;\n";
    for (size_t p = 0; p < g_.places.size(); ++p) {
        const Place& pl = g_.places[p];
        if (pl.comp != c) continue;
        std::string label(g_.str(pl.name));
        if (pl.initial > 0)
            label += "\n" + std::to_string(pl.initial) + (pl.initial == 1 ? " token" : " tokens");
        o_ << in << "  " << q("p" + std::to_string(p)) << " [shape=circle, fixedsize=false, label="
           << q(label) << "];\n";
    }
    for (size_t t = 0; t < g_.transitions.size(); ++t) {
        const Transition& tr = g_.transitions[t];
        if (tr.comp != c) continue;
        std::string id = q("t" + std::to_string(t));
        o_ << in << "  " << id << " [shape=box, height=0.25, style=filled, fillcolor=\"#dddddd\", label="
           << q(g_.str(tr.name)) << "];\n";
        auto arcs = [&](int32_t adr, int32_t num, bool consumed) {
            for (int32_t a = adr; a < adr + num; ++a) {
                if (!in_range(g_.arcs, a) || !in_range(g_.places, g_.arcs[a].place)) continue;
                std::string place = q("p" + std::to_string(g_.arcs[a].place));
                o_ << in << "  " << (consumed ? place : id) << " -> " << (consumed ? id : place);
                if (g_.arcs[a].weight > 1) o_ << " [label=" << q(std::to_string(g_.arcs[a].weight)) << "]";
                o_ << ";\n";
            }
        };
        arcs(tr.in_adr, tr.in_num, true);
        arcs(tr.out_adr, tr.out_num, false);
    }
    o_ << in << "}\n";
}

// A slot of an object known only at run time, drawn next to the slot holding it.
void Writer::access(int32_t a, int depth) {
    const Access& x = g_.accesses[a];
    std::string type = in_range(g_.do_types, x.do_type) ? std::string(g_.str(g_.do_types[x.do_type].name))
                                                        : std::string("?");
    o_ << indent(depth) << q("a" + std::to_string(a)) << " [shape=note, fontsize=9, label="
       << q(type + "." + std::string(g_.str(x.member))) << "];\n";
}

void Writer::edges() {
    for (size_t a = 0; a < g_.accesses.size(); ++a) {
        int32_t r = g_.accesses[a].ref_slot;
        if (!in_range(ends_, r) || ends_[r].node.empty()) continue;
        o_ << "  " << ep(ends_[r]) << " -> " << q("a" + std::to_string(a))
           << " [style=dotted, arrowhead=none];\n";
    }
    // Logic inputs that are negated, so an edge into one can be marked.
    std::vector<char> negated(g_.slots.size(), 0);
    for (const LogicIn& li : g_.logic_inputs)
        if (in_range(g_.slots, li.slot)) negated[li.slot] = li.negated;

    for (const Flow& f : g_.flows) {
        End from, to;
        if (in_range(g_.accesses, f.from_access)) from = {q("a" + std::to_string(f.from_access)), {}, {}};
        else if (in_range(ends_, f.from)) from = ends_[f.from];
        if (in_range(g_.accesses, f.to_access)) to = {q("a" + std::to_string(f.to_access)), {}, {}};
        else if (in_range(ends_, f.to)) to = ends_[f.to];
        if (from.node.empty() || to.node.empty()) continue;

        std::vector<std::string> attrs;
        std::string label;
        if (f.cond != Cond::Source) label = "when " + std::string(word(f.cond));
        if (f.once) label += std::string(label.empty() ? "" : ", ") + "once";
        if (!label.empty()) attrs.push_back("label=" + q(label));
        if (f.from_access >= 0 || f.to_access >= 0) attrs.push_back("style=dashed");
        if (!from.note.empty()) attrs.push_back("taillabel=" + q(from.note));
        if (!to.note.empty()) attrs.push_back("headlabel=" + q(to.note));
        if (f.to_access < 0 && in_range(g_.slots, f.to) && negated[f.to])
            attrs.push_back("arrowhead=odot, headlabel=\"not\"");

        o_ << "  " << ep(from) << " -> " << ep(to);
        for (size_t i = 0; i < attrs.size(); ++i) o_ << (i == 0 ? " [" : ", ") << attrs[i];
        o_ << (attrs.empty() ? "" : "]") << ";\n";
    }
}

}  // namespace

void write_dot(const Graph& g, std::ostream& o) { Writer(g, o).run(); }

}  // namespace plant::dot
