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
    std::map<std::pair<int32_t, int32_t>, AccessGroupId> by_range;  // (target_adr, target_num) -> group
    for (AccessId a : ids_of(g.accesses)) {
        const Access& ac = g.accesses[a];
        const auto [at, added] = by_range.try_emplace({ac.target_adr.v, ac.target_num}, out.first.next_id());
        if (added) out.first.push_back(a);
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
// producer is released, so each reader becomes ready exactly when it did). From
// nodes.size() + groups on are write groups: the flows that write through one kind of dynamic
// end (a station setting `(sw.bottle as Bottle).code.set`), each one node that stands for
// them as a producer of every slot the end may be (listed per flow, 14 million links at 417
// lines). A write group is released with its last writer, and a read group it feeds with it.
struct Dep;
using DepId = Id<Dep>;  // a node (below nodes.count()) or a group (from there on)

struct Deps {
    IdVector<DepId, Node> nodes;
    IdVector<DepId, std::vector<DepId>> succ, pred;  // nodes, then groups
};

Deps dependencies(const Graph& g) {
    Deps d;
    for (FlowId f : ids_of(g.flows)) d.nodes.push_back({NodeKind::Flow, f.v});
    for (LogicId l : ids_of(g.logics)) d.nodes.push_back({NodeKind::Logic, l.v});
    for (CompId c : ids_of(g.comps))
        if (g.comps[c].kind == CompKind::Router) d.nodes.push_back({NodeKind::Router, c.v});
    for (Id<Label> l : ids_of(g.labels)) d.nodes.push_back({NodeKind::Label, l.v});

    // Routers' outputs, by router (few: a list per router, not per component).
    std::vector<std::pair<int32_t, int32_t>> routes;  // (router comp, out slot), in route order
    for (const Route& r : g.routes) routes.emplace_back(r.comp, r.out_slot);
    std::stable_sort(routes.begin(), routes.end(), [](auto& a, auto& b) { return a.first < b.first; });

    const AccessGroups groups = access_groups(g);
    const IdVector<AccessId, AccessGroupId>& group_of = groups.of;
    const IdVector<AccessGroupId, AccessId>& group_access = groups.first;

    // Per slot: nodes that activate it, read it, or read it as their target's activity. Kept as
    // (slot, node) pairs sorted by slot, each slot's nodes in node order: memory for the links,
    // not for every slot (a pool of 1,000 bottles has 40,000 slots and no link). A read
    // through a dynamic end is a (group, node) pair instead. Counted first, then filled.
    const int32_t nn = d.nodes.count(), ng = group_access.count();
    using Link = std::pair<int32_t, DepId>;  // (slot or group, node)
    std::vector<Link> prod, read, tread, dyn, dynw;
    // A flow that writes through a dynamic end joins its write group, unless it reads a slot
    // of that group (directly, or through a dynamic source whose group shares one): the group
    // would then stand between it and itself, where the direct links skip it. Such a flow, and
    // one that reads its target's activity, lists every slot it may write, as before.
    auto targets_of = [&](AccessGroupId k) { return groups.targets(g, k); };
    std::vector<std::pair<int32_t, int32_t>> member;  // (slot, group), for every group's slots
    for (AccessGroupId k : group_access.ids())
        for (const AccessTarget& t : targets_of(k)) member.emplace_back(t.v.v, k.v);
    std::sort(member.begin(), member.end());
    auto in_group = [&member](int32_t x, int32_t k) { return std::binary_search(member.begin(), member.end(), std::pair{x, k}); };
    std::map<std::pair<int32_t, int32_t>, bool> shares;  // (read group, write group): a slot in both
    auto groups_share = [&](int32_t rk, int32_t wk) {
        const auto [at, added] = shares.try_emplace({rk, wk}, false);
        if (added)
            for (const AccessTarget& t : targets_of(AccessGroupId(rk)))
                if (in_group(t.v.v, wk)) {
                    at->second = true;
                    break;
                }
        return at->second;
    };
    IdVector<FlowId, int32_t> write_group(g.flows.count(), -1);  // a grouped writer's group
    std::vector<uint8_t> written_by_group(static_cast<size_t>(ng), 0);
    for (FlowId fi : ids_of(g.flows)) {
        const Flow& f = g.flows[fi];
        if (!f.to_access.valid() || f.cond != Cond::Source) continue;
        const int32_t k = group_of[f.to_access].v;
        bool own = in_group(g.accesses[f.to_access].ref_slot.v, k);
        if (f.from_access.valid()) own = own || in_group(g.accesses[f.from_access].ref_slot.v, k) ||
                                         groups_share(group_of[f.from_access].v, k);
        else own = own || in_group(f.from.v, k);
        if (own) continue;
        write_group[fi] = k;
        written_by_group[static_cast<size_t>(k)] = 1;
    }
    auto links = [&](auto&& add) {
        for (DepId id : d.nodes.ids()) {
            const Node& node = d.nodes[id];
            switch (node.kind) {
            case NodeKind::Flow: {
                const Flow& f = g.flows[node.flow()];
                if (write_group[node.flow()] >= 0) {
                    add(4, write_group[node.flow()], id);
                } else {
                    each_written_slot(g, f, [&](SlotId x) {
                        add(0, x.v, id);
                        if (f.cond != Cond::Source) add(2, x.v, id);
                    });
                }
                if (f.from_access.valid()) {
                    add(1, g.accesses[f.from_access].ref_slot.v, id);
                    add(3, group_of[f.from_access].v, id);
                } else {
                    add(1, f.from.v, id);
                }
                break;
            }
            case NodeKind::Logic: {
                const Logic& l = g.logics[node.logic()];
                for (Id<LogicIn> i : children(l.in_adr, l.in_num)) add(1, g.logic_inputs[i].slot.v, id);
                add(0, l.out_slot.v, id);
                break;
            }
            case NodeKind::Router: {
                add(1, (g.comps[node.router()].slot_adr + routerslot::query).v, id);
                auto r = std::lower_bound(routes.begin(), routes.end(), node.index,
                                          [](const std::pair<int32_t, int32_t>& x, int32_t c) { return x.first < c; });
                for (; r != routes.end() && r->first == node.index; ++r) add(0, r->second, id);
                break;
            }
            case NodeKind::Label: {
                const Comp& c = g.comps[g.labels[node.label()].comp];
                add(1, (c.slot_adr + labelslot::set).v, id);
                add(0, (c.slot_adr + labelslot::value).v, id);
                break;
            }
            }
        }
        // Each write group produces every slot of its group, after the nodes (by id).
        for (AccessGroupId k : group_access.ids())
            if (written_by_group[static_cast<size_t>(k.v)])
                for (const AccessTarget& t : targets_of(k)) add(0, t.v.v, DepId(nn + ng + k.v));
    };
    // Each list sorted by key (slot or group), then node, as it is made: a pass counts its
    // links per key, a second puts each link after those with a smaller key, and links come
    // in node order (a counting sort, a list at a time for one array of counts; std::sort's
    // n log n was a tenth of `plant check` at 400 lines of the bottling plant).
    std::vector<Link>* lists[5] = {&prod, &read, &tread, &dyn, &dynw};
    std::vector<uint32_t> at;
    for (int i = 0; i < 5; ++i) {
        at.assign(static_cast<size_t>(i >= 3 ? ng : g.slots.count()) + 1, 0);
        links([&](int list, int32_t x, DepId) {
            if (list == i) ++at[static_cast<size_t>(x) + 1];
        });
        for (size_t k = 1; k < at.size(); ++k) at[k] += at[k - 1];
        lists[i]->resize(at.back());
        links([&](int list, int32_t x, DepId id) {
            if (list == i) (*lists[i])[at[static_cast<size_t>(x)]++] = {x, id};
        });
    }
    std::vector<uint32_t>().swap(at);

    d.succ.resize(d.nodes.size() + 2 * group_access.size());
    d.pred.resize(d.nodes.size() + 2 * group_access.size());
    for (const auto& [k, writer] : dynw) {  // each writer before its write group
        d.succ[writer].push_back(DepId(nn + ng + k));
        d.pred[DepId(nn + ng + k)].push_back(writer);
    }
    auto edge = [&](DepId a, DepId b) {
        if (a == b) return;
        d.succ[a].push_back(b);
        d.pred[b].push_back(a);
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
    std::vector<DepId> producers, readers;
    size_t r = 0;
    for (AccessGroupId k : group_access.ids()) {
        readers.clear();
        for (; r < dyn.size() && dyn[r].first == k.v; ++r)
            if (readers.empty() || readers.back() != dyn[r].second) readers.push_back(dyn[r].second);
        if (readers.empty()) continue;
        producers.clear();
        for (const AccessTarget& t : targets_of(k)) {
            const int32_t x = t.v.v;
            auto at = std::lower_bound(prod.begin(), prod.end(), Link{x, DepId(INT32_MIN)});
            for (; at != prod.end() && at->first == x; ++at) producers.push_back(at->second);
        }
        std::sort(producers.begin(), producers.end());
        producers.erase(std::unique(producers.begin(), producers.end()), producers.end());
        bool both = false;
        for (DepId n : readers) both = both || std::binary_search(producers.begin(), producers.end(), n);
        const DepId group(nn + k.v);
        for (DepId p : producers) {
            if (both) {
                for (DepId n : readers) edge(p, n);
            } else {
                edge(p, group);
            }
        }
        if (!both && !producers.empty())
            for (DepId n : readers) edge(group, n);
    }
    return d;
}

CompId comp_of(const Graph& g, const Node& n) {
    switch (n.kind) {
    case NodeKind::Logic: return g.logics[n.logic()].comp;
    case NodeKind::Router: return n.router();
    case NodeKind::Label: return g.labels[n.label()].comp;
    case NodeKind::Flow: break;
    }
    return CompId{};
}

}  // namespace

Network analyse_network(const Graph& g) {
    Network net;
    const Deps d = dependencies(g);
    const int32_t nn = d.nodes.count();
    auto is_node = [&](DepId n) { return n.v < nn; };

    // Kahn's algorithm, smallest ready node first; a group is released the moment it is ready.
    IdVector<DepId, int32_t> indeg;
    for (const std::vector<DepId>& p : d.pred) indeg.push_back(count_of(p));
    IdVector<DepId, uint8_t> gone(d.succ.count(), 0);  // emitted or delayed (a group: released)
    std::priority_queue<DepId, std::vector<DepId>, std::greater<>> ready;
    for (DepId n : d.nodes.ids())
        if (indeg[n] == 0) ready.push(n);
    // A node's release makes its successors ready; a group made ready is released at once
    // (a write group may feed a read group: released in one go).
    std::vector<DepId> groups_ready;
    auto release = [&](DepId n) {
        gone[n] = 1;
        for (DepId m : d.succ[n]) {
            if (gone[m] || --indeg[m] != 0) continue;
            if (is_node(m)) ready.push(m);
            else groups_ready.push_back(m);
        }
        while (!groups_ready.empty()) {
            const DepId m = groups_ready.back();
            groups_ready.pop_back();
            gone[m] = 1;
            for (DepId k : d.succ[m]) {
                if (gone[k] || --indeg[k] != 0) continue;
                if (is_node(k)) ready.push(k);
                else groups_ready.push_back(k);
            }
        }
    };
    for (int32_t done = 0; done < nn;) {
        if (!ready.empty()) {
            DepId n = ready.top();
            ready.pop();
            if (gone[n]) continue;
            net.order.push_back(d.nodes[n]);
            release(n);
            ++done;
            continue;
        }
        // Stuck: every node left waits on another, so walking predecessors from the
        // first one must come back to a node already on the path: that is a cycle. A group
        // not yet released stands for its producers not yet gone.
        DepId cur(0);
        while (gone[cur]) ++cur;
        std::vector<DepId> path;
        IdVector<DepId, int32_t> pos(nn, -1);
        while (pos[cur] < 0) {
            pos[cur] = count_of(path);
            path.push_back(cur);
            // The lowest predecessor not yet gone; a group not yet released stands for its
            // own (a read group's may be a write group, which stands for its writers).
            DepId next;
            auto lowest = [&](auto&& self, DepId n) -> void {
                for (DepId p : d.pred[n]) {
                    if (gone[p]) continue;
                    if (!is_node(p)) self(self, p);
                    else if (!next.valid() || p < next) next = p;
                }
            };
            lowest(lowest, cur);
            cur = next;
        }
        DepId cut;
        std::vector<CompId> comps;
        for (auto i = path.begin() + pos[cur]; i != path.end(); ++i) {
            const Node& node = d.nodes[*i];
            if (node.kind == NodeKind::Flow && (!cut.valid() || *i < cut)) cut = *i;
            if (node.kind != NodeKind::Flow) comps.push_back(comp_of(g, node));
        }
        if (!cut.valid()) cut = cur;  // cannot happen: component nodes only connect through flows
        if (d.nodes[cut].kind == NodeKind::Flow) {
            // Predecessors were walked, so the path runs against the flow of activity.
            std::reverse(comps.begin(), comps.end());
            net.delayed.push_back(d.nodes[cut].flow());
            net.cycles.push_back(std::move(comps));
        } else {
            net.order.push_back(d.nodes[cut]);
        }
        release(cut);
        ++done;
    }
    return net;
}

namespace {

// A dynamic end reads as the reference slot, then the member: "a.object.sensor.on".
std::string end_text(const Graph& g, SlotId slot, AccessId access) {
    std::string s = g.slot_path(slot);
    if (access.valid()) {
        s += '.';
        s += g.str(g.accesses[access].member);
    }
    return s;
}

std::string flow_text(const Graph& g, FlowId f) {
    const Flow& fl = g.flows[f];
    std::string s = "flow " + std::to_string(f.v) + " " + end_text(g, fl.from, fl.from_access) + " -> " +
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
        case NodeKind::Flow: out += flow_text(g, node.flow()); break;
        case NodeKind::Logic: out += "connector " + g.comp_path(g.logics[node.logic()].comp); break;
        case NodeKind::Router: out += "router " + g.comp_path(node.router()); break;
        case NodeKind::Label: out += "label " + g.comp_path(g.labels[node.label()].comp); break;
        }
        out += "\n";
    }
    for (size_t i = 0; i < n.delayed.size(); ++i)
        out += "  " + std::to_string(n.order.size() + i + 1) + ". " + flow_text(g, n.delayed[i]) + "  (delayed: cuts a cycle)\n";
    return out;
}

}  // namespace plant::graph
