// Builds small plant graphs by hand for the runtime tests, laid out as the compiler
// lays them out (through graph/build.h, which the compiler uses too).
#pragma once

#include "graph/build.h"
#include "graph/graph.h"
#include "graph/kinds.h"

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace plant::test {

using namespace plant::graph;

inline Pose at(double x, double y, double z) { return Pose{{x, y, z}, {0, 0, 0, 1}}; }

struct ShapeSpec {
    ShapeKind kind = ShapeKind::Box;
    Vec3 size{0.1, 0.1, 0.1};
    Pose local{};
    std::vector<Vec3> points;
};
inline ShapeSpec box(Vec3 size, Pose local = {}) { return {ShapeKind::Box, size, local, {}}; }
inline ShapeSpec sphere(double r, Pose local = {}) { return {ShapeKind::Sphere, {r, 0, 0}, local, {}}; }
inline ShapeSpec cylinder(double r, double h) { return {ShapeKind::Cylinder, {r, h, 0}, {}, {}}; }

struct TransitionSpec {
    std::string name;
    std::vector<std::pair<int, int>> in, out;  // (place index within the net, weight)
};

struct SceneBuilder {
    Graph g;

    explicit SceneBuilder(double rate = 150) {
        g.settings.rate = rate;
        g.plant = g.intern("Test");
        dobj("", -1);  // DO 0: the plant itself
    }

    Name name(std::string_view s) { return g.intern(s); }

    int32_t type(std::string_view n) {
        g.do_types.push_back({name(n), 0, {}});
        return int32_t(g.do_types.size() - 1);
    }

    int32_t dobj(std::string_view path, int32_t parent = 0, int32_t type = -1, Pose pose = {}) {
        return add_do(g, path, DoId(parent), DoTypeId(type), pose).v;
    }

    // A component with its kind's fixed slots (graph/build.h): add a DO's components
    // right after creating it.
    int32_t comp(int32_t owner, CompKind kind, std::string_view n, int32_t detail) {
        const CompId id = add_comp(g, DoId(owner), kind, n);
        g.comps[id].detail.v = detail;
        return id.v;
    }

    int32_t slot(int32_t comp, std::string_view n, SlotType t, Dir d) { return add_slot(g, CompId(comp), n, t, d).v; }

    // Slot of a component by local name (fixed or dynamic).
    int32_t S(int32_t comp, std::string_view n) const {
        const Comp& c = g.comps[CompId(comp)];
        for (SlotId s : children(c.slot_adr, c.slot_num))
            if (g.str(g.slots[s].name) == n) return s.v;
        return -1;
    }

    int32_t body(int32_t owner, std::string_view n, BodyMode mode, const std::vector<ShapeSpec>& shapes,
                 double mass, Pose pose, double friction = 0, Vec3 com = {0, 0, 0}) {
        Body b;
        b.mode = mode;
        b.mass = mass;
        b.friction = friction;
        b.collision = true;
        b.dynamics = true;
        b.shape_adr = next_adr(g.shapes);
        b.shape_num = int32_t(shapes.size());
        b.pose = pose;
        b.com = Pose{com, {0, 0, 0, 1}};
        for (const ShapeSpec& s : shapes) {
            Shape sh;
            sh.kind = s.kind;
            sh.size = s.size;
            sh.local = s.local;
            sh.point_adr = next_adr(g.points);
            sh.point_num = int32_t(s.points.size());
            for (const Vec3& p : s.points) g.points.push_back({p});
            g.shapes.push_back(sh);
        }
        b.comp = CompId(comp(owner, CompKind::Body, n, int32_t(g.bodies.size())));
        g.bodies.push_back(b);
        return int32_t(g.bodies.size() - 1);
    }
    int32_t body_comp(int32_t b) const { return g.bodies[BodyId(b)].comp.v; }
    int32_t field_comp(int32_t f) const { return g.fields[FieldId(f)].comp.v; }

    int32_t field(int32_t owner, std::string_view n, Vec3 extent, Pose pose, Vec3 dir, double speed,
                  double gain, int32_t on_body = -1) {
        Field f{};
        f.body = BodyId(on_body);
        f.extent = extent;
        f.pose = pose;
        f.dir = dir;
        f.speed = speed;
        f.gain = gain;
        f.enabled = true;
        f.comp = CompId(comp(owner, CompKind::Field, n, int32_t(g.fields.size())));
        g.fields.push_back(f);
        return int32_t(g.fields.size() - 1);
    }

    int32_t joint(int32_t owner, std::string_view n, JointKind kind, int32_t a, int32_t b, Pose fa, Pose fb) {
        Joint j{};
        j.kind = kind;
        j.body_a = BodyId(a);
        j.body_b = BodyId(b);
        j.frame_a = fa;
        j.frame_b = fb;
        j.lower = 1;
        j.upper = -1;
        j.enabled = true;
        j.comp = CompId(comp(owner, CompKind::Constraint, n, int32_t(g.joints.size())));
        g.joints.push_back(j);
        return int32_t(g.joints.size() - 1);
    }

    int32_t trigger(int32_t owner, std::string_view n, Vec3 extent, Pose pose, int32_t filter = -1,
                    int32_t on_body = -1) {
        Trigger t{};
        t.body = BodyId(on_body);
        t.extent = extent;
        t.pose = pose;
        t.filter = DoTypeId(filter);
        t.comp = CompId(comp(owner, CompKind::Trigger, n, int32_t(g.triggers.size())));
        g.triggers.push_back(t);
        return int32_t(g.triggers.size() - 1);
    }

    int32_t timer(int32_t owner, std::string_view n, double period, bool periodic, bool autostart) {
        Timer t{};
        t.period = period;
        t.periodic = periodic;
        t.autostart = autostart;
        t.comp = CompId(comp(owner, CompKind::Timer, n, int32_t(g.timers.size())));
        g.timers.push_back(t);
        return int32_t(g.timers.size() - 1);
    }

    // A Petri net; returns the first place id (places are consecutive) and fills `tr`
    // with the transition ids.
    int32_t net(int32_t owner, std::string_view n, const std::vector<std::pair<std::string, int>>& places,
                const std::vector<TransitionSpec>& transitions, std::vector<int32_t>* tr = nullptr) {
        const int32_t c = comp(owner, CompKind::State, n, -1);
        const int32_t first = int32_t(g.places.size());
        for (auto& [pn, initial] : places) {
            Place p{};
            p.comp = CompId(c);
            p.name = name(pn);
            p.initial = initial;
            p.put_slot = SlotId(slot(c, pn + ".put", SlotType::Void, Dir::In));
            p.entered_slot = SlotId(slot(c, pn + ".entered", SlotType::Void, Dir::Out));
            p.tokens_slot = SlotId(slot(c, pn + ".tokens", SlotType::Int, Dir::Out));
            slot_value(g, p.tokens_slot) = initial;
            g.places.push_back(p);
        }
        for (const TransitionSpec& ts : transitions) {
            Transition t{};
            t.comp = CompId(c);
            t.name = name(ts.name);
            t.in_adr = next_adr(g.arcs);
            t.in_num = int32_t(ts.in.size());
            for (auto [p, w] : ts.in) g.arcs.push_back({PlaceId(first + p), w});
            t.out_adr = next_adr(g.arcs);
            t.out_num = int32_t(ts.out.size());
            for (auto [p, w] : ts.out) g.arcs.push_back({PlaceId(first + p), w});
            t.fired_slot = SlotId(slot(c, ts.name + ".fired", SlotType::Void, Dir::Out));
            g.transitions.push_back(t);
            if (tr) tr->push_back(int32_t(g.transitions.size() - 1));
        }
        return first;
    }
    int32_t put(int32_t place) const { return g.places[PlaceId(place)].put_slot.v; }
    int32_t entered(int32_t place) const { return g.places[PlaceId(place)].entered_slot.v; }

    int32_t logic(int32_t owner, std::string_view n, LogicOp op, const std::vector<bool>& negated) {
        Logic l{};
        l.op = op;
        l.comp = CompId(comp(owner, CompKind::Logic, n, int32_t(g.logics.size())));
        l.out_slot = SlotId(g.comps[l.comp].slot_adr + logicslot::out);
        l.in_adr = next_adr(g.logic_inputs);
        l.in_num = int32_t(negated.size());
        for (size_t i = 0; i < negated.size(); ++i)
            g.logic_inputs.push_back({SlotId(slot(l.comp.v, "in" + std::to_string(i), SlotType::Void, Dir::In)), negated[i]});
        g.logics.push_back(l);
        return int32_t(g.logics.size() - 1);
    }

    int32_t router(int32_t owner, std::string_view n, const std::vector<std::string>& patterns) {
        const int32_t c = comp(owner, CompKind::Router, n, -1);
        for (size_t i = 0; i < patterns.size(); ++i) {
            Route r{};
            r.comp = CompId(c);
            r.pattern = name(patterns[i]);
            r.out_slot = SlotId(slot(c, "r" + std::to_string(i), SlotType::Void, Dir::Out));
            g.routes.push_back(r);
        }
        return c;
    }

    int32_t label(int32_t owner, std::string_view n, std::string_view value) {
        Label l{};
        l.value = name(value);
        l.comp = CompId(comp(owner, CompKind::Label, n, int32_t(g.labels.size())));
        slot_value(g, SlotId(g.comps[l.comp].slot_adr + labelslot::value)) = l.value.id;
        g.labels.push_back(l);
        return int32_t(g.labels.size() - 1);
    }

    int32_t source(int32_t owner, std::string_view n, int32_t do_type, int32_t pool_adr, int32_t pool_num,
                   double rate, Pose pose, const std::vector<std::string>& ids) {
        Source s{};
        s.do_type = DoTypeId(do_type);
        s.pool_adr = Adr<Do>(pool_adr);
        s.pool_num = pool_num;
        s.rate = rate;
        s.pose = pose;
        s.id_adr = next_adr(g.ids);
        s.id_num = int32_t(ids.size());
        for (const std::string& id : ids) g.ids.push_back({name(id)});
        s.comp = CompId(comp(owner, CompKind::Source, n, int32_t(g.sources.size())));
        for (int32_t d = pool_adr; d < pool_adr + pool_num; ++d) g.dos[DoId(d)].pool = s.comp;
        g.sources.push_back(s);
        return int32_t(g.sources.size() - 1);
    }

    int32_t exit(int32_t owner, std::string_view n, int32_t trig) {
        Exit e{};
        e.trigger = TriggerId(trig);
        e.comp = CompId(comp(owner, CompKind::Exit, n, int32_t(g.exits.size())));
        g.exits.push_back(e);
        return int32_t(g.exits.size() - 1);
    }

    int32_t gripper(int32_t owner, std::string_view n, int32_t trig, int32_t on_body, int32_t gfx = -1) {
        Gripper gr{};
        gr.trigger = TriggerId(trig);
        gr.body = BodyId(on_body);
        gr.graphics = GraphicsId(gfx);
        gr.comp = CompId(comp(owner, CompKind::Gripper, n, int32_t(g.grippers.size())));
        g.grippers.push_back(gr);
        return int32_t(g.grippers.size() - 1);
    }

    struct AnimSpec {
        std::string name;
        double duration;
        std::vector<Key> keys;
    };
    int32_t graphics(int32_t owner, std::string_view n, Pose pose, int32_t on_body = -1,
                     const std::vector<AnimSpec>& anims = {}, const std::vector<std::string>& variants = {}) {
        Graphics gr{};
        gr.parent = {};
        gr.model = name("model.glb");
        gr.pose = pose;
        gr.body = BodyId(on_body);
        gr.variant = -1;
        gr.comp = CompId(comp(owner, CompKind::Graphics, n, int32_t(g.graphics.size())));
        const int32_t gi = int32_t(g.graphics.size());
        gr.anim_adr = next_adr(g.animations);
        gr.anim_num = int32_t(anims.size());
        for (const AnimSpec& a : anims) {
            Animation an{};
            an.graphics = GraphicsId(gi);
            an.name = name(a.name);
            an.duration = a.duration;
            an.key_adr = next_adr(g.keys);
            an.key_num = int32_t(a.keys.size());
            for (const Key& k : a.keys) g.keys.push_back(k);
            an.play_slot = SlotId(slot(gr.comp.v, a.name + ".play", SlotType::Void, Dir::In));
            an.finished_slot = SlotId(slot(gr.comp.v, a.name + ".finished", SlotType::Void, Dir::Out));
            g.animations.push_back(an);
        }
        gr.variant_adr = next_adr(g.variants);
        gr.variant_num = int32_t(variants.size());
        for (const std::string& v : variants) {
            Variant var{};
            var.graphics = GraphicsId(gi);
            var.name = name(v);
            var.model = name(v + ".glb");
            var.select_slot = SlotId(slot(gr.comp.v, v + ".select", SlotType::Void, Dir::In));
            g.variants.push_back(var);
        }
        g.graphics.push_back(gr);
        return gi;
    }

    int32_t access(int32_t ref_slot, int32_t do_type, const std::vector<int32_t>& targets) {
        Access a{};
        a.ref_slot = SlotId(ref_slot);
        a.do_type = DoTypeId(do_type);
        a.target_adr = next_adr(g.access_targets);
        a.target_num = int32_t(targets.size());
        for (int32_t t : targets) g.access_targets.push_back({SlotId(t)});
        g.accesses.push_back(a);
        return int32_t(g.accesses.size() - 1);
    }

    int32_t flow(int32_t from, int32_t to, Cond cond = Cond::Source, bool once = false, int32_t from_access = -1,
                 int32_t to_access = -1) {
        return add_flow(g, SlotId(from), SlotId(to), cond, once, AccessId(from_access), AccessId(to_access)).v;
    }

    void record(int32_t slot, std::string_view column) { g.records.push_back({SlotId(slot), name(column)}); }
};

}  // namespace plant::test
