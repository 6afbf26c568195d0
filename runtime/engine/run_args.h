// The values on a `plant run` command line and in an events file: durations
// ("10s", "500ms", "2min"), frequencies ("150Hz", "1kHz") and timed events
// ("5s sep.net.MoveToWorkingPos.put", "2s belt.field.set_speed 0.5").
#pragma once

#include "engine/engine.h"
#include "graph/graph.h"

#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace plant::engine {

bool parse_duration(std::string_view text, double& seconds, std::string& error);
bool parse_frequency(std::string_view text, double& hz, std::string& error);

// An external input at a time: the slot by its dotted path (Graph::slot_path) and a
// value for its type (none for void; "x,y,z" or "x y z" for vec3; text for strings;
// a DO path or id for references).
struct Event {
    double time = 0;
    int32_t slot = -1;
    std::vector<double> value;
    std::string text;  // string slots: interned into the engine when the run starts
};

using SlotIndex = std::unordered_map<std::string, int32_t>;
SlotIndex slot_index(const graph::Graph& g);

bool parse_event(const graph::Graph& g, const SlotIndex& slots, std::string_view line, Event& ev,
                 std::string& error);
// One event per line; blank lines and lines starting with '#' are skipped.
bool load_events(const graph::Graph& g, const SlotIndex& slots, const std::string& path,
                 std::vector<Event>& out, std::string& error);

}  // namespace plant::engine
