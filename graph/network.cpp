#include "graph/network.h"

#include "graph/kinds.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <functional>
#include <queue>

namespace plant::graph {

namespace {

// The dependency graph: nodes, and who must run before whom.
struct Deps {
    std::vector<Node> nodes;
    std::vector<std::vector<int32_t>> succ, pred;
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

    // Per slot: nodes that activate it, read it, or read it as their target's activity. Kept as
    // (slot, node) pairs sorted by slot, each slot's nodes in node order: memory for the links,
    // not for every slot (a pool of 1,000 bottles has 40,000 slots and no link).
    const size_t nn = d.nodes.size();
    using Link = std::pair<int32_t, int32_t>;  // (slot, node)
    std::vector<Link> prod, read, tread;
    for (size_t n = 0; n < nn; ++n) {
        const Node& node = d.nodes[n];
        const int32_t id = int32_t(n);
        switch (node.kind) {
        case NodeKind::Flow: {
            const Flow& f = g.flows[size_t(node.index)];
            each_written_slot(g, f, [&](int32_t x) {
                prod.emplace_back(x, id);
                if (f.cond != Cond::Source) tread.emplace_back(x, id);
            });
            each_read_slot(g, f, [&](int32_t x) { read.emplace_back(x, id); });
            break;
        }
        case NodeKind::Logic: {
            const Logic& l = g.logics[size_t(node.index)];
            for (int32_t i = 0; i < l.in_num; ++i) read.emplace_back(g.logic_inputs[size_t(l.in_adr + i)].slot, id);
            prod.emplace_back(l.out_slot, id);
            break;
        }
        case NodeKind::Router: {
            read.emplace_back(g.comps[size_t(node.index)].slot_adr + routerslot::query, id);
            auto r = std::lower_bound(routes.begin(), routes.end(), node.index,
                                      [](const std::pair<int32_t, int32_t>& x, int32_t c) { return x.first < c; });
            for (; r != routes.end() && r->first == node.index; ++r) prod.emplace_back(r->second, id);
            break;
        }
        case NodeKind::Label: {
            const Comp& c = g.comps[size_t(g.labels[size_t(node.index)].comp)];
            read.emplace_back(c.slot_adr + labelslot::set, id);
            prod.emplace_back(c.slot_adr + labelslot::value, id);
            break;
        }
        }
    }
    auto by_slot = [](const Link& a, const Link& b) { return a.first < b.first; };
    for (std::vector<Link>* v : {&prod, &read, &tread}) std::stable_sort(v->begin(), v->end(), by_slot);

    d.succ.resize(nn);
    d.pred.resize(nn);
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
    const size_t nn = d.nodes.size();

    // Kahn's algorithm, smallest ready node first.
    std::vector<int32_t> indeg(nn);
    for (size_t n = 0; n < nn; ++n) indeg[n] = int32_t(d.pred[n].size());
    std::vector<uint8_t> gone(nn, 0);  // emitted or delayed
    std::priority_queue<int32_t, std::vector<int32_t>, std::greater<>> ready;
    for (size_t n = 0; n < nn; ++n)
        if (indeg[n] == 0) ready.push(int32_t(n));
    auto release = [&](int32_t n) {
        gone[size_t(n)] = 1;
        for (int32_t m : d.succ[size_t(n)])
            if (!gone[size_t(m)] && --indeg[size_t(m)] == 0) ready.push(m);
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
        // first one must come back to a node already on the path: that is a cycle.
        int32_t cur = 0;
        while (gone[size_t(cur)]) ++cur;
        std::vector<int32_t> path, pos(nn, -1);
        while (pos[size_t(cur)] < 0) {
            pos[size_t(cur)] = int32_t(path.size());
            path.push_back(cur);
            int32_t next = -1;
            for (int32_t p : d.pred[size_t(cur)])
                if (!gone[size_t(p)] && (next < 0 || p < next)) next = p;
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
