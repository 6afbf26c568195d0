#include "petri/analysis.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <unordered_map>
#include <initializer_list>
#include <string_view>
#include <utility>

namespace plant::petri {
namespace {

using Count = int64_t;
using Marking = std::vector<Count>;
constexpr Count kOmega = -1;          // "any number of tokens" once a place is accelerated
// Stop before counts overflow in a net that never repeats: far above any start (at most
// graph::kMaxInitialTokens per place) and far below int64 overflow with arcs of at most
// graph::kMaxArcWeight, so that no start is runaway already.
constexpr Count kRunaway = Count(1) << 40;
constexpr int kAllSubsetsUpTo = 6;    // 2^6 environments per marking is still cheap
constexpr size_t kMaxCombos = 256;    // concretisations of omega places per step
constexpr int64_t kStepsPerMarking = 256;  // work budget, so omega branching stays bounded

// The net with arcs merged per (transition, place) and bad places dropped, so that
// enabling and consumption agree even when a place is listed twice.
struct Norm {
    int places = 0;
    std::vector<std::vector<std::pair<int, Count>>> in, out;
    std::vector<std::vector<int>> consumers;  // per place, transitions reading it
};

std::vector<std::pair<int, Count>> merge(const std::vector<Arc>& arcs, int places) {
    std::vector<std::pair<int, Count>> r;
    for (const Arc& a : arcs) {
        if (a.place < 0 || a.place >= places) continue;
        auto it = std::find_if(r.begin(), r.end(), [&](auto& e) { return e.first == a.place; });
        if (it == r.end()) r.emplace_back(a.place, std::max(0, a.weight));
        else it->second += std::max(0, a.weight);
    }
    return r;
}

Norm normalise(const Net& net) {
    Norm n;
    n.places = static_cast<int>(net.initial.size());
    n.consumers.resize(n.places);
    for (size_t t = 0; t < net.transitions.size(); ++t) {
        n.in.push_back(merge(net.transitions[t].in, n.places));
        n.out.push_back(merge(net.transitions[t].out, n.places));
        for (auto [p, w] : n.in.back()) n.consumers[p].push_back(static_cast<int>(t));
    }
    return n;
}

bool is_enabled(const Norm& n, int t, const Marking& m) {
    for (auto [p, w] : n.in[t])
        if (m[p] < w) return false;
    return true;
}

std::vector<char> enabled_set(const Norm& n, const Marking& m) {
    std::vector<char> e(n.in.size());
    for (size_t t = 0; t < e.size(); ++t) e[t] = is_enabled(n, static_cast<int>(t), m);
    return e;
}

Marking consumed_by(const Norm& n, const std::vector<char>& e) {
    Marking c(n.places, 0);
    for (size_t t = 0; t < e.size(); ++t)
        if (e[t])
            for (auto [p, w] : n.in[t]) c[p] += w;
    return c;
}

// Phase 2 of a step on a concrete marking that already holds the step's puts.
Marking fire(const Norm& n, const Marking& m, const std::vector<char>& e) {
    Marking r = m, c = consumed_by(n, e);
    for (int p = 0; p < n.places; ++p) r[p] = std::max<Count>(0, r[p] - c[p]);
    for (size_t t = 0; t < e.size(); ++t)
        if (e[t])
            for (auto [p, w] : n.out[t]) r[p] += w;
    return r;
}

Marking with_puts(const Marking& m, const std::vector<int>& puts) {
    Marking r = m;
    for (size_t p = 0; p < r.size() && p < puts.size(); ++p)
        if (r[p] != kOmega) r[p] += std::max(0, puts[p]);
    return r;
}

bool has_omega(const Marking& m) {
    return std::find(m.begin(), m.end(), kOmega) != m.end();
}

// a >= b with omega above every number.
bool covers(const Marking& a, const Marking& b) {
    for (size_t p = 0; p < a.size(); ++p)
        if (a[p] != kOmega && (b[p] == kOmega || a[p] < b[p])) return false;
    return true;
}

struct MarkingHash {
    size_t operator()(const Marking& m) const {
        size_t h = 1469598103934665603ull;
        for (Count v : m) h = (h ^ static_cast<size_t>(v)) * 1099511628211ull;
        return h;
    }
};

// The environments explored from every marking: per place, tokens put in the step.
std::vector<std::vector<int>> environments(const Net& net, int places) {
    std::vector<int> fed;
    for (int p = 0; p < places; ++p)
        if (p < static_cast<int>(net.fed.size()) && net.fed[p]) fed.push_back(p);
    std::vector<std::vector<int>> envs;
    auto add = [&](auto&& chosen) {
        std::vector<int> puts(places, 0);
        for (size_t i = 0; i < fed.size(); ++i)
            if (chosen(i)) puts[fed[i]] = 1;
        envs.push_back(std::move(puts));
    };
    if (fed.size() <= kAllSubsetsUpTo) {
        for (unsigned mask = 0; mask < (1u << fed.size()); ++mask)
            add([&](size_t i) { return (mask >> i & 1u) != 0; });
    } else {
        add([](size_t) { return false; });
        add([](size_t) { return true; });
        for (size_t one = 0; one < fed.size(); ++one) add([&](size_t i) { return i == one; });
    }
    return envs;
}

struct Node {
    Marking m;
    int parent;  // -1 for the initial marking
    int env;     // environment of the step from the parent
};

class Explorer {
public:
    Explorer(const Net& net, int limit)
        : net_(net), n_(normalise(net)), envs_(environments(net, n_.places)), limit_(limit),
          steps_left_(kStepsPerMarking * std::max(limit, 1)) {}

    Report run();

private:
    // Successors of one step from `m` under `puts`. Omega places are concretised with
    // a representative of every enabling threshold, so the result over-approximates.
    bool successors(const Marking& m, const std::vector<int>& puts, std::vector<Marking>& out);
    bool proves_pump(int ancestor, int last, int env, const Marking& r);
    void accelerate_exact(int parent, int env, Marking& r);
    void accelerate_inexact(int parent, Marking& r);
    std::string why(int place, const std::vector<std::pair<Marking, int>>& cycle,
                    const Marking& delta) const;
    std::string pname(int p) const;
    std::string tname(int t) const;

    const Net& net_;
    Norm n_;
    std::vector<std::vector<int>> envs_;
    int limit_;
    int64_t steps_left_;
    std::vector<Node> nodes_;
    std::vector<char> ever_enabled_;
    std::vector<std::string> why_;  // per place, non-empty once proved unbounded
    bool complete_ = true;
};

bool Explorer::successors(const Marking& m, const std::vector<int>& puts,
                          std::vector<Marking>& out) {
    Marking m1 = with_puts(m, puts);
    std::vector<int> omegas;
    std::vector<std::vector<Count>> reps;
    size_t combos = 1;
    for (int p = 0; p < n_.places; ++p) {
        if (m1[p] != kOmega || n_.consumers[p].empty()) continue;
        std::vector<Count> r{0};
        for (int t : n_.consumers[p])
            for (auto [q, w] : n_.in[t])
                if (q == p) r.push_back(w);
        std::sort(r.begin(), r.end());
        r.erase(std::unique(r.begin(), r.end()), r.end());
        omegas.push_back(p);
        combos *= r.size();
        reps.push_back(std::move(r));
        if (combos > kMaxCombos) return false;
    }
    steps_left_ -= static_cast<int64_t>(combos);
    if (steps_left_ < 0) return false;
    for (size_t c = 0; c < combos; ++c) {
        Marking conc = m1;
        for (int p = 0; p < n_.places; ++p)
            if (conc[p] == kOmega) conc[p] = 0;  // unconsumed omega places don't matter
        size_t rest = c;
        for (size_t i = 0; i < omegas.size(); ++i) {
            conc[omegas[i]] = reps[i][rest % reps[i].size()];
            rest /= reps[i].size();
        }
        auto e = enabled_set(n_, conc);
        for (size_t t = 0; t < e.size(); ++t) ever_enabled_[t] |= e[t];
        Marking r = fire(n_, conc, e);
        for (int p = 0; p < n_.places; ++p) {
            if (m1[p] == kOmega) r[p] = kOmega;
            else if (r[p] > kRunaway) return false;
        }
        out.push_back(std::move(r));
    }
    return true;
}

// The steps from `ancestor` to `last` and then `env` to `r` (all omega-free, so every
// step is exact) repeat forever from r if adding delta = r - ancestor changes neither
// which transitions are enabled nor any clamp at zero: then delta is added each time.
bool Explorer::proves_pump(int ancestor, int last, int env, const Marking& r) {
    const Marking& a = nodes_[ancestor].m;
    Marking delta(n_.places);
    for (int p = 0; p < n_.places; ++p) delta[p] = r[p] - a[p];
    std::vector<std::pair<Marking, int>> cycle;  // (marking before the step, env)
    cycle.emplace_back(nodes_[last].m, env);
    for (int j = last; j != ancestor; j = nodes_[j].parent)
        cycle.emplace_back(nodes_[nodes_[j].parent].m, nodes_[j].env);
    std::reverse(cycle.begin(), cycle.end());
    for (auto& [m, e] : cycle) {
        Marking m1 = with_puts(m, envs_[e]);
        auto en = enabled_set(n_, m1);
        for (size_t t = 0; t < en.size(); ++t) {
            if (en[t]) continue;
            bool stays_off = false;
            for (auto [p, w] : n_.in[t]) stays_off |= m1[p] < w && delta[p] == 0;
            if (!stays_off) return false;
        }
        Marking c = consumed_by(n_, en);
        for (int p = 0; p < n_.places; ++p)
            if (delta[p] > 0 && m1[p] < c[p]) return false;
    }
    for (int p = 0; p < n_.places; ++p)
        if (delta[p] > 0 && why_[p].empty()) why_[p] = why(p, cycle, delta);
    return true;
}

void Explorer::accelerate_exact(int parent, int env, Marking& r) {
    for (int a = parent; a >= 0; a = nodes_[a].parent) {
        if (!covers(r, nodes_[a].m) || r == nodes_[a].m) continue;
        if (!proves_pump(a, parent, env, r)) continue;
        Marking base = nodes_[a].m;
        for (int p = 0; p < n_.places; ++p)
            if (r[p] > base[p]) r[p] = kOmega;
        return;
    }
}

// Beyond the exact part, acceleration only has to keep the over-approximation finite.
void Explorer::accelerate_inexact(int parent, Marking& r) {
    for (int a = parent; a >= 0; a = nodes_[a].parent) {
        const Marking& base = nodes_[a].m;
        if (!covers(r, base)) continue;
        for (int p = 0; p < n_.places; ++p)
            if (r[p] != kOmega && r[p] > base[p]) r[p] = kOmega;
    }
}

Report Explorer::run() {
    Report rep;
    ever_enabled_.assign(n_.in.size(), 0);
    why_.assign(n_.places, {});
    std::unordered_map<Marking, int, MarkingHash> seen;
    Marking init(n_.places);
    for (int p = 0; p < n_.places; ++p) init[p] = std::max(0, net_.initial[p]);
    nodes_.push_back({init, -1, -1});
    seen.emplace(init, 0);
    std::vector<Marking> succ;
    for (size_t i = 0; i < nodes_.size() && complete_; ++i) {
        for (size_t e = 0; e < envs_.size() && complete_; ++e) {
            succ.clear();
            Marking from = nodes_[i].m;  // nodes_ may grow below
            if (!successors(from, envs_[e], succ)) {
                complete_ = false;
                break;
            }
            for (Marking& r : succ) {
                if (seen.count(r)) continue;
                if (!has_omega(r)) accelerate_exact(static_cast<int>(i), static_cast<int>(e), r);
                else accelerate_inexact(static_cast<int>(i), r);
                if (seen.count(r)) continue;
                if (static_cast<int>(nodes_.size()) >= limit_) {
                    complete_ = false;
                    break;
                }
                seen.emplace(r, static_cast<int>(nodes_.size()));
                nodes_.push_back({std::move(r), static_cast<int>(i), static_cast<int>(e)});
            }
        }
    }
    rep.complete = complete_;
    for (int p = 0; p < n_.places; ++p) {
        if (why_[p].empty()) continue;
        rep.unbounded.push_back(p);
        rep.unbounded_why.push_back(why_[p]);
    }
    if (complete_)
        for (size_t t = 0; t < ever_enabled_.size(); ++t)
            if (!ever_enabled_[t]) rep.dead.push_back(static_cast<int>(t));
    return rep;
}

// Appending piecewise sidesteps a GCC 12 -Wrestrict false positive on "x" + s at -O3.
std::string cat(std::initializer_list<std::string_view> parts) {
    std::string r;
    for (std::string_view p : parts) r += p;
    return r;
}

std::string in_quotes(std::string_view s) { return cat({"'", s, "'"}); }

std::string join(const std::vector<std::string>& items) {
    std::string r;
    for (size_t i = 0; i < items.size(); ++i) {
        if (i > 0) r += i + 1 == items.size() ? " and " : ", ";
        r += items[i];
    }
    return r;
}

std::string name_or(const std::vector<std::string>& names, int i, char prefix) {
    if (i < static_cast<int>(names.size()) && !names[i].empty()) return in_quotes(names[i]);
    std::string fallback(1, prefix);
    fallback += std::to_string(i);
    return in_quotes(fallback);
}

std::string Explorer::pname(int p) const { return name_or(net_.place_names, p, 'p'); }
std::string Explorer::tname(int t) const { return name_or(net_.transition_names, t, 't'); }

// "<where the tokens come from>; when <the marking it repeats in> <why nothing drains it>"
std::string Explorer::why(int place, const std::vector<std::pair<Marking, int>>& cycle,
                          const Marking& delta) const {
    bool put = false;
    std::vector<int> producers, fired_consumers;
    for (auto& [m, e] : cycle) {
        put |= envs_[e][place] > 0;
        auto en = enabled_set(n_, with_puts(m, envs_[e]));
        for (size_t t = 0; t < en.size(); ++t) {
            if (!en[t]) continue;
            int ti = static_cast<int>(t);
            for (auto [p, w] : n_.out[t])
                if (p == place && std::find(producers.begin(), producers.end(), ti) == producers.end())
                    producers.push_back(ti);
            for (auto [p, w] : n_.in[t])
                if (p == place && std::find(fired_consumers.begin(), fired_consumers.end(), ti) ==
                                      fired_consumers.end())
                    fired_consumers.push_back(ti);
        }
    }
    std::vector<std::string> from;
    if (put) from.push_back("fed by a flow");
    std::vector<std::string> tn;
    for (size_t i = 0; i < producers.size() && i < 2; ++i) tn.push_back(tname(producers[i]));
    if (!tn.empty()) from.push_back(cat({"produced by ", join(tn)}));
    std::string s = join(from);

    std::vector<std::string> marked;
    const Marking& start = cycle.front().first;
    for (int p = 0; p < n_.places; ++p)
        if (p != place && delta[p] == 0 && start[p] > 0) marked.push_back(pname(p));
    if (marked.size() > 3) {
        marked.resize(3);
        marked.push_back("others");
    }
    if (marked.empty()) s += "; while no other place is marked";
    else s += cat({"; when ", join(marked), marked.size() == 1 ? " is" : " are", " marked"});

    if (!fired_consumers.empty()) {
        s += cat({" ", tname(fired_consumers.front()), " consumes fewer tokens than it receives"});
        return s;
    }
    s += " no transition consumes it";
    if (n_.consumers[place].empty()) return s;
    int t = n_.consumers[place].front();
    Marking m1 = with_puts(start, envs_[cycle.front().second]);
    std::vector<std::string> missing;
    for (auto [p, w] : n_.in[t])
        if (p != place && m1[p] < w) missing.push_back(pname(p));
    if (!missing.empty()) s += cat({" (", tname(t), " also needs ", join(missing), ")"});
    return s;
}

}  // namespace

std::vector<int> enabled(const Net& net, const std::vector<int>& marking) {
    Norm n = normalise(net);
    Marking m(n.places, 0);
    for (int p = 0; p < n.places && p < static_cast<int>(marking.size()); ++p)
        m[p] = std::max(0, marking[p]);
    std::vector<int> r;
    for (size_t t = 0; t < n.in.size(); ++t)
        if (is_enabled(n, static_cast<int>(t), m)) r.push_back(static_cast<int>(t));
    return r;
}

std::vector<int> step(const Net& net, const std::vector<int>& marking,
                      const std::vector<int>& puts) {
    Norm n = normalise(net);
    Marking m(n.places, 0);
    for (int p = 0; p < n.places && p < static_cast<int>(marking.size()); ++p)
        m[p] = std::max(0, marking[p]);
    m = with_puts(m, puts);
    Marking r = fire(n, m, enabled_set(n, m));
    std::vector<int> out(r.size());
    for (size_t p = 0; p < r.size(); ++p) out[p] = static_cast<int>(std::min<Count>(r[p], INT_MAX));
    return out;
}

Report analyse(const Net& net, int max_markings) {
    return Explorer(net, max_markings).run();
}

}  // namespace plant::petri
