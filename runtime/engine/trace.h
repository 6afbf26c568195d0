// The CSV trace of a run: a `time` column, then one column per traced quantity, one
// row per sampled step (and one for the start, at time 0).
//
// Columns: the graph's records (Graph::records), each expanded by its slot's type:
// void -> the steps it was active since the previous row (0/1 when every step is a row,
// so a sampled trace never hides an event); bool/int/real/ref -> the value; string -> the text;
// vec3 -> .x .y .z; quat -> .qx .qy .qz .qw; pose -> .x .y .z .qx .qy .qz .qw.
// Without records, or when a selection is given, the default set:
//   bodies: every dynamic body's centre of mass, "<body>.x/.y/.z", and "<body>.speed";
//   places: every place's tokens, "<slot path of its tokens output>";
//   slots:  every void output's activity, "<slot path>".
// A plant with dynamic bodies has a column `lost`: the objects lost (left the world) since
// the previous row, "path off field at T s at (x y z) m" separated by ';' (empty when none;
// run.h, loss_text). A run with forces (docs/runtime.md, "Forced slots") has a last column
// `forced`: the slots forced at that row, "path=mode" separated by ';' (empty when none).
#pragma once

#include "engine/engine.h"

#include <fmt/format.h>

#include <iosfwd>
#include <string>
#include <vector>

namespace plant::engine {

struct TraceColumn {
    enum class Kind : uint8_t { Value, Text, Activity, BodyAxis, BodySpeed, Tokens, Lost, Forced };
    Kind kind;
    int32_t id;     // slot, body or place
    int32_t index;  // component of a value, axis of a body
    std::string name;
    std::vector<graph::SlotId> slots = {};  // Forced: the slots that may be forced

    graph::SlotId slot() const { return graph::SlotId(id); }
    graph::BodyId body() const { return graph::BodyId(id); }
    graph::PlaceId place() const { return graph::PlaceId(id); }
};

struct TraceSelect {
    bool bodies = false, places = false, slots = false;
    bool any() const { return bodies || places || slots; }
};

std::vector<TraceColumn> trace_columns(const graph::Graph& g, TraceSelect sel);
// Whether the plant has a dynamic body, something that can be lost; then the `lost` column.
bool can_lose(const graph::Graph& g);
TraceColumn lost_column();
// The `forced` column over the slots some event forces (ids, once each, in order).
TraceColumn forced_column(std::vector<graph::SlotId> slots);

class TraceWriter {
public:
    // Watches the slots it traces, so their values are refreshed every step.
    TraceWriter(Engine& e, std::vector<TraceColumn> columns, std::ostream& out);
    void header();
    void step();    // after every step: counts the void columns' activity
    void finish();  // after the last step: counts what it produced after its logic phase
    void row();     // writes the counts and starts them again
    void flush();
    size_t columns() const { return cols_.size(); }

private:
    Engine& e_;
    std::vector<TraceColumn> cols_;
    std::vector<int64_t> counts_;     // per column: steps active since the last row (activity)
    std::vector<size_t> activity_;    // the activity columns
    std::ostream& out_;
    fmt::memory_buffer buf_;
    int decimals_;  // of the time column (times.h)
    size_t lost_ = 0;  // Engine::lost() written so far
};

}  // namespace plant::engine
