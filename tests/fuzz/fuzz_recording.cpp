// Target `recording`: the bytes of a recording file (`plant run --record`, docs/viewer.md,
// "Recordings"), plain or zstd-compressed, as `plant serve --replay` reads them.
// Invariant: no crash, no sanitizer report, no exception; a refused recording says why; an
// accepted one has frames, each of which decodes again into a frame of the scene's counts.
#include "fuzz.h"
#include "serve/record.h"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    plant::view::Recording rec;
    std::string error;
    if (!plant::view::parse_recording(plant::fuzz::text(data, size), "fuzz.rec", rec, error)) {
        if (error.empty()) plant::fuzz::broken("a recording refused without a reason");
        return 0;
    }
    if (rec.frames.empty()) plant::fuzz::broken("a recording accepted without frames");
    plant::view::Frame f = plant::view::Frame::sized(rec.bodies, rec.graphics);
    for (const auto& fr : rec.frames) {
        bool full = false;
        if (!plant::view::decode_frame(fr.data, f, full)) plant::fuzz::broken("an accepted frame does not decode");
    }
    return 0;
}
