// Components: properties checked against the registry, slots created, kind tables filled.
#include "sema/elaborator.h"

#include "graph/hull.h"
#include "graph/kinds.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <fmt/format.h>

namespace plant::sema {

using graph::CompKind;
using graph::Dir;
using graph::SlotType;

namespace {

constexpr int32_t kMaxPool = 100000;

graph::Vec3 vec(const Value& v) { return {v.items[0].num, v.items[1].num, v.items[2].num}; }

// Properties of one component, looked up by name, checked once.
struct Props {
    std::map<std::string, std::pair<const ast::Property*, Value>> values;
    const Value* get(const std::string& n) const {
        auto it = values.find(n);
        return it == values.end() || it->second.second.kind == Value::Kind::None ? nullptr : &it->second.second;
    }
    bool has(const std::string& n) const { return values.count(n) > 0; }
};

}  // namespace

int32_t Elaborator::add_slot(int32_t comp, std::string_view n, SlotType t, Dir dir, Span span) {
    graph::Slot s;
    s.name = name(n);
    s.type = t;
    s.dir = dir;
    s.comp = comp;
    s.value_adr = -1;
    if (int w = graph::slot_width(t); w > 0) {
        s.value_adr = static_cast<int32_t>(g_.values.size());
        for (int i = 0; i < w; ++i) g_.values.push_back({0.0});
        // No object, no text: a string slot never written reads "" (not the first name).
        if (t == SlotType::Ref || t == SlotType::String) g_.values.back().v = -1;
        if (t == SlotType::Quat || t == SlotType::Pose) g_.values.back().v = 1;  // identity w
    }
    s.src = src(span);
    g_.slots.push_back(s);
    return static_cast<int32_t>(g_.slots.size()) - 1;
}

int32_t Elaborator::make_component(Scope& sc, const ast::ComponentDecl& c, const Env& env, int32_t parent_graphics,
                                   const std::string& prefix) {
    const KindSpec* spec = find_kind(c.kind.text);
    if (!spec) {
        auto& d = sink_.report(DiagId::UnknownComponentKind, c.kind.span,
                               fmt::format("unknown component kind '{}'", c.kind.text));
        if (auto hint = closest_name(c.kind.text, kind_words()); !hint.empty())
            d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
        return -1;
    }
    std::string cname = prefix.empty() ? c.name.text : prefix + "." + c.name.text;
    if (!declare(sc, cname, c.name.span)) return -1;

    // Mode word, e.g. `physics b: kinematic`.
    std::string mode = spec->modes.empty() ? "" : std::string(spec->modes.front());
    if (c.mode) {
        auto it = std::find(spec->modes.begin(), spec->modes.end(), c.mode->text);
        if (it == spec->modes.end()) {
            std::vector<std::string> words(spec->modes.begin(), spec->modes.end());
            auto& d = sink_.report(DiagId::UnknownName, c.mode->span,
                                   fmt::format("'{}' is not a mode of {}", c.mode->text, spec->word));
            d.notes.push_back({{}, words.empty() ? std::string("this kind takes no mode")
                                                 : fmt::format("modes: {}", fmt::join(words, ", "))});
        } else {
            mode = c.mode->text;
        }
    }

    // Properties: known, set once, of the right type and dimension.
    Props props;
    std::set<std::string> suggested;  // a misspelt property is not also reported missing
    for (const auto& p : c.properties) {
        const PropSpec* ps = find_prop(*spec, p.name.text);
        if (!ps) {
            std::vector<std::string> names;
            for (const auto& q : spec->props) names.emplace_back(q.name);
            auto& d = sink_.report(DiagId::UnknownProperty, p.name.span,
                                   fmt::format("{} has no property '{}'", spec->word, p.name.text));
            if (auto hint = closest_name(p.name.text, names); !hint.empty()) {
                d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
                suggested.insert(hint);
            } else if (!names.empty()) {
                d.notes.push_back({{}, fmt::format("its properties: {}", fmt::join(names, ", "))});
            }
            continue;
        }
        if (props.has(p.name.text)) {
            auto& d = sink_.report(DiagId::DuplicateProperty, p.name.span,
                                   fmt::format("property '{}' is set twice", p.name.text));
            d.notes.push_back({props.values[p.name.text].first->name.span, "first set here"});
            continue;
        }
        Value v = ev_.eval(*p.value, env);
        std::string what = fmt::format("'{}'", p.name.text);
        bool ok = v.kind != Value::Kind::None;
        switch (ps->type) {
        case PropType::Number:
            // Limits take the dimension of the joint: checked when the kind is known.
            if (ps->name == "lower" || ps->name == "upper") ok = ok && ev_.expect_number(v, v.dim, what);
            else ok = ok && ev_.expect_number(v, ps->dim, what);
            break;
        case PropType::Vec3: ok = ok && ev_.expect_vec3(v, ps->dim, what); break;
        case PropType::Int: ok = ok && ev_.expect_int(v, what); break;
        case PropType::Bool: ok = ok && ev_.expect_bool(v, what); break;
        case PropType::String: ok = ok && ev_.expect_string(v, what); break;
        case PropType::StringList:
            if (ok && v.kind != Value::Kind::List) {
                sink_.report(DiagId::ValueTypeMismatch, v.span, fmt::format("{} must be a list of strings", what));
                ok = false;
            }
            for (const auto& it : v.items) ok = ok && ev_.expect_string(it, "an entry of " + what);
            break;
        case PropType::Type:
            if (ok && v.kind == Value::Kind::Name && v.str.find('.') == std::string::npos) {
                std::vector<std::string> known;
                for (const auto& [n, t] : types_) known.push_back(n);
                auto& d = sink_.report(DiagId::UnknownType, v.span, fmt::format("unknown object type '{}'", v.str));
                if (auto hint = closest_name(v.str, known); !hint.empty())
                    d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
                ok = false;
            } else if (ok && v.kind == Value::Kind::Type) {
                ok = find_type(v.str, sc.module, v.span, nullptr) != nullptr;  // declared in a module this one sees
            } else if (ok && v.kind != Value::Kind::Type) {
                sink_.report(DiagId::ValueTypeMismatch, v.span,
                             fmt::format("{} must name an object type, not {}", what, with_article(describe(v))));
                ok = false;
            }
            break;
        case PropType::CompRef:
            if (ok && v.kind != Value::Kind::Name) {
                sink_.report(DiagId::ValueTypeMismatch, v.span,
                             fmt::format("{} must name a component of this object, not {}", what, with_article(describe(v))));
                ok = false;
            }
            break;
        }
        props.values[p.name.text] = {&p, ok ? v : Value{}};
    }
    for (const auto& ps : spec->props)
        if (ps.required && !props.has(std::string(ps.name)) && !suggested.count(std::string(ps.name)))
            sink_.report(DiagId::MissingProperty, c.name.span,
                         fmt::format("{} '{}' needs the property '{}' ({})", spec->word, c.name.text, ps.name, ps.doc));

    auto misplaced = [&](bool allowed, const auto& list, std::string_view what) {
        if (!allowed && !list.empty())
            sink_.report(DiagId::WrongComponentKind, list.front().span,
                         fmt::format("a {} component cannot hold {}", spec->word, what));
    };
    misplaced(spec->shapes, c.shapes, "shapes");
    misplaced(spec->animations, c.animations, "animations");
    misplaced(spec->variants, c.variants, "variants");
    misplaced(spec->places, c.places, "places");
    misplaced(spec->places, c.transitions, "transitions");
    misplaced(spec->routes, c.routes, "routes");
    misplaced(spec->children, c.children, "child components");
    if (c.on && !spec->on)
        sink_.report(DiagId::WrongComponentKind, c.on->span,
                     fmt::format("a {} component cannot be attached with 'on'", spec->word));

    const int32_t comp = static_cast<int32_t>(g_.comps.size());
    graph::Comp rec;
    rec.name = name(cname);
    rec.kind = spec->kind;
    rec.owner = sc.do_id;
    rec.detail = -1;
    rec.src = src(c.name.span);
    rec.slot_adr = static_cast<int32_t>(g_.slots.size());
    g_.comps.push_back(rec);
    sc.comps[cname] = comp;
    comp_spans_[comp] = c.name.span;
    for (const auto& s : kind_slots(*spec)) add_slot(comp, s.name, s.type, s.dir, c.name.span);

    const Frame frame = sc.frame * placement(c.placement ? &*c.placement : nullptr, env);
    auto num = [&](const char* n, double def) { const Value* v = props.get(n); return v ? v->num : def; };
    auto boolean = [&](const char* n, bool def) { const Value* v = props.get(n); return v ? v->boolean : def; };
    auto positive = [&](const char* n) {
        const Value* v = props.get(n);
        if (v && v->num <= 0) sink_.report(DiagId::NonPositive, v->span, fmt::format("'{}' must be positive", n));
    };
    auto positive_vec = [&](const char* n) {
        const Value* v = props.get(n);
        if (v && std::any_of(v->items.begin(), v->items.end(), [](const Value& x) { return x.num <= 0; }))
            sink_.report(DiagId::NonPositive, v->span, fmt::format("every extent in '{}' must be positive", n));
    };
    auto set_detail = [&](size_t size) { g_.comps[static_cast<size_t>(comp)].detail = static_cast<int32_t>(size) - 1; };

    switch (spec->kind) {
    case CompKind::Body: {
        graph::Body b;
        b.comp = comp;
        b.mode = mode == "static" ? graph::BodyMode::Static
               : mode == "kinematic" ? graph::BodyMode::Kinematic : graph::BodyMode::Dynamic;
        b.mass = num("mass", 0);
        if (b.mode == graph::BodyMode::Dynamic && !props.has("mass"))
            sink_.report(DiagId::MissingProperty, c.name.span,
                         fmt::format("dynamic body '{}' needs a 'mass'", c.name.text));
        positive("mass");
        if (const Value* in = props.get("inertia")) {
            b.inertia = vec(*in);
            b.inertia_set = true;
            positive_vec("inertia");
        }
        b.friction = num("friction", 0.5);
        b.restitution = num("restitution", 0);
        b.linear_damping = num("linear_damping", 0);
        b.angular_damping = num("angular_damping", 0);
        for (const char* n : {"friction", "restitution", "linear_damping", "angular_damping"})
            if (const Value* v = props.get(n); v && v->num < 0)
                sink_.report(DiagId::OutOfRange, v->span, fmt::format("'{}' cannot be negative", n));
        b.collision = boolean("collision", true);
        b.dynamics = boolean("dynamics", true);
        b.pose = frame.pose();
        b.shape_adr = static_cast<int32_t>(g_.shapes.size());
        for (const auto& sd : c.shapes) {
            graph::Shape sh;
            sh.local = placement(sd.placement ? &*sd.placement : nullptr, env).pose();
            std::vector<Value> a;
            bool ok = true;
            for (const auto& arg : sd.args) {
                if (arg.name && ok)  // once per shape
                    sink_.report(DiagId::UnknownArgument, arg.name->span,
                                 fmt::format("shape arguments are given in order, without names: {}(...)", sd.kind.text));
                ok = ok && !arg.name;
                a.push_back(ev_.eval(*arg.value, env));
                ok = ok && a.back().kind != Value::Kind::None;
            }
            if (!ok) continue;
            auto lengths = [&](size_t n, const char* form) {
                if (a.size() != n) {
                    sink_.report(DiagId::BadShape, sd.span, fmt::format("{} takes {}", sd.kind.text, form));
                    return false;
                }
                for (size_t i = 0; i < n; ++i) {
                    if (!ev_.expect_number(a[i], units::dims::length, fmt::format("{} size", sd.kind.text))) return false;
                    if (a[i].num <= 0) {
                        sink_.report(DiagId::NonPositive, a[i].span, fmt::format("{} sizes must be positive", sd.kind.text));
                        return false;
                    }
                    sh.size[i] = a[i].num;
                }
                return true;
            };
            const std::string& k = sd.kind.text;
            if (k == "box") { sh.kind = graph::ShapeKind::Box; ok = lengths(3, "three full extents (x, y, z)"); }
            else if (k == "sphere") { sh.kind = graph::ShapeKind::Sphere; ok = lengths(1, "a radius"); }
            else if (k == "cylinder") { sh.kind = graph::ShapeKind::Cylinder; ok = lengths(2, "a radius and a height"); }
            else if (k == "capsule") { sh.kind = graph::ShapeKind::Capsule; ok = lengths(2, "a radius and a height"); }
            else if (k == "hull") {
                sh.kind = graph::ShapeKind::Hull;
                sh.point_adr = static_cast<int32_t>(g_.points.size());
                for (const auto& p : a) {
                    if (!ev_.expect_vec3(p, units::dims::length, "hull point")) { ok = false; break; }
                    g_.points.push_back({vec(p)});
                }
                sh.point_num = static_cast<int32_t>(g_.points.size()) - sh.point_adr;
                if (ok && sh.point_num < 4) {
                    sink_.report(DiagId::BadShape, sd.span, "a convex hull needs at least 4 points");
                    ok = false;
                } else if (const auto flaw = ok ? graph::hull_flaw(&g_.points[size_t(sh.point_adr)], size_t(sh.point_num))
                                                : graph::HullFlaw::None;
                           flaw != graph::HullFlaw::None) {
                    auto& d = sink_.report(DiagId::BadShape, sd.span,
                                           fmt::format("this convex hull encloses no volume: {}", graph::hull_flaw_text(flaw)));
                    d.notes.push_back({{}, "a hull needs four points not in one plane (points within 1 µm count as one)"});
                    ok = false;
                }
            } else {
                auto& d = sink_.report(DiagId::BadShape, sd.kind.span, fmt::format("unknown shape '{}'", k));
                if (auto hint = closest_name(k, {"box", "sphere", "cylinder", "capsule", "hull"}); !hint.empty())
                    d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
                else
                    d.notes.push_back({{}, "shapes: box, sphere, cylinder, capsule, hull"});
                ok = false;
            }
            if (ok) g_.shapes.push_back(sh);
        }
        b.shape_num = static_cast<int32_t>(g_.shapes.size()) - b.shape_adr;
        if (c.shapes.empty())
            sink_.report(DiagId::MissingProperty, c.name.span,
                         fmt::format("body '{}' needs at least one shape, e.g. shape box(10 cm, 10 cm, 1 cm)", c.name.text));
        g_.bodies.push_back(b);
        set_detail(g_.bodies.size());
        // Output values start at the body's pose.
        const auto& slots = g_.slots;
        auto put = [&](int idx, std::initializer_list<double> xs) {
            int32_t adr = slots[static_cast<size_t>(rec.slot_adr + idx)].value_adr;
            for (double x : xs) g_.values[static_cast<size_t>(adr++)].v = x;
        };
        put(graph::bodyslot::pose, {b.pose.p[0], b.pose.p[1], b.pose.p[2], b.pose.q[0], b.pose.q[1], b.pose.q[2], b.pose.q[3]});
        put(graph::bodyslot::position, {b.pose.p[0], b.pose.p[1], b.pose.p[2]});
        put(graph::bodyslot::orientation, {b.pose.q[0], b.pose.q[1], b.pose.q[2], b.pose.q[3]});
        break;
    }
    case CompKind::Field: {
        graph::Field f;
        f.comp = comp;
        f.body = -1;
        if (const Value* e = props.get("extent")) f.extent = vec(*e);
        positive_vec("extent");
        f.pose = frame.pose();
        f.dir = {1, 0, 0};
        if (const Value* dv = props.get("direction")) {
            Eigen::Vector3d d(dv->items[0].num, dv->items[1].num, dv->items[2].num);
            if (d.norm() < 1e-12) sink_.report(DiagId::ZeroVector, dv->span, "'direction' is the zero vector");
            else d.normalize();
            f.dir = {d.x(), d.y(), d.z()};
        }
        f.speed = num("speed", 0);
        f.gain = num("gain", 0);
        positive("gain");
        f.max_force = num("max_force", 0);  // 0 in the graph: unlimited
        positive("max_force");
        f.enabled = boolean("enabled", true);
        g_.fields.push_back(f);
        set_detail(g_.fields.size());
        g_.values[static_cast<size_t>(g_.slots[static_cast<size_t>(rec.slot_adr + graph::fieldslot::speed)].value_adr)].v = f.speed;
        break;
    }
    case CompKind::Constraint: {
        graph::Joint j;
        j.comp = comp;
        j.kind = mode == "hinge" ? graph::JointKind::Hinge : mode == "slider" ? graph::JointKind::Slider : graph::JointKind::Fixed;
        j.body_a = j.body_b = -1;
        j.lower = 1;
        j.upper = -1;  // free unless limited
        units::Dim want = j.kind == graph::JointKind::Slider ? units::dims::length : units::dims::angle;
        int limits = 0, written = 0;  // valid ones; written ones (a wrong one is reported once)
        for (const char* n : {"lower", "upper"})
            if (props.has(n)) ++written;
        for (const char* n : {"lower", "upper"})
            if (const Value* v = props.get(n)) {
                if (j.kind == graph::JointKind::Fixed)
                    sink_.report(DiagId::UnknownProperty, v->span, fmt::format("a fixed constraint has no '{}' limit", n));
                else if (ev_.expect_number(*v, want, fmt::format("'{}'", n)))
                    (std::string(n) == "lower" ? j.lower : j.upper) = v->num, ++limits;
            }
        if (written == 1 && j.kind != graph::JointKind::Fixed)
            sink_.report(DiagId::LimitsIncomplete, c.name.span,
                         fmt::format("constraint '{}' has one limit; give both 'lower' and 'upper', or neither for a free joint",
                                     c.name.text));
        else if (limits == 2 && j.lower > j.upper)
            sink_.report(DiagId::LimitsIncomplete, props.get("lower")->span,
                         fmt::format("'lower' ({} {}) is above 'upper' ({} {})", j.lower, units::si_unit(want), j.upper,
                                     units::si_unit(want)));
        // The joint frame: its z axis is the hinge axis, its x axis the slider axis.
        Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
        if (const Value* av = props.get("axis")) {
            axis = Eigen::Vector3d(av->items[0].num, av->items[1].num, av->items[2].num);
            if (axis.norm() < 1e-12) {
                sink_.report(DiagId::ZeroVector, av->span, "'axis' is the zero vector");
                axis = Eigen::Vector3d::UnitZ();
            }
        }
        Eigen::Vector3d base = j.kind == graph::JointKind::Slider ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ();
        Frame jf = frame;
        jf.q = (frame.q * Eigen::Quaterniond::FromTwoVectors(base, axis.normalized())).normalized();
        j.frame_a = jf.pose();  // world for now; made relative in link_component
        j.frame_b = jf.pose();
        j.enabled = boolean("enabled", true);
        g_.joints.push_back(j);
        set_detail(g_.joints.size());
        break;
    }
    case CompKind::State: {
        std::map<std::string, int32_t> place_ids;
        for (const auto& p : c.places) {
            if (place_ids.count(p.name.text)) {
                sink_.report(DiagId::DuplicateName, p.name.span, fmt::format("place '{}' is declared twice", p.name.text));
                continue;
            }
            graph::Place pl;
            pl.comp = comp;
            pl.name = name(p.name.text);
            pl.src = src(p.name.span);
            if (p.initial) {
                Value v = ev_.eval(*p.initial, env);
                if (v.kind == Value::Kind::Num && v.dim.none() && std::floor(v.num) == v.num && v.num >= 0 &&
                    v.num <= graph::kMaxInitialTokens)
                    pl.initial = static_cast<int32_t>(v.num);
                else if (v.kind != Value::Kind::None)
                    sink_.report(DiagId::NegativeTokens, v.span,
                                 fmt::format("initial tokens of '{}' must be a whole number from 0 to {}, not {}", p.name.text,
                                             graph::kMaxInitialTokens,
                                             v.kind == Value::Kind::Num && v.dim.none() ? fmt::format("{}", v.num) : "a " + describe(v)));
            }
            pl.put_slot = add_slot(comp, p.name.text + ".put", SlotType::Void, Dir::In, p.name.span);
            pl.entered_slot = add_slot(comp, p.name.text + ".entered", SlotType::Void, Dir::Out, p.name.span);
            pl.tokens_slot = add_slot(comp, p.name.text + ".tokens", SlotType::Int, Dir::Out, p.name.span);
            g_.values[static_cast<size_t>(g_.slots[static_cast<size_t>(pl.tokens_slot)].value_adr)].v = pl.initial;
            place_ids[p.name.text] = static_cast<int32_t>(g_.places.size());
            place_spans_[static_cast<int32_t>(g_.places.size())] = p.name.span;
            g_.places.push_back(pl);
        }
        std::set<std::string> tnames;
        std::vector<std::string> pnames;
        for (const auto& p : c.places) pnames.push_back(p.name.text);
        for (const auto& t : c.transitions) {
            if (!tnames.insert(t.name.text).second || place_ids.count(t.name.text)) {
                sink_.report(DiagId::DuplicateName, t.name.span, fmt::format("'{}' is declared twice in this net", t.name.text));
                continue;
            }
            graph::Transition tr;
            tr.comp = comp;
            tr.name = name(t.name.text);
            tr.src = src(t.name.span);
            auto arcs = [&](const std::vector<ast::ArcDecl>& list, int32_t& adr, int32_t& n) {
                adr = static_cast<int32_t>(g_.arcs.size());
                for (const auto& a : list) {
                    auto it = place_ids.find(a.place.text);
                    if (it == place_ids.end()) {
                        auto& d = sink_.report(DiagId::ArcUnknownPlace, a.place.span,
                                               fmt::format("transition '{}' names '{}', which is not a place of net '{}'",
                                                           t.name.text, a.place.text, c.name.text));
                        if (auto hint = closest_name(a.place.text, pnames); !hint.empty())
                            d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
                        continue;
                    }
                    if (a.weight_written && (a.weight < 1 || std::floor(a.weight) != a.weight || a.weight > graph::kMaxArcWeight)) {
                        sink_.report(DiagId::ArcBadWeight, a.weight_span,
                                     fmt::format("arc weight {} is not a whole number from 1 to {}", a.weight,
                                                 graph::kMaxArcWeight));
                        continue;
                    }
                    g_.arcs.push_back({it->second, static_cast<int32_t>(a.weight)});
                }
                n = static_cast<int32_t>(g_.arcs.size()) - adr;
            };
            arcs(t.inputs, tr.in_adr, tr.in_num);
            arcs(t.outputs, tr.out_adr, tr.out_num);
            if (t.inputs.empty())
                sink_.report(DiagId::EmptyTransition, t.name.span,
                             fmt::format("transition '{}' has no input place, so it would fire in every step", t.name.text));
            tr.fired_slot = add_slot(comp, t.name.text + ".fired", SlotType::Void, Dir::Out, t.name.span);
            transition_spans_[static_cast<int32_t>(g_.transitions.size())] = t.name.span;
            g_.transitions.push_back(tr);
        }
        break;
    }
    case CompKind::Trigger: {
        graph::Trigger t;
        t.comp = comp;
        t.body = -1;
        if (const Value* e = props.get("extent")) t.extent = vec(*e);
        positive_vec("extent");
        t.pose = frame.pose();
        t.filter = -1;
        if (const Value* f = props.get("filter")) {
            t.filter = do_type(f->str, f->span);
            ref_types_[rec.slot_adr + graph::triggerslot::object] = t.filter;
        }
        g_.triggers.push_back(t);
        set_detail(g_.triggers.size());
        break;
    }
    case CompKind::Timer: {
        graph::Timer t;
        t.comp = comp;
        t.period = num("period", 0);
        positive("period");
        t.periodic = mode != "oneshot";
        t.autostart = boolean("autostart", false);
        g_.timers.push_back(t);
        set_detail(g_.timers.size());
        break;
    }
    case CompKind::Gripper: {
        graph::Gripper gr;
        gr.comp = comp;
        gr.trigger = gr.body = gr.graphics = -1;
        g_.grippers.push_back(gr);
        set_detail(g_.grippers.size());
        break;
    }
    case CompKind::Source: {
        graph::Source s;
        s.comp = comp;
        s.do_type = -1;
        s.pose = frame.pose();
        s.rate = num("rate", 0);
        if (const Value* r = props.get("rate"); r && r->num < 0)
            sink_.report(DiagId::OutOfRange, r->span, "'rate' cannot be negative");
        int32_t pool = 0;
        if (const Value* p = props.get("pool")) {
            if (p->num < 1 || p->num > kMaxPool)
                sink_.report(p->num < 1 ? DiagId::NonPositive : DiagId::LoopTooLarge, p->span,
                             fmt::format("'pool' must be between 1 and {}", kMaxPool));
            else pool = static_cast<int32_t>(p->num);
        }
        s.pool_num = pool;  // the DOs are built by make_pools
        s.pool_adr = -1;
        if (const Value* t = props.get("object")) {
            s.do_type = do_type(t->str, t->span);
            ref_types_[rec.slot_adr + graph::sourceslot::object] = s.do_type;
        }
        s.id_adr = static_cast<int32_t>(g_.ids.size());
        if (const Value* ids = props.get("ids")) {
            for (const auto& it : ids->items) g_.ids.push_back({name(it.str)});
            if (ids->items.empty()) sink_.report(DiagId::OutOfRange, ids->span, "'ids' is empty");
        } else {
            for (int32_t i = 1; i <= pool; ++i) g_.ids.push_back({name(fmt::format("{}-{}", c.name.text, i))});
        }
        s.id_num = static_cast<int32_t>(g_.ids.size()) - s.id_adr;
        g_.sources.push_back(s);
        set_detail(g_.sources.size());
        break;
    }
    case CompKind::Exit: {
        g_.exits.push_back({comp, -1});
        set_detail(g_.exits.size());
        break;
    }
    case CompKind::Router: {
        std::map<std::string, int32_t> outs;
        for (const auto& r : c.routes) {
            auto it = outs.find(r.output.text);
            if (it == outs.end()) {
                if (graph::fixed_slot_index(CompKind::Router, r.output.text) >= 0) {
                    sink_.report(DiagId::DuplicateName, r.output.span,
                                 fmt::format("'{}' is the router's own input; name the entry otherwise", r.output.text));
                    continue;
                }
                it = outs.emplace(r.output.text, add_slot(comp, r.output.text, SlotType::Void, Dir::Out, r.output.span)).first;
            }
            if (!r.pattern_expr) {
                g_.routes.push_back({comp, name("*"), it->second});
                continue;
            }
            // A string, or a list of strings (one entry each), from parameters and lets too.
            Value v = ev_.eval(*r.pattern_expr, env);
            if (v.kind == Value::Kind::None) continue;
            std::vector<Value> patterns = v.kind == Value::Kind::List ? v.items : std::vector<Value>{v};
            if (patterns.empty())
                sink_.report(DiagId::ValueTypeMismatch, r.pattern_span,
                             "a routing entry needs at least one pattern; this list is empty");
            for (const Value& pv : patterns) {
                if (!ev_.expect_string(pv, "a routing pattern")) break;
                g_.routes.push_back({comp, name(pv.str), it->second});
            }
        }
        break;
    }
    case CompKind::Plugin: lower_plugin(comp, *spec->plugin, props.values); break;
    case CompKind::Label: {
        graph::Label l{comp, name(props.get("value") ? props.get("value")->str : "")};
        g_.labels.push_back(l);
        set_detail(g_.labels.size());
        g_.values[static_cast<size_t>(g_.slots[static_cast<size_t>(rec.slot_adr + graph::labelslot::value)].value_adr)].v = l.value.id;
        break;
    }
    case CompKind::Graphics: {
        graph::Graphics gr;
        gr.comp = comp;
        gr.parent = parent_graphics;
        gr.body = -1;
        gr.model = name(props.get("model") ? props.get("model")->str : "");
        gr.pose = frame.pose();
        gr.variant = -1;
        gr.anim_adr = static_cast<int32_t>(g_.animations.size());
        const int32_t gid = static_cast<int32_t>(g_.graphics.size());
        for (const auto& a : c.animations) {
            graph::Animation an;
            an.graphics = gid;
            an.name = name(a.name.text);
            an.key_adr = static_cast<int32_t>(g_.keys.size());
            double duration = -1;
            for (const auto& p : a.properties) {
                Value v = ev_.eval(*p.value, env);
                if (p.name.text != "duration") {
                    sink_.report(DiagId::UnknownProperty, p.name.span,
                                 fmt::format("an animation has no property '{}' (only 'duration')", p.name.text));
                } else if (ev_.expect_number(v, units::dims::time, "'duration'")) {
                    if (v.num <= 0) sink_.report(DiagId::NonPositive, v.span, "'duration' must be positive");
                    duration = v.num;
                }
            }
            if (!a.keys.empty() && (!a.moves.empty() || !a.rotations.empty())) {
                sink_.report(DiagId::AnimationMixed, a.name.span,
                             fmt::format("animation '{}' has keys and also move/rotate; use keys alone, or "
                                         "move/rotate with a duration", a.name.text));
            }
            if (!a.keys.empty()) {
                double last = -1;
                for (const auto& k : a.keys) {
                    Value t = ev_.eval(*k.time, env);
                    if (!ev_.expect_number(t, units::dims::time, "key time")) continue;
                    if (t.num < 0 || t.num <= last)
                        sink_.report(DiagId::OutOfRange, t.span, "key times must start at 0 or later and increase");
                    last = t.num;
                    g_.keys.push_back({t.num, placement(&k.placement, env).pose()});
                }
                if (duration < 0) duration = std::max(0.0, last);
            } else {
                // rotate/move: from the start pose to the moved pose over the duration. A
                // turn of 90 deg or more gets intermediate keys, so that interpolating
                // between keys (the short way) still turns the whole angle.
                Eigen::Vector3d move = Eigen::Vector3d::Zero();
                for (const auto& m : a.moves) {
                    Value v = ev_.eval(*m, env);
                    if (ev_.expect_vec3(v, units::dims::length, "move"))
                        move += Eigen::Vector3d(v.items[0].num, v.items[1].num, v.items[2].num);
                }
                double largest = 0;
                Eigen::Quaterniond probe = Eigen::Quaterniond::Identity();
                for (const auto& r : a.rotations) {
                    double angle = 0;
                    rotate(probe, r, env, 1.0, &angle);
                    largest = std::max(largest, std::abs(angle));
                }
                if (duration < 0) {
                    sink_.report(DiagId::MissingProperty, a.name.span,
                                 fmt::format("animation '{}' needs a 'duration' (or keys)", a.name.text));
                    duration = 0;
                }
                const int pieces = std::max(1, static_cast<int>(std::ceil(largest / (std::numbers::pi / 2) - 1e-9)));
                g_.keys.push_back({0.0, Frame{}.pose()});
                for (int i = 1; i <= pieces; ++i) {
                    const double share = static_cast<double>(i) / pieces;
                    Frame k;
                    k.p = move * share;
                    for (const auto& r : a.rotations) rotate(k.q, r, env, share);
                    g_.keys.push_back({duration * share, k.pose()});
                }
            }
            an.duration = duration;
            an.key_num = static_cast<int32_t>(g_.keys.size()) - an.key_adr;
            an.play_slot = add_slot(comp, a.name.text + ".play", SlotType::Void, Dir::In, a.name.span);
            an.finished_slot = add_slot(comp, a.name.text + ".finished", SlotType::Void, Dir::Out, a.name.span);
            g_.animations.push_back(an);
        }
        gr.anim_num = static_cast<int32_t>(g_.animations.size()) - gr.anim_adr;
        gr.variant_adr = static_cast<int32_t>(g_.variants.size());
        for (const auto& v : c.variants) {
            Value m = ev_.eval(*v.model, env);
            if (!ev_.expect_string(m, "variant model")) continue;
            int32_t sel = add_slot(comp, v.name.text + ".select", SlotType::Void, Dir::In, v.name.span);
            g_.variants.push_back({gid, name(v.name.text), name(m.str), sel});
        }
        gr.variant_num = static_cast<int32_t>(g_.variants.size()) - gr.variant_adr;
        if (const Value* v = props.get("show")) {
            for (int32_t i = 0; i < gr.variant_num; ++i)
                if (g_.str(g_.variants[static_cast<size_t>(gr.variant_adr + i)].name) == v->str) gr.variant = i;
            if (gr.variant < 0) {
                std::vector<std::string> names;
                for (const auto& var : c.variants) names.push_back(var.name.text);
                auto& d = sink_.report(DiagId::UnknownName, v->span, fmt::format("no variant named '{}' in '{}'", v->str, c.name.text));
                if (auto hint = closest_name(v->str, names); !hint.empty())
                    d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
                else
                    d.notes.push_back({{}, names.empty() ? std::string("it declares no variant; add `variant NAME = \"model.glb\"`")
                                                         : fmt::format("its variants: {}", fmt::join(names, ", "))});
            }
        }
        g_.graphics.push_back(gr);
        set_detail(g_.graphics.size());
        break;
    }
    case CompKind::Logic: break;
    }
    g_.comps[static_cast<size_t>(comp)].slot_num = static_cast<int32_t>(g_.slots.size()) - rec.slot_adr;

    // Child graphics: their own components, named parent.child, posed relative to it.
    for (const auto& child : c.children) {
        if (spec->kind != CompKind::Graphics) break;  // reported above: this kind holds no children
        if (child.kind.text != "graphics") {
            sink_.report(DiagId::WrongComponentKind, child.kind.span, "only graphics can hold child graphics");
            continue;
        }
        Frame saved = sc.frame;
        sc.frame = frame;
        make_component(sc, child, env, g_.comps[static_cast<size_t>(comp)].detail, cname);
        sc.frame = saved;
    }
    return comp;
}

// References between components of one DO, resolved once they all exist.
void Elaborator::link_component(Scope& sc, int32_t comp, const ast::ComponentDecl& c, const Env& env) {
    const graph::Comp rec = g_.comps[static_cast<size_t>(comp)];
    auto find = [&](const std::string& n, Span span, CompKind want, const char* what) -> int32_t {
        auto it = sc.comps.find(n);
        if (it == sc.comps.end()) {
            std::vector<std::string> names;
            for (const auto& [k, v] : sc.comps) names.push_back(k);
            auto& d = sink_.report(DiagId::UnknownName, span, fmt::format("no component '{}' in this object", n));
            if (auto hint = closest_name(n, names); !hint.empty())
                d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
            return -1;
        }
        const auto& target = g_.comps[static_cast<size_t>(it->second)];
        if (target.kind != want) {
            // The words of the language: a Body is written `physics`.
            auto word = [](CompKind k) { return k == CompKind::Body ? std::string_view("physics") : graph::word(k); };
            sink_.report(DiagId::WrongComponentKind, span,
                         fmt::format("'{}' is a {} component, but {} must be a {} component", n, word(target.kind), what,
                                     word(want)));
            return -1;
        }
        return target.detail;
    };
    auto prop = [&](const char* n) -> const ast::Property* {
        for (const auto& p : c.properties)
            if (p.name.text == n) return &p;
        return nullptr;
    };
    auto ref_name = [&](const ast::Property* p) -> std::string {
        Value v = ev_.eval(*p->value, env);
        return v.kind == Value::Kind::Name ? v.str : std::string();
    };
    std::string on = c.on ? [&] {
        std::string s;
        for (const auto& seg : c.on->segs) s += (s.empty() ? "" : ".") + seg.name.text;
        return s;
    }() : std::string();

    switch (rec.kind) {
    case CompKind::Field:
        if (c.on) g_.fields[static_cast<size_t>(rec.detail)].body = find(on, c.on->span, CompKind::Body, "'on'");
        break;
    case CompKind::Trigger:
        if (c.on) g_.triggers[static_cast<size_t>(rec.detail)].body = find(on, c.on->span, CompKind::Body, "'on'");
        break;
    case CompKind::Graphics:
        if (c.on && rec.detail >= 0)
            g_.graphics[static_cast<size_t>(rec.detail)].body = find(on, c.on->span, CompKind::Body, "'on'");
        break;
    case CompKind::Gripper: {
        auto& gr = g_.grippers[static_cast<size_t>(rec.detail)];
        if (const auto* p = prop("trigger"); p && !ref_name(p).empty()) {
            gr.trigger = find(ref_name(p), p->value->span, CompKind::Trigger, "'trigger'");
            if (gr.trigger >= 0) {
                int32_t tslot = g_.comps[static_cast<size_t>(g_.triggers[static_cast<size_t>(gr.trigger)].comp)].slot_adr +
                                graph::triggerslot::object;
                if (auto it = ref_types_.find(tslot); it != ref_types_.end())
                    ref_types_[rec.slot_adr + graph::gripperslot::object] = it->second;
            }
        }
        if (c.on) {
            auto it = sc.comps.find(on);
            if (it != sc.comps.end() && g_.comps[static_cast<size_t>(it->second)].kind == CompKind::Graphics)
                gr.graphics = g_.comps[static_cast<size_t>(it->second)].detail;
            else
                gr.body = find(on, c.on->span, CompKind::Body, "'on'");
        }
        break;
    }
    case CompKind::Exit:
        if (const auto* p = prop("trigger"); p && !ref_name(p).empty())
            g_.exits[static_cast<size_t>(rec.detail)].trigger = find(ref_name(p), p->value->span, CompKind::Trigger, "'trigger'");
        break;
    case CompKind::Constraint: {
        auto& j = g_.joints[static_cast<size_t>(rec.detail)];
        auto body_frame = [&](int32_t body) {
            const auto& p = g_.bodies[static_cast<size_t>(body)].pose;
            Frame f;
            f.p = Eigen::Vector3d(p.p[0], p.p[1], p.p[2]);
            f.q = Eigen::Quaterniond(p.q[3], p.q[0], p.q[1], p.q[2]);
            return f;
        };
        Frame world;
        world.p = Eigen::Vector3d(j.frame_a.p[0], j.frame_a.p[1], j.frame_a.p[2]);
        world.q = Eigen::Quaterniond(j.frame_a.q[3], j.frame_a.q[0], j.frame_a.q[1], j.frame_a.q[2]);
        if (const auto* p = prop("a"); p && !ref_name(p).empty()) j.body_a = find(ref_name(p), p->value->span, CompKind::Body, "'a'");
        if (const auto* p = prop("b"); p && !ref_name(p).empty()) j.body_b = find(ref_name(p), p->value->span, CompKind::Body, "'b'");
        if (j.body_a >= 0) j.frame_a = (body_frame(j.body_a).inverse() * world).pose();
        if (j.body_b >= 0) j.frame_b = (body_frame(j.body_b).inverse() * world).pose();
        if (j.body_a >= 0 && j.body_a == j.body_b)
            sink_.report(DiagId::OutOfRange, c.name.span, "a constraint needs two different bodies");
        break;
    }
    default: break;
    }
}

void Elaborator::make_logic(Scope& sc, const ast::LogicDecl& l) {
    if (!declare(sc, l.name.text, l.name.span)) return;
    graph::Comp rec;
    rec.name = name(l.name.text);
    rec.kind = CompKind::Logic;
    rec.owner = sc.do_id;
    rec.src = src(l.name.span);
    rec.slot_adr = static_cast<int32_t>(g_.slots.size());
    const int32_t comp = static_cast<int32_t>(g_.comps.size());
    g_.comps.push_back(rec);
    sc.comps[l.name.text] = comp;
    comp_spans_[comp] = l.name.span;
    graph::Logic lg;
    lg.comp = comp;
    lg.op = graph::LogicOp::And;
    lg.out_slot = add_slot(comp, "out", SlotType::Void, Dir::Out, l.name.span);
    for (size_t i = 0; i < l.ops.size(); ++i) {
        if (l.ops[i].text != l.ops[0].text) {
            sink_.report(DiagId::LogicMixedOps, l.ops[i].span,
                         "a connector is either 'and' or 'or'; split it into two logic declarations");
            break;
        }
    }
    if (!l.ops.empty() && l.ops[0].text == "or") lg.op = graph::LogicOp::Or;
    lg.in_adr = static_cast<int32_t>(g_.logic_inputs.size());
    for (size_t i = 0; i < l.terms.size(); ++i) {
        int32_t s = add_slot(comp, fmt::format("in{}", i), SlotType::Void, Dir::In, l.terms[i].span);
        g_.logic_inputs.push_back({s, l.terms[i].negated});
    }
    lg.in_num = static_cast<int32_t>(l.terms.size());
    g_.comps[static_cast<size_t>(comp)].detail = static_cast<int32_t>(g_.logics.size());
    g_.comps[static_cast<size_t>(comp)].slot_num = static_cast<int32_t>(g_.slots.size()) - rec.slot_adr;
    g_.logics.push_back(lg);
}

}  // namespace plant::sema
