// Recordings (`plant run --record run.rec`, played by `plant serve --replay run.rec`):
// what the viewer needs of a run, in the viewer's own messages. Format (docs/viewer.md):
//
//   "plant-rec 1\n", then chunks: a tag byte, a u32 length (little-endian), the payload.
//   'C' the scene message (JSON, first chunk), 'F' a binary frame (at the recording's rate,
//   30 Hz of simulated time unless told, a full one each second, else what changed), 'S' a
//   status message (JSON, every 0.2 s, or every frame when frames are rarer), 'E' an event
//   message (JSON: {"type":"event","line":...}).
//
// Compressed (the default), the whole of that is one zstd frame with a checksum: the file
// starts with zstd's magic bytes, and the reader tells the two forms apart by them.
#pragma once

#include "engine/run.h"
#include "serve/view.h"

#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace plant::view {

struct RecordOptions {
    double rate = 30;      // frames per second of simulated time (events are all kept)
    bool compress = true;  // zstd
    int level = 3;         // zstd's compression level
};

class Recorder : public engine::RunObserver {
public:
    // Opens `path` for writing; check ok().
    Recorder(const graph::Graph& g, const std::string& path, ModelDirs dirs, RecordOptions opt = {});
    ~Recorder() override;
    bool ok() const { return bool(out_) && (!opt_.compress || zstd_); }

    void started(const engine::Engine& e) override;
    void event(const engine::Engine& e, const engine::Event& ev) override;
    void stepped(const engine::Engine& e, const engine::RecordTally& tally) override;
    bool finished(const engine::Engine& e, const engine::RecordTally& tally, std::string& error) override;

private:
    void frame(const engine::Engine& e);
    void chunk(char tag, std::string_view payload);
    void write(std::string_view bytes);  // through the compressor when there is one
    bool flush_zstd(bool end);
    const graph::Graph& g_;
    std::string path_;
    ModelDirs dirs_;
    RecordOptions opt_;
    double frame_every_, status_every_;
    int64_t full_every_;
    std::ofstream out_;
    struct ZstdStream;
    std::unique_ptr<ZstdStream> zstd_;
    FrameTracker tracker_;
    int64_t frames_ = 0;
    uint64_t last_seq_ = 0;
    double next_frame_ = 0, next_status_ = 0;
    std::string buf_;
};

struct Recording {
    std::string scene;
    struct Chunk {
        double time;
        std::string data;
        bool full = false;  // frames: a full frame
    };
    std::vector<Chunk> frames, statuses, events;
    double duration = 0;
    size_t bodies = 0, graphics = 0;  // the scene's counts: what frames hold
};

// Reads a recording, compressed or not; false with `error` (the offset of what is wrong)
// otherwise. Frames are checked against the scene's counts.
bool load_recording(const std::string& path, Recording& rec, std::string& error);
// The same from a recording's bytes; `name` starts the error messages.
bool parse_recording(std::string_view bytes, const std::string& name, Recording& rec, std::string& error);

}  // namespace plant::view
