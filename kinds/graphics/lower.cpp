// The graphics' lowering: a row of `graphics` with its model, its animations (rows of
// `animations` and `keys`, each with its play and finished slots) and its variants (rows of
// `variants`, each with its select slot); child graphics are made by the generic part
// (components.cpp: a kind that holds children of its own). Its linking: the body it is `on`.
#include "sema/kinds/lowering.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <fmt/format.h>

namespace plant::kinds::graphics {

using namespace plant::sema;
using graph::Dir;
using graph::SlotType;

namespace {

// One animation of Graphics `gid`: its keys (given, or made from move/rotate over a
// duration) and its play/finished slots.
void lower_animation(Lowering& lw, const ast::AnimationDecl& a, graph::GraphicsId gid) {
    Elaborator& el = lw.el;
    graph::Graph& g = lw.el.g_;
    const Env& env = lw.env;
    graph::Animation an;
    an.graphics = gid;
    an.name = el.name(a.name.text);
    an.key_adr = graph::next_adr(g.keys);
    double duration = -1;
    for (const auto& p : a.properties) {
        Value v = el.ev_.eval(*p.value, env);
        if (p.name.text != "duration") {
            el.sink_.report(DiagId::UnknownProperty, p.name.span,
                            fmt::format("an animation has no property '{}' (only 'duration')", p.name.text));
        } else if (el.ev_.expect_number(v, units::dims::time, "'duration'")) {
            if (v.num <= 0) el.sink_.report(DiagId::NonPositive, v.span, "'duration' must be positive");
            duration = v.num;
        }
    }
    if (!a.keys.empty() && (!a.moves.empty() || !a.rotations.empty())) {
        el.sink_.report(DiagId::AnimationMixed, a.name.span,
                        fmt::format("animation '{}' has keys and also move/rotate; use keys alone, or "
                                    "move/rotate with a duration", a.name.text));
    }
    if (!a.keys.empty()) {
        double last = -1;
        for (const auto& k : a.keys) {
            Value t = el.ev_.eval(*k.time, env);
            if (!el.ev_.expect_number(t, units::dims::time, "key time")) continue;
            if (t.num < 0 || t.num <= last)
                el.sink_.report(DiagId::OutOfRange, t.span, "key times must start at 0 or later and increase");
            last = t.num;
            g.keys.push_back({t.num, el.placement(&k.placement, env).pose()});
        }
        if (duration < 0) duration = std::max(0.0, last);
    } else {
        // rotate/move: from the start pose to the moved pose over the duration. A
        // turn of 90 deg or more gets intermediate keys, so that interpolating
        // between keys (the short way) still turns the whole angle.
        Eigen::Vector3d move = Eigen::Vector3d::Zero();
        for (const auto& m : a.moves) {
            Value v = el.ev_.eval(*m, env);
            if (el.ev_.expect_vec3(v, units::dims::length, "move"))
                move += Eigen::Vector3d(v.items[0].num, v.items[1].num, v.items[2].num);
        }
        double largest = 0;
        Eigen::Quaterniond probe = Eigen::Quaterniond::Identity();
        for (const auto& r : a.rotations) {
            double angle = 0;
            el.rotate(probe, r, env, 1.0, &angle);
            largest = std::max(largest, std::abs(angle));
        }
        if (duration < 0) {
            el.sink_.report(DiagId::MissingProperty, a.name.span,
                            fmt::format("animation '{}' needs a 'duration' (or keys)", a.name.text));
            duration = 0;
        }
        const int pieces = std::max(1, static_cast<int>(std::ceil(largest / (std::numbers::pi / 2) - 1e-9)));
        g.keys.push_back({0.0, Frame{}.pose()});
        for (int i = 1; i <= pieces; ++i) {
            const double share = static_cast<double>(i) / pieces;
            Frame k;
            k.p = move * share;
            for (const auto& r : a.rotations) el.rotate(k.q, r, env, share);
            g.keys.push_back({duration * share, k.pose()});
        }
    }
    an.duration = duration;
    an.key_num = graph::rows_since(g.keys, an.key_adr);
    an.play_slot = el.add_slot(lw.comp, a.name.text + ".play", SlotType::Void, Dir::In, a.name.span);
    an.finished_slot = el.add_slot(lw.comp, a.name.text + ".finished", SlotType::Void, Dir::Out, a.name.span);
    g.animations.push_back(an);
}

void lower(Lowering& lw) {
    Elaborator& el = lw.el;
    graph::Graph& g = lw.el.g_;
    const ast::ComponentDecl& c = lw.decl;
    const Env& env = lw.env;
    graph::Graphics gr;
    gr.comp = lw.comp;
    if (lw.parent.valid()) gr.parent = graph::detail_of<graph::Graphics>(g.comps[lw.parent]);
    gr.body = {};
    gr.model = el.name(lw.props.get("model") ? lw.props.get("model")->str : "");
    gr.pose = lw.frame.pose();
    gr.variant = -1;
    gr.anim_adr = graph::next_adr(g.animations);
    const graph::GraphicsId gid = graph::next_id(g.graphics);
    for (const auto& a : c.animations) lower_animation(lw, a, gid);
    gr.anim_num = graph::rows_since(g.animations, gr.anim_adr);
    gr.variant_adr = graph::next_adr(g.variants);
    for (const auto& v : c.variants) {
        Value m = el.ev_.eval(*v.model, env);
        if (!el.ev_.expect_string(m, "variant model")) continue;
        const graph::SlotId sel = el.add_slot(lw.comp, v.name.text + ".select", SlotType::Void, Dir::In, v.name.span);
        g.variants.push_back({gid, el.name(v.name.text), el.name(m.str), sel});
    }
    gr.variant_num = graph::rows_since(g.variants, gr.variant_adr);
    if (const Value* v = lw.props.get("show")) {
        for (int32_t i = 0; i < gr.variant_num; ++i)
            if (g.str(g.variants[gr.variant_adr + i].name) == v->str) gr.variant = i;
        if (gr.variant < 0) {
            std::vector<std::string> names;
            for (const auto& var : c.variants) names.push_back(var.name.text);
            auto& d = el.sink_.report(DiagId::UnknownName, v->span, fmt::format("no variant named '{}' in '{}'", v->str, c.name.text));
            if (auto hint = closest_name(v->str, names); !hint.empty())
                d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
            else
                d.notes.push_back({{}, names.empty() ? std::string("it declares no variant; add `variant NAME = \"model.glb\"`")
                                                     : fmt::format("its variants: {}", fmt::join(names, ", "))});
        }
    }
    lw.set_detail(g.graphics.push_back(gr));
}

void link(Linking& lk) {
    if (lk.decl.on && lk.rec.detail.valid()) lk.el.g_.graphics[lk.row<graph::Graphics>()].body = lk.on_body();
}

}  // namespace

constexpr KindLowering lowering{.lower = lower, .link = link};

}  // namespace plant::kinds::graphics
