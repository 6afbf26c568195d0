#include "engine/events.h"

#include "engine/plugin.h"
#include "graph/range.h"
#include "graph/utf8.h"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace plant::engine {

using namespace plant::graph;

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

namespace {

// A number followed by an optional unit (spaces allowed between them).
bool number_unit(std::string_view text, double& v, std::string_view& unit) {
    text = trim(text);
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || !std::isfinite(v)) return false;
    unit = trim(text.substr(end - text.data()));
    return true;
}

bool numbers(std::string_view text, std::vector<double>& out, size_t n) {
    std::string s(trim(text));
    for (char& c : s)
        if (c == ',' || c == '(' || c == ')' || c == '|') c = ' ';
    std::string_view rest = s;
    out.clear();
    while (!(rest = trim(rest)).empty()) {
        double v;
        auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), v);
        if (ec != std::errc() || !std::isfinite(v)) return false;
        out.push_back(v);
        rest.remove_prefix(end - rest.data());
    }
    return out.size() == n;
}

// The rotation at `q` (x y z w): a unit quaternion, as typed to a few digits; made exact.
bool unit_rotation(double* q) {
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (std::abs(n - 1) > 1e-3) return false;
    for (int i = 0; i < 4; ++i) q[i] /= n;
    return true;
}

bool whole(double v) { return std::floor(v) == v && std::abs(v) < 9e15; }

}  // namespace

bool parse_duration(std::string_view text, double& seconds, std::string& error) {
    double v;
    std::string_view unit;
    if (!number_unit(text, v, unit)) {
        error = fmt::format("'{}' is not a duration (e.g. 10s, 500ms, 2min, 1h)", text);
        return false;
    }
    if (unit.empty()) {
        error = fmt::format("'{}': a duration needs a unit: s, ms, min or h", text);
        return false;
    }
    if (unit == "s") seconds = v;
    else if (unit == "ms") seconds = v / 1000;
    else if (unit == "min") seconds = v * 60;
    else if (unit == "h") seconds = v * 3600;
    else {
        error = fmt::format("'{}': unknown unit '{}'; a duration takes s, ms, min or h", text, unit);
        return false;
    }
    if (v < 0) {
        error = fmt::format("'{}': a duration must not be negative", text);
        return false;
    }
    return true;
}

bool parse_frequency(std::string_view text, double& hz, std::string& error) {
    double v;
    std::string_view unit;
    if (!number_unit(text, v, unit)) {
        error = fmt::format("'{}' is not a frequency (e.g. 150Hz)", text);
        return false;
    }
    if (unit != "Hz" && unit != "kHz") {
        error = unit.empty() ? fmt::format("'{}': a frequency needs a unit: Hz or kHz", text)
                             : fmt::format("'{}': unknown unit '{}'; a frequency takes Hz or kHz", text, unit);
        return false;
    }
    if (!(v > 0)) {
        error = fmt::format("'{}': a frequency must be above 0", text);
        return false;
    }
    hz = unit == "kHz" ? v * 1000 : v;
    return true;
}

SlotIndex slot_index(const Graph& g) {
    SlotIndex idx;
    for (SlotId s : ids_of(g.slots))
        idx.emplace(g.slot_path(s), SlotTarget{{s}, g.slots[s].type, g.slots[s].dir, false});
    for (PortId p : ids_of(g.ports)) {
        const Port& pt = g.ports[p];
        SlotTarget t{{}, pt.type, pt.dir, true};
        for (const PortTarget& target : g.port_targets.slice(pt.target_adr, pt.target_num)) t.slots.push_back(target.v);
        idx.emplace(g.port_path(p), std::move(t));  // a slot of the same path wins
    }
    return idx;
}

namespace {

// Edits (insert, delete, replace) between two strings, stopping early past `limit`.
size_t edits(std::string_view a, std::string_view b, size_t limit) {
    if ((a.size() > b.size() ? a.size() - b.size() : b.size() - a.size()) > limit) return limit + 1;
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diag = row[0], best = row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diag = up;
            best = std::min(best, row[j]);
        }
        if (best > limit) return limit + 1;
    }
    return row[b.size()];
}

std::string number_text(const std::vector<double>& v) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += fmt::format("{}{}", i ? "," : "", v[i]);
    return s;
}

}  // namespace

std::string closest_path(const SlotIndex& slots, std::string_view path) {
    // A third of the path's length, at most 4 edits; ties go to the smaller path.
    const size_t limit = std::min<size_t>(4, std::max<size_t>(1, path.size() / 3));
    std::string best;
    size_t best_d = limit + 1;
    for (const auto& [p, t] : slots) {
        const size_t d = edits(path, p, std::min(limit, best_d));
        if (d < best_d || (d == best_d && d <= limit && p < best)) best = p, best_d = d;
    }
    return best_d <= limit ? best : std::string{};
}

std::string format_event(const Graph& g, const Event& ev, double dt) {
    const std::string t = time_text(ev.time, dt > 0 ? dt : 1 / g.settings.rate);
    switch (ev.hand) {
    case HandAct::None: break;
    case HandAct::Grab: return fmt::format("{}s grab {} at {}", t, ev.path, number_text(ev.value));
    case HandAct::Move: return fmt::format("{}s move {} to {}", t, ev.path, number_text(ev.value));
    case HandAct::Drop: return fmt::format("{}s drop {}", t, ev.path);
    case HandAct::Remove: return fmt::format("{}s remove {}", t, ev.path);
    }
    if (ev.force && ev.mode != ForceMode::Stuck)
        return fmt::format("{}s {} {}{}", t, ev.mode == ForceMode::None ? "release" : "force", ev.path,
                           ev.mode == ForceMode::Open ? " open" : ev.mode == ForceMode::Invert ? " invert" : "");
    std::string line = ev.force ? fmt::format("{}s force {} stuck", t, ev.path) : fmt::format("{}s {}", t, ev.path);
    if (ev.slots.empty()) return line;
    const SlotType type = g.slots[ev.slots[0]].type;
    if (ev.force && type == SlotType::Void) return line + (ev.value[0] != 0 ? " on" : " off");
    switch (type) {
    case SlotType::Void: break;
    case SlotType::Bool: line += ev.value[0] != 0 ? " true" : " false"; break;
    case SlotType::String: line += fmt::format(" \"{}\"", ev.text); break;
    case SlotType::Ref: {
        const double d = ev.value[0];
        line += d >= 0 && d < double(g.dos.size()) && !g.str(g.dos[DoId(d)].path).empty()
                    ? fmt::format(" {}", g.str(g.dos[DoId(d)].path))
                    : fmt::format(" {}", d);
        break;
    }
    default: line += fmt::format(" {}", number_text(ev.value)); break;
    }
    return line;
}

void apply_event(Engine& e, const Event& ev) {
    if (ev.hand != HandAct::None) {
        const Vec3 p = ev.value.size() == 3 ? Vec3{ev.value[0], ev.value[1], ev.value[2]} : Vec3{0, 0, 0};
        switch (ev.hand) {
        case HandAct::Grab: e.hand_grab(ev.body, p); break;
        case HandAct::Move: e.hand_move(ev.body, p); break;
        case HandAct::Drop: e.hand_drop(ev.body); break;
        case HandAct::Remove: e.remove_object(ev.object); break;
        case HandAct::None: break;
        }
        return;
    }
    if (ev.slots.empty()) return;
    const Graph& g = e.graph();
    double name[1];
    std::span<const double> value = ev.value;
    if (g.slots[ev.slots[0]].type == SlotType::String && (!ev.force || ev.mode == ForceMode::Stuck)) {
        name[0] = double(e.intern(ev.text));
        value = name;
    }
    for (SlotId s : ev.slots) {
        if (ev.force) e.force(s, ev.mode, value);
        else e.input(s, value);
    }
}

bool parse_event(const Graph& g, const SlotIndex& slots, std::string_view line, Event& ev,
                 std::string& error) {
    if (const size_t bad = graph::invalid_utf8(line); bad != std::string_view::npos) {
        error = graph::utf8_error(line, bad);
        return false;
    }
    line = trim(line);
    size_t sp = line.find_first_of(" \t");
    if (sp == std::string_view::npos) {
        error = fmt::format("'{}': expected '<time> <path> [value]'", line);
        return false;
    }
    if (!parse_duration(line.substr(0, sp), ev.time, error)) return false;
    return parse_input(g, slots, trim(line.substr(sp)), ev, error);
}

namespace {

// A value for a slot of `type` into ev.value (ev.text for strings); false with `error`.
bool parse_value(const Graph& g, SlotType type, const std::string& path, std::string_view value, Event& ev,
                 std::string& error) {
    ev.value.clear();
    ev.text.clear();
    bool ok = true;
    switch (type) {
    case SlotType::Void: ok = value.empty(); break;
    case SlotType::Bool:
        ok = value == "true" || value == "false" || value == "1" || value == "0";
        ev.value = {value == "true" || value == "1" ? 1.0 : 0.0};
        break;
    case SlotType::Int: ok = numbers(value, ev.value, 1) && whole(ev.value[0]); break;
    case SlotType::Real: ok = numbers(value, ev.value, 1); break;
    case SlotType::Vec3: ok = numbers(value, ev.value, 3); break;
    case SlotType::Quat: ok = numbers(value, ev.value, 4) && unit_rotation(&ev.value[0]); break;
    case SlotType::Pose:  // a place, within the range a plant lies in (graph/range.h)
        ok = numbers(value, ev.value, 7) && unit_rotation(&ev.value[3]) && place_in_range(ev.value.data());
        break;
    case SlotType::String:
        ev.text = std::string(value.size() >= 2 && value.front() == '"' && value.back() == '"'
                                  ? value.substr(1, value.size() - 2) : value);
        break;
    case SlotType::Ref: {
        ok = false;
        for (DoId d : ids_of(g.dos))
            if (!ok && g.str(g.dos[d].path) == value) {
                ev.value = {double(d.v)};
                ok = true;
            }
        if (!ok)  // a DO id, or -1 for none
            ok = numbers(value, ev.value, 1) && whole(ev.value[0]) && ev.value[0] >= -1 &&
                 ev.value[0] < double(g.dos.size());
        break;
    }
    }
    if (!ok) {
        error = value.empty() && type != SlotType::Void
                    ? fmt::format("'{}' ({}) needs a value", path, word(type))
                    : fmt::format("'{}' is not a {} value for '{}'{}", value, word(type), path,
                                  type == SlotType::Quat ? " (finite numbers, a unit quaternion x y z w)"
                                  : type == SlotType::Pose ? " (a place within 100 km, a unit quaternion x y z w)"
                                  : type == SlotType::Ref ? " (a DO path, or its id)" : "");
    }
    return ok;
}

// A well-formed value that would put the physics out of its range (graph/range.h: a place
// beyond 100 km, a speed beyond 100 km/s, ...) is refused like a malformed one, whichever way
// in it takes (--event, an events file, a forced value, the viewer).
bool in_range(const Graph& g, const Event& ev, std::string_view value, std::string& error) {
    for (SlotId s : ev.slots)
        if (const std::string_view r = input_range(g, s, ev.value.data()); !r.empty()) {
            error = fmt::format("'{}' is out of range for '{}': it takes {}", value, ev.path, r);
            return false;
        }
    return true;
}

// The slot (or port) at `path`; false with a "did you mean" error.
const SlotTarget* find_target(const SlotIndex& slots, const std::string& path, std::string& error) {
    auto it = slots.find(path);
    if (it != slots.end()) return &it->second;
    const std::string hint = closest_path(slots, path);
    error = hint.empty() ? fmt::format("no slot '{}' (`plant info --slots FILE` lists them)", path)
                         : fmt::format("no slot '{}'; did you mean '{}'?", path, hint);
    return nullptr;
}

std::pair<std::string_view, std::string_view> first_word(std::string_view text) {
    text = trim(text);
    const size_t sp = text.find_first_of(" \t");
    if (sp == std::string_view::npos) return {text, {}};
    return {text.substr(0, sp), trim(text.substr(sp))};
}

// "force PATH stuck VALUE | open | invert" and "release PATH" (after the first word).
bool parse_force(const Graph& g, const SlotIndex& slots, bool release, std::string_view rest, Event& ev,
                 std::string& error) {
    const auto [path_text, tail] = first_word(rest);
    const std::string path(path_text);
    const SlotTarget* t = find_target(slots, path, error);
    if (!t) return false;
    ev.path = path;
    ev.slots = t->slots;
    ev.force = true;
    ev.value.clear();
    ev.text.clear();
    if (release) {
        ev.mode = ForceMode::None;
        if (!tail.empty()) error = fmt::format("release '{}': unexpected '{}'", path, tail);
        return tail.empty();
    }
    const auto [mode, value] = first_word(tail);
    const SlotType type = t->type;
    if (mode == "open" || mode == "invert") {
        ev.mode = mode == "open" ? ForceMode::Open : ForceMode::Invert;
        if (!value.empty()) {
            error = fmt::format("force '{}' {}: unexpected '{}'", path, mode, value);
            return false;
        }
        if (mode == "invert" && type != SlotType::Bool) {
            error = fmt::format("force '{}' invert: only a bool slot can be inverted ('{}' is {})", path, path, word(type));
            return false;
        }
        if (mode == "open" && (type == SlotType::Vec3 || type == SlotType::Quat || type == SlotType::Pose)) {
            error = fmt::format("force '{}' open: a {} slot has no 'off' (force it stuck at a value)", path, word(type));
            return false;
        }
        return true;
    }
    if (mode != "stuck") {
        error = mode.empty() ? fmt::format("force '{}': which way? stuck VALUE, open or invert", path)
                             : fmt::format("force '{}': '{}' is not a way to force (stuck VALUE, open or invert)", path, mode);
        return false;
    }
    ev.mode = ForceMode::Stuck;
    if (type == SlotType::Void) {  // a void slot is stuck on (active every step) or off
        if (value == "on" || value == "true" || value == "1") ev.value = {1.0};
        else if (value == "off" || value == "false" || value == "0") ev.value = {0.0};
        else {
            error = fmt::format("force '{}' stuck: a void slot is stuck on or off, not '{}'", path, value);
            return false;
        }
        return true;
    }
    return parse_value(g, type, path, value, ev, error) && in_range(g, ev, value, error);
}

// The body whose physics component has the dotted path `path`, or none.
BodyId find_body(const Graph& g, std::string_view path) {
    for (BodyId b : ids_of(g.bodies)) {
        const Comp& c = g.comps[g.bodies[b].comp];
        const std::string_view owner = g.str(g.dos[c.owner].path), name = g.str(c.name);
        if (path.size() == (owner.empty() ? 0 : owner.size() + 1) + name.size() && path.ends_with(name) &&
            (owner.empty() || (path.starts_with(owner) && path[owner.size()] == '.')))
            return b;
    }
    return {};
}

DoId find_object(const Graph& g, std::string_view path) {
    for (DoId d : ids_of(g.dos))
        if (g.str(g.dos[d].path) == path && !path.empty()) return d;
    return {};
}

// The dynamic bodies' paths closest to a misspelt one, for "did you mean".
std::string closest_body(const Graph& g, std::string_view path) {
    const size_t limit = std::min<size_t>(4, std::max<size_t>(1, path.size() / 3));
    std::string best;
    size_t best_d = limit + 1;
    for (BodyId b : ids_of(g.bodies)) {
        if (g.bodies[b].mode != BodyMode::Dynamic) continue;
        const std::string p = g.comp_path(g.bodies[b].comp);
        const size_t d = edits(path, p, std::min(limit, best_d));
        if (d < best_d || (d == best_d && d <= limit && p < best)) best = p, best_d = d;
    }
    return best_d <= limit ? best : std::string{};
}

// "grab BODY at X,Y,Z", "move BODY to X,Y,Z", "drop BODY", "remove OBJECT" (after the verb).
bool parse_hand(const Graph& g, std::string_view verb, std::string_view rest, Event& ev, std::string& error) {
    const auto [path_text, tail] = first_word(rest);
    const std::string path(path_text);
    ev.slots.clear();
    ev.value.clear();
    ev.text.clear();
    ev.force = false;
    ev.mode = ForceMode::None;
    if (verb == "remove") {
        DoId d = find_object(g, path);
        if (const BodyId b = d.valid() ? BodyId{} : find_body(g, path); b.valid()) d = g.comps[g.bodies[b].comp].owner;
        if (!d.valid()) {
            error = fmt::format("remove '{}': no object of that path (an object's path, e.g. a bottle's)", path);
            return false;
        }
        if (!tail.empty()) {
            error = fmt::format("remove '{}': unexpected '{}'", path, tail);
            return false;
        }
        ev.hand = HandAct::Remove;
        ev.object = d;
        ev.path = std::string(g.str(g.dos[d].path));
        return true;
    }
    const BodyId b = find_body(g, path);
    if (!b.valid()) {
        const std::string hint = closest_body(g, path);
        error = hint.empty() ? fmt::format("{} '{}': no body of that path (a physics component's path)", verb, path)
                             : fmt::format("{} '{}': no body of that path; did you mean '{}'?", verb, path, hint);
        return false;
    }
    if (g.bodies[b].mode != BodyMode::Dynamic) {
        error = fmt::format("{} '{}': only a dynamic body can be taken by hand (this one is {})", verb, path,
                            word(g.bodies[b].mode));
        return false;
    }
    ev.path = path;
    ev.body = b;
    if (verb == "drop") {
        ev.hand = HandAct::Drop;
        if (!tail.empty()) error = fmt::format("drop '{}': unexpected '{}'", path, tail);
        return tail.empty();
    }
    const bool grab = verb == "grab";
    ev.hand = grab ? HandAct::Grab : HandAct::Move;
    const auto [word_at, point] = first_word(tail);
    if (word_at != (grab ? "at" : "to") || !numbers(point, ev.value, 3) || !place_in_range(ev.value.data())) {
        error = fmt::format("{} '{}': expected '{} X,Y,Z' (a point in metres, within 100 km), not '{}'", verb, path,
                            grab ? "at" : "to", tail);
        return false;
    }
    return true;
}

}  // namespace

bool parse_input(const Graph& g, const SlotIndex& slots, std::string_view rest, Event& ev, std::string& error) {
    if (const size_t bad = graph::invalid_utf8(rest); bad != std::string_view::npos) {
        error = graph::utf8_error(rest, bad);  // a string value would reach traces and pages as is
        return false;
    }
    const auto [head, tail] = first_word(rest);
    ev.hand = HandAct::None;
    ev.body = {};
    ev.object = {};
    if ((head == "force" || head == "release") && !tail.empty() && !slots.count(std::string(head)))
        return parse_force(g, slots, head == "release", tail, ev, error);
    if ((head == "grab" || head == "move" || head == "drop" || head == "remove") && !tail.empty() &&
        !slots.count(std::string(head)))
        return parse_hand(g, head, tail, ev, error);
    std::string path(head);
    std::string_view value = tail;
    const SlotTarget* t = find_target(slots, path, error);
    if (!t) return false;
    if (t->dir != Dir::In) {
        error = fmt::format("'{}' is an output: events drive inputs (`plant info --slots FILE` lists them)", path);
        return false;
    }
    ev.path = path;
    ev.slots = t->slots;
    ev.force = false;
    return parse_value(g, t->type, path, value, ev, error) && in_range(g, ev, value, error);
}

bool read_lines(const std::string& path, std::string_view what,
                const std::function<bool(std::string_view line, int n, size_t col)>& f, std::string& error) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        error = fmt::format("{}: is a folder, not {}", path, what);
        return false;
    }
    std::ifstream in(path);
    if (!in) {
        error = fmt::format("{}: cannot open", path);
        return false;
    }
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        const std::string_view l = trim(line);
        if (l.empty() || l.front() == '#') continue;
        if (!f(l, n, l.data() - line.data() + 1)) return false;
    }
    if (in.bad()) {
        error = fmt::format("{}: cannot read", path);
        return false;
    }
    return true;
}

bool load_events(const Graph& g, const SlotIndex& slots, const std::string& path,
                 std::vector<Event>& out, std::string& error) {
    return read_lines(path, "an events file", [&](std::string_view l, int n, size_t) {
        Event ev;
        if (!parse_event(g, slots, l, ev, error)) {
            error = fmt::format("{}:{}: {}", path, n, error);
            return false;
        }
        out.push_back(std::move(ev));
        return true;
    }, error);
}

std::string path_of(const SlotIndex& slots, const std::vector<SlotId>& which) {
    std::string best;
    for (const auto& [path, target] : slots)
        if (target.slots == which && (best.empty() || path.size() < best.size() || (path.size() == best.size() && path < best)))
            best = path;
    return best;
}

std::vector<Event> plant_events(const Graph& g) {
    std::vector<Event> out;
    for (PluginId p : ids_of(g.plugins))
        if (const KindBehaviour* b = find_behaviour(g.str(g.plugins[p].kind)); b && b->schedule)
            b->schedule(g, p, out);
    std::stable_sort(out.begin(), out.end(), [](const Event& x, const Event& y) { return x.time < y.time; });
    return out;
}

std::vector<Event> run_events(const Graph& g, std::vector<Event> given) {
    std::vector<Event> all = plant_events(g);
    all.insert(all.end(), std::make_move_iterator(given.begin()), std::make_move_iterator(given.end()));
    std::stable_sort(all.begin(), all.end(), [](const Event& x, const Event& y) { return x.time < y.time; });
    return all;
}

}  // namespace plant::engine
