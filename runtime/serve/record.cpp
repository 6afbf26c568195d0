#include "serve/record.h"

#include "engine/events.h"

#include <nlohmann/json.hpp>
#include <zstd.h>

#include <cmath>
#include <cstring>
#include <fmt/format.h>
#include <iterator>

namespace plant::view {

using json = nlohmann::json;

namespace {

constexpr std::string_view kMagic = "plant-rec 1\n";
constexpr std::string_view kZstdMagic = "\x28\xB5\x2F\xFD";
constexpr double kStatusEvery = 0.2;
constexpr size_t kMaxChunk = size_t(1) << 30;
// A compressed recording that expands past this many times its size is refused as damaged:
// a recording compresses about 4 to 5 times.
constexpr size_t kMaxRatio = 1000;

}  // namespace

struct Recorder::ZstdStream {
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    std::string out = std::string(ZSTD_CStreamOutSize(), '\0');
    bool ended = false, failed = false;
    ~ZstdStream() { ZSTD_freeCCtx(cctx); }
};

Recorder::Recorder(const graph::Graph& g, const std::string& path, ModelDirs dirs, RecordOptions opt)
    : g_(g),
      path_(path),
      dirs_(std::move(dirs)),
      opt_(opt),
      frame_every_(1.0 / opt.rate),
      status_every_(std::max(kStatusEvery, 1.0 / opt.rate)),
      full_every_(std::max<int64_t>(1, std::llround(opt.rate))),  // a full frame each second
      out_(path, std::ios::binary),
      tracker_(g) {
    if (!opt_.compress) return;
    auto z = std::make_unique<ZstdStream>();
    if (!z->cctx || ZSTD_isError(ZSTD_CCtx_setParameter(z->cctx, ZSTD_c_compressionLevel, opt_.level)) ||
        ZSTD_isError(ZSTD_CCtx_setParameter(z->cctx, ZSTD_c_checksumFlag, 1)))
        return;
    zstd_ = std::move(z);
}

Recorder::~Recorder() {
    // A run that ended without finished() (an error on the way) still leaves a whole file.
    if (zstd_ && !zstd_->ended) flush_zstd(true);
}

bool Recorder::flush_zstd(bool end) {
    ZstdStream& z = *zstd_;
    if (z.ended || z.failed) return !z.failed;
    ZSTD_inBuffer in{nullptr, 0, 0};
    for (;;) {
        ZSTD_outBuffer o{z.out.data(), z.out.size(), 0};
        const size_t left = ZSTD_compressStream2(z.cctx, &o, &in, end ? ZSTD_e_end : ZSTD_e_flush);
        if (ZSTD_isError(left)) return !(z.failed = true);
        out_.write(z.out.data(), std::streamsize(o.pos));
        if (left == 0) break;
    }
    z.ended = end;
    return true;
}

void Recorder::write(std::string_view bytes) {
    if (!zstd_) {
        out_.write(bytes.data(), std::streamsize(bytes.size()));
        return;
    }
    ZstdStream& z = *zstd_;
    if (z.failed || z.ended) return;
    ZSTD_inBuffer in{bytes.data(), bytes.size(), 0};
    while (in.pos < in.size) {
        ZSTD_outBuffer o{z.out.data(), z.out.size(), 0};
        if (ZSTD_isError(ZSTD_compressStream2(z.cctx, &o, &in, ZSTD_e_continue))) {
            z.failed = true;
            return;
        }
        out_.write(z.out.data(), std::streamsize(o.pos));
    }
}

void Recorder::chunk(char tag, std::string_view payload) {
    const uint32_t n = uint32_t(payload.size());
    char head[5];
    head[0] = tag;
    std::memcpy(head + 1, &n, 4);
    write({head, 5});
    write(payload);
}

void Recorder::frame(const engine::Engine& e) {
    const uint64_t seq = tracker_.take(e);
    buf_.clear();
    const bool full = frames_ % full_every_ == 0;
    encode_frame(tracker_.frame(), tracker_.body_seq(), tracker_.gfx_seq(), full ? 0 : last_seq_, false, buf_);
    chunk('F', buf_);
    last_seq_ = seq;
    ++frames_;
}

void Recorder::started(const engine::Engine& e) {
    write(kMagic);
    chunk('C', scene_json(g_, dirs_, true, 0));
    frame(e);
    chunk('S', status_json(e, engine::RecordTally(g_), {}));  // nothing counted yet
    next_frame_ = frame_every_;
    next_status_ = status_every_;
}

void Recorder::event(const engine::Engine& e, const engine::Event& ev) {
    const json j{{"type", "event"}, {"line", engine::format_event(e.graph(), ev, e.dt())}, {"time", ev.time}};
    chunk('E', j.dump(-1, ' ', false, json::error_handler_t::replace));
}

void Recorder::stepped(const engine::Engine& e, const engine::RecordTally& tally) {
    if (e.time() + 1e-9 >= next_frame_) {
        frame(e);
        next_frame_ = double(frames_) * frame_every_;
    }
    if (e.time() + 1e-9 >= next_status_) {
        chunk('S', status_json(e, tally, {}));
        next_status_ += status_every_;
    }
}

bool Recorder::finished(const engine::Engine& e, const engine::RecordTally& tally, std::string& error) {
    frame(e);
    chunk('S', status_json(e, tally, {}));
    if (zstd_ && !flush_zstd(true)) {
        error = fmt::format("--record: cannot compress '{}'", path_);
        return false;
    }
    out_.flush();
    if (!out_) {
        error = fmt::format("--record: cannot write '{}'", path_);
        return false;
    }
    return true;
}

namespace {

// A compressed recording's content; false with `error` when it is damaged or cut short.
bool decompress(std::string_view bytes, const std::string& name, std::string& out, std::string& error) {
    std::unique_ptr<ZSTD_DCtx, size_t (*)(ZSTD_DCtx*)> d(ZSTD_createDCtx(), ZSTD_freeDCtx);
    if (!d) {
        error = fmt::format("{}: cannot decompress (out of memory)", name);
        return false;
    }
    const size_t limit = std::max<size_t>(size_t(64) << 20, bytes.size() * kMaxRatio);
    ZSTD_inBuffer in{bytes.data(), bytes.size(), 0};
    out.clear();
    size_t left = 1;
    while (in.pos < in.size || left != 0) {
        const size_t was = out.size(), room = ZSTD_DStreamOutSize();
        if (was + room > limit) {
            error = fmt::format("{}: the compressed recording expands past {} bytes ({} times its size): it is damaged",
                                name, limit, kMaxRatio);
            return false;
        }
        out.resize(was + room);
        ZSTD_outBuffer o{out.data() + was, room, 0};
        const size_t before = in.pos;
        left = ZSTD_decompressStream(d.get(), &o, &in);
        out.resize(was + o.pos);
        if (ZSTD_isError(left)) {
            error = fmt::format("{}: the compressed data is damaged (zstd: {}; read up to byte {})", name,
                                ZSTD_getErrorName(left), in.pos);
            return false;
        }
        if (left != 0 && in.pos == in.size && o.pos < room && in.pos == before) {
            error = fmt::format("{}: the compressed data is cut short after {} bytes (the file ends inside its "
                                "zstd frame)",
                                name, bytes.size());
            return false;
        }
    }
    return true;
}

}  // namespace

bool load_recording(const std::string& path, Recording& rec, std::string& error) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = fmt::format("{}: cannot open", path);
        return false;
    }
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) {
        error = fmt::format("{}: cannot read", path);
        return false;
    }
    return parse_recording(bytes, path, rec, error);
}

bool parse_recording(std::string_view bytes, const std::string& path, Recording& rec, std::string& error) {
    std::string plain;
    const bool compressed = bytes.substr(0, kZstdMagic.size()) == kZstdMagic;
    if (compressed) {
        if (!decompress(bytes, path, plain, error)) return false;
        bytes = plain;
    }
    // Offsets in messages count in the recording's content (decompressed).
    const std::string name = compressed ? path + " (decompressed)" : path;
    if (bytes.substr(0, kMagic.size()) != kMagic) {
        error = fmt::format("{}: not a plant recording (it does not start with 'plant-rec 1')", name);
        return false;
    }
    rec = Recording{};
    Frame shape;  // sized from the scene, to check frames
    bool have_scene = false;
    for (size_t at = kMagic.size(); at < bytes.size();) {
        if (bytes.size() - at < 5) {
            error = fmt::format("{}: byte {}: a chunk header is cut short", name, at);
            return false;
        }
        uint32_t n;
        std::memcpy(&n, bytes.data() + at + 1, 4);
        if (n > kMaxChunk) {
            error = fmt::format("{}: byte {}: a chunk of {} bytes", name, at, n);
            return false;
        }
        if (bytes.size() - at - 5 < n) {
            error = fmt::format("{}: byte {}: a chunk is cut short", name, at);
            return false;
        }
        const char tag = bytes[at];
        std::string data(bytes.substr(at + 5, n));
        const size_t here = at;
        at += 5 + size_t(n);
        if (!have_scene && tag != 'C') {
            error = fmt::format("{}: byte {}: the scene must come first", name, here);
            return false;
        }
        if (tag == 'C') {
            const json s = json::parse(data, nullptr, false);
            if (have_scene || s.is_discarded() || !s.is_object() || !s.contains("bodies") || !s["bodies"].is_array() ||
                !s.contains("graphics") || !s["graphics"].is_array()) {
                error = fmt::format("{}: byte {}: not a scene", name, here);
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
                error = fmt::format("{}: byte {}: a malformed frame", name, here);
                return false;
            }
            rec.duration = std::max(rec.duration, shape.time);
            rec.frames.push_back({shape.time, std::move(data), full});
        } else if (tag == 'S' || tag == 'E') {
            const json j = json::parse(data, nullptr, false);
            if (j.is_discarded() || !j.is_object() || !j.contains("time") || !j["time"].is_number()) {
                error = fmt::format("{}: byte {}: a malformed {} message", name, here, tag == 'S' ? "status" : "event");
                return false;
            }
            (tag == 'S' ? rec.statuses : rec.events).push_back({j["time"].get<double>(), std::move(data), false});
        } else {
            error = fmt::format("{}: byte {}: unknown chunk '{}'", name, here, tag);
            return false;
        }
    }
    if (rec.frames.empty()) {
        error = fmt::format("{}: no frames", name);
        return false;
    }
    return true;
}

}  // namespace plant::view
