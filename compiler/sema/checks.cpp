// Whole-plant checks once every flow is known: Petri-net analysis, inputs nothing
// drives and outputs that drive nothing, logic cycles. Warnings are reported per
// declaration, so a type used many times warns once.
#include "sema/elaborator.h"

#include "graph/kinds.h"
#include "graph/network.h"
#include "graph/range.h"
#include "petri/analysis.h"

#include <fmt/format.h>
#include <set>
#include <tuple>

namespace plant::sema {

using graph::CompId;
using graph::CompKind;
using graph::DoId;
using graph::PlaceId;
using graph::SlotId;
using graph::TransitionId;
using SlotFlags = graph::IdVector<SlotId, uint8_t>;

namespace {

SlotFlags driven_inputs(const graph::Graph& g) {
    SlotFlags driven(g.slots.count(), 0);
    for (const auto& f : g.flows) graph::each_written_slot(g, f, [&](SlotId s) { driven[s] = 1; });
    return driven;
}

SlotFlags used_outputs(const graph::Graph& g) {
    SlotFlags used(g.slots.count(), 0);
    for (const auto& f : g.flows) graph::each_read_slot(g, f, [&](SlotId s) { used[s] = 1; });
    for (const auto& r : g.records) used[r.slot] = 1;
    return used;
}

}  // namespace

// Inputs driven by a flow, or exposed by an input port of their object: what a port
// forwards to is the object's interface, fed from outside whether or not this plant
// connects it (an unconnected port is the plant's choice, not a mistake in the type).
SlotFlags Elaborator::driven_or_exposed() const {
    auto driven = driven_inputs(g_);
    for (const auto& scope : scopes_)
        for (const auto& [n, port] : scope.ports)
            if (port.input)
                for (SlotId s : port.slots) driven[s] = 1;
    return driven;
}

void Elaborator::check_petri_nets() {
    const auto driven = driven_or_exposed();
    graph::IdVector<CompId, std::vector<PlaceId>> places_of(g_.comps.count());
    graph::IdVector<CompId, std::vector<TransitionId>> transitions_of(g_.comps.count());
    for (PlaceId p : ids_of(g_.places)) places_of[g_.places[p].comp].push_back(p);
    for (TransitionId t : ids_of(g_.transitions)) transitions_of[g_.transitions[t].comp].push_back(t);
    std::set<std::tuple<int32_t, uint32_t, std::string>> reported;  // one analysis per declaration and marking
    for (CompId c : ids_of(g_.comps)) {
        if (g_.comps[c].kind != CompKind::State || places_of[c].empty()) continue;
        petri::Net net;
        std::map<PlaceId, int> local;
        for (PlaceId p : places_of[c]) {
            local[p] = graph::count_of(net.initial);
            net.initial.push_back(g_.places[p].initial);
            net.fed.push_back(driven[g_.places[p].put_slot] != 0);
            net.place_names.emplace_back(g_.str(g_.places[p].name));
        }
        for (TransitionId t : transitions_of[c]) {
            const auto& tr = g_.transitions[t];
            petri::Transition pt;
            for (const graph::Arc& a : g_.arcs.slice(tr.in_adr, tr.in_num)) pt.in.push_back({local[a.place], a.weight});
            for (const graph::Arc& a : g_.arcs.slice(tr.out_adr, tr.out_num)) pt.out.push_back({local[a.place], a.weight});
            net.transitions.push_back(std::move(pt));
            net.transition_names.emplace_back(g_.str(tr.name));
        }
        // Instances of one type with the same marking and feeding give the same answer.
        std::string sig;
        for (size_t i = 0; i < net.initial.size(); ++i) sig += fmt::format("{}{},", net.initial[i], net.fed[i] ? "f" : "");
        const Span decl = comp_spans_[c];
        if (!reported.insert({decl.file, decl.begin, sig}).second)
            continue;
        petri::Report rep = petri::analyse(net);
        const std::string net_name(g_.str(g_.comps[c].name));
        for (size_t i = 0; i < rep.unbounded.size(); ++i) {
            const PlaceId p = places_of[c][rep.unbounded[i]];
            const auto& pl = g_.places[p];
            auto& d = sink_.report(DiagId::UnboundedPlace, place_spans_[p],
                                   fmt::format("place '{}' of net '{}' can accumulate tokens without bound", g_.str(pl.name), net_name));
            if (i < rep.unbounded_why.size()) d.notes.push_back({{}, rep.unbounded_why[i]});
            d.notes.push_back({{}, "add a transition that drains surplus tokens, e.g. `transition drain: Held + Request -> Held`"});
        }
        for (int idx : rep.dead) {
            const TransitionId t = transitions_of[c][idx];
            const auto& tr = g_.transitions[t];
            sink_.report(DiagId::DeadTransition, transition_spans_[t],
                         fmt::format("transition '{}' of net '{}' can never fire", g_.str(tr.name), net_name));
        }
    }
}

void Elaborator::check_unused() {
    const auto driven = driven_or_exposed();
    const auto used = used_outputs(g_);
    for (CompId c : ids_of(g_.comps)) {
        const auto& comp = g_.comps[c];
        const Span span = comp_spans_[c];
        const std::string cname(g_.str(comp.name));
        auto slot = [&](int idx) { return comp.slot_adr + idx; };
        // A kind on the kind table says which outputs it wants used (graph/plugin.h:
        // unused_output, idle_output) and which input it needs (idle_input).
        if (const graph::KindDesc* k = graph::builtin_kind(comp.kind)) {
            if (!k->unused_output.empty())
                for (int32_t i = graph::count_of(k->slots); i < comp.slot_num; ++i)
                    if (!used[slot(i)])
                        sink_.report(DiagId::OutputDrivesNothing, span,
                                     fmt::format(fmt::runtime(k->unused_output), g_.str(g_.slots[slot(i)].name), cname));
            if (k->idle_input >= 0 && !(k->runs_alone && k->runs_alone(g_, comp.detail.v)) && !driven[slot(k->idle_input)])
                sink_.report(DiagId::InputNotDriven, span, fmt::format(fmt::runtime(k->idle_warning), cname));
            if (k->idle_output >= 0 && !used[slot(k->idle_output)])
                sink_.report(DiagId::OutputDrivesNothing, span, fmt::format(fmt::runtime(k->idle_output_warning), cname));
        }
    }
}

// Every cycle the runtime cuts (graph/network.h), at the flow it delays.
void Elaborator::check_logic_cycles() {
    const graph::Network net = graph::analyse_network(g_);
    for (size_t i = 0; i < net.delayed.size(); ++i) {
        std::string through;
        for (CompId c : net.cycles[i]) {
            const auto& comp = g_.comps[c];
            const graph::KindDesc* k = graph::builtin_kind(comp.kind);
            through += fmt::format("{}{} '{}'", through.empty() ? "" : ", ",
                                   k && !k->noun.empty() ? k->noun : graph::word(comp.kind), g_.str(comp.name));
        }
        sink_.report(DiagId::LogicCycle, flow_spans_[net.delayed[i]],
                     fmt::format("this flow closes a logic cycle through {}; it is evaluated with a one-step delay", through));
    }
}

// A flow into a static body's set_velocity or set_angular_velocity: a static body does not
// move, so the runtime would refuse every value the flow sends (graph/range.h). A flow whose
// target is found at run time (an object reference) is refused there, counted as out of range.
// One error per flow declaration, so a type used many times reports once (its body by name).
void Elaborator::check_static_velocities() {
    std::set<std::tuple<int32_t, uint32_t, int32_t>> reported;  // the flow's file and place, the slot's index
    for (graph::FlowId f : ids_of(g_.flows)) {
        if (g_.flows[f].to_access.valid()) continue;
        graph::each_written_slot(g_, g_.flows[f], [&](SlotId s) {
            if (!graph::static_velocity(g_, s)) return;
            const CompId c = g_.slots[s].comp;
            const Span at = flow_spans_[f];
            if (!reported.insert({at.file, at.begin, s.v - g_.comps[c].slot_adr.v}).second) return;
            auto& d = sink_.report(DiagId::StaticVelocity, at,
                                   fmt::format("'{}' is a static body: it does not move, so its {} takes no value",
                                               g_.str(g_.comps[c].name), g_.str(g_.slots[s].name)));
            d.notes.push_back({comp_spans_[c], "declare it kinematic to command its velocity"});
        });
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
    graph::IdVector<DoId, uint8_t> do_done(g_.dos.count(), 0);
    std::set<CompId> comp_done;  // components of the plant itself
    std::set<DoId> top_done;     // the objects it makes
    auto within_done = [&](DoId d) {
        for (; d.valid(); d = g_.dos[d].parent)
            if (do_done[d]) return true;
        return false;
    };
    auto path = [&](DoId d) { return g_.str(g_.dos[d].path); };
    for (const graph::RangeFlaw& f : flaws) {
        if (!f.comp.valid()) {  // a DO
            const DoId row(f.row);
            if (within_done(g_.dos[row].parent)) continue;
            do_done[row] = 1;
            const auto a = do_at_spans_.find(row);
            const Span at = a != do_at_spans_.end() ? a->second : do_spans_[row];
            sink_.report(DiagId::OutOfRange, at, fmt::format("the {} of '{}' {}", f.what, path(row), f.text))
                .notes.push_back({{}, range_note(f)});
            continue;
        }
        const CompId c = f.comp;
        if (comp_done.count(c) || within_done(g_.comps[c].owner)) continue;
        comp_done.insert(c);
        const std::string who(g_.str(g_.comps[c].name));
        const DoId owner = g_.comps[c].owner;
        if (!g_.dos[owner].parent.valid()) {  // the plant's own component
            sink_.report(DiagId::OutOfRange, comp_spans_[c], fmt::format("the {} of '{}' {}", f.what, who, f.text))
                .notes.push_back({{}, range_note(f)});
            continue;
        }
        // A part of an object the plant makes: at that object, where its arguments are (most
        // likely what put the part out of range), once per object, with the part's declaration.
        DoId top = owner;
        while (g_.dos[g_.dos[top].parent].parent.valid()) top = g_.dos[top].parent;
        if (!top_done.insert(top).second) continue;
        auto& d = sink_.report(DiagId::OutOfRange, do_spans_[top],
                               fmt::format("the {} of '{}' in '{}' {}", f.what, who, path(owner), f.text));
        d.notes.push_back({comp_spans_[c], fmt::format("'{}' is declared here", who)});
        d.notes.push_back({{}, range_note(f)});
    }
}

}  // namespace plant::sema
