// Drills (docs/training.md, "Drills"): faults an instructor schedules now, at a time, or when
// a condition holds ("when bottle 10 passes S2"), each hidden from trainees or shown, each
// ended by its release or by a repair rule (an input operated, a part replaced by hand). One
// drill is one line:
//
//     [hidden|shown] TRIGGER EVENT [repaired by PATH | repaired by hand PATH]
//     TRIGGER: TIME (as in an events file: "20s"), `now`, or `when PATH >= N`
//
//     20s force line[0].s2.sw.reader.bottle open
//     when line[0].s2.seen >= 10 force line[0].s2.sw.reader.bottle open repaired by line[0].ops.start.press
//
// One way in: a drill never touches the run itself. At each step boundary Drills::due looks
// at the engine as the last step left it and hands back the events that fire now, each timed
// at the end of the coming step; the caller applies them through engine::apply_event with the
// step's other events and writes them to the session's events file as the timed events they
// became, so `plant run --events` replays the session without evaluating any condition.
#pragma once

#include "engine/engine.h"
#include "engine/events.h"
#include "graph/graph.h"

#include <string>
#include <string_view>
#include <vector>

namespace plant::faults {

struct Drill {
    enum class Trigger : uint8_t { Now, At, When };
    Trigger trigger = Trigger::Now;
    double at = 0;                    // At: plant time
    std::string when_path;            // When: the slot (or port) watched
    std::vector<graph::SlotId> when_slots;  //   its slots
    bool when_void = false;           //   a void slot: the times it was active so far
    double threshold = 0;             //   fires when the value (or count) is >= threshold
    engine::Event event;              // what it does (time set when it fires)
    std::string repair_path;          // "" none: an input whose operation releases the fault
    std::vector<graph::SlotId> repair_slots;
    // `repaired by hand PATH`: the fault is released once a hand has let go of a part PATH
    // names (an object, the objects inside it, or a body: their dynamic bodies), having held
    // it since the fault was set — the part taken and put back, or taken off the line.
    bool repair_hand = false;
    std::vector<graph::BodyId> repair_bodies;
    bool shown = false;  // trainees see it (its force, its release); hidden by default
    std::string text;    // the line as written
    std::string by, role;  // who scheduled it ("drill file", "page 2"), their role

    // The run's own state of it.
    enum class State : uint8_t { Waiting, Holding, Released, Repaired, Done, Cancelled };
    State state = State::Waiting;
    int64_t count = 0;        // When on a void slot: activations seen so far
    bool hand_held = false;   // repaired by hand: a hand has held the part while the fault held
    int64_t counted_to = -1;  // the last step counted
    double fired = -1, ended = -1;  // Cancelled: `ended` is when
    std::string cancelled_by;       // Cancelled: who ("page 1 (instructor)")
    bool watched = false;  // its slots watched in this run's engine
};

std::string_view word(Drill::State s);

// One drill line (the syntax above); false with `error` (the part of the line at fault).
bool parse_drill(const graph::Graph& g, const engine::SlotIndex& slots, std::string_view line, Drill& out,
                 std::string& error);
// A drill file: one drill per line, blank lines and '#' comments skipped; errors as
// FILE:LINE:COL.
bool load_drills(const graph::Graph& g, const engine::SlotIndex& slots, const std::string& path, std::vector<Drill>& out,
                 std::string& error);

// The drills of a run and their state.
class Drills {
public:
    struct Fired {
        engine::Event event;
        size_t drill = 0;  // its index
        bool repair = false;  // the release its repair rule made
    };

    void add(Drill d);
    // A new run (a restart): every drill waits again, but a cancelled one stays cancelled
    // (from the run's start).
    void reset();
    // Drops waiting drill `number` (1-based) before it fires, at plant time `t`, by `by`: it
    // never fires. A drill that has fired is ended by releasing its fault, not cancelled:
    // false with `error` saying so (or that there is no such drill). Touches no plant state.
    bool cancel(int number, double t, const std::string& by, std::string& error);
    // At a step boundary, before the step: what fires now (in the order of the drills), each
    // timed at the end of the coming step. A drill whose fault was released (by anyone)
    // meanwhile ends; one whose repair input was active in the last step gets its release.
    void due(engine::Engine& e, std::vector<Fired>& out);
    const std::vector<Drill>& list() const { return drills_; }
    bool empty() const { return drills_.empty(); }

private:
    std::vector<Drill> drills_;
};

}  // namespace plant::faults
