// Whole-plant checks once every flow is known: Petri-net analysis, inputs nothing
// drives and outputs that drive nothing, logic cycles. Warnings are reported per
// declaration, so a type used many times warns once.
#include "sema/elaborator.h"

#include "graph/kinds.h"
#include "graph/network.h"
#include "graph/range.h"
#include "petri/analysis.h"

#include <fmt/format.h>
#include <tuple>

namespace plant::sema {

using graph::CompKind;

namespace {

std::vector<bool> driven_inputs(const graph::Graph& g) {
    std::vector<bool> driven(g.slots.size(), false);
    for (const auto& f : g.flows) graph::each_written_slot(g, f, [&](int32_t s) { driven[static_cast<size_t>(s)] = true; });
    return driven;
}

std::vector<bool> used_outputs(const graph::Graph& g) {
    std::vector<bool> used(g.slots.size(), false);
    for (const auto& f : g.flows) graph::each_read_slot(g, f, [&](int32_t s) { used[static_cast<size_t>(s)] = true; });
    for (const auto& r : g.records) used[static_cast<size_t>(r.slot)] = true;
    return used;
}

}  // namespace

// Inputs driven by a flow, or exposed by an input port of their object: what a port
// forwards to is the object's interface, fed from outside whether or not this plant
// connects it (an unconnected port is the plant's choice, not a mistake in the type).
std::vector<bool> Elaborator::driven_or_exposed() const {
    auto driven = driven_inputs(g_);
    for (const auto& scope : scopes_)
        for (const auto& [n, port] : scope.ports)
            if (port.input)
                for (int32_t s : port.slots) driven[static_cast<size_t>(s)] = true;
    return driven;
}

void Elaborator::check_petri_nets() {
    const auto driven = driven_or_exposed();
    std::vector<std::vector<int32_t>> places_of(g_.comps.size()), transitions_of(g_.comps.size());
    for (size_t p = 0; p < g_.places.size(); ++p) places_of[static_cast<size_t>(g_.places[p].comp)].push_back(static_cast<int32_t>(p));
    for (size_t t = 0; t < g_.transitions.size(); ++t)
        transitions_of[static_cast<size_t>(g_.transitions[t].comp)].push_back(static_cast<int32_t>(t));
    std::set<std::tuple<int32_t, uint32_t, std::string>> reported;  // one analysis per declaration and marking
    for (size_t c = 0; c < g_.comps.size(); ++c) {
        if (g_.comps[c].kind != CompKind::State || places_of[c].empty()) continue;
        petri::Net net;
        std::map<int32_t, int> local;
        for (int32_t p : places_of[c]) {
            local[p] = static_cast<int>(net.initial.size());
            net.initial.push_back(g_.places[static_cast<size_t>(p)].initial);
            net.fed.push_back(driven[static_cast<size_t>(g_.places[static_cast<size_t>(p)].put_slot)]);
            net.place_names.emplace_back(g_.str(g_.places[static_cast<size_t>(p)].name));
        }
        for (int32_t t : transitions_of[c]) {
            const auto& tr = g_.transitions[static_cast<size_t>(t)];
            petri::Transition pt;
            for (int32_t i = 0; i < tr.in_num; ++i) {
                const auto& a = g_.arcs[static_cast<size_t>(tr.in_adr + i)];
                pt.in.push_back({local[a.place], a.weight});
            }
            for (int32_t i = 0; i < tr.out_num; ++i) {
                const auto& a = g_.arcs[static_cast<size_t>(tr.out_adr + i)];
                pt.out.push_back({local[a.place], a.weight});
            }
            net.transitions.push_back(std::move(pt));
            net.transition_names.emplace_back(g_.str(tr.name));
        }
        // Instances of one type with the same marking and feeding give the same answer.
        std::string sig;
        for (size_t i = 0; i < net.initial.size(); ++i) sig += fmt::format("{}{},", net.initial[i], net.fed[i] ? "f" : "");
        const Span decl = comp_spans_[static_cast<int32_t>(c)];
        if (!reported.insert({decl.file, decl.begin, sig}).second)
            continue;
        petri::Report rep = petri::analyse(net);
        const std::string net_name(g_.str(g_.comps[c].name));
        for (size_t i = 0; i < rep.unbounded.size(); ++i) {
            const auto& pl = g_.places[static_cast<size_t>(places_of[c][static_cast<size_t>(rep.unbounded[i])])];
            auto& d = sink_.report(DiagId::UnboundedPlace, place_spans_[places_of[c][static_cast<size_t>(rep.unbounded[i])]],
                                   fmt::format("place '{}' of net '{}' can accumulate tokens without bound", g_.str(pl.name), net_name));
            if (i < rep.unbounded_why.size()) d.notes.push_back({{}, rep.unbounded_why[i]});
            d.notes.push_back({{}, "add a transition that drains surplus tokens, e.g. `transition drain: Held + Request -> Held`"});
        }
        for (int idx : rep.dead) {
            const auto& tr = g_.transitions[static_cast<size_t>(transitions_of[c][static_cast<size_t>(idx)])];
            sink_.report(DiagId::DeadTransition, transition_spans_[transitions_of[c][static_cast<size_t>(idx)]],
                         fmt::format("transition '{}' of net '{}' can never fire", g_.str(tr.name), net_name));
        }
    }
}

void Elaborator::check_unused() {
    const auto driven = driven_or_exposed();
    const auto used = used_outputs(g_);
    for (size_t c = 0; c < g_.comps.size(); ++c) {
        const auto& comp = g_.comps[c];
        const Span span = comp_spans_[static_cast<int32_t>(c)];
        const std::string cname(g_.str(comp.name));
        auto slot = [&](int idx) { return static_cast<size_t>(comp.slot_adr + idx); };
        // A kind on the kind table says which input it needs (graph/plugin.h: idle_input).
        if (const graph::KindDesc* k = graph::builtin_kind(comp.kind); k && k->idle_input >= 0) {
            if (!(k->runs_alone && k->runs_alone(g_, comp.detail)) && !driven[slot(k->idle_input)])
                sink_.report(DiagId::InputNotDriven, span, fmt::format(fmt::runtime(k->idle_warning), cname));
            continue;
        }
        switch (comp.kind) {
        case CompKind::Logic:
            if (!used[slot(graph::logicslot::out)])
                sink_.report(DiagId::OutputDrivesNothing, span, fmt::format("connector '{}' drives nothing", cname));
            break;
        case CompKind::Router:
            for (int32_t i = 1; i < comp.slot_num; ++i)
                if (!used[slot(i)])
                    sink_.report(DiagId::OutputDrivesNothing, span,
                                 fmt::format("route '{}' of router '{}' drives nothing", g_.str(g_.slots[slot(i)].name), cname));
            if (!driven[slot(graph::routerslot::query)])
                sink_.report(DiagId::InputNotDriven, span, fmt::format("router '{}' is never queried: nothing drives its 'query'", cname));
            break;
        default: break;
        }
    }
}

// Every cycle the runtime cuts (graph/network.h), at the flow it delays.
void Elaborator::check_logic_cycles() {
    const graph::Network net = graph::analyse_network(g_);
    for (size_t i = 0; i < net.delayed.size(); ++i) {
        std::string through;
        for (int32_t c : net.cycles[i]) {
            const auto& comp = g_.comps[static_cast<size_t>(c)];
            through += fmt::format("{}{} '{}'", through.empty() ? "" : ", ",
                                   comp.kind == CompKind::Logic ? "connector" : graph::word(comp.kind), g_.str(comp.name));
        }
        sink_.report(DiagId::LogicCycle, flow_spans_[static_cast<size_t>(net.delayed[i])],
                     fmt::format("this flow closes a logic cycle through {}; it is evaluated with a one-step delay", through));
    }
}

namespace {

// Why the bound: the one that applies to the flaw's field (language.md §6, "Range").
std::string range_note(const graph::RangeFlaw& f) {
    if (f.field == "speed" || f.field == "gain")
        return "a belt's speed is at most 100 km/s and its gain at most 1e12 kg/s: beyond, its law leaves the "
               "physics' range";
    return "the physics is single precision: model the plant within 100 km, with sizes from 0.1 mm and "
           "bodies from 1 mg to 1,000 t";
}

}  // namespace

// Places, sizes and masses within graph/range.h's bounds, the loader's. One error per
// declaration of the plant: at an object placed out of range (and none for what it holds), at
// a component of its own, or at an object whose parts its arguments put out of range.
void Elaborator::check_ranges() {
    const std::vector<graph::RangeFlaw> flaws = graph::range_flaws(g_);
    if (flaws.empty()) return;
    std::vector<bool> do_done(g_.dos.size(), false);
    std::set<int32_t> comp_done, top_done;  // components of the plant itself; the objects it makes
    auto within_done = [&](int32_t d) {
        for (; d >= 0; d = g_.dos[static_cast<size_t>(d)].parent)
            if (do_done[static_cast<size_t>(d)]) return true;
        return false;
    };
    auto path = [&](int32_t d) { return g_.names[static_cast<size_t>(g_.dos[static_cast<size_t>(d)].path.id)]; };
    for (const graph::RangeFlaw& f : flaws) {
        if (f.comp < 0) {  // a DO
            const auto& d = g_.dos[static_cast<size_t>(f.row)];
            if (within_done(d.parent)) continue;
            do_done[static_cast<size_t>(f.row)] = true;
            const auto a = do_at_spans_.find(f.row);
            const Span at = a != do_at_spans_.end() ? a->second : do_spans_[static_cast<size_t>(f.row)];
            sink_.report(DiagId::OutOfRange, at, fmt::format("the {} of '{}' {}", f.what, path(f.row), f.text))
                .notes.push_back({{}, range_note(f)});
            continue;
        }
        const int32_t c = f.comp;
        if (comp_done.count(c) || within_done(g_.comps[static_cast<size_t>(c)].owner)) continue;
        comp_done.insert(c);
        const std::string& who = g_.names[static_cast<size_t>(g_.comps[static_cast<size_t>(c)].name.id)];
        const int32_t owner = g_.comps[static_cast<size_t>(c)].owner;
        if (g_.dos[static_cast<size_t>(owner)].parent < 0) {  // the plant's own component
            sink_.report(DiagId::OutOfRange, comp_spans_[c], fmt::format("the {} of '{}' {}", f.what, who, f.text))
                .notes.push_back({{}, range_note(f)});
            continue;
        }
        // A part of an object the plant makes: at that object, where its arguments are (most
        // likely what put the part out of range), once per object, with the part's declaration.
        int32_t top = owner;
        while (g_.dos[static_cast<size_t>(g_.dos[static_cast<size_t>(top)].parent)].parent >= 0)
            top = g_.dos[static_cast<size_t>(top)].parent;
        if (!top_done.insert(top).second) continue;
        auto& d = sink_.report(DiagId::OutOfRange, do_spans_[static_cast<size_t>(top)],
                               fmt::format("the {} of '{}' in '{}' {}", f.what, who, path(owner), f.text));
        d.notes.push_back({comp_spans_[c], fmt::format("'{}' is declared here", who)});
        d.notes.push_back({{}, range_note(f)});
    }
}

}  // namespace plant::sema
