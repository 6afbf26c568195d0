// The recorder's part of `plant run` (docs/viewer.md): --record FILE, --record-rate,
// --record-compress; the recording is the run's observer.
#include "app/parts.h"

#include "engine/events.h"
#include "serve/record.h"

#include <fmt/format.h>

namespace plant::app {

namespace {

class RecordPart : public Part {
public:
    void add_flags(Cli& cli, Where where) override {
        if (where != Where::Run) return;
        cli.value("--record", path_,
                  "write what the viewer needs (poses, graphics, status,\nevents) for `plant serve --replay FILE`",
                  "FILE", "a FILE");
        rate_ = cli.value("--record-rate", rate_text_,
                          "frames recorded per second of simulated time (default\n30Hz; events are all kept)", "10Hz");
        compress_ = cli.value("--record-compress", compress_text_,
                              "compress the recording (default zstd; --replay reads both)", "zstd|none");
    }
    bool check(Where where, std::string& error) override {
        if (where != Where::Run) return true;
        if (rate_->count()) {
            std::string why;
            if (!engine::parse_frequency(rate_text_, options_.rate, why)) {
                error = "--record-rate: " + why;
                return false;
            }
        }
        if (compress_->count()) {
            if (compress_text_ != "zstd" && compress_text_ != "none") {
                error = fmt::format("--record-compress takes zstd or none, not '{}'", compress_text_);
                return false;
            }
            options_.compress = compress_text_ == "zstd";
        }
        if (path_.empty() && (rate_->count() || compress_->count())) {
            error = "--record-rate and --record-compress need --record FILE";
            return false;
        }
        return true;
    }
    bool observer(const graph::Graph& g, const RunPlace& place, std::unique_ptr<engine::RunObserver>& out,
                  std::string& error, int& code) override {
        if (path_.empty()) return true;
        view::ModelDirs dirs;
        dirs.plant_dir = place.plant_dir;
        dirs.stdlib_dir = place.stdlib;
        auto rec = std::make_unique<view::Recorder>(g, path_, dirs, options_);
        if (!rec->ok()) {
            error = fmt::format("--record: cannot write '{}'", path_);
            code = 2;
            return false;
        }
        out = std::move(rec);
        return true;
    }

private:
    std::string path_, rate_text_, compress_text_;
    view::RecordOptions options_;
    CLI::Option* rate_ = nullptr;
    CLI::Option* compress_ = nullptr;
};

}  // namespace

std::unique_ptr<Part> make_record_part() { return std::make_unique<RecordPart>(); }

}  // namespace plant::app
