// The state's lowering: its places (each with its put, entered and tokens slots) and its
// transitions (each with its arcs and its fired slot), rows of `places`, `transitions` and
// `arcs`; a state has no row of its own (its detail stays none).
#include "sema/kinds/lowering.h"

#include "graph/build.h"

#include <cmath>
#include <set>
#include <fmt/format.h>

namespace plant::kinds::state {

using namespace plant::sema;
using graph::Dir;
using graph::SlotType;

namespace {

void lower(Lowering& lw) {
    Elaborator& el = lw.el;
    graph::Graph& g = lw.el.g_;
    const ast::ComponentDecl& c = lw.decl;
    const Env& env = lw.env;
    std::map<std::string, graph::PlaceId> place_ids;
    for (const auto& p : c.places) {
        if (place_ids.count(p.name.text)) {
            el.sink_.report(DiagId::DuplicateName, p.name.span, fmt::format("place '{}' is declared twice", p.name.text));
            continue;
        }
        graph::Place pl;
        pl.comp = lw.comp;
        pl.name = el.name(p.name.text);
        pl.src = el.src(p.name.span);
        if (p.initial) {
            Value v = el.ev_.eval(*p.initial, env);
            if (v.kind == Value::Kind::Num && v.dim.none() && std::floor(v.num) == v.num && v.num >= 0 &&
                v.num <= graph::kMaxInitialTokens)
                pl.initial = static_cast<int32_t>(v.num);
            else if (v.kind != Value::Kind::None)
                el.sink_.report(DiagId::NegativeTokens, v.span,
                                fmt::format("initial tokens of '{}' must be a whole number from 0 to {}, not {}", p.name.text,
                                            graph::kMaxInitialTokens,
                                            v.kind == Value::Kind::Num && v.dim.none() ? fmt::format("{}", v.num) : "a " + describe(v)));
        }
        pl.put_slot = el.add_slot(lw.comp, p.name.text + ".put", SlotType::Void, Dir::In, p.name.span);
        pl.entered_slot = el.add_slot(lw.comp, p.name.text + ".entered", SlotType::Void, Dir::Out, p.name.span);
        pl.tokens_slot = el.add_slot(lw.comp, p.name.text + ".tokens", SlotType::Int, Dir::Out, p.name.span);
        graph::slot_value(g, pl.tokens_slot) = pl.initial;
        const graph::PlaceId id = g.places.push_back(pl);
        place_ids[p.name.text] = id;
        el.place_spans_[id] = p.name.span;
    }
    std::set<std::string> tnames;
    std::vector<std::string> pnames;
    for (const auto& p : c.places) pnames.push_back(p.name.text);
    for (const auto& t : c.transitions) {
        if (!tnames.insert(t.name.text).second || place_ids.count(t.name.text)) {
            el.sink_.report(DiagId::DuplicateName, t.name.span, fmt::format("'{}' is declared twice in this net", t.name.text));
            continue;
        }
        graph::Transition tr;
        tr.comp = lw.comp;
        tr.name = el.name(t.name.text);
        tr.src = el.src(t.name.span);
        auto arcs = [&](const std::vector<ast::ArcDecl>& list, graph::Adr<graph::Arc>& adr, int32_t& n) {
            adr = graph::next_adr(g.arcs);
            for (const auto& a : list) {
                auto it = place_ids.find(a.place.text);
                if (it == place_ids.end()) {
                    auto& d = el.sink_.report(DiagId::ArcUnknownPlace, a.place.span,
                                              fmt::format("transition '{}' names '{}', which is not a place of net '{}'",
                                                          t.name.text, a.place.text, c.name.text));
                    if (auto hint = closest_name(a.place.text, pnames); !hint.empty())
                        d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
                    continue;
                }
                el.name_use(a.place.span, c.name.span, a.place.text);  // a place of this net: its slot
                if (a.weight_written && (a.weight < 1 || std::floor(a.weight) != a.weight || a.weight > graph::kMaxArcWeight)) {
                    el.sink_.report(DiagId::ArcBadWeight, a.weight_span,
                                    fmt::format("arc weight {} is not a whole number from 1 to {}", a.weight,
                                                graph::kMaxArcWeight));
                    continue;
                }
                g.arcs.push_back({it->second, static_cast<int32_t>(a.weight)});
            }
            n = graph::rows_since(g.arcs, adr);
        };
        arcs(t.inputs, tr.in_adr, tr.in_num);
        arcs(t.outputs, tr.out_adr, tr.out_num);
        if (t.inputs.empty())
            el.sink_.report(DiagId::EmptyTransition, t.name.span,
                            fmt::format("transition '{}' has no input place, so it would fire in every step", t.name.text));
        tr.fired_slot = el.add_slot(lw.comp, t.name.text + ".fired", SlotType::Void, Dir::Out, t.name.span);
        el.transition_spans_[g.transitions.push_back(tr)] = t.name.span;
    }
}

}  // namespace

constexpr KindLowering lowering{.lower = lower};

}  // namespace plant::kinds::state
