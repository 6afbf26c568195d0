#include "graph/network.h"

#include "graph/kinds.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <functional>
#include <map>
#include <queue>

namespace plant::graph {

AccessGroups access_groups(const Graph& g) {
    // The compiler gives every access to one member of one type the same range of targets
    // (sema's finish_accesses), so a range is a group; a graph written by hand with equal
    // lists in two ranges has two groups, which orders the same, only with more nodes.
    AccessGroups out;
    std::map<std::pair<int32_t, int32_t>, int32_t> by_range;  // (target_adr, target_num) -> group
    for (size_t a = 0; a < g.accesses.size(); ++a) {
        const Access& ac = g.accesses[a];
        const auto [at, added] = by_range.try_emplace({ac.target_adr.v, ac.target_num}, int32_t(out.first.size()));
        if (added) out.first.push_back(int32_t(a));
        out.of.push_back(at->second);
    }
    return out;
}

namespace {

// The dependency graph: nodes, and who must run before whom. Ids from nodes.size() on
// are groups: the slots one kind of dynamic end may be (every bottle's label value, for
// the flows reading `(sw.bottle as Bottle).code`), each one node between those slots'
// producers and the flows that read through the end. Edges from each producer to each such
// reader made the network quadratic in a plant's size (83 lines of the bottling plant with
// 40 bottles per storage: 2.8 million edges, 4.2 million links, 70 MB of the compiler's
// peak); a group holds the same order (analyse_network releases it the moment its last
// producer is released, so each reader becomes ready exactly when it did).
struct Deps {
    std::vector<Node> nodes;
    std::vector<std::vector<int32_t>> succ, pred;  // nodes, then groups
};

Deps dependencies(const Graph& g) {
    Deps d;
    for (size_t f = 0; f < g.flows.size(); ++f) d.nodes.push_back({NodeKind::Flow, int32_t(f)});
    for (size_t l = 0; l < g.logics.size(); ++l) d.nodes.push_back({NodeKind::Logic, int32_t(l)});
    for (size_t c = 0; c < g.comps.size(); ++c)
        if (g.comps[c].kind == CompKind::Router) d.nodes.push_back({NodeKind::Router, int32_t(c)});
    for (size_t l = 0; l < g.labels.size(); ++l) d.nodes.push_back({NodeKind::Label, int32_t(l)});

    // Routers' outputs, by router (few: a list per router, not per component).
    std::vector<std::pair<int32_t, int32_t>> routes;  // (router comp, out slot), in route order
    for (const Route& r : g.routes) routes.emplace_back(r.comp, r.out_slot);
    std::stable_sort(routes.begin(), routes.end(), [](auto& a, auto& b) { return a.first < b.first; });

    const AccessGroups groups = access_groups(g);
    const std::vector<int32_t>& group_of = groups.of;
    const std::vector<int32_t>& group_access = groups.first;

    // Per slot: nodes that activate it, read it, or read it as their target's activity. Kept as
    // (slot, node) pairs sorted by slot, each slot's nodes in node order: memory for the links,
    // not for every slot (a pool of 1,000 bottles has 40,000 slots and no link). A read
    // through a dynamic end is a (group, node) pair instead. Counted first, then filled.
    const size_t nn = d.nodes.size();
    using Link = std::pair<int32_t, int32_t>;  // (slot or group, node)
    std::vector<Link> prod, read, tread, dyn;
    size_t counts[4] = {0, 0, 0, 0};
    auto links = [&](auto&& add) {
        for (size_t n = 0; n < nn; ++n) {
            const Node& node = d.nodes[n];
            const int32_t id = int32_t(n);
            switch (node.kind) {
            case NodeKind::Flow: {
                const Flow& f = g.flows[size_t(node.index)];
                each_written_slot(g, f, [&](int32_t x) {
                    add(0, x, id);
                    if (f.cond != Cond::Source) add(2, x, id);
                });
                if (f.from_access >= 0) {
                    add(1, g.accesses[size_t(f.from_access)].ref_slot.v, id);
                    add(3, group_of[size_t(f.from_access)], id);
                } else {
                    add(1, f.from.v, id);
                }
                break;
            }
            case NodeKind::Logic: {
                const Logic& l = g.logics[size_t(node.index)];
                for (int32_t i = 0; i < l.in_num; ++i) add(1, g.logic_inputs[size_t(l.in_adr + i)].slot, id);
                add(0, l.out_slot, id);
                break;
            }
            case NodeKind::Router: {
                add(1, g.comps[size_t(node.index)].slot_adr + routerslot::query, id);
                auto r = std::lower_bound(routes.begin(), routes.end(), node.index,
                                          [](const std::pair<int32_t, int32_t>& x, int32_t c) { return x.first < c; });
                for (; r != routes.end() && r->first == node.index; ++r) add(0, r->second, id);
                break;
            }
            case NodeKind::Label: {
                const Comp& c = g.comps[size_t(g.labels[size_t(node.index)].comp)];
                add(1, c.slot_adr + labelslot::set, id);
                add(0, c.slot_adr + labelslot::value, id);
                break;
            }
            }
        }
    };
    links([&](int list, int32_t, int32_t) { ++counts[list]; });
    std::vector<Link>* lists[4] = {&prod, &read, &tread, &dyn};
    for (int i = 0; i < 4; ++i) lists[i]->reserve(counts[i]);
    links([&](int list, int32_t x, int32_t id) { lists[list]->emplace_back(x, id); });
    // By slot, then node: as a stable sort by slot of lists made in node order, without its buffer.
    for (std::vector<Link>* v : lists) std::sort(v->begin(), v->end());

    const size_t ng = group_access.size();
    d.succ.resize(nn + ng);
    d.pred.resize(nn + ng);
    auto edge = [&](int32_t a, int32_t b) {
        if (a == b) return;
        d.succ[size_t(a)].push_back(b);
        d.pred[size_t(b)].push_back(a);
    };
    // Each slot with links, in slot order: [p0, p1) of prod, [r0, r1) of read, [t0, t1) of tread.
    size_t p0 = 0, r0 = 0, t0 = 0;
    while (p0 < prod.size() || r0 < read.size() || t0 < tread.size()) {
        int32_t x = INT32_MAX;
        if (p0 < prod.size()) x = std::min(x, prod[p0].first);
        if (r0 < read.size()) x = std::min(x, read[r0].first);
        if (t0 < tread.size()) x = std::min(x, tread[t0].first);
        size_t p1 = p0, r1 = r0, t1 = t0;
        while (p1 < prod.size() && prod[p1].first == x) ++p1;
        while (r1 < read.size() && read[r1].first == x) ++r1;
        while (t1 < tread.size() && tread[t1].first == x) ++t1;
        for (size_t i = p0; i < p1; ++i)
            for (size_t j = r0; j < r1; ++j) edge(prod[i].second, read[j].second);
        for (size_t j = t0; j < t1; ++j)
            for (size_t i = p0; i < p1; ++i) {
                bool also_tread = false;
                for (size_t k = t0; k < t1 && !also_tread; ++k) also_tread = tread[k].second == prod[i].second;
                if (!also_tread) edge(prod[i].second, tread[j].second);
            }
        p0 = p1, r0 = r1, t0 = t1;
    }
    // Each group: its producers (of any of its slots) before it, it before its readers. Where
    // a node is both (it reads a slot it may write), the group would make a cycle the direct
    // edges do not have: those producers and readers are joined directly, as each slot would.
    std::vector<int32_t> producers, readers;
    for (size_t k = 0, r = 0; k < ng; ++k) {
        readers.clear();
        for (; r < dyn.size() && dyn[r].first == int32_t(k); ++r)
            if (readers.empty() || readers.back() != dyn[r].second) readers.push_back(dyn[r].second);
        if (readers.empty()) continue;
        producers.clear();
        const Access& ac = g.accesses[size_t(group_access[k])];
        for (int32_t i = 0; i < ac.target_num; ++i) {
            const int32_t x = g.access_targets[size_t(ac.target_adr.v + i)].v;
            auto at = std::lower_bound(prod.begin(), prod.end(), Link{x, INT32_MIN});
            for (; at != prod.end() && at->first == x; ++at) producers.push_back(at->second);
        }
        std::sort(producers.begin(), producers.end());
        producers.erase(std::unique(producers.begin(), producers.end()), producers.end());
        bool both = false;
        for (int32_t n : readers) both = both || std::binary_search(producers.begin(), producers.end(), n);
        const int32_t group = int32_t(nn + k);
        for (int32_t p : producers) {
            if (both) {
                for (int32_t n : readers) edge(p, n);
            } else {
                edge(p, group);
            }
        }
        if (!both && !producers.empty())
            for (int32_t n : readers) edge(group, n);
    }
    return d;
}

int32_t comp_of(const Graph& g, const Node& n) {
    switch (n.kind) {
    case NodeKind::Logic: return g.logics[size_t(n.index)].comp;
    case NodeKind::Router: return n.index;
    case NodeKind::Label: return g.labels[size_t(n.index)].comp;
    case NodeKind::Flow: break;
    }
    return -1;
}

}  // namespace

Network analyse_network(const Graph& g) {
    Network net;
    const Deps d = dependencies(g);
    const size_t nn = d.nodes.size(), total = d.succ.size();

    // Kahn's algorithm, smallest ready node first; a group is released the moment it is ready.
    std::vector<int32_t> indeg(total);
    for (size_t n = 0; n < total; ++n) indeg[n] = int32_t(d.pred[n].size());
    std::vector<uint8_t> gone(total, 0);  // emitted or delayed (a group: released)
    std::priority_queue<int32_t, std::vector<int32_t>, std::greater<>> ready;
    for (size_t n = 0; n < nn; ++n)
        if (indeg[n] == 0) ready.push(int32_t(n));
    auto release = [&](int32_t n) {
        gone[size_t(n)] = 1;
        for (int32_t m : d.succ[size_t(n)]) {
            if (gone[size_t(m)] || --indeg[size_t(m)] != 0) continue;
            if (size_t(m) < nn) {
                ready.push(m);
                continue;
            }
            gone[size_t(m)] = 1;  // a group: its successors are nodes
            for (int32_t k : d.succ[size_t(m)])
                if (!gone[size_t(k)] && --indeg[size_t(k)] == 0) ready.push(k);
        }
    };
    for (size_t done = 0; done < nn;) {
        if (!ready.empty()) {
            int32_t n = ready.top();
            ready.pop();
            if (gone[size_t(n)]) continue;
            net.order.push_back(d.nodes[size_t(n)]);
            release(n);
            ++done;
            continue;
        }
        // Stuck: every node left waits on another, so walking predecessors from the
        // first one must come back to a node already on the path: that is a cycle. A group
        // not yet released stands for its producers not yet gone.
        int32_t cur = 0;
        while (gone[size_t(cur)]) ++cur;
        std::vector<int32_t> path, pos(nn, -1);
        while (pos[size_t(cur)] < 0) {
            pos[size_t(cur)] = int32_t(path.size());
            path.push_back(cur);
            int32_t next = -1;
            for (int32_t p : d.pred[size_t(cur)]) {
                if (gone[size_t(p)]) continue;
                if (size_t(p) < nn) {
                    if (next < 0 || p < next) next = p;
                    continue;
                }
                for (int32_t q : d.pred[size_t(p)])
                    if (!gone[size_t(q)] && (next < 0 || q < next)) next = q;
            }
            cur = next;
        }
        int32_t cut = -1;
        std::vector<int32_t> comps;
        for (size_t i = size_t(pos[size_t(cur)]); i < path.size(); ++i) {
            const Node& node = d.nodes[size_t(path[i])];
            if (node.kind == NodeKind::Flow && (cut < 0 || path[i] < cut)) cut = path[i];
            if (node.kind != NodeKind::Flow) comps.push_back(comp_of(g, node));
        }
        if (cut < 0) cut = cur;  // cannot happen: component nodes only connect through flows
        if (d.nodes[size_t(cut)].kind == NodeKind::Flow) {
            // Predecessors were walked, so the path runs against the flow of activity.
            std::reverse(comps.begin(), comps.end());
            net.delayed.push_back(d.nodes[size_t(cut)].index);
            net.cycles.push_back(std::move(comps));
        } else {
            net.order.push_back(d.nodes[size_t(cut)]);
        }
        release(cut);
        ++done;
    }
    return net;
}

namespace {

// A dynamic end reads as the reference slot, then the member: "a.object.sensor.on".
std::string end_text(const Graph& g, int32_t slot, int32_t access) {
    std::string s = g.slot_path(slot);
    if (access >= 0) {
        s += '.';
        s += g.str(g.accesses[size_t(access)].member);
    }
    return s;
}

std::string flow_text(const Graph& g, int32_t f) {
    const Flow& fl = g.flows[size_t(f)];
    std::string s = "flow " + std::to_string(f) + " " + end_text(g, fl.from, fl.from_access) + " -> " +
                    end_text(g, fl.to, fl.to_access);
    if (fl.cond != Cond::Source) s += " when " + std::string(word(fl.cond));
    if (fl.once) s += " once";
    return s;
}

}  // namespace

std::string network_text(const Graph& g, const Network& n) {
    std::string out;
    for (size_t i = 0; i < n.order.size(); ++i) {
        const Node& node = n.order[i];
        out += "  " + std::to_string(i + 1) + ". ";
        switch (node.kind) {
        case NodeKind::Flow: out += flow_text(g, node.index); break;
        case NodeKind::Logic: out += "connector " + g.comp_path(g.logics[size_t(node.index)].comp); break;
        case NodeKind::Router: out += "router " + g.comp_path(node.index); break;
        case NodeKind::Label: out += "label " + g.comp_path(g.labels[size_t(node.index)].comp); break;
        }
        out += "\n";
    }
    for (size_t i = 0; i < n.delayed.size(); ++i)
        out += "  " + std::to_string(n.order.size() + i + 1) + ". " + flow_text(g, n.delayed[i]) + "  (delayed: cuts a cycle)\n";
    return out;
}

}  // namespace plant::graph
