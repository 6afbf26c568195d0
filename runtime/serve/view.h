// What the viewer sees of a running plant (docs/viewer.md): the scene (the static
// description, JSON), frames (poses, binary), status (counters, records, sensors, the
// inspected object; JSON). Shared by `plant serve` and the recorder of `plant run --record`.
#pragma once

#include "engine/engine.h"
#include "engine/run.h"
#include "graph/graph.h"
#include "serve/models.h"

#include <cstdint>
#include <string>
#include <vector>

namespace plant::view {

constexpr int kProtocolVersion = 1;

// The scene message: {"type":"scene", ...}; `model_problems` lists the models not shown.
std::string scene_json(const graph::Graph& g, const ModelDirs& dirs, bool replay, double duration);

// Poses at one moment: every body and every graphics (floats, as sent).
struct Frame {
    double time = 0;
    int64_t step = 0;
    std::vector<float> body_pose;     // 7 per body
    std::vector<uint8_t> body_state;  // bit 0 in the world, bit 1 collision on
    std::vector<float> gfx_pose;      // 7 per graphics
    std::vector<int32_t> gfx_variant;

    // A frame for `bodies` bodies and `graphics` graphics, all zero (variants -1).
    static Frame sized(size_t bodies, size_t graphics);
};

// Takes frames from an engine and keeps, per body and graphics, the number of the last
// frame in which it changed, so a client is sent only what changed since it last looked.
class FrameTracker {
public:
    explicit FrameTracker(const graph::Graph& g);
    // Takes the engine's poses into `now` and bumps the change numbers; returns its number.
    uint64_t take(const engine::Engine& e);
    // Replaces the current frame (a replay), marking what differs as changed.
    uint64_t put(const Frame& f);
    const Frame& frame() const { return now_; }
    uint64_t seq() const { return seq_; }
    const std::vector<uint64_t>& body_seq() const { return body_seq_; }
    const std::vector<uint64_t>& gfx_seq() const { return gfx_seq_; }

private:
    uint64_t commit();
    const graph::Graph& g_;
    std::vector<graph::BodyId> movable_;  // bodies that are not static
    Frame now_, prev_;
    std::vector<uint64_t> body_seq_, gfx_seq_;
    uint64_t seq_ = 0;
};

// The binary frame of docs/viewer.md: bodies and graphics changed after frame `since`
// (every one when `since` is 0), appended to `out`.
void encode_frame(const Frame& f, const std::vector<uint64_t>& body_seq, const std::vector<uint64_t>& gfx_seq,
                  uint64_t since, bool paused, std::string& out);
// Decodes a binary frame into `f` (which must be sized for the graph): applies the poses it
// holds. False on a malformed frame.
bool decode_frame(std::string_view bytes, Frame& f, bool& full);

// The status message: {"type":"status", ...}. `inspect` is the dotted path of the object
// the client inspects ("" none).
struct StatusExtra {
    bool paused = false;
    double speed = 1;  // chosen (0: as fast as possible)
    double rtf = 0;    // achieved over the last seconds
    std::string forced;  // JSON: the forced slots, with who forced them and since when ("": none)
};
// Status lists at most this many lost objects (the first lost; counters.lost counts them all).
constexpr size_t kMaxLost = 100;
std::string status_json(const engine::Engine& e, const engine::RecordTally& tally, const StatusExtra& x);
// The counters (history.h's order), then the records: a sample of the run's history.
std::vector<double> history_sample(const engine::Engine& e, const engine::RecordTally& tally);
// {"path", "slots": [{path, value, active, forced}], "places": [{id, tokens}]} of one object
// and its components (not its children); null when the path names no object. Without
// `forces` every `forced` is null (a trainee's inspector).
std::string inspect_json(const engine::Engine& e, std::string_view path, bool forces = true);
// The output slots inside the object `path` (its components') that the engine must refresh
// for an inspector (Engine::watch).
std::vector<graph::SlotId> object_slots(const graph::Graph& g, std::string_view path);

}  // namespace plant::view
