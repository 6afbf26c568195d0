#include "serve/view.h"
#include "serve/panels.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <map>
#include <filesystem>
#include <system_error>

namespace plant::view {

using namespace plant::graph;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

json pose_json(const Pose& p) { return json::array({p.p[0], p.p[1], p.p[2], p.q[0], p.q[1], p.q[2], p.q[3]}); }
json vec_json(const Vec3& v) { return json::array({v[0], v[1], v[2]}); }

}  // namespace

std::string scene_json(const Graph& g, const ModelDirs& dirs, bool replay, double duration) {
    json s;
    s["type"] = "scene";
    s["version"] = kProtocolVersion;
    s["mode"] = replay ? "replay" : "live";
    if (replay) s["duration"] = duration;
    s["plant"] = g.str(g.plant);
    s["rate"] = g.settings.rate;
    // Each model name looked up once (a thousand bottles name the same five).
    std::map<std::string, json, std::less<>> urls;
    auto model_url = [&](std::string_view model) -> const json& {
        auto it = urls.find(model);
        if (it == urls.end())
            it = urls.emplace(std::string(model), find_model(dirs, model).file.empty() ? json(nullptr)
                                                                                       : json("/models/" + std::string(model)))
                     .first;
        return it->second;
    };
    json problems = json::array();
    for (const ModelProblem& p : model_problems(g, dirs)) problems.push_back({{"model", p.model}, {"problem", p.problem}});
    s["model_problems"] = std::move(problems);

    // Each object's own inputs and outputs (its ports, its components' slots), relative to
    // its path; objects of one type share one list.
    IdVector<DoId, std::vector<PortId>> ports_of(g.dos.count());
    for (PortId p : ids_of(g.ports)) ports_of[g.ports[p].owner].push_back(p);
    json dos = json::array(), slot_lists = json::array();
    std::map<std::string, size_t> slot_index;
    for (DoId d : ids_of(g.dos)) {
        const Do& o = g.dos[d];
        json list = json::array();
        for (PortId p : ports_of[d]) {
            const Port& pt = g.ports[p];
            list.push_back(json::array({g.str(pt.name), word(pt.type), word(pt.dir), true}));
        }
        for (const Comp& cp : g.comps.slice(o.comp_adr, o.comp_num)) {
            for (const Slot& slot : g.slots.slice(cp.slot_adr, cp.slot_num)) {
                list.push_back(json::array({std::string(g.str(cp.name)) + "." + std::string(g.str(slot.name)),
                                            word(slot.type), word(slot.dir), false}));
            }
        }
        const auto [it, fresh] = slot_index.emplace(list.dump(), slot_lists.size());
        if (fresh) slot_lists.push_back(std::move(list));
        dos.push_back({{"id", d},
                       {"path", g.str(o.path)},
                       {"type", o.type.valid() ? g.str(g.do_types[o.type].name) : g.str(g.plant)},
                       {"parent", o.parent},
                       {"pooled", o.pool.valid()},
                       {"slots", it->second}});
    }
    s["slot_lists"] = std::move(slot_lists);
    s["dos"] = std::move(dos);

    // Bodies share their shape lists (every bottle has the same): each distinct list once.
    json bodies = json::array(), shape_lists = json::array();
    std::map<std::string, size_t> shape_index;
    for (BodyId b : ids_of(g.bodies)) {
        const Body& body = g.bodies[b];
        json shapes = json::array();
        for (const Shape& sh : g.shapes.slice(body.shape_adr, body.shape_num)) {
            json j{{"kind", word(sh.kind)}, {"local", pose_json(sh.local)}};
            switch (sh.kind) {
            case ShapeKind::Box: j["size"] = vec_json(sh.size); break;
            case ShapeKind::Sphere: j["size"] = json::array({sh.size[0]}); break;
            case ShapeKind::Cylinder:
            case ShapeKind::Capsule: j["size"] = json::array({sh.size[0], sh.size[1]}); break;
            case ShapeKind::Hull: {
                json pts = json::array();
                for (const Point& pt : g.points.slice(sh.point_adr, sh.point_num)) pts.push_back(vec_json(pt.p));
                j["points"] = std::move(pts);
                break;
            }
            }
            shapes.push_back(std::move(j));
        }
        const auto [it, fresh] = shape_index.emplace(shapes.dump(), shape_lists.size());
        if (fresh) shape_lists.push_back(std::move(shapes));
        const DoId owner = g.comps[body.comp].owner;
        bodies.push_back({{"id", b},
                          {"do", owner},
                          {"path", g.comp_path(body.comp)},
                          {"mode", word(body.mode)},
                          {"collision", body.collision},
                          {"pose", pose_json(body.pose)},
                          {"shapes", it->second}});
    }
    s["shape_lists"] = std::move(shape_lists);
    s["bodies"] = std::move(bodies);

    json fields = json::array();
    for (FieldId f : ids_of(g.fields)) {
        const Field& fd = g.fields[f];
        fields.push_back({{"id", f},
                          {"path", g.comp_path(fd.comp)},
                          {"body", fd.body},
                          {"extent", vec_json(fd.extent)},
                          {"pose", pose_json(fd.pose)},
                          {"dir", vec_json(fd.dir)},
                          {"speed", fd.speed},
                          {"radius", fd.radius},
                          {"pivot", vec_json(fd.pivot)}});
    }
    s["fields"] = std::move(fields);

    json triggers = json::array();
    for (TriggerId t : ids_of(g.triggers)) {
        const Trigger& tr = g.triggers[t];
        triggers.push_back({{"id", t},
                            {"path", g.comp_path(tr.comp)},
                            {"body", tr.body},
                            {"extent", vec_json(tr.extent)},
                            {"pose", pose_json(tr.pose)}});
    }
    s["triggers"] = std::move(triggers);

    json graphics = json::array();
    for (GraphicsId i : ids_of(g.graphics)) {
        const Graphics& gr = g.graphics[i];
        json variants = json::array();
        for (const Variant& var : g.variants.slice(gr.variant_adr, gr.variant_num)) {
            variants.push_back({{"name", g.str(var.name)},
                                {"model", g.str(var.model)},
                                {"model_url", model_url(g.str(var.model))}});
        }
        graphics.push_back({{"id", i},
                            {"path", g.comp_path(gr.comp)},
                            {"parent", gr.parent},
                            {"body", gr.body},
                            {"pose", pose_json(gr.pose)},
                            {"model", g.str(gr.model)},
                            {"model_url", model_url(g.str(gr.model))},
                            {"variant", gr.variant},
                            {"variants", std::move(variants)}});
    }
    s["graphics"] = std::move(graphics);

    json records = json::array();
    for (const Record& r : g.records)
        records.push_back({{"column", g.str(r.column)}, {"type", word(g.slots[r.slot].type)}});
    s["records"] = std::move(records);

    json places = json::array();
    for (PlaceId p : ids_of(g.places))
        places.push_back({{"id", p},
                          {"path", g.comp_path(g.places[p].comp) + "." + std::string(g.str(g.places[p].name))},
                          {"initial", g.places[p].initial}});
    s["places"] = std::move(places);
    s["panels"] = panels_json(g);
    return s.dump(-1, ' ', false, json::error_handler_t::replace);
}

// ---- frames ----

Frame Frame::sized(size_t bodies, size_t graphics) {
    Frame f;
    f.body_pose.assign(7 * bodies, 0.f);
    f.body_state.assign(bodies, 0);
    f.gfx_pose.assign(7 * graphics, 0.f);
    f.gfx_variant.assign(graphics, -1);
    return f;
}

namespace {

void store_pose(float* d, const Pose& p) {
    for (size_t i = 0; i < 3; ++i) d[i] = float(p.p[i]);
    for (size_t i = 0; i < 4; ++i) d[3 + i] = float(p.q[i]);
}

}  // namespace

FrameTracker::FrameTracker(const Graph& g)
    : g_(g), now_(Frame::sized(g.bodies.size(), g.graphics.size())), body_seq_(g.bodies.size(), 1),
      gfx_seq_(g.graphics.size(), 1) {
    for (BodyId b : ids_of(g.bodies))
        if (g.bodies[b].mode != BodyMode::Static) movable_.push_back(b);
    // Static bodies never move: their pose is the graph's.
    for (BodyId b : ids_of(g.bodies)) {
        store_pose(&now_.body_pose[7 * b.v], g.bodies[b].pose);
        now_.body_state[b.v] = uint8_t(1 | (g.bodies[b].collision ? 2 : 0));
    }
    prev_ = now_;
}

uint64_t FrameTracker::take(const engine::Engine& e) {
    std::swap(now_, prev_);
    now_.time = e.time();
    now_.step = e.steps();
    for (BodyId b : movable_) store_pose(&now_.body_pose[7 * b.v], e.body_pose(b));
    for (BodyId b : ids_of(g_.bodies))
        now_.body_state[b.v] = uint8_t((e.body_in_world(b) ? 1 : 0) | (e.body_collision(b) ? 2 : 0));
    for (GraphicsId i : ids_of(g_.graphics)) {
        store_pose(&now_.gfx_pose[7 * i.v], e.graphics_pose(i));
        now_.gfx_variant[i.v] = e.graphics_variant(i);
    }
    return commit();
}

uint64_t FrameTracker::put(const Frame& f) {
    std::swap(now_, prev_);
    now_ = f;
    return commit();
}

uint64_t FrameTracker::commit() {
    ++seq_;
    for (size_t b = 0; b < body_seq_.size(); ++b)
        if (now_.body_state[b] != prev_.body_state[b] ||
            std::memcmp(&now_.body_pose[7 * b], &prev_.body_pose[7 * b], 7 * sizeof(float)) != 0)
            body_seq_[b] = seq_;
    for (size_t i = 0; i < gfx_seq_.size(); ++i)
        if (now_.gfx_variant[i] != prev_.gfx_variant[i] ||
            std::memcmp(&now_.gfx_pose[7 * i], &prev_.gfx_pose[7 * i], 7 * sizeof(float)) != 0)
            gfx_seq_[i] = seq_;
    return seq_;
}

namespace {

template <class T>
void put_raw(std::string& out, const T& v) {
    const size_t at = out.size();
    out.resize(at + sizeof(T));
    std::memcpy(out.data() + at, &v, sizeof(T));
}

template <class T>
bool get_raw(std::string_view& in, T& v) {
    if (in.size() < sizeof(T)) return false;
    std::memcpy(&v, in.data(), sizeof(T));
    in.remove_prefix(sizeof(T));
    return true;
}

}  // namespace

void encode_frame(const Frame& f, const std::vector<uint64_t>& body_seq, const std::vector<uint64_t>& gfx_seq,
                  uint64_t since, bool paused, std::string& out) {
    // Ids on the wire are 4-byte numbers (int32_t), counts and the kind unsigned.
    std::vector<int32_t> bodies, gfx;
    for (int32_t b = 0; b < count_of(body_seq); ++b)
        if (since == 0 || body_seq[b] > since) bodies.push_back(b);
    for (int32_t i = 0; i < count_of(gfx_seq); ++i)
        if (since == 0 || gfx_seq[i] > since) gfx.push_back(i);
    put_raw<uint32_t>(out, 1);
    put_raw<uint32_t>(out, count_of(bodies));
    put_raw(out, f.time);
    put_raw(out, double(f.step));
    put_raw<uint32_t>(out, count_of(gfx));
    put_raw<uint32_t>(out, (since == 0 ? 1u : 0u) | (paused ? 2u : 0u));
    for (int32_t b : bodies) put_raw(out, b);
    for (int32_t b : bodies)
        for (int32_t k = 0; k < 7; ++k) put_raw(out, f.body_pose[7 * b + k]);
    for (int32_t b : bodies) put_raw(out, f.body_state[b]);
    out.append((4 - bodies.size() % 4) % 4, '\0');
    for (int32_t i : gfx) put_raw(out, i);
    for (int32_t i : gfx)
        for (int32_t k = 0; k < 7; ++k) put_raw(out, f.gfx_pose[7 * i + k]);
    for (int32_t i : gfx) put_raw(out, f.gfx_variant[i]);
}

bool decode_frame(std::string_view in, Frame& f, bool& full) {
    uint32_t kind = 0, nb = 0, ng = 0, flags = 0;
    double time = 0, step = 0;
    if (!get_raw(in, kind) || kind != 1 || !get_raw(in, nb) || !get_raw(in, time) || !get_raw(in, step) ||
        !get_raw(in, ng) || !get_raw(in, flags))
        return false;
    // A step count is a whole number a double holds exactly (2^53), the time a finite number:
    // anything else is a damaged recording, not a frame.
    if (!(step >= 0 && step <= 9007199254740992.0 && step == std::floor(step)) || !std::isfinite(time)) return false;
    const size_t nbodies = nb, ngfx = ng;  // sizes below in size_t: no 32-bit overflow
    const size_t need = nbodies * (4 + 28 + 1) + (4 - nb % 4) % 4 + ngfx * (4 + 28 + 4);
    if (nb > f.body_state.size() || ng > f.gfx_variant.size() || in.size() != need) return false;
    const char* ids = in.data();
    const char* poses = ids + 4 * nbodies;
    const char* states = poses + 28 * nbodies;
    for (uint32_t k = 0; k < nb; ++k) {
        int32_t b;
        std::memcpy(&b, ids + 4 * k, 4);
        if (b < 0 || b >= count_of(f.body_state)) return false;
        std::memcpy(&f.body_pose[7 * b], poses + 28 * k, 28);
        f.body_state[b] = uint8_t(states[k]);
    }
    const char* gids = states + nb + (4 - nb % 4) % 4;
    const char* gposes = gids + 4 * ngfx;
    const char* gvars = gposes + 28 * ngfx;
    for (uint32_t k = 0; k < ng; ++k) {
        int32_t i;
        std::memcpy(&i, gids + 4 * k, 4);
        if (i < 0 || i >= count_of(f.gfx_variant)) return false;
        std::memcpy(&f.gfx_pose[7 * i], gposes + 28 * k, 28);
        std::memcpy(&f.gfx_variant[i], gvars + 4 * k, 4);
    }
    f.time = time;
    f.step = int64_t(step);
    full = (flags & 1) != 0;
    return true;
}

// ---- status ----

std::vector<double> history_sample(const engine::Engine& e, const engine::RecordTally& tally) {
    const engine::MaterialCounts m = engine::material_counts(e);
    std::vector<double> v{double(m.issued), double(m.taken), double(m.on_line),
                          double(m.lost),   double(m.stalled), double(m.removed)};
    const std::vector<double> r = tally.values(e);
    v.insert(v.end(), r.begin(), r.end());
    return v;
}

std::string status_json(const engine::Engine& e, const engine::RecordTally& tally, const StatusExtra& x) {
    const Graph& g = e.graph();
    const engine::MaterialCounts m = engine::material_counts(e);
    json s{{"type", "status"},
           {"time", e.time()},
           {"step", e.steps()},
           {"paused", x.paused},
           {"speed", x.speed},
           {"rtf", x.rtf},
           {"counters",
            {{"issued", m.issued},
             {"taken", m.taken},
             {"on_line", m.on_line},
             {"lost", m.lost},
             {"stalled", m.stalled},
             {"removed", m.removed}}},
           {"records", tally.values(e)}};
    if (!x.forced.empty()) s["forced"] = json::parse(x.forced, nullptr, false);
    json occupied = json::array();
    for (TriggerId t : ids_of(g.triggers))
        if (e.trigger_occupied(t)) occupied.push_back(t);
    s["occupied"] = std::move(occupied);
    json fields = json::array();
    for (FieldId f : ids_of(g.fields)) fields.push_back(json::array({e.field_on(f) ? 1 : 0, e.field_speed(f)}));
    s["fields"] = std::move(fields);
    // The lost objects, in the order lost (the first kMaxLost): where each left the line
    // (engine::Loss), for a marker where it fell.
    json lost = json::array();
    const std::span<const DoId> order = e.lost();
    for (size_t i = 0; i < order.size() && i < kMaxLost; ++i) {
        const engine::Loss& l = e.loss(order[i]);
        lost.push_back({{"do", order[i].v},
                        {"path", std::string(g.str(g.dos[order[i]].path))},
                        {"time", double(l.step) * e.dt()},
                        {"left", double(l.field_step) * e.dt()},
                        {"place", l.place},
                        {"field", l.field.valid() ? json(l.field.v) : json(nullptr)},
                        {"out", l.out}});
    }
    s["lost"] = std::move(lost);
    s["panel"] = panel_values(e);
    return s.dump(-1, ' ', false, json::error_handler_t::replace);
}

namespace {

DoId find_do(const Graph& g, std::string_view path) {
    for (DoId d : ids_of(g.dos))
        if (g.str(g.dos[d].path) == path) return d;
    return DoId{};
}

json slot_value(const engine::Engine& e, SlotId sl) {
    const Graph& g = e.graph();
    const SlotType t = g.slots[sl].type;
    const auto v = e.value(sl);
    switch (t) {
    case SlotType::Void: return nullptr;
    case SlotType::Bool: return v[0] != 0;
    case SlotType::String: {
        const double n = v[0];
        return n >= 0 ? json(std::string(e.str(int32_t(n)))) : json("");
    }
    case SlotType::Ref: {
        const double d = v[0];
        return d >= 0 && d < double(g.dos.size()) ? json(std::string(g.str(g.dos[DoId(d)].path))) : json(nullptr);
    }
    case SlotType::Int:
    case SlotType::Real: return v[0];
    default: return json(std::vector<double>(v.begin(), v.end()));
    }
}

}  // namespace

std::vector<SlotId> object_slots(const Graph& g, std::string_view path) {
    std::vector<SlotId> out;
    const DoId d = find_do(g, path);
    if (!d.valid()) return out;
    const Do& o = g.dos[d];
    for (const Comp& cp : g.comps.slice(o.comp_adr, o.comp_num))
        for (SlotId sl : children(cp.slot_adr, cp.slot_num)) out.push_back(sl);
    for (const Port& p : g.ports)
        if (p.owner == d && p.dir == Dir::Out) out.push_back(g.port_targets[p.target_adr.first()].v);
    return out;
}

namespace {

// A slot's force for the inspector: "stuck", "open", "invert", or null.
json force_word(const engine::Engine& e, SlotId slot) {
    switch (e.forced(slot)) {
    case engine::ForceMode::Stuck: return "stuck";
    case engine::ForceMode::Open: return "open";
    case engine::ForceMode::Invert: return "invert";
    case engine::ForceMode::None: break;
    }
    return nullptr;
}

}  // namespace

std::string inspect_json(const engine::Engine& e, std::string_view path, bool forces) {
    const Graph& g = e.graph();
    const DoId d = find_do(g, path);
    if (!d.valid()) return "null";
    const Do& o = g.dos[d];
    json slots = json::array();
    for (PortId p : ids_of(g.ports)) {
        const Port& pt = g.ports[p];
        if (pt.owner != d) continue;
        const SlotId first = g.port_targets[pt.target_adr.first()].v;
        slots.push_back({{"path", g.port_path(p)},
                         {"value", pt.dir == Dir::Out ? slot_value(e, first) : json(nullptr)},
                         {"active", e.active(first)},
                         {"forced", forces ? force_word(e, first) : json(nullptr)}});
    }
    json places = json::array();
    for (const Comp& cp : g.comps.slice(o.comp_adr, o.comp_num)) {
        for (SlotId sl : children(cp.slot_adr, cp.slot_num))
            slots.push_back({{"path", g.slot_path(sl)}, {"value", slot_value(e, sl)}, {"active", e.active(sl)},
                             {"forced", forces ? force_word(e, sl) : json(nullptr)}});
    }
    for (PlaceId p : ids_of(g.places))
        if (g.comps[g.places[p].comp].owner == d) places.push_back({{"id", p}, {"tokens", e.tokens(p)}});
    json j{{"path", path}, {"slots", std::move(slots)}, {"places", std::move(places)}};
    return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

}  // namespace plant::view
