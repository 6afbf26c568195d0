// The CSV trace of a run: a `time` column, then one column per traced quantity, one
// row per sampled step (and one for the start, at time 0).
//
// Columns: the graph's records (Graph::records), each expanded by its slot's type:
// void -> its activity 0/1; bool/int/real/ref -> the value; string -> the text;
// vec3 -> .x .y .z; quat -> .qx .qy .qz .qw; pose -> .x .y .z .qx .qy .qz .qw.
// Without records, or when a selection is given, the default set:
//   bodies: every dynamic body's centre of mass, "<body>.x/.y/.z", and "<body>.speed";
//   places: every place's tokens, "<slot path of its tokens output>";
//   slots:  every void output's activity, "<slot path>".
#pragma once

#include "engine/engine.h"

#include <fmt/format.h>

#include <iosfwd>
#include <string>
#include <vector>

namespace plant::engine {

struct TraceColumn {
    enum class Kind : uint8_t { Value, Text, Activity, BodyAxis, BodySpeed, Tokens };
    Kind kind;
    int32_t id;     // slot, body or place
    int32_t index;  // component of a value, axis of a body
    std::string name;
};

struct TraceSelect {
    bool bodies = false, places = false, slots = false;
    bool any() const { return bodies || places || slots; }
};

std::vector<TraceColumn> trace_columns(const graph::Graph& g, TraceSelect sel);

class TraceWriter {
public:
    // Watches the slots it traces, so their values are refreshed every step.
    TraceWriter(Engine& e, std::vector<TraceColumn> columns, std::ostream& out);
    void header();
    void row();
    void flush();
    size_t columns() const { return cols_.size(); }

private:
    Engine& e_;
    std::vector<TraceColumn> cols_;
    std::ostream& out_;
    fmt::memory_buffer buf_;
};

}  // namespace plant::engine
