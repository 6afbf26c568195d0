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
    std::vector<std::vector<int32_t>> ports_of(g.dos.size());
    for (size_t p = 0; p < g.ports.size(); ++p) ports_of[size_t(g.ports[p].owner)].push_back(int32_t(p));
    json dos = json::array(), slot_lists = json::array();
    std::map<std::string, size_t> slot_index;
    for (size_t d = 0; d < g.dos.size(); ++d) {
        const Do& o = g.dos[d];
        json list = json::array();
        for (int32_t p : ports_of[d]) {
            const Port& pt = g.ports[size_t(p)];
            list.push_back(json::array({g.str(pt.name), word(pt.type), word(pt.dir), true}));
        }
        for (int32_t c = o.comp_adr; c < o.comp_adr + o.comp_num; ++c) {
            const Comp& cp = g.comps[size_t(c)];
            for (int32_t sl = cp.slot_adr; sl < cp.slot_adr + cp.slot_num; ++sl) {
                const Slot& slot = g.slots[size_t(sl)];
                list.push_back(json::array({std::string(g.str(cp.name)) + "." + std::string(g.str(slot.name)),
                                            word(slot.type), word(slot.dir), false}));
            }
        }
        const auto [it, fresh] = slot_index.emplace(list.dump(), slot_lists.size());
        if (fresh) slot_lists.push_back(std::move(list));
        dos.push_back({{"id", d},
                       {"path", g.str(o.path)},
                       {"type", o.type >= 0 ? g.str(g.do_types[size_t(o.type)].name) : g.str(g.plant)},
                       {"parent", o.parent},
                       {"pooled", o.pool >= 0},
                       {"slots", it->second}});
    }
    s["slot_lists"] = std::move(slot_lists);
    s["dos"] = std::move(dos);

    // Bodies share their shape lists (every bottle has the same): each distinct list once.
    json bodies = json::array(), shape_lists = json::array();
    std::map<std::string, size_t> shape_index;
    for (size_t b = 0; b < g.bodies.size(); ++b) {
        const Body& body = g.bodies[b];
        json shapes = json::array();
        for (int32_t k = 0; k < body.shape_num; ++k) {
            const Shape& sh = g.shapes[size_t(body.shape_adr + k)];
            json j{{"kind", word(sh.kind)}, {"local", pose_json(sh.local)}};
            switch (sh.kind) {
            case ShapeKind::Box: j["size"] = vec_json(sh.size); break;
            case ShapeKind::Sphere: j["size"] = json::array({sh.size[0]}); break;
            case ShapeKind::Cylinder:
            case ShapeKind::Capsule: j["size"] = json::array({sh.size[0], sh.size[1]}); break;
            case ShapeKind::Hull: {
                json pts = json::array();
                for (int32_t i = 0; i < sh.point_num; ++i) pts.push_back(vec_json(g.points[size_t(sh.point_adr + i)].p));
                j["points"] = std::move(pts);
                break;
            }
            }
            shapes.push_back(std::move(j));
        }
        const auto [it, fresh] = shape_index.emplace(shapes.dump(), shape_lists.size());
        if (fresh) shape_lists.push_back(std::move(shapes));
        const int32_t owner = g.comps[size_t(body.comp)].owner;
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
    for (size_t f = 0; f < g.fields.size(); ++f) {
        const Field& fd = g.fields[f];
        fields.push_back({{"id", f},
                          {"path", g.comp_path(fd.comp)},
                          {"body", fd.body},
                          {"extent", vec_json(fd.extent)},
                          {"pose", pose_json(fd.pose)},
                          {"dir", vec_json(fd.dir)},
                          {"speed", fd.speed}});
    }
    s["fields"] = std::move(fields);

    json triggers = json::array();
    for (size_t t = 0; t < g.triggers.size(); ++t) {
        const Trigger& tr = g.triggers[t];
        triggers.push_back({{"id", t},
                            {"path", g.comp_path(tr.comp)},
                            {"body", tr.body},
                            {"extent", vec_json(tr.extent)},
                            {"pose", pose_json(tr.pose)}});
    }
    s["triggers"] = std::move(triggers);

    json graphics = json::array();
    for (size_t i = 0; i < g.graphics.size(); ++i) {
        const Graphics& gr = g.graphics[i];
        json variants = json::array();
        for (int32_t v = 0; v < gr.variant_num; ++v) {
            const Variant& var = g.variants[size_t(gr.variant_adr + v)];
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
        records.push_back({{"column", g.str(r.column)}, {"type", word(g.slots[size_t(r.slot)].type)}});
    s["records"] = std::move(records);

    json places = json::array();
    for (size_t p = 0; p < g.places.size(); ++p)
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
    for (int i = 0; i < 3; ++i) d[i] = float(p.p[size_t(i)]);
    for (int i = 0; i < 4; ++i) d[3 + i] = float(p.q[size_t(i)]);
}

}  // namespace

FrameTracker::FrameTracker(const Graph& g)
    : g_(g), now_(Frame::sized(g.bodies.size(), g.graphics.size())), body_seq_(g.bodies.size(), 1),
      gfx_seq_(g.graphics.size(), 1) {
    for (size_t b = 0; b < g.bodies.size(); ++b)
        if (g.bodies[b].mode != BodyMode::Static) movable_.push_back(int32_t(b));
    // Static bodies never move: their pose is the graph's.
    for (size_t b = 0; b < g.bodies.size(); ++b) {
        store_pose(&now_.body_pose[7 * b], g.bodies[b].pose);
        now_.body_state[b] = uint8_t(1 | (g.bodies[b].collision ? 2 : 0));
    }
    prev_ = now_;
}

uint64_t FrameTracker::take(const engine::Engine& e) {
    std::swap(now_, prev_);
    now_.time = e.time();
    now_.step = e.steps();
    for (int32_t b : movable_) store_pose(&now_.body_pose[7 * size_t(b)], e.body_pose(BodyId(b)));
    for (size_t b = 0; b < g_.bodies.size(); ++b)
        now_.body_state[b] = uint8_t((e.body_in_world(BodyId(int32_t(b))) ? 1 : 0) | (e.body_collision(BodyId(int32_t(b))) ? 2 : 0));
    for (size_t i = 0; i < g_.graphics.size(); ++i) {
        store_pose(&now_.gfx_pose[7 * i], e.graphics_pose(GraphicsId(int32_t(i))));
        now_.gfx_variant[i] = e.graphics_variant(GraphicsId(int32_t(i)));
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
    std::vector<int32_t> bodies, gfx;
    for (size_t b = 0; b < body_seq.size(); ++b)
        if (since == 0 || body_seq[b] > since) bodies.push_back(int32_t(b));
    for (size_t i = 0; i < gfx_seq.size(); ++i)
        if (since == 0 || gfx_seq[i] > since) gfx.push_back(int32_t(i));
    put_raw(out, uint32_t(1));
    put_raw(out, uint32_t(bodies.size()));
    put_raw(out, f.time);
    put_raw(out, double(f.step));
    put_raw(out, uint32_t(gfx.size()));
    put_raw(out, uint32_t((since == 0 ? 1u : 0u) | (paused ? 2u : 0u)));
    for (int32_t b : bodies) put_raw(out, b);
    for (int32_t b : bodies)
        for (int k = 0; k < 7; ++k) put_raw(out, f.body_pose[7 * size_t(b) + size_t(k)]);
    for (int32_t b : bodies) put_raw(out, f.body_state[size_t(b)]);
    out.append((4 - bodies.size() % 4) % 4, '\0');
    for (int32_t i : gfx) put_raw(out, i);
    for (int32_t i : gfx)
        for (int k = 0; k < 7; ++k) put_raw(out, f.gfx_pose[7 * size_t(i) + size_t(k)]);
    for (int32_t i : gfx) put_raw(out, f.gfx_variant[size_t(i)]);
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
    const size_t need = size_t(nb) * (4 + 28 + 1) + (4 - nb % 4) % 4 + size_t(ng) * (4 + 28 + 4);
    if (nb > f.body_state.size() || ng > f.gfx_variant.size() || in.size() != need) return false;
    const char* ids = in.data();
    const char* poses = ids + 4 * size_t(nb);
    const char* states = poses + 28 * size_t(nb);
    for (uint32_t k = 0; k < nb; ++k) {
        int32_t b;
        std::memcpy(&b, ids + 4 * k, 4);
        if (b < 0 || size_t(b) >= f.body_state.size()) return false;
        std::memcpy(&f.body_pose[7 * size_t(b)], poses + 28 * k, 28);
        f.body_state[size_t(b)] = uint8_t(states[k]);
    }
    const char* gids = states + nb + (4 - nb % 4) % 4;
    const char* gposes = gids + 4 * size_t(ng);
    const char* gvars = gposes + 28 * size_t(ng);
    for (uint32_t k = 0; k < ng; ++k) {
        int32_t i;
        std::memcpy(&i, gids + 4 * k, 4);
        if (i < 0 || size_t(i) >= f.gfx_variant.size()) return false;
        std::memcpy(&f.gfx_pose[7 * size_t(i)], gposes + 28 * k, 28);
        std::memcpy(&f.gfx_variant[size_t(i)], gvars + 4 * k, 4);
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
    for (size_t t = 0; t < g.triggers.size(); ++t)
        if (e.trigger_occupied(TriggerId(int32_t(t)))) occupied.push_back(t);
    s["occupied"] = std::move(occupied);
    json fields = json::array();
    for (size_t f = 0; f < g.fields.size(); ++f)
        fields.push_back(json::array({e.field_on(FieldId(int32_t(f))) ? 1 : 0, e.field_speed(FieldId(int32_t(f)))}));
    s["fields"] = std::move(fields);
    // The lost objects, in the order lost (the first kMaxLost): where each left the line
    // (engine::Loss), for a marker where it fell.
    json lost = json::array();
    const std::span<const DoId> order = e.lost();
    for (size_t i = 0; i < order.size() && i < kMaxLost; ++i) {
        const engine::Loss& l = e.loss(order[i]);
        lost.push_back({{"do", order[i].v},
                        {"path", std::string(g.str(g.dos[size_t(order[i])].path))},
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

int32_t find_do(const Graph& g, std::string_view path) {
    for (size_t d = 0; d < g.dos.size(); ++d)
        if (g.str(g.dos[d].path) == path) return int32_t(d);
    return -1;
}

json slot_value(const engine::Engine& e, SlotId sl) {
    const Graph& g = e.graph();
    const SlotType t = g.slots[size_t(sl)].type;
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
        return d >= 0 && d < double(g.dos.size()) ? json(std::string(g.str(g.dos[size_t(d)].path))) : json(nullptr);
    }
    case SlotType::Int:
    case SlotType::Real: return v[0];
    default: return json(std::vector<double>(v.begin(), v.end()));
    }
}

}  // namespace

std::vector<int32_t> object_slots(const Graph& g, std::string_view path) {
    std::vector<int32_t> out;
    const int32_t d = find_do(g, path);
    if (d < 0) return out;
    const Do& o = g.dos[size_t(d)];
    for (int32_t c = o.comp_adr; c < o.comp_adr + o.comp_num; ++c) {
        const Comp& cp = g.comps[size_t(c)];
        for (int32_t sl = cp.slot_adr; sl < cp.slot_adr + cp.slot_num; ++sl) out.push_back(sl);
    }
    for (const Port& p : g.ports)
        if (p.owner == d && p.dir == Dir::Out) out.push_back(g.port_targets[size_t(p.target_adr)].v);
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
    const int32_t d = find_do(g, path);
    if (d < 0) return "null";
    const Do& o = g.dos[size_t(d)];
    json slots = json::array();
    for (size_t p = 0; p < g.ports.size(); ++p) {
        const Port& pt = g.ports[p];
        if (pt.owner != d) continue;
        const SlotId first = g.port_targets[size_t(pt.target_adr)].v;
        slots.push_back({{"path", g.port_path(int32_t(p))},
                         {"value", pt.dir == Dir::Out ? slot_value(e, first) : json(nullptr)},
                         {"active", e.active(first)},
                         {"forced", forces ? force_word(e, first) : json(nullptr)}});
    }
    json places = json::array();
    for (int32_t c = o.comp_adr; c < o.comp_adr + o.comp_num; ++c) {
        const Comp& cp = g.comps[size_t(c)];
        for (SlotId sl(cp.slot_adr); sl < cp.slot_adr + cp.slot_num; ++sl)
            slots.push_back({{"path", g.slot_path(sl)}, {"value", slot_value(e, sl)}, {"active", e.active(sl)},
                             {"forced", forces ? force_word(e, sl) : json(nullptr)}});
    }
    for (size_t p = 0; p < g.places.size(); ++p)
        if (g.comps[size_t(g.places[p].comp)].owner == d)
            places.push_back({{"id", p}, {"tokens", e.tokens(PlaceId(int32_t(p)))}});
    json j{{"path", path}, {"slots", std::move(slots)}, {"places", std::move(places)}};
    return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

}  // namespace plant::view
