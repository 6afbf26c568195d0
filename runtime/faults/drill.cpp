#include "faults/drill.h"

#include "graph/utf8.h"

#include <fmt/format.h>

#include <cmath>
#include <charconv>

namespace plant::faults {

namespace {

using engine::trim;

// The first word of `s` (up to a blank), and `s` after it, trimmed.
std::string_view first_word(std::string_view& s) {
    s = trim(s);
    const size_t sp = s.find_first_of(" \t");
    const std::string_view w = s.substr(0, sp);
    s = sp == std::string_view::npos ? std::string_view() : trim(s.substr(sp));
    return w;
}

// A slot (or port) by its path, with a suggestion when it is misspelt.
const engine::SlotTarget* find_slot(const engine::SlotIndex& slots, std::string_view path, std::string& error) {
    if (auto it = slots.find(std::string(path)); it != slots.end()) return &it->second;
    const std::string near = engine::closest_path(slots, path);
    error = near.empty() ? fmt::format("no slot '{}' in the plant", path)
                         : fmt::format("no slot '{}' in the plant (did you mean '{}'?)", path, near);
    return nullptr;
}

// The dynamic bodies a hand can take that `path` names: a body's component path, or an
// object's path (and every object inside it: `line[0]` names every bottle of the line).
std::vector<graph::BodyId> hand_bodies(const graph::Graph& g, std::string_view path) {
    std::vector<graph::BodyId> out;
    for (graph::BodyId b : graph::ids_of(g.bodies)) {
        const graph::Body& body = g.bodies[b];
        if (body.mode != graph::BodyMode::Dynamic) continue;
        const graph::CompId comp = body.comp;
        const std::string_view owner = g.str(g.dos[g.comps[comp].owner].path);
        const bool inside = owner == path || (owner.size() > path.size() && owner.starts_with(path) &&
                                              (owner[path.size()] == '.' || owner[path.size()] == '['));
        if (inside || g.comp_path(comp) == path) out.push_back(b);
    }
    return out;
}

}  // namespace

std::string_view word(Drill::State s) {
    switch (s) {
    case Drill::State::Waiting: return "waiting";
    case Drill::State::Holding: return "holding";
    case Drill::State::Released: return "released";
    case Drill::State::Repaired: return "repaired";
    case Drill::State::Done: return "done";
    case Drill::State::Cancelled: return "cancelled";
    }
    return "?";
}

bool parse_drill(const graph::Graph& g, const engine::SlotIndex& slots, std::string_view line, Drill& out,
                 std::string& error) {
    if (const size_t bad = graph::invalid_utf8(line); bad != std::string_view::npos) {
        error = graph::utf8_error(line, bad);
        return false;
    }
    Drill d;
    std::string_view rest = trim(line);
    d.text = std::string(rest);
    // [hidden|shown]
    {
        std::string_view peek = rest;
        const std::string_view w = first_word(peek);
        if (w == "hidden" || w == "shown") {
            d.shown = w == "shown";
            rest = peek;
        }
    }
    // ... repaired by PATH (the last such clause: an event's text may hold the words).
    if (const size_t r = rest.rfind(" repaired by "); r != std::string_view::npos) {
        std::string_view path = trim(rest.substr(r + 13));
        std::string_view after = path;
        if (first_word(after) == "hand" && !after.empty()) {  // repaired by hand PATH
            d.repair_hand = true;
            path = after;
        }
        if (path.empty() || path.find_first_of(" \t") != std::string_view::npos) {
            error = fmt::format("'repaired by' takes one input's path, or 'hand' and a part's path, not '{}'", path);
            return false;
        }
        if (d.repair_hand) {
            d.repair_bodies = hand_bodies(g, path);
            if (d.repair_bodies.empty()) {
                error = fmt::format("'repaired by hand {}': no object or body of that path has a dynamic body a hand "
                                    "can take",
                                    path);
                return false;
            }
        } else {
            const engine::SlotTarget* t = find_slot(slots, path, error);
            if (!t) return false;
            d.repair_slots = t->slots;
        }
        d.repair_path = std::string(path);
        rest = trim(rest.substr(0, r));
    }
    std::string_view peek = rest;
    const std::string_view trig = first_word(peek);
    if (trig == "now") {
        d.trigger = Drill::Trigger::Now;
        if (!engine::parse_input(g, slots, peek, d.event, error)) return false;
    } else if (trig == "when") {
        d.trigger = Drill::Trigger::When;
        const std::string_view path = first_word(peek);
        const std::string_view op = first_word(peek);
        const std::string_view n = first_word(peek);
        if (path.empty() || op != ">=" || n.empty()) {
            error = fmt::format("'{}': a condition is 'when PATH >= NUMBER' followed by the event", trim(rest));
            return false;
        }
        const engine::SlotTarget* t = find_slot(slots, path, error);
        if (!t) return false;
        if (t->type != graph::SlotType::Void && t->type != graph::SlotType::Bool && t->type != graph::SlotType::Int &&
            t->type != graph::SlotType::Real) {
            error = fmt::format("'when {}': a condition counts a void slot's events or compares a bool, int or real "
                                "slot's value; this one is {}",
                                path, graph::word(t->type));
            return false;
        }
        double v = 0;
        auto [end, ec] = std::from_chars(n.data(), n.data() + n.size(), v);
        if (ec != std::errc() || end != n.data() + n.size() || !std::isfinite(v)) {
            error = fmt::format("'when {} >= {}': '{}' is not a number", path, n, n);
            return false;
        }
        d.when_path = std::string(path);
        d.when_slots = t->slots;
        d.when_void = t->type == graph::SlotType::Void;
        d.threshold = v;
        if (peek.empty()) {
            error = fmt::format("'when {} >= {}': the event that fires is missing", path, n);
            return false;
        }
        if (!engine::parse_input(g, slots, peek, d.event, error)) return false;
    } else {
        d.trigger = Drill::Trigger::At;
        if (!engine::parse_event(g, slots, rest, d.event, error)) return false;
        d.at = d.event.time;
    }
    if (!d.repair_path.empty() && (!d.event.force || d.event.mode == engine::ForceMode::None)) {
        error = fmt::format("'repaired by {}{}': a repair rule ends a fault, and this drill forces nothing",
                            d.repair_hand ? "hand " : "", d.repair_path);
        return false;
    }
    out = std::move(d);
    return true;
}

bool load_drills(const graph::Graph& g, const engine::SlotIndex& slots, const std::string& path, std::vector<Drill>& out,
                 std::string& error) {
    return engine::read_lines(path, "a drill file", [&](std::string_view l, int n, size_t col) {
        Drill d;
        if (!parse_drill(g, slots, l, d, error)) {
            error = fmt::format("{}:{}:{}: {}", path, n, col, error);
            return false;
        }
        d.by = "drill file";
        out.push_back(std::move(d));
        return true;
    }, error);
}

void Drills::add(Drill d) {
    d.state = Drill::State::Waiting;
    drills_.push_back(std::move(d));
}

void Drills::reset() {
    for (Drill& d : drills_) {
        if (d.state == Drill::State::Cancelled) {
            d.ended = 0;
            d.watched = false;
            continue;
        }
        d.state = Drill::State::Waiting;
        d.count = 0;
        d.counted_to = -1;
        d.hand_held = false;
        d.fired = d.ended = -1;
        d.watched = false;
    }
}

bool Drills::cancel(int number, double t, const std::string& by, std::string& error) {
    if (number < 1 || size_t(number) > drills_.size()) {
        error = drills_.empty() ? fmt::format("no drill {}: none is scheduled", number)
                                : fmt::format("no drill {} (they are 1 to {})", number, drills_.size());
        return false;
    }
    Drill& d = drills_[size_t(number - 1)];
    if (d.state != Drill::State::Waiting) {
        error = d.state == Drill::State::Holding
                    ? fmt::format("drill {} has fired (its fault holds): release its slot to end it", number)
                    : fmt::format("drill {} is {}: only a waiting drill can be cancelled", number, word(d.state));
        return false;
    }
    d.state = Drill::State::Cancelled;
    d.ended = t;
    d.cancelled_by = by;
    return true;
}

void Drills::due(engine::Engine& e, std::vector<Fired>& out) {
    const double t = double(e.steps() + 1) * e.dt();  // the end of the coming step: when its events apply
    for (size_t i = 0; i < drills_.size(); ++i) {
        Drill& d = drills_[i];
        if (!d.watched) {  // read every step from now on (watching changes no result)
            for (graph::SlotId s : d.when_slots) e.watch(s);
            for (graph::SlotId s : d.repair_slots) e.watch(s);
            d.watched = true;
        }
        if (d.state == Drill::State::Waiting) {
            bool fire = false;
            if (d.trigger == Drill::Trigger::Now) {
                fire = true;
            } else if (d.trigger == Drill::Trigger::At) {
                fire = engine::due(e, d.event);
            } else if (d.when_void) {
                // The times the slot was active, one look per step (the last step's).
                if (e.steps() > d.counted_to && e.steps() > 0) {
                    for (graph::SlotId s : d.when_slots)
                        if (e.active(s)) {
                            ++d.count;
                            break;
                        }
                    d.counted_to = e.steps();
                }
                fire = double(d.count) >= d.threshold;
            } else {
                for (graph::SlotId s : d.when_slots) fire = fire || e.value(s)[0] >= d.threshold;
            }
            if (!fire) continue;
            Fired f{d.event, i, false};
            f.event.time = t;
            d.fired = t;
            d.state = d.event.force && d.event.mode != engine::ForceMode::None ? Drill::State::Holding : Drill::State::Done;
            if (d.state == Drill::State::Done) d.ended = t;
            out.push_back(std::move(f));
            continue;
        }
        if (d.state != Drill::State::Holding || d.event.slots.empty()) continue;
        // Released by someone (the instructor, a drill, a link): the drill ends.
        if (e.forced(d.event.slots[0]) == engine::ForceMode::None) {
            d.state = Drill::State::Released;
            d.ended = double(e.steps()) * e.dt();
            continue;
        }
        bool repaired = false;
        for (graph::SlotId s : d.repair_slots) repaired = repaired || e.active(s);
        if (d.repair_hand) {  // held by a hand at an earlier boundary, let go of by this one
            bool held = false;
            for (graph::BodyId b : d.repair_bodies) held = held || e.held(b);
            repaired = d.hand_held && !held;
            d.hand_held = d.hand_held || held;
        }
        if (!repaired) continue;
        Fired f;
        f.drill = i;
        f.repair = true;
        f.event.time = t;
        f.event.path = d.event.path;
        f.event.slots = d.event.slots;
        f.event.force = true;
        f.event.mode = engine::ForceMode::None;
        d.state = Drill::State::Repaired;
        d.ended = t;
        out.push_back(std::move(f));
    }
}

}  // namespace plant::faults
