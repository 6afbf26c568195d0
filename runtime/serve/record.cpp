#include "serve/record.h"

#include <nlohmann/json.hpp>

#include <cstring>
#include <fmt/format.h>

namespace plant::view {

using json = nlohmann::json;

namespace {

constexpr std::string_view kMagic = "plant-rec 1\n";
constexpr double kFrameEvery = 1.0 / 30, kStatusEvery = 0.2;
constexpr int64_t kFullEvery = 30;  // frames
constexpr size_t kMaxChunk = size_t(1) << 30;

}  // namespace

Recorder::Recorder(const graph::Graph& g, const std::string& path, ModelDirs dirs)
    : g_(g), path_(path), dirs_(std::move(dirs)), out_(path, std::ios::binary), tracker_(g) {}

void Recorder::chunk(char tag, std::string_view payload) {
    const uint32_t n = uint32_t(payload.size());
    char head[5];
    head[0] = tag;
    std::memcpy(head + 1, &n, 4);
    out_.write(head, 5);
    out_.write(payload.data(), std::streamsize(payload.size()));
}

void Recorder::frame(const engine::Engine& e) {
    const uint64_t seq = tracker_.take(e);
    buf_.clear();
    const bool full = frames_ % kFullEvery == 0;
    encode_frame(tracker_.frame(), tracker_.body_seq(), tracker_.gfx_seq(), full ? 0 : last_seq_, false, buf_);
    chunk('F', buf_);
    last_seq_ = seq;
    ++frames_;
}

void Recorder::started(const engine::Engine& e) {
    out_.write(kMagic.data(), std::streamsize(kMagic.size()));
    chunk('C', scene_json(g_, dirs_, true, 0));
    frame(e);
    chunk('S', status_json(e, engine::RecordTally(g_), {}));  // nothing counted yet
    next_frame_ = kFrameEvery;
    next_status_ = kStatusEvery;
}

void Recorder::event(const engine::Engine& e, const engine::Event& ev) {
    const json j{{"type", "event"}, {"line", engine::format_event(e.graph(), ev, e.dt())}, {"time", ev.time}};
    chunk('E', j.dump(-1, ' ', false, json::error_handler_t::replace));
}

void Recorder::stepped(const engine::Engine& e, const engine::RecordTally& tally) {
    if (e.time() + 1e-9 >= next_frame_) {
        frame(e);
        next_frame_ = double(frames_) * kFrameEvery;
    }
    if (e.time() + 1e-9 >= next_status_) {
        chunk('S', status_json(e, tally, {}));
        next_status_ += kStatusEvery;
    }
}

bool Recorder::finished(const engine::Engine& e, const engine::RecordTally& tally, std::string& error) {
    frame(e);
    chunk('S', status_json(e, tally, {}));
    out_.flush();
    if (!out_) {
        error = fmt::format("--record: cannot write '{}'", path_);
        return false;
    }
    return true;
}

bool load_recording(const std::string& path, Recording& rec, std::string& error) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = fmt::format("{}: cannot open", path);
        return false;
    }
    std::string magic(kMagic.size(), '\0');
    in.read(magic.data(), std::streamsize(magic.size()));
    if (!in || magic != kMagic) {
        error = fmt::format("{}: not a plant recording (it does not start with 'plant-rec 1')", path);
        return false;
    }
    rec = Recording{};
    Frame shape;  // sized from the scene, to check frames
    bool have_scene = false;
    for (;;) {
        const auto at = size_t(in.tellg());
        char head[5];
        in.read(head, 5);
        if (in.gcount() == 0) break;
        if (in.gcount() != 5) {
            error = fmt::format("{}: byte {}: a chunk header is cut short", path, at);
            return false;
        }
        uint32_t n;
        std::memcpy(&n, head + 1, 4);
        if (n > kMaxChunk) {
            error = fmt::format("{}: byte {}: a chunk of {} bytes", path, at, n);
            return false;
        }
        std::string data(n, '\0');
        in.read(data.data(), std::streamsize(n));
        if (size_t(in.gcount()) != n) {
            error = fmt::format("{}: byte {}: a chunk is cut short", path, at);
            return false;
        }
        const char tag = head[0];
        if (!have_scene && tag != 'C') {
            error = fmt::format("{}: byte {}: the scene must come first", path, at);
            return false;
        }
        if (tag == 'C') {
            const json s = json::parse(data, nullptr, false);
            if (have_scene || s.is_discarded() || !s.is_object() || !s.contains("bodies") || !s["bodies"].is_array() ||
                !s.contains("graphics") || !s["graphics"].is_array()) {
                error = fmt::format("{}: byte {}: not a scene", path, at);
                return false;
            }
            rec.bodies = s["bodies"].size();
            rec.graphics = s["graphics"].size();
            shape = Frame::sized(rec.bodies, rec.graphics);
            rec.scene = std::move(data);
            have_scene = true;
        } else if (tag == 'F') {
            bool full = false;
            if (!decode_frame(data, shape, full) || (rec.frames.empty() && !full)) {
                error = fmt::format("{}: byte {}: a malformed frame", path, at);
                return false;
            }
            rec.duration = std::max(rec.duration, shape.time);
            rec.frames.push_back({shape.time, std::move(data), full});
        } else if (tag == 'S' || tag == 'E') {
            const json j = json::parse(data, nullptr, false);
            if (j.is_discarded() || !j.is_object() || !j.contains("time") || !j["time"].is_number()) {
                error = fmt::format("{}: byte {}: a malformed {} message", path, at, tag == 'S' ? "status" : "event");
                return false;
            }
            (tag == 'S' ? rec.statuses : rec.events).push_back({j["time"].get<double>(), std::move(data), false});
        } else {
            error = fmt::format("{}: byte {}: unknown chunk '{}'", path, at, tag);
            return false;
        }
    }
    if (rec.frames.empty()) {
        error = fmt::format("{}: no frames", path);
        return false;
    }
    return true;
}

}  // namespace plant::view
