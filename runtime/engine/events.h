// Events: the one way in. Every external input to a running plant (`--event`, an events
// file, the viewer's clicks, a PLC write, a forced fault, a hand grab) is an Event, applied
// between steps through apply_event. Here too the text forms they are read from: timed
// events ("5s sep.net.MoveToWorkingPos.put", "2s belt.field.set_speed 0.5"), durations
// ("10s", "500ms", "2min") and frequencies ("150Hz", "1kHz").
#pragma once

#include "engine/engine.h"
#include "engine/times.h"
#include "graph/graph.h"

#include <functional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace plant::engine {

bool parse_duration(std::string_view text, double& seconds, std::string& error);
bool parse_frequency(std::string_view text, double& hz, std::string& error);

// A trainee's hand (docs/runtime.md, "Hands"): "grab BODY at X,Y,Z", "move BODY to X,Y,Z",
// "drop BODY", "remove OBJECT".
enum class HandAct : uint8_t { None, Grab, Move, Drop, Remove };

// An external input at a time: the slot by its dotted path (Graph::slot_path, or a
// declared port's Graph::port_path: an input port feeds every slot it forwards to) and a
// value for its type (none for void; "x,y,z" or "x y z" for vec3; text for strings;
// a DO path or id for references).
struct Event {
    double time = 0;
    std::string path;            // as addressed
    std::vector<graph::SlotId> slots;  // the input slots it feeds (several for a port)
    std::vector<double> value;
    std::string text;  // string slots: interned into the engine when the run starts
    // A force ("force PATH stuck VALUE | open | invert") or, with mode None, its release
    // ("release PATH"): outputs and inputs alike (docs/runtime.md, "Forced slots").
    bool force = false;
    ForceMode mode = ForceMode::None;
    bool planned = false;  // declared in the plant file (plant_events), not given to the run
    // A hand's act (no slots then): grab, move and drop a `body`, remove an `object`; `value`
    // the point (grab: the point taken, move: where to).
    HandAct hand = HandAct::None;
    graph::BodyId body;
    graph::DoId object;
};

// Every addressable input and output by its dotted path: component slots and ports.
struct SlotTarget {
    std::vector<graph::SlotId> slots;
    graph::SlotType type = graph::SlotType::Void;
    graph::Dir dir = graph::Dir::In;
    bool port = false;
};
using SlotIndex = std::unordered_map<std::string, SlotTarget>;
SlotIndex slot_index(const graph::Graph& g);
// The dotted path that names exactly `slots` (a slot, or a port forwarding to them all):
// the shortest ("" when none does).
std::string path_of(const SlotIndex& slots, const std::vector<graph::SlotId>& which);
// The closest path in the index to a misspelt one ("" when nothing is close).
std::string closest_path(const SlotIndex& slots, std::string_view path);

// The events-file line that replays `ev` ("12.500s s1.to_working", "3.000s b1.drive.set_speed
// 0.25"): its time on the step grid of step length `dt` (times.h; 0: the graph's own rate).
std::string format_event(const graph::Graph& g, const Event& ev, double dt = 0);
// Whether `ev` is applied before the engine's next step: its time is at or before the end
// of that step, to within half the last printed decimal (times.h), so that a time the run
// printed reads back to its step (the rule `plant run`, `plant serve` and the replays share).
inline bool due(const Engine& e, const Event& ev) {
    return ev.time <= double(e.steps() + 1) * e.dt() + time_slack(e.dt());
}
// Writes the event's value into the engine (strings interned) and activates its slots,
// for the next step: the one way external inputs reach a running plant.
void apply_event(Engine& e, const Event& ev);

bool parse_event(const graph::Graph& g, const SlotIndex& slots, std::string_view line, Event& ev,
                 std::string& error);
// The same without the time: "PATH [VALUE]", "force PATH ...", "release PATH", "grab BODY at
// X,Y,Z", "move BODY to X,Y,Z", "drop BODY", "remove OBJECT" (the viewer's and the PLC link's
// inputs).
bool parse_input(const graph::Graph& g, const SlotIndex& slots, std::string_view text, Event& ev,
                 std::string& error);
// The timed inputs the plant file itself declares (its plugin components' schedule hooks,
// engine/plugin.h: a `faults` component's entries), sorted by time; a run applies them
// before the command line's events of the same step.
std::vector<Event> plant_events(const graph::Graph& g);
// The events a run applies, in the order it applies them: the plant's own (plant_events)
// and then `given` (the command line's, an events file's) sorted by time, the plant's first
// at equal times and `given` in its own order (a later force of the same slot wins).
std::vector<Event> run_events(const graph::Graph& g, std::vector<Event> given);

// `s` without blanks (spaces, tabs, carriage returns, newlines) at either end.
std::string_view trim(std::string_view s);
// Reads a file of one item per line, as an events file and a drill file are: blank lines and
// lines starting with '#' are skipped, and f(line, n, col) gets every other line, trimmed, with
// its number and the column it starts at (both from 1). False, with `error` set, when the path
// is a folder (`what` says what it should be: "an events file"), cannot be opened or read, or f
// returns false (having set `error`).
bool read_lines(const std::string& path, std::string_view what,
                const std::function<bool(std::string_view line, int n, size_t col)>& f, std::string& error);

// One event per line; blank lines and lines starting with '#' are skipped.
bool load_events(const graph::Graph& g, const SlotIndex& slots, const std::string& path,
                 std::vector<Event>& out, std::string& error);

}  // namespace plant::engine
