#include "dot/dot.h"

#include "graph/plugin.h"

#include <fmt/format.h>

#include <functional>
#include <map>
#include <set>

#include <algorithm>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace plant::dot {
namespace {

using namespace plant::graph;

// A loaded graph may be unsound (dot draws what it is given): every id is looked up checked.
template <class IdT, class T>
bool in_range(const IdVector<IdT, T>& v, std::type_identity_t<IdT> i) {  // an OptId<R> too
    return v.contains(i);
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

DoId owner_of_slot(const Graph& g, SlotId slot) {
    if (!in_range(g.slots, slot) || !in_range(g.comps, g.slots[slot].comp)) return DoId{};
    return g.comps[g.slots[slot].comp].owner;
}

// A component's kind as written in plant files: a plugin's own word (`faults`), not "plugin".
std::string kind_word(const Graph& g, CompId c) {
    const Comp& k = g.comps[c];
    if (const PluginId p = detail_of<Plugin>(k); k.kind == CompKind::Plugin && in_range(g.plugins, p)) return std::string(g.str(g.plugins[p].kind));
    return std::string(word(k.kind));
}

// One slot an entry of a plugin component's table names (`open 20 s => s2.bottle`, `coil 3
// => s1.to_working`): the component acts on it (it drives an input, or forces the slot) or
// reads it (an output it shows); `label` is the entry's word and key.
struct EntryEdge {
    CompId comp;
    SlotId slot;
    bool reads = false;   // slot -> component
    bool forces = false;  // an entry that may name either direction: it forces the slot
    std::string label;
};

std::vector<EntryEdge> entry_edges(const Graph& g) {
    std::vector<EntryEdge> out;
    for (const Plugin& p : g.plugins) {
        const CompId c = p.comp;
        if (!in_range(g.comps, c)) continue;
        const KindDesc* desc = plugin_of(g, c);
        for (Id<PluginEntry> e : children(p.entry_adr, p.entry_num)) {
            if (!in_range(g.plugin_entries, e)) continue;
            const PluginEntry& en = g.plugin_entries[e];
            const EntrySpec* spec = desc ? find_entry(*desc, g.str(en.word)) : nullptr;
            const bool time = spec && spec->key == EntryKey::Time;
            const std::string label = fmt::format("{} {:g}{}", g.str(en.word), en.key, time ? " s" : "");
            for (Id<PluginEntrySlot> at : children(en.slot_adr, en.slot_num)) {
                if (!in_range(g.plugin_entry_slots, at)) continue;
                const SlotId s = g.plugin_entry_slots[at].v;
                if (!in_range(g.slots, s)) continue;
                out.push_back({c, s, spec && !spec->any_dir && spec->target == Dir::Out, spec && spec->any_dir, label});
            }
        }
    }
    return out;
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
    Writer(const Graph& g, std::ostream& o, DoId only = DoId{}) : g_(g), o_(o), only_(only) {}
    void run();

private:
    void cluster(DoId d, int depth);
    void component(CompId c, int depth);
    void net(CompId c, int depth);
    void access(AccessId a, int depth);
    void edges();
    std::string indent(int depth) const { return std::string(2 * depth, ' '); }
    std::string comp_label(CompId c) const { return kind_word(g_, c) + " " + std::string(g_.str(g_.comps[c].name)); }
    std::string ep(const End& e) const { return e.port.empty() ? e.node : e.node + ":" + e.port; }

    // With `only_` set: inside that object (itself or below it).
    bool inside(DoId d) const {
        if (!only_.valid()) return true;
        for (int32_t hops = 0; in_range(g_.dos, d) && hops <= g_.dos.count(); ++hops, d = g_.dos[d].parent)
            if (d == only_) return true;
        return false;
    }
    bool slot_inside(SlotId s) const { return !only_.valid() || inside(owner_of_slot(g_, s)); }

    const Graph& g_;
    std::ostream& o_;
    DoId only_;
    IdVector<DoId, std::vector<DoId>> child_dos_;
    IdVector<DoId, std::vector<CompId>> do_comps_;
    IdVector<DoId, std::vector<AccessId>> do_accesses_;
    std::vector<DoId> top_dos_;
    std::vector<CompId> top_comps_;
    std::vector<AccessId> top_accesses_;
    IdVector<DoId, char> drawn_;  // guards against a parent cycle in a loaded graph
    IdVector<SlotId, End> ends_;
};

void Writer::run() {
    const size_t nd = g_.dos.size();
    child_dos_.resize(nd);
    do_comps_.resize(nd);
    do_accesses_.resize(nd);
    drawn_.assign(nd, 0);
    for (DoId d : ids_of(g_.dos)) {
        const DoId p = g_.dos[d].parent;
        (in_range(g_.dos, p) && p != d ? child_dos_[p] : top_dos_).push_back(d);
    }
    for (CompId c : ids_of(g_.comps)) {
        const DoId d = g_.comps[c].owner;
        (in_range(g_.dos, d) ? do_comps_[d] : top_comps_).push_back(c);
    }
    for (AccessId a : ids_of(g_.accesses)) {
        const DoId d = owner_of_slot(g_, g_.accesses[a].ref_slot);
        (in_range(g_.dos, d) ? do_accesses_[d] : top_accesses_).push_back(a);
    }

    ends_.assign(g_.slots.size(), {});
    for (SlotId s : ids_of(g_.slots)) {
        const CompId c = g_.slots[s].comp;
        if (!in_range(g_.comps, c)) continue;
        // The compass point keeps a flow on the side of the table its slot is drawn on.
        std::string port = q(fmt::format("s{}", s));
        port += g_.slots[s].dir == Dir::In ? ":w" : ":e";
        ends_[s] = {q(fmt::format("c{}", c)), port, {}};
        if (g_.comps[c].kind == CompKind::Logic) ends_[s].port.clear();
    }
    auto note = [&](SlotId slot, const std::string& node, std::string_view owner_name) {
        if (!in_range(g_.slots, slot)) return;
        std::string_view n = g_.str(g_.slots[slot].name);
        if (n.substr(0, owner_name.size()) == owner_name && n.size() > owner_name.size() &&
            n[owner_name.size()] == '.')
            n.remove_prefix(owner_name.size() + 1);  // "BasePos.entered" -> "entered"
        ends_[slot] = {node, {}, std::string(n)};
    };
    for (PlaceId p : ids_of(g_.places)) {
        const Place& pl = g_.places[p];
        std::string node = q(fmt::format("p{}", p));
        for (SlotId s : {pl.put_slot, pl.entered_slot, pl.tokens_slot}) note(s, node, g_.str(pl.name));
    }
    for (TransitionId t : ids_of(g_.transitions))
        note(g_.transitions[t].fired_slot, q(fmt::format("t{}", t)), g_.str(g_.transitions[t].name));

    std::string_view plant = g_.str(g_.plant);
    o_ << "digraph " << q(plant.empty() ? "plant" : plant) << " {\n"
       << "  graph [rankdir=LR, compound=true, fontname=\"Helvetica\", fontsize=11];\n"
       << "  node [fontname=\"Helvetica\", fontsize=10];\n"
       << "  edge [fontname=\"Helvetica\", fontsize=9];\n";
    if (only_.valid()) {
        cluster(only_, 1);
    } else {
        for (DoId d : top_dos_) cluster(d, 1);
        for (CompId c : top_comps_) component(c, 1);
        for (AccessId a : top_accesses_) access(a, 1);
    }
    edges();
    o_ << "}\n";
}

void Writer::cluster(DoId d, int depth) {
    if (drawn_[d]) return;
    drawn_[d] = 1;
    const Do& x = g_.dos[d];
    std::string label(g_.str(x.path));
    if (!x.parent.valid() && label.empty()) label = g_.str(g_.plant);
    std::string in = indent(depth);
    o_ << in << "subgraph " << q(fmt::format("cluster_do{}", d)) << " {\n"
       << in << "  label=" << q(label) << ";\n";
    for (CompId c : do_comps_[d]) component(c, depth + 1);
    for (AccessId a : do_accesses_[d]) access(a, depth + 1);
    for (DoId child : child_dos_[d]) cluster(child, depth + 1);
    o_ << in << "}\n";
}

void Writer::component(CompId c, int depth) {
    const Comp& k = g_.comps[c];
    std::string in = indent(depth);
    std::string id = q(fmt::format("c{}", c));
    if (k.kind == CompKind::State) return net(c, depth);
    if (k.kind == CompKind::Logic) {
        std::string_view op = "logic";
        if (const LogicId l = detail_of<Logic>(k); in_range(g_.logics, l)) op = word(g_.logics[l].op);
        o_ << in << id << " [shape=diamond, width=0.4, height=0.4, fontsize=8, label=" << q(op)
           << ", xlabel=" << q(g_.str(k.name)) << "];\n";
        return;
    }
    // A table: inputs down the left, the component in the middle, outputs down the
    // right, each slot a port. (HTML-like labels, not records: graphviz loses flat
    // edges between record nodes.)
    std::vector<SlotId> ins, outs;
    for (SlotId s : children(k.slot_adr, k.slot_num))
        if (in_range(g_.slots, s)) (g_.slots[s].dir == Dir::In ? ins : outs).push_back(s);
    const size_t rows = std::max({ins.size(), outs.size(), size_t{1}});
    auto cell = [&](const std::vector<SlotId>& side, size_t r) {
        if (r >= side.size()) return std::string("<TD BORDER=\"0\"></TD>");
        return fmt::format("<TD PORT=\"s{}\">", side[r]) + html(g_.str(g_.slots[side[r]].name)) + "</TD>";
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

void Writer::net(CompId c, int depth) {
    std::string in = indent(depth);
    o_ << in << "subgraph " << q(fmt::format("cluster_net{}", c)) << " {\n"
       << in << "  label=" << q(comp_label(c)) << ";\n"
       << in << "  style=rounded;\n";
    for (PlaceId p : ids_of(g_.places)) {
        const Place& pl = g_.places[p];
        if (pl.comp != c) continue;
        std::string label(g_.str(pl.name));
        if (pl.initial > 0)
            label += "\n" + std::to_string(pl.initial) + (pl.initial == 1 ? " token" : " tokens");
        o_ << in << "  " << q(fmt::format("p{}", p)) << " [shape=circle, fixedsize=false, label="
           << q(label) << "];\n";
    }
    for (TransitionId t : ids_of(g_.transitions)) {
        const Transition& tr = g_.transitions[t];
        if (tr.comp != c) continue;
        std::string id = q(fmt::format("t{}", t));
        o_ << in << "  " << id << " [shape=box, height=0.25, style=filled, fillcolor=\"#dddddd\", label="
           << q(g_.str(tr.name)) << "];\n";
        auto arcs = [&](Adr<Arc> adr, int32_t num, bool consumed) {
            for (Id<Arc> a : children(adr, num)) {
                if (!in_range(g_.arcs, a) || !in_range(g_.places, g_.arcs[a].place)) continue;
                std::string place = q(fmt::format("p{}", g_.arcs[a].place));
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
void Writer::access(AccessId a, int depth) {
    const Access& x = g_.accesses[a];
    std::string type = in_range(g_.do_types, x.do_type) ? std::string(g_.str(g_.do_types[x.do_type].name))
                                                        : std::string("?");
    o_ << indent(depth) << q(fmt::format("a{}", a)) << " [shape=note, fontsize=9, label="
       << q(type + "." + std::string(g_.str(x.member))) << "];\n";
}

void Writer::edges() {
    for (AccessId a : ids_of(g_.accesses)) {
        const SlotId r = g_.accesses[a].ref_slot;
        if (!in_range(ends_, r) || ends_[r].node.empty() || !slot_inside(r)) continue;
        o_ << "  " << ep(ends_[r]) << " -> " << q(fmt::format("a{}", a))
           << " [style=dotted, arrowhead=none];\n";
    }
    // Logic inputs that are negated, so an edge into one can be marked.
    IdVector<SlotId, char> negated(g_.slots.count(), 0);
    for (const LogicIn& li : g_.logic_inputs)
        if (in_range(g_.slots, li.slot)) negated[li.slot] = li.negated;

    for (const Flow& f : g_.flows) {
        // A dynamic end is drawn at its reference slot, which from/to hold (the Flow contract).
        if (!slot_inside(f.from) || !slot_inside(f.to)) continue;
        End from, to;
        if (in_range(g_.accesses, f.from_access)) from = {q(fmt::format("a{}", f.from_access)), {}, {}};
        else if (in_range(ends_, f.from)) from = ends_[f.from];
        if (in_range(g_.accesses, f.to_access)) to = {q(fmt::format("a{}", f.to_access)), {}, {}};
        else if (in_range(ends_, f.to)) to = ends_[f.to];
        if (from.node.empty() || to.node.empty()) continue;

        std::vector<std::string> attrs;
        std::string label;
        if (f.cond != Cond::Source) label = "when " + std::string(word(f.cond));
        if (f.once) label += std::string(label.empty() ? "" : ", ") + "once";
        if (!label.empty()) attrs.push_back("label=" + q(label));
        if (f.from_access.valid() || f.to_access.valid()) attrs.push_back("style=dashed");
        if (!from.note.empty()) attrs.push_back("taillabel=" + q(from.note));
        if (!to.note.empty()) attrs.push_back("headlabel=" + q(to.note));
        if (!f.to_access.valid() && in_range(g_.slots, f.to) && negated[f.to])
            attrs.push_back("arrowhead=odot, headlabel=\"not\"");

        o_ << "  " << ep(from) << " -> " << ep(to);
        for (size_t i = 0; i < attrs.size(); ++i) o_ << (i == 0 ? " [" : ", ") << attrs[i];
        o_ << (attrs.empty() ? "" : "]") << ";\n";
    }
    // A plugin component's entries: what it drives or forces, and what it reads.
    for (const EntryEdge& e : entry_edges(g_)) {
        if (!inside(g_.comps[e.comp].owner) || !slot_inside(e.slot) || ends_[e.slot].node.empty()) continue;
        const End comp{q(fmt::format("c{}", e.comp)), {}, {}};
        const End& slot = ends_[e.slot];
        std::string attrs = "label=" + q(e.label) + ", style=dashed";
        if (e.forces) attrs += ", color=\"#b03030\", fontcolor=\"#b03030\"";
        if (!slot.note.empty()) attrs += std::string(e.reads ? ", taillabel=" : ", headlabel=") + q(slot.note);
        o_ << "  " << ep(e.reads ? slot : comp) << " -> " << ep(e.reads ? comp : slot) << " [" << attrs << "];\n";
    }
}

}  // namespace

// The overview: nodes for an object's children and own components, bundled flows.
class Overview {
public:
    Overview(const Graph& g, std::ostream& o) : g_(g), o_(o) {}

    void run() {
        const int32_t nd = g_.dos.count();
        IdVector<DoId, std::vector<DoId>> sub(nd);  // child objects
        std::vector<DoId> roots;
        for (DoId d : ids_of(g_.dos)) {
            const DoId p = g_.dos[d].parent;
            if (g_.dos[d].pool.valid()) continue;  // pooled objects (bottles) are not the plant's layout
            (in_range(g_.dos, p) && p != d ? sub[p] : roots).push_back(d);
        }
        DoId focus = roots.empty() ? DoId{} : roots[0];
        // A wrapper with one child object and no components of its own shows that child.
        for (int32_t hops = 0; focus.valid() && hops < nd; ++hops) {
            const auto& ch = sub[focus];
            if (ch.size() != 1 || g_.dos[focus].comp_num > 0) break;
            focus = ch[0];
        }
        // Node of every DO and component: the child of `focus` (or own component) it is in.
        node_of_do_.assign(g_.dos.size(), -1);
        std::string_view plant = g_.str(g_.plant);
        o_ << "digraph " << q(plant.empty() ? "plant" : plant) << " {\n"
           << "  graph [rankdir=TB, nodesep=0.2, ranksep=0.35, fontname=\"Helvetica\", fontsize=11, label="
           << q(focus.valid() ? overview_title(focus) : std::string("empty")) << ", labelloc=t];\n"
           << "  node [fontname=\"Helvetica\", fontsize=10];\n"
           << "  edge [fontname=\"Helvetica\", fontsize=7];\n";
        if (!focus.valid()) {
            o_ << "}\n";
            return;
        }
        std::vector<std::string> nodes;
        for (DoId c : sub[focus]) {
            nodes.push_back(fmt::format("d{}", c));
            const Do& x = g_.dos[c];
            const std::string path(g_.str(x.path));
            const std::string name = path.substr(path.rfind('.') == std::string::npos ? 0 : path.rfind('.') + 1);
            const std::string type = in_range(g_.do_types, x.type) ? std::string(g_.str(g_.do_types[x.type].name)) : "";
            o_ << "  " << q(fmt::format("d{}", c)) << " [shape=box, style=rounded, label=" << q(name + ": " + type)
               << ", tooltip=" << q(path) << "];\n";
            mark(c, c.v, sub);
        }
        const Do& f = g_.dos[focus];
        comp_node_.assign(g_.comps.size(), "");
        for (CompId c : children(f.comp_adr, f.comp_num)) {
            const Comp& k = g_.comps[c];
            const std::string id = fmt::format("c{}", c);
            comp_node_[c] = id;
            nodes.push_back(id);
            o_ << "  " << q(id) << " [shape=" << (k.kind == CompKind::Logic ? "diamond" : k.kind == CompKind::State ? "doublecircle" : "ellipse")
               << ", fontsize=9, label=" << q(kind_word(g_, c) + "\n" + std::string(g_.str(k.name))) << "];\n";
        }
        // Flows bundled per (from node, to node).
        std::map<std::pair<std::string, std::string>, std::vector<std::string>> bundles;
        // The entries of plugin components (a fault forcing a sensor, a PLC link's coil),
        // bundled apart from the flows: drawn dashed, forces in red.
        std::map<std::pair<std::string, std::string>, std::vector<std::string>> entries, forces;
        for (const Flow& fl : g_.flows) {
            const SlotId a = fl.from, b = fl.to;  // a dynamic end: its reference slot
            const std::string from = node_of_slot(a), to = node_of_slot(b);
            if (from.empty() || to.empty() || from == to) continue;
            // The target slot names the flow well enough at this scale ("query", "MoveToBasePos.put").
            bundles[{from, to}].push_back(std::string(g_.str(g_.slots[b].name)));
        }
        for (const EntryEdge& e : entry_edges(g_)) {
            const std::string comp = node_of_comp(e.comp), slot = node_of_slot(e.slot);
            if (comp.empty() || slot.empty() || comp == slot) continue;
            (e.forces ? forces : entries)[e.reads ? std::pair{slot, comp} : std::pair{comp, slot}].push_back(
                e.label + " " + std::string(g_.str(g_.slots[e.slot].name)));
        }
        // Objects without flows (belts, curves: joined by physics only) in rows of four, in a box.
        std::set<std::string> joined;
        for (const auto* b : {&bundles, &entries, &forces})
            for (const auto& [ends, names] : *b) joined.insert(ends.first), joined.insert(ends.second);
        std::vector<std::string> alone;
        for (const std::string& n : nodes)
            if (!joined.count(n)) alone.push_back(n);
        if (!alone.empty()) {
            o_ << "  subgraph cluster_alone {\n    label=\"without flows (joined by physics only)\"; style=dashed;\n";
            for (size_t r = 0; r < alone.size(); r += 4) {
                o_ << "    { rank=same;";
                for (size_t k = r; k < std::min(alone.size(), r + 4); ++k) o_ << " " << q(alone[k]) << ";";
                o_ << " }\n";
                if (r > 0) o_ << "    " << q(alone[r - 4]) << " -> " << q(alone[r]) << " [style=invis];\n";
            }
            o_ << "  }\n";
        }
        // The connected groups (and the box) in rows, so the drawing is about as wide as tall:
        // an invisible edge puts each group below the one a row before it.
        std::map<std::string, std::string> up;  // union-find over node names
        std::function<std::string(const std::string&)> find = [&](const std::string& n) {
            auto it = up.find(n);
            if (it == up.end() || it->second == n) return n;
            return it->second = find(it->second);
        };
        for (const std::string& n : nodes) up[n] = n;
        for (const auto* b : {&bundles, &entries, &forces})
            for (const auto& [ends, names] : *b) up[find(ends.first)] = find(ends.second);
        std::vector<std::string> groups;  // one member of each group, in node order
        std::set<std::string> seen;
        for (const std::string& n : nodes) {
            if (!joined.count(n)) continue;
            if (seen.insert(find(n)).second) groups.push_back(n);
        }
        if (!alone.empty()) groups.push_back(alone.back());
        // Groups are wider than tall (a switch with its routers and connectors): fewer per row.
        size_t per_row = 1;
        while (2 * per_row * per_row < groups.size()) ++per_row;
        for (size_t i = per_row; i < groups.size(); ++i)
            o_ << "  " << q(groups[i - per_row]) << " -> " << q(groups[i]) << " [style=invis, minlen=3];\n";
        auto draw = [&](const auto& bundled, const char* many, const char* style) {
            for (const auto& [ends, names] : bundled) {
                std::string label = names.size() <= 2 ? names[0] + (names.size() == 2 ? ", " + names[1] : "")
                                                      : std::to_string(names.size()) + " " + many;
                o_ << "  " << q(ends.first) << " -> " << q(ends.second) << " [label=" << q(label)
                   << (names.size() > 1 ? ", penwidth=2" : "") << style << "];\n";
            }
        };
        draw(bundles, "flows", "");
        draw(entries, "entries", ", style=dashed");
        draw(forces, "forces", ", style=dashed, color=\"#b03030\", fontcolor=\"#b03030\"");
        o_ << "}\n";
    }

private:
    std::string overview_title(DoId focus) const {
        const std::string path(g_.str(g_.dos[focus].path));
        const std::string type = in_range(g_.do_types, g_.dos[focus].type)
                                     ? std::string(g_.str(g_.do_types[g_.dos[focus].type].name))
                                     : std::string(g_.str(g_.plant));
        return (path.empty() ? type : path + ": " + type) +
               " (overview: plant graph --object PATH draws one object in full)";
    }
    void mark(DoId d, int32_t node, const IdVector<DoId, std::vector<DoId>>& sub) {
        std::vector<DoId> todo{d};
        while (!todo.empty()) {
            const DoId x = todo.back();
            todo.pop_back();
            if (node_of_do_[x] >= 0) continue;
            node_of_do_[x] = node;
            for (DoId c : sub[x]) todo.push_back(c);
        }
    }
    std::string node_of_slot(SlotId s) const {
        if (!in_range(g_.slots, s)) return {};
        return node_of_comp(g_.slots[s].comp);
    }
    // The focus's own component's node, or the node of the child object it is in.
    std::string node_of_comp(CompId c) const {
        if (!in_range(g_.comps, c)) return {};
        if (!comp_node_[c].empty()) return comp_node_[c];
        const DoId d = g_.comps[c].owner;
        if (!in_range(g_.dos, d) || node_of_do_[d] < 0) return {};
        return "d" + std::to_string(node_of_do_[d]);
    }

    const Graph& g_;
    std::ostream& o_;
    IdVector<DoId, int32_t> node_of_do_;  // the node: a child of the focus (its DO id)
    IdVector<CompId, std::string> comp_node_;
};

void write_dot(const Graph& g, std::ostream& o) { Writer(g, o).run(); }

bool write_dot_object(const Graph& g, std::string_view path, std::ostream& o) {
    for (DoId d : ids_of(g.dos))
        if (g.str(g.dos[d].path) == path) {
            Writer(g, o, d).run();
            return true;
        }
    return false;
}

void write_overview(const Graph& g, std::ostream& o) { Overview(g, o).run(); }

}  // namespace plant::dot
